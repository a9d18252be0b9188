"""Time the add-on's first click (solver built) against later clicks (solver cached).

Runs the real operator ``mesh.heat_geodesic_distance`` headless through
``bpy`` on a ~100k-vertex mesh: Suzanne with four levels of Catmull-Clark
subdivision applied (126,478 vertices, quads), or an OBJ file given with
``--mesh``. Prints one line per click and a Markdown table for
docs/blender.md.

Examples
--------
::

    python scripts/bench_blender_cache.py
    python scripts/bench_blender_cache.py --mesh ../shared/meshes/nefertiti.obj
"""

import argparse
import statistics
import time
from pathlib import Path

import bpy
import numpy as np
from blender_addon_loader import load_addon


def make_mesh(path=None, levels=4):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    if path:
        bpy.ops.wm.obj_import(filepath=str(path))
        obj = bpy.context.selected_objects[0]
        bpy.context.view_layer.objects.active = obj
        return obj
    bpy.ops.mesh.primitive_monkey_add()
    obj = bpy.context.active_object
    mod = obj.modifiers.new("subdivision", "SUBSURF")
    mod.levels = levels
    bpy.ops.object.modifier_apply(modifier=mod.name)
    return obj


def click(obj, vertex):
    select = np.zeros(len(obj.data.vertices), dtype=bool)
    select[vertex] = True
    obj.data.vertices.foreach_set("select", select)
    start = time.perf_counter()
    bpy.ops.mesh.heat_geodesic_distance(isolines=10)
    return time.perf_counter() - start


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--mesh", help="OBJ file (default: subdivided Suzanne)")
    parser.add_argument("--clicks", type=int, default=5, help="cached clicks to time")
    args = parser.parse_args(argv)

    addon = load_addon()
    obj = make_mesh(args.mesh)
    n = len(obj.data.vertices)
    rng = np.random.default_rng(0)
    addon.SOLVERS.clear()
    first = click(obj, 0)
    print(f"{obj.name}: {n:,} vertices, {len(obj.data.polygons):,} faces")
    print(f"first click (solver built): {first:.3f} s")
    later = []
    for k in range(args.clicks):
        later.append(click(obj, int(rng.integers(n))))
        print(f"click {k + 2} (cached solver, new source): {later[-1]:.3f} s")
    med = statistics.median(later)
    co = np.empty(3 * n)
    obj.data.vertices.foreach_get("co", co)
    co[2] += 1e-3  # move one vertex: the cache must rebuild
    obj.data.vertices.foreach_set("co", co)
    obj.data.update()
    edited = click(obj, 0)
    print(f"after a geometry edit (solver rebuilt): {edited:.3f} s")
    print(f"median cached click / first click = {med / first:.1%}")
    print()
    print("| mesh | vertices | first click | later clicks (median of %d) | ratio | after an edit |" % args.clicks)
    print("|---|---|---|---|---|---|")
    name = Path(args.mesh).stem if args.mesh else "Suzanne, subdivision level 4"
    print(f"| {name} | {n:,} | {first:.2f} s | {med:.3f} s | {med / first:.1%} | {edited:.2f} s |")
    addon.unregister()


if __name__ == "__main__":
    main()
