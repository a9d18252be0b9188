"""Render *Signed Distance from Edges* on spot (docs/signed.md): a mask from the border of a selection.

The faces of spot (Keenan Crane, public domain) within geodesic distance 0.35
of its nose are selected, as a user would select them, and
``signed_distance_from_edges`` measures the signed distance to their border:
positive (red) on the snout, negative (blue) elsewhere, each side scaled to
its own extreme, and a weight group *inside* (1 on the snout, a soft edge 0.1
wide) that drives a Displace modifier: the snout swells along the normals,
with the border at half strength. Headless Workbench render
through ``bpy``, attribute colors.

Examples
--------
::

    python scripts/render_blender_signed.py docs/images/blender_signed_spot.png
"""

import argparse
import math
from pathlib import Path

import bpy
import numpy as np
from blender_addon_loader import load_addon

import heatcore as hc

REPO = Path(__file__).resolve().parents[1]
NOSE = 1453


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("output", nargs="?", default=str(REPO / "docs" / "images" / "blender_signed_spot.png"))
    parser.add_argument("--size", type=int, nargs=2, default=[960, 640])
    args = parser.parse_args(argv)

    bpy.ops.wm.read_factory_settings(use_empty=True)
    addon = load_addon()
    V, F = hc.io.load_demo_mesh()
    mesh = bpy.data.meshes.new("spot")
    mesh.from_pydata(V.tolist(), [], F.tolist())
    obj = bpy.data.objects.new("spot", mesh)
    bpy.context.collection.objects.link(obj)
    bpy.context.view_layer.objects.active = obj
    obj.rotation_euler = (math.pi / 2, 0.0, math.pi)  # spot is y-up, facing -z: stand it up, facing the camera
    d = hc.geodesic_distance(V, F, [NOSE])
    snout = d[F].max(axis=1) < 0.35
    mesh.polygons.foreach_set("select", snout)
    result = addon.signed_distance_from_edges(obj, weight_group="inside", weight_band=0.1)
    displace = obj.modifiers.new("Displace", "DISPLACE")
    displace.vertex_group, displace.direction, displace.mid_level, displace.strength = "inside", "NORMAL", 0.0, 0.06
    for polygon in mesh.polygons:
        polygon.use_smooth = True

    cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    bpy.context.collection.objects.link(cam)
    cam.location = (1.5, -3.3, 1.1)
    look = -np.array(cam.location) + [0.0, 0.0, 0.2]
    cam.rotation_euler = (math.atan2(math.hypot(look[0], look[1]), -look[2]), 0.0,
                          math.atan2(look[1], look[0]) - math.pi / 2)
    scene = bpy.context.scene
    scene.camera = cam
    scene.render.engine = "BLENDER_WORKBENCH"
    scene.render.resolution_x, scene.render.resolution_y = args.size
    scene.view_settings.view_transform = "Standard"
    scene.display.shading.light = "STUDIO"
    scene.display.shading.color_type = "VERTEX"
    scene.render.filepath = str(Path(args.output).resolve())
    bpy.ops.render.render(write_still=True)
    print(f"wrote {scene.render.filepath}: {result.curves} curve, inside up to {result.max_distance:.3f}, "
          f"outside down to {result.min_distance:.3f}")
    addon.unregister()


if __name__ == "__main__":
    main()
