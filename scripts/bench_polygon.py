"""Accuracy of PolygonMesh (virtual refinement, Bunge et al. 2020) on polygon meshes.

Compares, per mesh and source vertex, the mean relative error of

* ``PolygonMesh`` with its defaults (heatcore's triangulation of every polygon, refined as
  ``TriangleMesh`` refines), and with ``virtual=True`` (virtual refinement: polygon-aware refinement
  of small meshes) and ``virtual=True, refine=0`` (the paper's operators on the polygons as given),
* ``TriangleMesh`` on the fan triangulation of the polygons, without refinement
  (``refine=0``: like with like) and with its default (``refine="auto"``),
* potpourri3d's ``PolygonMeshHeatSolver`` (in a child process: it crashes on
  some meshes),

against Euclidean distance (planar quad grids) or exact geodesics (gdist, on
the fan triangulation of the manifold part: Catmull-Clark cube, suzanne,
beast). Writes a markdown table and the pictures of docs/polygon.md.

Usage::

    python scripts/bench_polygon.py --out docs/polygon_table.md --images docs/images

Needs the ``test`` extra (gdist, potpourri3d) and the shared meshes.
"""

import argparse
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

from conftest import mean_relative_error
from test_polygon import (
    catmull_clark,
    cube,
    exact_in_subprocess,
    load_polygons,
    manifold_part,
    potpourri_distance,
    quad_grid,
)
from test_polygon_refine import cc_sphere, great_circle, hex_grid

import heatcore as hc
from heatcore.domains.polygon import PolygonMesh, fan_triangulate, polygon_arrays


def cases(tmp):
    """(name, V, polygons, sources, exact distances per source)."""
    for jitter in (0.0, 0.2):
        V, H = hex_grid(jitter=jitter)
        s = int(np.argmin(np.linalg.norm(V - V.mean(0), axis=1)))
        label = "hex grid 18x26" + (", jittered 0.2" if jitter else "")
        yield label, V, H, *exact_sources(V, H, [s], tmp)
    for n in (11, 31):
        for jitter in (0.0, 0.3):
            V, Q = quad_grid(n, jitter)
            sources = [(n // 2) * n + n // 2, 0, n + 2]
            label = f"quad grid {n}x{n}" + (", jittered 0.3" if jitter else "")
            yield label, V, Q, sources, [np.linalg.norm(V - V[s], axis=1) for s in sources]
    V, Q = cc_sphere(3)
    yield "Catmull-Clark sphere (3 levels)", V, Q, [0, 100, 300], [great_circle(V, s) for s in (0, 100, 300)]
    V, Q = catmull_clark(*cube(), levels=4)
    yield "Catmull-Clark cube (4 levels)", V, Q, *exact_sources(V, Q, [0, 700, 1200], tmp)
    m = load_polygons("suzanne")
    P = manifold_part(m.vertices, m.polygons)
    yield "suzanne, manifold part", m.vertices, P, *exact_sources(m.vertices, P, [100, 200, 300], tmp)
    m = load_polygons("beast")
    P = manifold_part(m.vertices, m.polygons)
    yield "beast, manifold part", m.vertices, P, *exact_sources(m.vertices, P, [0, 10000, 20000], tmp)


def exact_sources(V, P, sources, tmp):
    offsets, idx = polygon_arrays(P, len(V))
    F = fan_triangulate(offsets, idx)[0]
    return sources, [exact_in_subprocess(V, F, s, tmp) for s in sources]


def run(V, polygons, sources, exact, tmp):
    offsets, idx = polygon_arrays(polygons, len(V))
    F = fan_triangulate(offsets, idx)[0]
    solvers = {
        "PolygonMesh": lambda: PolygonMesh(V, polygons, split_crossing=True),
        "virtual=True": lambda: PolygonMesh(V, polygons, virtual=True, split_crossing=True),
        "virtual=True refine=0": lambda: PolygonMesh(V, polygons, refine=0, virtual=True, split_crossing=True),
        "TriangleMesh fan refine=0": lambda: hc.TriangleMesh(V, F, refine=0),
        "TriangleMesh fan default": lambda: hc.TriangleMesh(V, F),
    }
    out = {}
    for name, build in solvers.items():
        start = time.perf_counter()
        solver = hc.HeatSolver(build())
        errs = [mean_relative_error(solver.distance([s]), e) for s, e in zip(sources, exact)]
        out[name] = (float(np.mean(errs)), time.perf_counter() - start)
    errs, start = [], time.perf_counter()
    for s, e in zip(sources, exact):
        d = potpourri_distance(V, polygons, s, tmp)
        errs.append(None if d is None else mean_relative_error(d, e))
    out["potpourri3d"] = (None if None in errs else float(np.mean(errs)), time.perf_counter() - start)
    return out


def pictures(images):
    """docs/images/polygon_grid.png (isolines vs exact circles) and polygon_beast.png."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import PolyCollection

    from heatcore.viz.render import render_distance

    fig, axes = plt.subplots(1, 2, figsize=(11, 5.4))
    for ax, jitter in zip(axes, (0.0, 0.3)):
        V, Q = quad_grid(21, jitter, seed=3)
        s = 10 * 21 + 10
        d = hc.HeatSolver(PolygonMesh(V, Q)).distance([s])
        F = fan_triangulate(*polygon_arrays(Q, len(V)))[0]
        exact = np.linalg.norm(V - V[s], axis=1)
        levels = np.linspace(0.05, 0.65, 7)
        ax.add_collection(PolyCollection(V[Q][:, :, :2], facecolor="none", edgecolor="0.75", linewidth=0.5))
        ax.tricontourf(V[:, 0], V[:, 1], F, d, levels=30, cmap="viridis", alpha=0.55)
        ax.tricontour(V[:, 0], V[:, 1], F, d, levels=levels, colors="k", linewidths=1.2)
        ax.tricontour(V[:, 0], V[:, 1], F, exact, levels=levels, colors="r", linewidths=0.9, linestyles="--")
        ax.plot(*V[s, :2], "ro")
        err = mean_relative_error(d, exact)
        ax.set_title(f"{'jittered' if jitter else 'regular'} 21x21 quad grid: {100 * err:.1f}% mean error")
        ax.set_aspect("equal")
        ax.set_axis_off()
    fig.suptitle("PolygonMesh distance isolines (black) vs exact circles (red dashed)")
    fig.tight_layout()
    fig.savefig(images / "polygon_grid.png", dpi=110)
    plt.close(fig)

    m = load_polygons("beast")
    d = hc.HeatSolver(PolygonMesh(m.vertices, m.polygons, split_crossing=True)).distance([0])
    F = fan_triangulate(m.offsets, m.indices)[0]
    render_distance(
        images / "polygon_beast.png",
        m.vertices,
        F,
        d,
        sources=[0],
        isolines=20,
        azimuth=35,
        title="beast.obj (32,364 polygons, read whole): PolygonMesh distance",
        size=(7, 6),
        dpi=110,
    )


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, help="markdown table to write (default: print)")
    parser.add_argument("--images", type=Path, help="folder for the pictures (default: none)")
    args = parser.parse_args(argv)
    warnings.simplefilter("ignore", hc.HeatcoreWarning)
    tmp = Path(tempfile.mkdtemp())
    cols = ["PolygonMesh", "virtual=True", "virtual=True refine=0", "TriangleMesh fan refine=0",
            "TriangleMesh fan default", "potpourri3d"]
    lines = [
        "| mesh | vertices | polygons | sources | " + " | ".join(cols) + " | virtual=True / PolygonMesh |",
        "|---|---:|---:|---:|" + "---:|" * (len(cols) + 1),
    ]
    for name, V, P, sources, exact in cases(tmp):
        res = run(V, P, sources, exact, tmp)
        cells = [
            "crashed" if res[c][0] is None else f"{100 * res[c][0]:.2f}% ({res[c][1]:.2f} s)" for c in cols
        ]
        line = f"| {name} | {len(np.unique(np.concatenate([np.ravel(p) for p in P])))} | {len(P)} | {len(sources)} | "
        ratio = res["virtual=True"][0] / res["PolygonMesh"][0]
        lines.append(line + " | ".join(cells) + f" | {ratio:.2f} |")
        print(lines[-1], flush=True)
    table = "\n".join(lines) + "\n"
    if args.out:
        args.out.write_text(table)
    if args.images:
        args.images.mkdir(parents=True, exist_ok=True)
        pictures(args.images)


if __name__ == "__main__":
    main()
