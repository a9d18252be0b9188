"""Render the *Geodesic Path* curve on homer in Blender: front and back, the path around the back of the neck.

One picture for docs/paths.md and docs/blender.md, a headless Workbench render
through ``bpy``. Two copies of the shared homer mesh (scaled 5 times), the right
one turned round; on each, ``geodesic_path`` from vertex 4785 to vertex 1983
(the pair where potpourri3d's edge flip goes round the front of the neck, 7.9%
longer: docs/paths.md) writes the curve object *"<name> Geodesic Path"*, drawn
here with a bevel so that it shows. The camera and the light are those of
``render_blender_decal.py``.

Examples
--------
::

    python scripts/render_blender_path.py                        # docs/images/blender_path.png
    python scripts/render_blender_path.py --meshes ../shared/meshes --out path.png
"""

import math

import bpy
from render_blender_decal import parse_arguments, render_scene

SOURCE, TARGET = 4785, 1983
SCALE = 5.0
#: Where the two copies stand along x, and their turn about z (the camera looks along +y at the front).
PLACES = ((-1.5, 0.0), (1.5, math.pi))


def solid(name, rgb):
    mat = bpy.data.materials.new(name)
    mat.diffuse_color = (*rgb, 1.0)
    return mat


def build(addon, mesh_path):
    bpy.ops.wm.obj_import(filepath=str(mesh_path))
    homer = bpy.context.selected_objects[0]
    bpy.ops.object.shade_smooth()
    grey, red = solid("grey", (0.62, 0.62, 0.62)), solid("path", (0.85, 0.08, 0.08))
    copies = [homer, homer.copy()]
    bpy.context.collection.objects.link(copies[1])
    for obj, (x, turn) in zip(copies, PLACES):
        obj.scale = (SCALE, SCALE, SCALE)
        obj.rotation_euler = (math.pi / 2, 0.0, turn)  # the importer's y-up turn, then about z
        obj.location = (x, 0.0, 0.0)
        obj.data.materials.clear()
        obj.data.materials.append(grey)
    bpy.context.view_layer.update()
    for obj, (x, _) in zip(copies, PLACES):  # each mesh's centre at (x, 0, -0.1)
        box = [obj.matrix_world @ v.co for v in list(obj.data.vertices)[::50]]
        obj.location.x += x - sum(p.x for p in box) / len(box)
        obj.location.y -= sum(p.y for p in box) / len(box)
        obj.location.z += -0.1 - (min(p.z for p in box) + max(p.z for p in box)) / 2
    bpy.context.view_layer.update()
    for obj in copies:
        result = addon.geodesic_path(obj, SOURCE, TARGET)
        curve = result.curve
        curve.data.bevel_depth, curve.data.bevel_resolution = 0.018, 3
        curve.data.materials.append(red)
        print(f"{obj.name}: {len(result.points)} points, length {result.length:.4f} ({result.seconds:.2f} s)")


def main(argv=None):
    render_scene(build, *parse_arguments(__doc__, "blender_path.png", "homer", argv), direction=(0.0, -1.0, 0.12),
                 size=(960, 720), color_type="MATERIAL")


if __name__ == "__main__":
    main()
