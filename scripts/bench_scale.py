"""Scale benchmark: heatcore and its peers side by side, up to a million vertices and beyond.

Every (solver, mesh) pair runs in a child process of its own, so that its peak memory is its own
and a peer that aborts cannot take the benchmark down. The meshes are midpoint subdivisions of
shared test meshes: subdivision keeps the surface and the original vertices, so exact geodesics
(MMP, gdist) on the coarse mesh are the truth at the original vertices of the fine mesh, which is
where the error is measured. ``sphere:K`` is a cube sphere with 6 K^2 + 2 vertices (K = 408: one
million), measured against great-circle distances at every vertex.

Reported per mesh and solver: precompute time (constructor), first query, cached query (median of
3), peak resident memory of the child, mean relative error at the original vertices (source:
vertex 0), and the count of reachable original vertices left at 0, inf or NaN. ``heatcore-oneoff``
times the whole ``hc.geodesic_distance(V, F, [v])`` call as its query (precompute 0, as MeshLab's
filters, which keep nothing across calls either).

Usage::

    python scripts/bench_scale.py --out docs/scale.md --plot docs/images/scale.png
    python scripts/bench_scale.py --meshes nefertiti:0,nefertiti:1 --solvers heatcore,potpourri3d-robust
    python scripts/bench_scale.py --meshes sphere:408,sphere:913 --solvers heatcore,heatcore-gpu  # 1M, 5M

Needs the ``bench`` extra (gdist, potpourri3d, libigl, pymeshlab) and matplotlib.
"""

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
DEFAULT_MESH_DIR = REPO.parent / "shared" / "meshes"
DEFAULT_MESHES = "nefertiti:0,nefertiti:1,cheburashka:3,nefertiti:2,sphere:408,cheburashka:4"
SOLVERS = [
    "heatcore",
    "heatcore-high",  # accuracy="high": its first query also builds the fast marching's corner table
    "heatcore-oneoff",  # hc.geodesic_distance(V, F, [v]): the whole call is the query (accuracy="auto")
    "potpourri3d-robust",
    "potpourri3d-plain",
    "libigl",
    "meshlab-heat",
    "meshlab-geodesic",
]
#: Also measurable, not run by default: "heatcore-gpu" (backend="gpu": cuDSS on an NVIDIA GPU, the gpu extra).
OPTIONAL_SOLVERS = ["heatcore-gpu"]
QUERY_SOURCES = (0, 1, 2, 3)  # first query from vertex 0, then three cached ones


def cube_sphere(cells):
    """Unit sphere: a cube with ``cells`` x ``cells`` squares per side (two triangles each), projected.

    ``6 cells^2 + 2`` vertices of valence 4 to 6 (no poles). Vertex 0 is moved off the cube's
    corners and edges, to the middle of a side.
    """
    t = np.linspace(-1.0, 1.0, cells + 1)
    a, b = (g.ravel() for g in np.meshgrid(t, t, indexing="ij"))
    one = np.ones_like(a)
    sides = [np.column_stack(c) for c in ([one, a, b], [-one, a, b], [a, one, b], [a, -one, b], [a, b, one], [a, b, -one])]
    i, j = np.meshgrid(np.arange(cells), np.arange(cells), indexing="ij")
    corner = (i * (cells + 1) + j).ravel()
    quad = np.column_stack([corner, corner + cells + 1, corner + cells + 2, corner + 1])
    F = np.vstack([np.vstack([quad[:, [0, 1, 2]], quad[:, [0, 2, 3]]]) + k * (cells + 1) ** 2 for k in range(6)])
    P = np.vstack(sides)
    # Merge the copies of the points shared by two or three sides.
    P, index = np.unique(np.round(P, 12), axis=0, return_inverse=True)
    F = index.ravel()[F]
    V = P / np.linalg.norm(P, axis=1, keepdims=True)
    # Orient every triangle outwards.
    normal = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    inward = np.einsum("ij,ij->i", normal, V[F].sum(axis=1)) < 0
    F[inward] = F[inward][:, ::-1]
    # Vertex 0: the centre of the +z side.
    centre = int(np.argmax(V[:, 2]))
    order = np.arange(len(V))
    order[[0, centre]] = order[[centre, 0]]
    rank = np.empty_like(order)
    rank[order] = np.arange(len(V))
    return V[order], rank[F]


def load(mesh_dir, name, levels):
    """(coarse V, F, fine V, F): a shared mesh midpoint-subdivided ``levels`` times, or
    ``sphere:K``, :func:`cube_sphere` with K cells per side (all vertices "original")."""
    if name == "sphere":
        V, F = cube_sphere(levels)
        return V, F, V, F
    import heatcore as hc
    from heatcore.domains.refine import midpoint_subdivide

    mesh = hc.io.read_mesh(Path(mesh_dir) / f"{name}.obj")
    sub = midpoint_subdivide(mesh.vertices, mesh.faces, levels)
    return mesh.vertices, mesh.faces, sub.vertices, sub.faces


def peak_rss_gb():
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmHWM:"):
            return int(line.split()[1]) / 1e6
    import resource

    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1e6


def run_solver(solver, V, F):
    """(precompute seconds, [query seconds], distance from vertex 0, {stage: seconds}) for one solver."""
    timings = {}
    if solver == "heatcore-oneoff":
        import heatcore as hc

        pre = 0.0  # nothing kept across calls: each query builds the mesh (and what its accuracy needs)
        query = lambda v: hc.geodesic_distance(V, F, [v])
    elif solver.startswith("heatcore"):
        import heatcore as hc

        start = time.perf_counter()
        mesh = hc.TriangleMesh(V, F)
        build = time.perf_counter() - start
        s = hc.HeatSolver(mesh, accuracy="high" if solver == "heatcore-high" else "smooth",
                          backend="gpu" if solver == "heatcore-gpu" else "auto")
        pre = time.perf_counter() - start
        timings.update({"mesh build": build, **s.timings})
        query = lambda v: s.distance([v])
    elif solver.startswith("potpourri3d"):
        import potpourri3d as pp3d

        start = time.perf_counter()
        s = pp3d.MeshHeatMethodDistanceSolver(V, F, t_coef=1.0, use_robust=solver.endswith("robust"))
        pre = time.perf_counter() - start
        query = lambda v: s.compute_distance(v)
    elif solver == "libigl":
        import igl

        start = time.perf_counter()
        data = igl.HeatGeodesicsData()
        igl.heat_geodesics_precompute(V, F.astype(np.int64), data)
        pre = time.perf_counter() - start
        query = lambda v: igl.heat_geodesics_solve(data, np.array([v], dtype=np.int64))
    elif solver.startswith("meshlab"):
        import pymeshlab

        ms = pymeshlab.MeshSet()
        ms.add_mesh(pymeshlab.Mesh(V, F.astype(np.int32)))
        pre = 0.0  # MeshLab's filters precompute nothing across calls
        diag = ms.current_mesh().bounding_box().diagonal()

        def query(v):
            ms.set_selection_none(allfaces=True, allverts=True)
            ms.compute_selection_by_condition_per_vertex(condselect=f"vi == {int(v)}")
            if solver == "meshlab-heat":
                ms.compute_scalar_by_heat_geodesic_distance_from_selection_per_vertex(m=1.0)
            else:
                ms.compute_scalar_by_geodesic_distance_from_selection_per_vertex(
                    maxdistance=pymeshlab.PureValue(1e6 * diag)
                )
            return ms.current_mesh().vertex_scalar_array().copy()

    else:
        raise ValueError(solver)
    times, first = [], None
    for v in QUERY_SOURCES:
        start = time.perf_counter()
        d = query(v)
        times.append(time.perf_counter() - start)
        if first is None:
            first = np.asarray(d, dtype=float)
    return pre, times, first, timings


def child(args):
    """Run one solver on one mesh; print a JSON line; save distances at the original vertices."""
    name, levels = args.child.split(":")
    V0, _, V, F = load(args.mesh_dir, name, int(levels))
    pre, times, d, timings = run_solver(args.solver, V, F)
    np.save(args.save, d[: len(V0)])
    print(json.dumps({"precompute": pre, "queries": times, "rss_gb": peak_rss_gb(), "n": len(V), "timings": timings}))


def exact_on_coarse(mesh_dir, spec, cache):
    """Exact distance from vertex 0 at the original vertices: MMP on the coarse mesh, or the
    great-circle distance on the sphere."""
    name, levels = spec.split(":")
    if name == "sphere":
        V = cube_sphere(int(levels))[0]
        return np.arccos(np.clip(V @ V[0], -1.0, 1.0))
    path = Path(cache) / f"{name}_exact0.npy"
    if path.exists():
        return np.load(path)
    import gdist

    import heatcore as hc

    mesh = hc.io.read_mesh(Path(mesh_dir) / f"{name}.obj")
    d = gdist.compute_gdist(mesh.vertices, mesh.faces.astype(np.int32), np.array([0], dtype=np.int32))
    np.save(path, d)
    return d


def measure(mesh_dir, spec, solver, workdir, timeout):
    save = Path(workdir) / f"{spec.replace(':', '_')}_{solver}.npy"
    cmd = [sys.executable, __file__, "--child", spec, "--solver", solver, "--save", str(save), "--mesh-dir", str(mesh_dir)]
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return {"status": f"timeout > {timeout} s"}
    if proc.returncode != 0:
        tail = (proc.stderr.strip().splitlines() or ["?"])[-1][:80]
        return {"status": f"failed (exit {proc.returncode}: {tail})"}
    result = json.loads(proc.stdout.strip().splitlines()[-1])
    result["distance"] = np.load(save)
    result["status"] = "ok"
    return result


def error_stats(d, exact):
    mask = np.isfinite(exact) & (exact > 0)
    bad = int(np.sum((d[mask] == 0) | ~np.isfinite(d[mask])))
    rel = np.abs(np.where(np.isfinite(d[mask]), d[mask], 0) - exact[mask]) / exact[mask]
    return float(rel.mean()), bad


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--mesh-dir", default=str(DEFAULT_MESH_DIR))
    parser.add_argument(
        "--meshes", default=DEFAULT_MESHES, help="name:levels,... (midpoint subdivision levels), or sphere:K (cube sphere)"
    )
    parser.add_argument("--solvers", default=",".join(SOLVERS), help=f"also: {', '.join(OPTIONAL_SOLVERS)}")
    parser.add_argument("--timeout", type=int, default=900, help="seconds per solver and mesh")
    parser.add_argument("--workdir", default="/tmp/heatcore-bench-scale")
    parser.add_argument("--out", default=None, help="markdown report")
    parser.add_argument("--plot", default=None, help="PNG: log-log time vs vertex count")
    parser.add_argument("--child", help=argparse.SUPPRESS)
    parser.add_argument("--solver", help=argparse.SUPPRESS)
    parser.add_argument("--save", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        return child(args)

    Path(args.workdir).mkdir(parents=True, exist_ok=True)
    rows = []
    for spec in args.meshes.split(","):
        exact = exact_on_coarse(args.mesh_dir, spec, args.workdir)
        for solver in args.solvers.split(","):
            r = measure(args.mesh_dir, spec, solver, args.workdir, args.timeout)
            row = {"mesh": spec, "solver": solver, **{k: v for k, v in r.items() if k != "distance"}}
            if r["status"] == "ok":
                row["error"], row["bad"] = error_stats(r["distance"], exact)
            rows.append(row)
            print(json.dumps(row), flush=True)
    if args.out:
        write_markdown(args.out, rows)
    if args.plot:
        plot(args.plot, rows)


def write_markdown(path, rows):
    lines = [
        "| mesh (subdivision levels) | vertices | solver | precompute | first query | cached query | peak RSS | error at original vertices | reachable left at 0/inf/NaN |",
        "|---|---:|---|---:|---:|---:|---:|---:|---:|",
    ]
    for r in rows:
        if r["status"] != "ok":
            lines.append(f"| {r['mesh']} | | {r['solver']} | {r['status']} | | | | | |")
            continue
        q = r["queries"]
        lines.append(
            f"| {r['mesh']} | {r['n']:,} | {r['solver']} | {r['precompute']:.2f} s | {q[0]:.3f} s | "
            f"{np.median(q[1:]):.3f} s | {r['rss_gb']:.2f} GB | {100 * r['error']:.2f}% | {r['bad']} |"
        )
    Path(path).write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


def plot(path, rows):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for solver in dict.fromkeys(r["solver"] for r in rows):
        ok = sorted((r for r in rows if r["solver"] == solver and r["status"] == "ok"), key=lambda r: r["n"])
        if not ok:
            continue
        n = [r["n"] for r in ok]
        axes[0].loglog(n, [r["precompute"] + r["queries"][0] for r in ok], "o-", label=solver)
        axes[1].loglog(n, [np.median(r["queries"][1:]) for r in ok], "o-", label=solver)
    axes[0].set_title("precompute + first query")
    axes[1].set_title("cached query")
    for ax in axes:
        ax.set_xlabel("vertices")
        ax.set_ylabel("seconds")
        ax.grid(True, which="both", alpha=0.3)
    axes[1].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


if __name__ == "__main__":
    main()
