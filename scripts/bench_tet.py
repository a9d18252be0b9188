"""Accuracy of heatcore on tetrahedral meshes against analytic distances, and a picture.

Cube and ball (jittered BCC points, Delaunay) with Euclidean distance, and an
L-shaped prism (jittered Kuhn grid) whose distance bends around the
re-entrant edge. Uses the mesh builders of ``tests/test_tet.py``. Prints a
markdown table, a second one of sources on the boundary (Robin heat against
the Neumann heat of before), and writes a slice picture of the L prism.

Usage::

    python scripts/bench_tet.py [--image docs/images/tet_l_prism.png]
"""

import argparse
import importlib.util
import time
from pathlib import Path

import numpy as np

import heatcore as hc
from heatcore.domains.tet import TetMesh

REPO = Path(__file__).resolve().parents[1]


def load_builders():
    spec = importlib.util.spec_from_file_location("test_tet", REPO / "tests" / "test_tet.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def row(name, n, V, T, source_name, exact_fn, source_point, pin_neighbors=True):
    tt = load_builders.cache
    src = tt.nearest_vertex(V, source_point)
    start = time.perf_counter()
    solver = hc.HeatSolver(TetMesh(V, T, pin_neighbors=pin_neighbors))
    setup = time.perf_counter() - start
    start = time.perf_counter()
    d = solver.distance([src])
    query = time.perf_counter() - start
    exact = exact_fn(V, V[src])
    err = tt.mean_relative_error(d, exact)
    mask = exact > 0
    signed = float(np.mean((d[mask] - exact[mask]) / exact[mask]))
    return (
        f"| {name} | {n} | {len(V)} | {len(T)} | {source_name} | {'yes' if pin_neighbors else 'no'} "
        f"| {100 * err:.2f}% | {100 * signed:+.2f}% | {setup:.2f} | {query:.3f} |"
    )


def boundary_vertex(mesh, V, point):
    """The boundary vertex nearest to ``point``."""
    used = np.flatnonzero(mesh.vertex_map >= 0)
    on = used[mesh.operators.boundary[mesh.vertex_map[used]]]
    return int(on[np.argmin(np.linalg.norm(V[on] - np.asarray(point, float), axis=1))])


def boundary_rows(name, n, V, T, exact_fn, sources):
    """Rows of the boundary-source table: the Robin heat against the Neumann heat of before.

    "Before" is the same mesh with no ``boundary_surface`` in its operators,
    which is what the solver did before heatcore.steps.boundary_source.
    """
    tt = load_builders.cache
    mesh = TetMesh(V, T)
    start = time.perf_counter()
    solver = hc.HeatSolver(mesh)
    setup = time.perf_counter() - start
    old_mesh = TetMesh(V, T)
    old_mesh.operators.boundary_surface = None
    old = hc.HeatSolver(old_mesh)
    for source_name, point in sources:
        src = boundary_vertex(mesh, V, point)
        exact = exact_fn(V, V[src])
        mask = exact > 0
        out = []
        for s in (solver, old):
            s.distance([src])  # warm
            start = time.perf_counter()
            d = s.distance([src])
            out.append((d, time.perf_counter() - start))
        (d, query), (d0, query0) = out
        signed = float(np.mean((d[mask] - exact[mask]) / exact[mask]))
        print(
            f"| {name} | {n} | {len(V)} | {source_name} | {100 * tt.mean_relative_error(d, exact):.2f}% "
            f"| {100 * signed:+.2f}% | {100 * tt.mean_relative_error(d0, exact):.2f}% "
            f"| {solver.heat_flow.boundary_source.iterations} | {setup:.2f} | {query:.3f} | {query0:.3f} |",
            flush=True,
        )


def euclid(V, s):
    return np.linalg.norm(V - s, axis=1)


def picture(path, tt):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.tri import Triangulation

    V, T = tt.l_prism_mesh(12)
    src = tt.nearest_vertex(V, (1.75, 0.5, 0.5))
    mesh = TetMesh(V, T)
    d = hc.HeatSolver(mesh).distance([src])
    exact, _ = tt.l_prism_distance(V, V[src])
    F = mesh.boundary_faces
    top = F[(V[F][:, :, 2] > V[:, 2].max() - 1e-9).all(axis=1)]  # the top cap, z = 1
    # a horizontal slab at mid height, half a grid spacing thick
    layer = np.abs(V[:, 2] - 0.5) < 0.5 / 12
    fig, axes = plt.subplots(1, 2, figsize=(11, 5), constrained_layout=True)
    for ax, title, values, faces in (
        (axes[0], "heat distance, top face z = 1", d, top),
        (axes[1], "|heat - exact| / exact, vertices with |z - 0.5| < h/2", None, None),
    ):
        if values is not None:
            tri = Triangulation(V[:, 0], V[:, 1], faces)
            art = ax.tripcolor(tri, values, shading="gouraud", cmap="viridis")
            ax.tricontour(tri, values, levels=14, colors="white", linewidths=0.6)
            fig.colorbar(art, ax=ax, shrink=0.8)
        else:
            P = V[layer]
            rel = np.abs(d[layer] - exact[layer]) / np.where(exact[layer] > 0, exact[layer], 1)
            art = ax.scatter(P[:, 0], P[:, 1], c=rel, s=14, cmap="magma", vmin=0, vmax=0.12)
            fig.colorbar(art, ax=ax, shrink=0.8)
        ax.plot(*V[src, :2], "r*", markersize=14)
        ax.plot([1, 2, 2, 0, 0, 1, 1], [1, 1, 0, 0, 2, 2, 1], "k-", lw=1)
        ax.set_aspect("equal")
        ax.set_title(title)
    fig.suptitle("Distance inside an L-shaped prism from the red vertex: it bends around the edge x = y = 1")
    fig.savefig(path, dpi=110)
    print(f"wrote {path}")


def interior_table(tt, lprism):
    """The main table: each domain and source, with and without neighbour pins."""
    print("| domain | n | vertices | tets | source | neighbour pins | mean rel. error | signed | setup s | query s |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for n in (9, 13, 17):
        V, T = tt.cube_mesh(n)
        for source_name, point in (("interior (0.3,0.4,0.2)", (0.3, 0.4, 0.2)), ("centre", (0.5,) * 3),
                                   ("corner", (0, 0, 0)), ("face centre", (0.5, 0.5, 0))):
            for pin in (True, False):
                print(row("cube", n, V, T, source_name, euclid, point, pin), flush=True)
    for n in (9, 13, 17):
        V, T = tt.ball_mesh(n)
        for source_name, point in (("interior (0.3,0.2,0.1)", (0.3, 0.2, 0.1)), ("centre", (0, 0, 0)),
                                   ("pole (boundary)", (0, 0, 1))):
            for pin in (True, False):
                print(row("ball", n, V, T, source_name, euclid, point, pin), flush=True)
    for n in (6, 8, 10, 12):
        V, T = tt.l_prism_mesh(n)
        for pin in (True, False):
            print(row("L prism", n, V, T, "(1.75, 0.5, 0.5)", lprism, (1.75, 0.5, 0.5), pin), flush=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--image", default=str(REPO / "docs" / "images" / "tet_l_prism.png"))
    parser.add_argument("--no-image", action="store_true")
    parser.add_argument("--image-only", action="store_true")
    parser.add_argument("--boundary-only", action="store_true", help="only the table of sources on the boundary")
    args = parser.parse_args()
    tt = load_builders.cache = load_builders()
    if args.image_only:
        return picture(args.image, tt)

    def lprism(V, s):
        return tt.l_prism_distance(V, s)[0]

    if not args.boundary_only:
        interior_table(tt, lprism)
    print()
    print("| domain | n | vertices | source on the boundary | mean rel. error | signed | before (Neumann heat) "
          "| CG iterations | setup s | query s | query s before |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for n in (9, 13, 17, 24):
        V, T = tt.cube_mesh(n)
        boundary_rows("cube", n, V, T, euclid, (("face centre", (0.5, 0.5, 0)), ("face (0.3, 0.6, 0)", (0.3, 0.6, 0)),
                                                 ("edge", (0.5, 0, 0)), ("corner", (0, 0, 0))))
    for n in (9, 13, 17):
        V, T = tt.ball_mesh(n)
        boundary_rows("ball", n, V, T, euclid, (("pole", (0, 0, 1)),))
    for n in (8, 12):
        V, T = tt.l_prism_mesh(n)
        boundary_rows("L prism", n, V, T, lprism, (("end wall (2, 0.5, 0.5)", (2, 0.5, 0.5)),
                                                    ("floor (1.75, 0.5, 0)", (1.75, 0.5, 0)),
                                                    ("side wall (1.5, 0, 0.5)", (1.5, 0, 0.5))))
    if not args.no_image:
        picture(args.image, tt)


load_builders.cache = None

if __name__ == "__main__":
    main()
