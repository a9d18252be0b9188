"""The vector heat method: log map accuracy and timings against potpourri3d 1.4, and analytic checks.

Tables (written into docs/vector-heat.md after its ``<!-- measured -->`` line with ``--out``):

meshes
    |log map| against the exact (MMP, gdist) geodesic distance on the shared
    meshes, mean relative error over every vertex, averaged over three random
    source vertices (the seeds of tests/test_accuracy.py): heatcore
    (``VectorHeatSolver`` with defaults, ``accuracy="smooth"`` and ``"high"``)
    and potpourri3d (``MeshVectorHeatSolver(V, F).compute_log_map``, its
    default ``AffineLocal`` strategy). Each mesh is compacted to its
    referenced vertices first (potpourri3d asserts on unreferenced ones).
analytic
    an icosphere of 10,242 vertices (radius against the great-circle distance,
    angle against the longitude after the best rotation), a flat 60 x 60 grid
    triangulated by Delaunay (log map against the planar offset after the best
    rotation, relative to ``|x|``), a cylinder (the unrolled plane), and the
    holonomy of latitude loops on a UV sphere.
angles
    the log map's angle against the initial direction of exact polyhedral
    geodesics (potpourri3d's edge-flip shortest paths, 100 random targets from
    each of 4 random sources), median of the error after the best rotation.
    Homer is left out: its shortest paths leave the source along a few edges
    towards saddle vertices and fan out there, so the exact direction takes a
    handful of values (our and potpourri3d's are both 0.75 rad off on average).
factorization
    the vector heat matrix factored by each backend (complex CHOLMOD or the
    real form).

Usage::

    python scripts/bench_vector_heat.py --meshes ../shared/meshes --out docs/vector-heat.md
    python scripts/bench_vector_heat.py --picture docs/images/vector_heat_spot.png

Needs the ``bench`` extra (gdist, potpourri3d, cvxopt), trimesh and matplotlib.
"""

import argparse
import time
from pathlib import Path

import numpy as np
import scipy.sparse as sp
from scipy.spatial import Delaunay

import heatcore as hc
from heatcore.reference import exact_directions, exact_distance, mean_relative_error

REPO = Path(__file__).resolve().parents[1]
MESHES = ["spot", "homer", "fandisk", "cheburashka", "rocker-arm", "nefertiti", "stanford-bunny"]


def compact(V, F):
    """The mesh without unreferenced vertices."""
    used = np.unique(F)
    index = np.full(len(V), -1)
    index[used] = np.arange(used.size)
    return np.ascontiguousarray(V[used], dtype=float), np.ascontiguousarray(index[F], dtype=np.int64)


def sources_of(F, k=3, seed=0):
    """``k`` random source vertices (as tests/test_accuracy.py draws them)."""
    return np.random.default_rng(seed).choice(np.unique(F), k, replace=False)


def best_rotation_error(L, X):
    """Mean ``|R L - X| / |X|`` over ``X != 0`` with the rotation ``R`` that fits best (least squares)."""
    z, w = L[:, 0] + 1j * L[:, 1], X[:, 0] + 1j * X[:, 1]
    keep = np.abs(w) > 0
    turn = np.vdot(z[keep], w[keep])
    turn /= abs(turn)
    return float(np.mean(np.abs(z[keep] * turn - w[keep]) / np.abs(w[keep])))


def angle_error(angle, exact, fit):
    """Mean ``|angle - exact|`` (wrapped) after the constant offset that fits best on the vertices ``fit``."""
    d = np.angle(np.exp(1j * (angle - exact)))
    offset = np.angle(np.mean(np.exp(1j * d[fit])))
    return float(np.mean(np.abs(np.angle(np.exp(1j * (d - offset))))))


def mesh_rows(names, mesh_dir):
    import potpourri3d as pp3d

    rows = []
    for name in names:
        mesh = hc.io.read_mesh(mesh_dir / f"{name}.obj")
        V, F = compact(mesh.vertices, mesh.faces)
        sources = sources_of(F)
        exact = [exact_distance(V, F, int(s)) for s in sources]
        start = time.perf_counter()
        domain = hc.TriangleMesh(V, F)
        smooth = hc.VectorHeatSolver(domain, accuracy="smooth")
        build = time.perf_counter() - start
        high = hc.VectorHeatSolver(domain, accuracy="high")  # the default; shares the domain's factorizations
        row = {"mesh": name, "n": len(V), "operator n": domain.operators.n_vertices, "build": build}
        for label, solver in (("smooth", smooth), ("high", high)):
            start = time.perf_counter()
            maps = [solver.log_map(int(s)) for s in sources]
            row[f"{label} s"] = (time.perf_counter() - start) / len(sources)
            row[label] = np.mean([mean_relative_error(np.linalg.norm(L, axis=1), e) for L, e in zip(maps, exact)])
        start = time.perf_counter()
        peer = pp3d.MeshVectorHeatSolver(V, F)
        maps = [peer.compute_log_map(int(s)) for s in sources]
        row["pp s"] = (time.perf_counter() - start) / len(sources)  # its factorizations happen on the first call
        row["pp"] = np.mean([mean_relative_error(np.linalg.norm(L, axis=1), e) for L, e in zip(maps, exact)])
        rows.append(row)
        print(name, {k: (round(v, 5) if isinstance(v, float) else v) for k, v in row.items()}, flush=True)
    return rows


def path_angle_rows(names, mesh_dir, n_sources=4, n_targets=100):
    """Median angle error of the log map against exact geodesic directions, heatcore and potpourri3d."""
    import potpourri3d as pp3d

    rows = []
    for name in names:
        mesh = hc.io.read_mesh(mesh_dir / f"{name}.obj")
        V, F = compact(mesh.vertices, mesh.faces)
        rng = np.random.default_rng(1)
        solver, peer = hc.VectorHeatSolver(hc.TriangleMesh(V, F)), pp3d.MeshVectorHeatSolver(V, F)
        errors = {"heatcore": [], "potpourri3d": []}
        for s in rng.choice(len(V), n_sources, replace=False):
            targets = rng.choice(np.setdiff1d(np.arange(len(V)), [s]), n_targets, replace=False)
            found = exact_directions(V, F, s, targets)  # the paths that are the shortest (MMP's length)
            exact, ok = found.angle, found.shortest & np.isfinite(found.angle)
            for label, L in (("heatcore", solver.log_map(int(s))), ("potpourri3d", peer.compute_log_map(int(s)))):
                d = np.angle(np.exp(1j * (np.arctan2(L[targets, 1], L[targets, 0])[ok] - exact[ok])))
                turn = np.angle(np.median(np.exp(1j * d)))
                errors[label].append(np.abs(np.angle(np.exp(1j * (d - turn)))))
        rows.append((name, {k: float(np.median(np.concatenate(v))) for k, v in errors.items()}))
        print("angles", rows[-1], flush=True)
    return rows


def icosphere_figures():
    """Radius and angle errors on the icosphere of 10,242 vertices, source vertex 0."""
    import potpourri3d as pp3d
    import trimesh

    sphere = trimesh.creation.icosphere(5)
    V, F = np.asarray(sphere.vertices), np.asarray(sphere.faces)
    p = V[0]
    great = np.arccos(np.clip(V @ p, -1.0, 1.0))
    e1 = np.cross(p, [0.3, 0.5, 0.8])
    e1 /= np.linalg.norm(e1)
    longitude = np.arctan2(V @ np.cross(p, e1), V @ e1)
    away, near = great > 0, (great > 0) & (great < np.pi / 2)
    out = {}
    domain = hc.TriangleMesh(V, F)
    maps = {label: hc.VectorHeatSolver(domain, accuracy=label).log_map(0) for label in ("smooth", "high")}
    peer = pp3d.MeshVectorHeatSolver(V, F)
    maps["potpourri3d"] = peer.compute_log_map(0)
    # Parallel transport of e1 from vertex 0 along the great circles, against the exact one.
    solver = hc.VectorHeatSolver(domain)
    start_e1 = solver.tangent_basis().e1[0]
    transported = {"smooth": solver.transport(0, start_e1)}
    transported["high"] = transported["smooth"]  # transport does not use the distance
    bx, by, _ = peer.get_tangent_frames()
    X2 = peer.transport_tangent_vector(0, [1.0, 0.0])
    transported["potpourri3d"] = X2[:, :1] * bx + X2[:, 1:] * by
    U = V / np.linalg.norm(V, axis=1)[:, None]
    for label, L in maps.items():
        r, a = np.linalg.norm(L, axis=1), np.arctan2(L[:, 1], L[:, 0])
        e = transported[label][0] / np.linalg.norm(transported[label][0])
        exact = exact_sphere_transport(p, e, U)
        X = transported[label]
        turn = np.arctan2(np.einsum("ij,ij->i", np.cross(exact, X), U), np.einsum("ij,ij->i", exact, X))
        far = away & (great < 0.9 * np.pi)
        out[label] = (
            mean_relative_error(r, great),
            float(np.mean(np.abs(r - great)[far] / great[far])),
            angle_error(a[away], longitude[away], near[away]),
            float(np.mean(np.abs(turn[far]))),
        )
    return out


def exact_sphere_transport(p, e, U):
    """``e`` (tangent at ``p``) carried along the great circles from ``p`` to the unit vectors ``U``."""
    cos = np.clip(U @ p, -1.0, 1.0)
    sin = np.sqrt(1.0 - cos**2)
    u = U - cos[:, None] * p  # the initial direction of each great circle, times sin
    u = np.divide(u, sin[:, None], out=np.zeros_like(u), where=sin[:, None] > 1e-12)
    along = u @ e
    ahead = -sin[:, None] * p + cos[:, None] * u  # the great circle's direction at U
    return e - along[:, None] * u + along[:, None] * ahead


def grid_figures(n=60):
    """Log map against the planar offset (best rotation) on a flat n x n Delaunay grid, source in the middle."""
    import potpourri3d as pp3d

    x, y = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n))
    P = np.c_[x.ravel(), y.ravel()]
    F = Delaunay(P).simplices
    V = np.c_[P, np.zeros(len(P))]
    s = (n // 2) * n + n // 2
    offset = P - P[s]
    domain = hc.TriangleMesh(V, F)
    out = {label: best_rotation_error(hc.VectorHeatSolver(domain, accuracy=label).log_map(s), offset)
           for label in ("smooth", "high")}
    out["potpourri3d"] = best_rotation_error(pp3d.MeshVectorHeatSolver(V, F).compute_log_map(s), offset)
    return out


def cylinder(n_around=96, n_up=60, radius=1.0, height=4.0):
    """A polygonal cylinder (open), its vertices' unrolled coordinates (arc along the polygon, height)."""
    k = np.arange(n_around)
    theta = 2 * np.pi * k / n_around
    z = np.linspace(0.0, height, n_up)
    V = np.array([[radius * np.cos(t), radius * np.sin(t), h] for h in z for t in theta])
    side = 2 * radius * np.sin(np.pi / n_around)
    unrolled = np.array([[side * kk, h] for h in z for kk in k])
    F = []
    for j in range(n_up - 1):
        for i in range(n_around):
            a, b = j * n_around + i, j * n_around + (i + 1) % n_around
            F += [[a, b, b + n_around], [a, b + n_around, a + n_around]]
    return V, np.array(F), unrolled, side * n_around


def cylinder_figures():
    """Log map against the unrolled plane, for vertices less than a third of the way around."""
    V, F, U, perimeter = cylinder()
    s = 30 * 96  # halfway up, at angle 0
    offset = U - U[s]
    offset[:, 0] = (offset[:, 0] + perimeter / 2) % perimeter - perimeter / 2
    near = np.abs(offset[:, 0]) < perimeter / 3
    domain = hc.TriangleMesh(V, F)
    out = {}
    for label in ("smooth", "high"):
        L = hc.VectorHeatSolver(domain, accuracy=label).log_map(s, reference=[0.0, 0.0, 1.0])
        X = offset[:, [1, 0]] * [1.0, -1.0]  # +x along the axis; +y = normal x axis at angle 0 (the -tangent)
        out[label] = float(np.mean(np.linalg.norm(L - X, axis=1)[near & (np.linalg.norm(X, axis=1) > 0)]
                                   / np.linalg.norm(X, axis=1)[near & (np.linalg.norm(X, axis=1) > 0)]))
    return out


def holonomy_figures(colatitudes=(0.3, 0.7, 1.1, 1.5)):
    """Discrete holonomy of latitude loops on a UV sphere against 2π(1 - cos θ), and the transport error."""
    import trimesh

    from heatcore.domains.intrinsic import IntrinsicTriangulation
    from heatcore.vector_heat.frames import vertex_frames

    sphere = trimesh.creation.uv_sphere(count=[128, 256])
    V, F = compact(np.asarray(sphere.vertices), np.asarray(sphere.faces))
    tri = IntrinsicTriangulation.from_mesh(V, F)
    frames = vertex_frames(tri, len(V))
    h = np.arange(3 * len(F))
    tails, heads = F[:, [1, 2, 0]].ravel(), F[:, [2, 0, 1]].ravel()
    rotation = dict(zip(zip(tails.tolist(), heads.tolist()), frames.transport(h).tolist()))
    colat = np.arccos(np.clip(V[:, 2] / np.linalg.norm(V, axis=1), -1, 1))
    out = []
    for target in colatitudes:
        ring = np.flatnonzero(np.abs(colat - colat[np.argmin(np.abs(colat - target))]) < 1e-9)
        ring = ring[np.argsort(np.arctan2(V[ring, 1], V[ring, 0]))]
        total = sum(rotation[(int(a), int(b))] for a, b in zip(ring, np.roll(ring, -1)))
        theta = colat[ring[0]]
        exact = 2 * np.pi * (1 - np.cos(theta))
        out.append((theta, exact, total % (2 * np.pi)))
    return out


def factorization_rows():
    """Seconds to factor the vector heat matrix of two meshes with each backend."""
    import trimesh

    from heatcore.linalg import available_backends
    from heatcore.linalg.hermitian import factor_hermitian
    from heatcore.vector_heat.connection import connection_laplacian
    from heatcore.vector_heat.frames import vertex_frames

    cases = {"spot refined once": hc.io.load_demo_mesh()}
    sphere = trimesh.creation.icosphere(5)
    cases["icosphere refined once"] = (np.asarray(sphere.vertices), np.asarray(sphere.faces))
    rows = []
    for name, (V, F) in cases.items():
        mesh = hc.TriangleMesh(V, F)
        ops = mesh.operators
        h = np.broadcast_to(ops.mean_edge_length, (ops.n_vertices,))
        L = connection_laplacian(mesh.intrinsic, vertex_frames(mesh.intrinsic, ops.n_vertices))
        A = (sp.diags(ops.mass.astype(complex)) + sp.diags(h * h) @ L).tocsr()
        row = {"matrix": name, "n": ops.n_vertices}
        for backend in ("qdldl", "cholmod", "supernodal"):
            if backend in available_backends():
                start = time.perf_counter()
                factor_hermitian(A, backend)
                row[backend] = time.perf_counter() - start
        rows.append(row)
    return rows


def report(rows, ico, grid, cyl, holonomy, factors, angles):
    lines = ["### Shared meshes: |log map| against exact geodesics (gdist)", "",
             "| mesh | vertices | heatcore smooth | heatcore high (default) | potpourri3d 1.4 | heatcore build (s) | "
             "log map smooth / high (s) | potpourri3d build + log map (s) |", "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['mesh']} | {r['n']:,} | {100 * r['smooth']:.2f}% | {100 * r['high']:.2f}% | "
                     f"{100 * r['pp']:.2f}% | {r['build']:.2f} | {r['smooth s']:.3f} / {r['high s']:.3f} | "
                     f"{r['pp s']:.2f} |")
    lines += ["", "### Analytic surfaces", "",
              "| case | heatcore smooth | heatcore high (default) | potpourri3d 1.4 |", "|---|---|---|---|"]
    lines.append("| icosphere 10,242: |log map| vs great circle, every vertex | "
                 + " | ".join(f"{100 * ico[k][0]:.3f}%" for k in ("smooth", "high", "potpourri3d")) + " |")
    lines.append("| icosphere: the same, vertices closer than 0.9π | "
                 + " | ".join(f"{100 * ico[k][1]:.3f}%" for k in ("smooth", "high", "potpourri3d")) + " |")
    lines.append("| icosphere: angle vs longitude (rad, best rotation) | "
                 + " | ".join(f"{ico[k][2]:.5f}" for k in ("smooth", "high", "potpourri3d")) + " |")
    lines.append("| icosphere: transport from vertex 0 vs exact (rad), vertices closer than 0.9π | "
                 + " | ".join(f"{ico[k][3]:.5f}" for k in ("smooth", "high", "potpourri3d")) + " |")
    lines.append("| flat 60 x 60 Delaunay grid: log map vs offset, best rotation, relative to \\|x\\| | "
                 + " | ".join(f"{100 * grid[k]:.4f}%" for k in ("smooth", "high", "potpourri3d")) + " |")
    lines.append(f"| cylinder (96 x 60): log map vs the unrolled plane, a third of the way around | "
                 f"{100 * cyl['smooth']:.3f}% | {100 * cyl['high']:.3f}% | |")
    lines += ["", "### Angles against exact geodesics (median, rad; paths of MMP's length only)", "",
              "| mesh | heatcore | potpourri3d 1.4 |", "|---|---|---|"]
    for name, e in angles:
        lines.append(f"| {name} | {e['heatcore']:.4f} | {e['potpourri3d']:.4f} |")
    lines += ["", "### Holonomy of latitude loops (UV sphere 128 x 256, the discrete connection)", "",
              "| colatitude | 2π(1 - cos θ) | measured | error |", "|---|---|---|---|"]
    for theta, exact, measured in holonomy:
        lines.append(f"| {theta:.3f} | {exact:.5f} | {measured:.5f} | {100 * abs(measured - exact) / exact:.3f}% |")
    lines += ["", "### Factoring the vector heat matrix (seconds)", "",
              "| matrix | vertices | qdldl (real form) | cholmod (real form) | supernodal (complex) |", "|---|---|---|---|---|"]
    for r in factors:
        lines.append(f"| {r['matrix']} | {r['n']:,} | " + " | ".join(
            f"{r[b]:.2f}" if b in r else "-" for b in ("qdldl", "cholmod", "supernodal")) + " |")
    return "\n".join(lines)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--meshes", type=Path, default=REPO.parent / "shared" / "meshes")
    parser.add_argument("--only", nargs="*", default=MESHES)
    parser.add_argument("--out", type=Path)
    parser.add_argument("--picture", type=Path)
    args = parser.parse_args()
    if args.picture:
        from bench_vector_heat_picture import checker_picture

        checker_picture(args.picture, args.meshes)
        return
    rows = mesh_rows(args.only, args.meshes)
    ico, grid, cyl = icosphere_figures(), grid_figures(), cylinder_figures()
    print("icosphere", ico, "grid", grid, "cylinder", cyl, flush=True)
    holonomy = holonomy_figures()
    print("holonomy", holonomy, flush=True)
    angles = path_angle_rows([m for m in ("spot", "fandisk", "cheburashka", "rocker-arm") if m in args.only], args.meshes)
    text = report(rows, ico, grid, cyl, holonomy, factorization_rows(), angles)
    print(text)
    if args.out:
        head = args.out.read_text().split("<!-- measured -->")[0]
        args.out.write_text(head + "<!-- measured -->\n\n" + text + "\n")


if __name__ == "__main__":
    main()
