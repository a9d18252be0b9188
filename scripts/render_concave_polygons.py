"""Picture of docs/polygon.md: a dissolved grid (concave n-gons) measured as polygons and as triangles.

Blender's Dissolve Edges on a 24 x 24 grid (150 random interior edges, seed 0) leaves concave
n-gons with 180-degree corners. Three panels, each with its polygon (or triangle) edges, the
distance from the centre and its isolines, and the mean relative error against the exact
straight-line distance:

1. virtual refinement on every polygon, concave ones too (their fans fold): ``PolygonMesh`` until
   2026-11-28;
2. ``PolygonMesh(virtual=True)``: concave and straight-cornered polygons triangulated, the others
   spanned by virtual refinement (the default until 2026-11-29);
3. ``PolygonMesh`` now (its default): heatcore's triangulation of every polygon, the same field as
   ``TriangleMesh`` on that triangulation (the triangulated twin).

Usage::

    python scripts/render_concave_polygons.py docs/images/polygon_dissolved.png

Needs bpy (the ``blender`` extra) and matplotlib.
"""

import argparse
import sys
import warnings
from pathlib import Path

import bpy  # noqa: F401  (before pymeshlab and the tests' helpers)
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402

import heatcore as hc  # noqa: E402
import heatcore.domains.polygon as polygon_module  # noqa: E402
from heatcore.domains.polygon import polygon_arrays, triangulate_polygons  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from concave_meshes import dissolved_grid  # noqa: E402  (Blender's Dissolve Edges, as the tests build it)


def folded_polygon_mesh(V, P):
    """Virtual refinement on every polygon, as before the concave ones were triangulated."""
    kept = polygon_module.triangulate_where_needed
    polygon_module.triangulate_where_needed = lambda X, offsets, corners, origin, everywhere=False, planes=None: (
        offsets, corners, origin, 0)
    try:
        return hc.PolygonMesh(V, P, virtual=True)
    finally:
        polygon_module.triangulate_where_needed = kept


def error(d, exact):
    far = exact > 0
    return np.abs(d[far] - exact[far]) / exact[far]


def panel(ax, V, edges, T, d, exact, title):
    levels = np.linspace(0, np.nanmax(exact), 14)[1:-1]
    ax.tripcolor(V[:, 0], V[:, 1], T, d, shading="gouraud", cmap="magma", vmin=0, vmax=exact.max())
    ax.tricontour(V[:, 0], V[:, 1], T, d, levels=levels, colors="white", linewidths=0.9)
    ax.tricontour(V[:, 0], V[:, 1], T, exact, levels=levels, colors="cyan", linewidths=0.6, linestyles="dashed")
    ax.add_collection(LineCollection(V[edges][:, :, :2], colors="black", linewidths=0.45, alpha=0.8))
    e = error(d, exact)
    ax.set_title(f"{title}\nmean {100 * e.mean():.2f}%, max {100 * e.max():.1f}%", fontsize=10)
    ax.set_aspect("equal")
    ax.set_axis_off()


def sides(offsets, corners):
    nxt = np.arange(corners.size) + 1
    nxt[offsets[1:] - 1] = offsets[:-1]
    return np.stack([corners, corners[nxt]], axis=1)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out")
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    V, P = dissolved_grid()
    offsets, corners = polygon_arrays(P, len(V))
    T, _ = triangulate_polygons(V, offsets, corners)
    source = int(np.argmin(np.linalg.norm(V, axis=1)))
    exact = np.linalg.norm(V - V[source], axis=1)
    polygon_edges = sides(offsets, corners)
    triangle_edges = sides(np.arange(0, T.size + 1, 3), T.ravel())
    virtual = hc.PolygonMesh(V, P, virtual=True)
    fields = [
        (polygon_edges, hc.HeatSolver(folded_polygon_mesh(V, P)).distance([source]),
         "virtual refinement on every polygon\n(until 2026-11-28: fans fold on concave ones)"),
        (polygon_edges, hc.HeatSolver(virtual).distance([source]),
         (f"virtual=True (the default until 2026-11-29)\n({virtual.n_triangulated} concave or straight-cornered "
          "polygons triangulated)")),
        (triangle_edges, hc.HeatSolver(hc.PolygonMesh(V, P)).distance([source]),
         "PolygonMesh now: heatcore's triangulation\n(the same field as TriangleMesh on it)"),
    ]
    fig, axes = plt.subplots(1, 3, figsize=(13.5, 5.4))
    for ax, (edges, d, title) in zip(axes, fields):
        panel(ax, V, edges, T, d, exact, title)
    sizes = np.bincount(np.diff(offsets))
    counts = ", ".join(f"{c} {k}-gons" for k, c in enumerate(sizes) if c and k > 3)
    fig.suptitle(f"Dissolve Edges on a 24 x 24 grid ({counts}); distance from the centre, white: isolines, "
                 "dashed cyan: exact", fontsize=10)
    fig.tight_layout(rect=(0, 0, 1, 0.93))
    fig.savefig(args.out, dpi=110)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
