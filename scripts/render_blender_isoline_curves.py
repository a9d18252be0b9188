"""Render the *Isoline Curves* of the geodesic distance from spot's nose in Blender: one curve object, a spline per isoline.

One picture for docs/isolines.md and docs/paths.md, a headless Workbench render
through ``bpy``: the shared spot mesh, the distance from the tip of its nose
(vertex 1453, the demo's source; ``compute_geodesic_distance``), and
``isoline_curves`` (12 isolines, the curves of ``heatcore.isolines`` on the
displayed shape) drawn with a bevel so that they show, on spot coloured by the
distance (its colors without stripes). Two copies: a three-quarter front view and the back. The camera and
the light are those of ``render_blender_decal.py``.

Examples
--------
::

    python scripts/render_blender_isoline_curves.py            # docs/images/blender_isoline_curves_spot.png
"""

import math

import bpy
from render_blender_decal import parse_arguments, render_scene

SOURCE = 1453
#: Where the two copies stand along x, and their turn about z.
PLACES = ((-1.3, -math.pi / 4), (1.3, math.pi * 0.75))


def build(addon, mesh_path):
    bpy.ops.wm.obj_import(filepath=str(mesh_path))
    spot = bpy.context.selected_objects[0]
    bpy.ops.object.shade_smooth()
    dark = bpy.data.materials.new("isolines")
    dark.diffuse_color = (0.03, 0.03, 0.03, 1.0)
    copies = [spot, spot.copy()]
    copies[1].data = spot.data.copy()
    bpy.context.collection.objects.link(copies[1])
    for obj, (x, turn) in zip(copies, PLACES):
        obj.scale = (1.3, 1.3, 1.3)
        obj.rotation_euler = (math.pi / 2, 0.0, turn)
        obj.location = (x, 0.0, 0.0)
    bpy.context.view_layer.update()
    for obj in copies:  # each mesh's vertical middle at the scene's z = -0.1 (the camera's centre)
        z = [(obj.matrix_world @ v.co).z for v in obj.data.vertices]
        obj.location.z += -0.1 - (min(z) + max(z)) / 2
    bpy.context.view_layer.update()
    for obj in copies:
        result = addon.compute_geodesic_distance(obj, sources=[SOURCE], isolines=0)  # colors without stripes
        curve, n = addon.isoline_operator.isoline_curves(obj, "geodesic_distance", count=12)
        curve.data.bevel_depth, curve.data.bevel_resolution = 0.008, 2
        curve.data.materials.append(dark)
        print(f"{obj.name}: {n} isolines, max distance {result.max_distance:.3f}")


def main(argv=None):
    render_scene(build, *parse_arguments(__doc__, "blender_isoline_curves_spot.png", argv=argv),
                 direction=(0.0, -1.0, 0.3), size=(960, 480), color_type="VERTEX")


if __name__ == "__main__":
    main()
