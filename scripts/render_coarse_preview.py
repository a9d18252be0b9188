"""Picture of docs/blender-benchmarks.md: the button's coarse preview beside the result it precedes.

Suzanne with four levels of Catmull-Clark subdivision applied in Blender (126,290 vertices, quads),
one source vertex on the head. Left: the coarse preview the button draws while the solver builds
(``heatcore.CoarsePreview.of_arrays`` of the polygons, clustered to a tenth of the vertices at most
10,000, as ``blender_addon/preview.py`` asks for); right: the distance written when the solver is
ready (``PolygonMesh``, the add-on's default). Each panel's title gives its time in this process and
the preview's mean and largest difference from the result, in percent of the largest distance.

Usage::

    python scripts/render_coarse_preview.py docs/images/coarse_preview.png

Needs bpy (the ``blender`` extra) and matplotlib.
"""

import argparse
import tempfile
import time
from pathlib import Path

import bpy
import matplotlib

matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import heatcore as hc  # noqa: E402
from heatcore.domains.polygon_triangulate import covering_triangles  # noqa: E402
from heatcore.viz.render import render_distance  # noqa: E402

#: The add-on's rule (``blender_addon/preview.py``): a tenth of the vertices, at most this many clusters.
CLUSTERS = 10_000


def suzanne(levels=4):
    """Vertices and polygons ``(offsets, indices)`` of Suzanne subdivided ``levels`` times in Blender."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.mesh.primitive_monkey_add()
    obj = bpy.context.active_object
    modifier = obj.modifiers.new("subdivision", "SUBSURF")
    modifier.levels = levels
    bpy.ops.object.modifier_apply(modifier=modifier.name)
    mesh = obj.data
    V = np.empty(3 * len(mesh.vertices))
    mesh.vertices.foreach_get("co", V)
    corners = np.empty(len(mesh.loops), dtype=np.int64)
    mesh.loops.foreach_get("vertex_index", corners)
    starts = np.empty(len(mesh.polygons), dtype=np.int64)
    mesh.polygons.foreach_get("loop_start", starts)
    return V.reshape(-1, 3), (np.r_[starts, len(corners)], corners)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("out", help="PNG to write")
    args = parser.parse_args(argv)
    V, polygons = suzanne()
    source = int(np.argmax(V[:, 2]))  # the top of the head
    start = time.perf_counter()
    preview = hc.CoarsePreview.of_arrays(V, polygons, vertices=min(CLUSTERS, len(V) // 10), only_parts_of=[source])
    coarse = preview.distance([source])
    preview_seconds = time.perf_counter() - start
    start = time.perf_counter()
    exact = hc.HeatSolver(hc.PolygonMesh(V, polygons, only_parts_of=[source])).distance([source])
    solver_seconds = time.perf_counter() - start
    seen = np.isfinite(exact)
    scale = exact[seen].max()
    mean, worst = (100 * f(np.abs(coarse[seen] - exact[seen])) / scale for f in (np.mean, np.max))
    F = covering_triangles(V, *polygons)
    panels = [
        (coarse, f"coarse preview: {preview.n_clusters:,} clusters, {preview_seconds:.2f} s\n"
                 f"off by {mean:.2f}% of the largest distance on average, {worst:.1f}% at most"),
        (exact, f"written result: PolygonMesh on {len(V):,} vertices, {solver_seconds:.2f} s"),
    ]
    fig, axes = plt.subplots(1, 2, figsize=(12, 6.2))
    with tempfile.TemporaryDirectory() as tmp:
        for ax, (distance, title) in zip(axes, panels):
            path = Path(tmp) / "panel.png"
            shown = np.where(seen, distance, np.inf)  # the other parts (eyes) stay gray, as in Blender
            render_distance(path, V, F, shown, sources=[source], isolines=12, up="z", elevation=10.0,
                            azimuth=-25.0, size=(6, 5.4), dpi=110)
            ax.imshow(mpimg.imread(path))
            ax.set_title(title, fontsize=10)
            ax.axis("off")
    fig.tight_layout(rect=(0, 0, 1, 0.97))
    fig.savefig(args.out, dpi=110)
    print(f"wrote {args.out}: preview {preview_seconds:.2f} s, solver {solver_seconds:.2f} s, "
          f"mean {mean:.2f}%, worst {worst:.1f}%")


if __name__ == "__main__":
    main()
