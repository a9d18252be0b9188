"""Render *Straighten Edges* and a traced line on homer in Blender (docs/paths.md, docs/blender.md).

A headless Workbench render through ``bpy``: the shared homer mesh (scaled 7 times), with

- the jagged loop of edges around its arm where the plane x = 0.36 (in the file's coordinates) cuts
  the faces (dark), and ``straighten_edges`` of it: the closed geodesic around the arm (red);
- a traced line (blue): ``HeatSolver.trace`` from a vertex on the belly, up and to the side for 0.45
  (file units), written with the add-on's curve writer.

The camera and the light are those of ``render_blender_decal.py``.

Examples
--------
::

    python scripts/render_blender_straighten.py          # docs/images/blender_straighten_homer.png
"""

import math

import bpy
import numpy as np
from render_blender_decal import parse_arguments, render_scene
from render_blender_path import solid

import heatcore as hc

SCALE = 7.0
CUT_X = 0.36


def build(addon, mesh_path):
    bpy.ops.wm.obj_import(filepath=str(mesh_path))
    homer = bpy.context.selected_objects[0]
    bpy.ops.object.shade_smooth()
    homer.scale = (SCALE, SCALE, SCALE)
    homer.rotation_euler = (math.pi / 2, 0.0, 0.0)
    homer.data.materials.clear()
    homer.data.materials.append(solid("grey", (0.62, 0.62, 0.62)))
    bpy.context.view_layer.update()
    box = [homer.matrix_world @ v.co for v in list(homer.data.vertices)[::50]]
    homer.location -= sum(box, box[0] * 0) / len(box)
    homer.location.z -= 0.1
    bpy.context.view_layer.update()
    V = np.array([v.co[:] for v in homer.data.vertices])
    homer.data.calc_loop_triangles()
    F = np.array([t.vertices[:] for t in homer.data.loop_triangles])
    (loop,) = hc.region_boundary_curves(F, np.flatnonzero(V[F].mean(axis=1)[:, 0] < CUT_X), mesh_boundary=False)
    M = np.array(homer.matrix_world)
    world = V @ M[:3, :3].T + M[:3, 3]
    jagged = addon.curves.write_curves(homer, "Edges", [world[loop]], closed=[True])
    result = addon.straighten_edges(homer, edges=np.column_stack([loop[:-1], loop[1:]]))
    belly = int(np.argmin(np.linalg.norm(V - [0.5, 0.45, 0.62], axis=1)))
    traced = hc.HeatSolver(hc.TriangleMesh(V, F)).trace(belly, [0.3, 1.0, 0.0], 0.45)
    line = addon.curves.write_curves(homer, "Trace", [traced.points @ M[:3, :3].T + M[:3, 3]])
    for curve, rgb, depth in ((jagged, (0.1, 0.1, 0.1), 0.008), (result.curve, (0.85, 0.08, 0.08), 0.018),
                              (line, (0.1, 0.3, 0.9), 0.018)):
        curve.data.bevel_depth, curve.data.bevel_resolution = depth, 3
        curve.data.materials.append(solid(curve.name, rgb))
    print(f"loop of {len(loop) - 1} edges: {result.before[0]:.4f} -> {result.lengths[0]:.4f} (closed geodesic); "
          f"trace {traced.length:.4f} in file units, stopped: {traced.stopped}")


def main(argv=None):
    render_scene(build, *parse_arguments(__doc__, "blender_straighten_homer.png", "homer", argv),
                 direction=(0.0, -1.0, 0.12), size=(720, 720), color_type="MATERIAL")


if __name__ == "__main__":
    main()
