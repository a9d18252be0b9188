"""Time the geodesic probe's updates: a drag's new source point -> distance field -> what is drawn.

Runs :class:`GeodesicProbe` headless through ``bpy`` on tori of about 100k
and 1M vertices (a torus with Catmull-Clark levels applied; or OBJ files given
with ``--mesh``). After the solver is built, a drag is simulated: rays cast
straight down onto the torus along a line, a third of the mean edge length
apart (mouse moves of a few pixels), each hit moved to with ``probe.move_to``
(one update: the heat query for the surface point, then the overlay's data:
the field's colors and the source); then five jumps (a point far from the
last, whose face's corners were never pinned). Each update is split into its
parts, medians over the drag:

- ray: the ray cast and barycentric coordinates of the hit (``probe.ray_cast``);
- query: ``solver.distance(points=...)`` for the face point (a vertex source, the
  "core cached query", is timed beside it for comparison);
- overlay: the overlay's data (:meth:`OverlayData.of`: colors from the table,
  source points), what the probe draws while dragging;
- update: the whole ``move_to`` (query + overlay), while dragging and after a
  jump (the drag reuses the unit responses of corners pinned just before,
  ``heatcore.steps.column_cache``; a jump solves three more
  columns of the Poisson step);
- writes instead: what writing the outputs at each update would cost
  (``colorize`` + distance and color attributes, as the one-shot operator),
  the alternative the probe does not take while dragging;
- release: the overlay redone when the button is up, with the isoline curves
  of ``heatcore.isolines`` (left out while dragging);
- check: the full check of the object made at every press (re-reading the
  geometry), and the start of a probe with the solver cached.

The GPU side (uploading the overlay's batches, Blender redrawing) cannot run
in a headless ``bpy`` and is not timed. Prints one line per mesh and the
Markdown table of docs/blender-benchmarks.md.

Examples
--------
::

    python scripts/bench_blender_probe.py                  # 102,400 and 1,048,576 vertices
    python scripts/bench_blender_probe.py --sizes 100k     # only the first
    python scripts/bench_blender_probe.py --mesh ../shared/meshes/nefertiti.obj
"""

import argparse
import os
import statistics
import time
import warnings

import bpy
import numpy as np
from blender_addon_loader import load_addon

#: Tori: label -> (major segments, minor segments, Catmull-Clark levels).
SIZES = {"100k": (160, 160, 1), "1M": (256, 256, 2)}


def torus(major, minor, levels):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.mesh.primitive_torus_add(major_segments=major, minor_segments=minor)
    obj = bpy.context.active_object
    if levels:
        mod = obj.modifiers.new("subdivision", "SUBSURF")
        mod.levels = levels
        bpy.ops.object.modifier_apply(modifier=mod.name)
    return obj


def from_file(path):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.wm.obj_import(filepath=str(path))
    obj = bpy.context.selected_objects[0]
    bpy.context.view_layer.objects.active = obj
    return obj


def timed(call, *args):
    start = time.perf_counter()
    value = call(*args)
    return time.perf_counter() - start, value


def bench(addon, obj, label, steps):
    probe_mod, adapters, outputs = addon.probe, addon.adapters, addon.outputs
    n = len(obj.data.vertices)
    build, probe = timed(lambda: probe_mod.GeodesicProbe(obj, isolines=10))
    V, F = probe.surface.positions, probe.triangles
    edge = float(np.linalg.norm(V[F[:, 0]] - V[F[:, 1]], axis=1).mean())
    center, radius = V.mean(axis=0), np.linalg.norm(V[:, :2] - V[:, :2].mean(axis=0), axis=1).max()
    top = V[:, 2].max() + 1.0
    rows = {k: [] for k in ("ray", "query", "overlay", "update", "jump", "vertex query", "writes instead")}
    errors = []  # the coarse preview's mean error, of the largest distance
    start_x = center[0] + 0.8 * radius
    probe.dragging = True  # as the tool sets it between press and release: no isoline curves
    for i in range(steps):  # a drag: a third of an edge per mouse move, straight-down rays
        x = start_x + i * edge / 3
        t_ray, hit = timed(probe.ray_cast, (x, center[1] + 0.01, top), (0.0, 0.0, -1.0))
        probe.move_to(hit.face, hit.barycentric)
        t_overlay, _ = timed(probe.overlay_data)
        if i:  # the first move of the drag is a jump
            rows["ray"].append(t_ray)
            rows["query"].append(probe.timings["query"])
            rows["overlay"].append(t_overlay)
            rows["update"].append(probe.timings["update"])
        rows["vertex query"].append(timed(probe.run.solver.distance, [int(F[hit.face, 0])])[0])
        d = probe.distance
        start = time.perf_counter()
        adapters.write_float_attribute(obj.data, "bench_distance", d)
        adapters.write_color_attribute(obj.data, "bench_colors", outputs.colormaps.colorize(d, isolines=10))
        obj.data.update()
        rows["writes instead"].append(time.perf_counter() - start)
    for i in range(5):  # jumps: clicks far apart, no corner pinned before
        hit = probe.ray_cast((center[0] - radius * (0.8 + 0.03 * i), center[1] + 0.1 * i, top), (0.0, 0.0, -1.0))
        probe.move_to(hit.face, hit.barycentric)
        rows["jump"].append(probe.timings["update"])
    if probe._previews():  # a large mesh: the drag again, as the tool makes it (the coarse preview)
        rows["preview build"] = [timed(addon.probe.heatcore.CoarsePreview, probe.run.solver.domain)[0]]
        rows["preview update"], rows["settle"] = [], []
        for i in range(steps):
            hit = probe.ray_cast((start_x + i * edge / 3, center[1] + 0.01, top), (0.0, 0.0, -1.0))
            probe.move_to(hit.face, hit.barycentric, preview=True)
            rows["preview update"].append(probe.timings["update"] + timed(probe.overlay_data)[0])
            coarse = probe.distance.copy()
            rows["settle"].append(timed(probe.settle)[0])
            errors.append(float(np.abs(coarse - probe.distance).mean() / probe.distance.max()))
    rows["release"] = [timed(probe.end_drag)[0]]  # the button up: the overlay with heatcore's isoline curves
    t_check, _ = timed(probe.check)
    probe.cancel()
    t_start, again = timed(lambda: probe_mod.GeodesicProbe(obj, isolines=10))
    again.cancel()
    med = {k: statistics.median(v) for k, v in rows.items()}
    print(f"{label}: {n:,} vertices, first start {build:.1f} s (solver and ray tree), cached start {t_start:.2f} s, "
          f"check {t_check * 1e3:.0f} ms, " + ", ".join(f"{k} {v * 1e3:.1f} ms" for k, v in med.items()), flush=True)
    if errors:
        print(f"  coarse preview: mean error {100 * statistics.median(errors):.2f}% of the largest distance")
    return {"label": label, "n": n, "build": build, "start": t_start, "check": t_check, **med,
            "preview error": statistics.median(errors) if errors else None}


def table(results):
    head = ("| mesh | vertices | update while dragging (query + overlay) | query (face point) | overlay data | "
            "ray cast | update after a jump | vertex query | writes instead (per update) | release (isoline curves) "
            "| check (each press) | start, solver cached | first start (build) |")
    lines = [head, "|" + "---|" * (head.count("|") - 1)]
    extra = ["", ("Drags on large meshes (`PREVIEW_FROM` solver vertices) show the coarse preview "
                  "(`heatcore.CoarsePreview`) until the mouse rests:"), "",
             ("| mesh | preview update (query + overlay) | settle (the solver's field) | preview error (mean, of the "
              "largest distance) | preview build |"), "|---|---|---|---|---|"]
    for r in results:
        ms = lambda k: f"{r[k] * 1e3:.0f} ms" if r[k] >= 0.01 else f"{r[k] * 1e3:.1f} ms"  # noqa: E731
        if "preview update" in r:
            extra.append(f"| {r['label']} | **{ms('preview update')}** | {ms('settle')} | "
                         f"{100 * r['preview error']:.2f}% | {r['preview build']:.1f} s |")
        lines.append(f"| {r['label']} | {r['n']:,} | **{ms('update')}** | {ms('query')} | {ms('overlay')} | "
                     f"{ms('ray')} | {ms('jump')} | {ms('vertex query')} | {ms('writes instead')} | {ms('release')} | "
                     f"{ms('check')} | "
                     f"{r['start']:.2f} s | {r['build']:.1f} s |")
    return "\n".join(lines + (extra if len(extra) > 5 else []))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", nargs="*", default=list(SIZES), choices=list(SIZES))
    parser.add_argument("--mesh", action="append", default=[], help="an OBJ file (repeatable)")
    parser.add_argument("--steps", type=int, default=30, help="mouse moves in the simulated drag")
    args = parser.parse_args()
    warnings.simplefilter("ignore")
    addon = load_addon()
    results = []
    for path in args.mesh:
        results.append(bench(addon, from_file(path), os.path.basename(path), args.steps))
    for size in [] if args.mesh else args.sizes:
        major, minor, levels = SIZES[size]
        label = f"torus {major} x {minor}, {levels} subdivision level{'s' * (levels > 1)}"
        results.append(bench(addon, torus(major, minor, levels), label, args.steps))
        addon.SOLVERS.clear()
    print(f"\nload average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores\n")
    print(table(results))
    addon.unregister()


if __name__ == "__main__":
    main()
