"""Render the add-on's result headless: spot colored by geodesic distance, with isolines.

Imports spot (heatcore's demo mesh), runs ``mesh.heat_geodesic_distance``
from one vertex with its default options (the isoline material on: isolines
drawn per pixel from the distance attribute) and renders it headless through
``bpy`` with EEVEE (what Material Preview shows; it runs on software OpenGL
through EGL) or, with ``--engine CYCLES``, Cycles on the CPU: the first
picture of README.md and docs/blender.md. ``--style FLAT`` renders the
material's unlit style.

Examples
--------
::

    python scripts/render_blender_example.py docs/images/blender_render.png
"""

import argparse
import math
from pathlib import Path

import bpy
import numpy as np
from blender_addon_loader import load_addon

REPO = Path(__file__).resolve().parents[1]


def scene_with_spot(mesh_path, levels):
    """Import the mesh and apply ``levels`` of Catmull-Clark subdivision (a smooth silhouette; the material's
    isolines are sharp on spot's own 2,930 vertices, the vertex colors' stripes need two levels)."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.wm.obj_import(filepath=str(mesh_path))
    obj = bpy.context.selected_objects[0]
    bpy.context.view_layer.objects.active = obj
    if levels:
        mod = obj.modifiers.new("subdivision", "SUBSURF")
        mod.levels = levels
        bpy.ops.object.modifier_apply(modifier=mod.name)
    bpy.ops.object.shade_smooth()
    return obj


def color_material(name):
    """A material showing the color attribute ``name`` (for Cycles and EEVEE)."""
    mat = bpy.data.materials.new("geodesic")
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    bsdf = nodes["Principled BSDF"]
    attr = nodes.new("ShaderNodeAttribute")
    attr.attribute_name = name
    mat.node_tree.links.new(attr.outputs["Color"], bsdf.inputs["Base Color"])
    bsdf.inputs["Roughness"].default_value = 0.6
    return mat


def setup_camera_and_light(obj):
    V = np.array([v.co for v in obj.data.vertices])
    center = 0.5 * (V.min(axis=0) + V.max(axis=0))
    size = float(np.linalg.norm(V.max(axis=0) - V.min(axis=0)))
    cam_data = bpy.data.cameras.new("camera")
    cam = bpy.data.objects.new("camera", cam_data)
    bpy.context.collection.objects.link(cam)
    direction = np.array([1.1, 1.6, 0.6])  # chosen by eye: spot seen from the front left
    direction /= np.linalg.norm(direction)
    cam.location = center + 1.45 * size * direction
    look = center - np.array(cam.location)
    cam.rotation_euler = (
        math.atan2(math.hypot(look[0], look[1]), -look[2]),
        0.0,
        math.atan2(look[1], look[0]) - math.pi / 2,
    )
    bpy.context.scene.camera = cam
    sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
    sun.data.energy = 3.0
    sun.rotation_euler = (math.radians(40), math.radians(10), math.radians(30))
    bpy.context.collection.objects.link(sun)
    world = bpy.data.worlds.new("world")
    world.color = (0.85, 0.85, 0.85)  # Workbench background
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.85, 0.85, 0.85, 1.0)
    bpy.context.scene.world = world


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("output", nargs="?", default=str(REPO / "docs" / "images" / "blender_render.png"))
    parser.add_argument("--mesh", default=str(REPO / "heatcore" / "data" / "spot.obj"))
    parser.add_argument("--levels", type=int, default=1, help="subdivision levels before the run")
    parser.add_argument("--isolines", type=int, default=10, help="the operator's default: 10")
    parser.add_argument("--style", default="SHADED", choices=["SHADED", "FLAT"], help="the isoline material's style")
    parser.add_argument("--engine", default="BLENDER_EEVEE", choices=["CYCLES", "BLENDER_EEVEE"])
    parser.add_argument("--samples", type=int, default=16)
    parser.add_argument("--size", type=int, nargs=2, default=[960, 720])
    args = parser.parse_args(argv)

    addon = load_addon()
    obj = scene_with_spot(args.mesh, args.levels)
    V = np.array([v.co for v in obj.data.vertices])
    source = int(np.argmax(V[:, 1]))  # the top of a horn (the OBJ is Y-up; the importer rotates the object)
    select = np.zeros(len(V), dtype=bool)
    select[source] = True
    obj.data.vertices.foreach_set("select", select)
    bpy.ops.mesh.heat_geodesic_distance(isolines=args.isolines, colormap="viridis", isoline_style=args.style)
    setup_camera_and_light(obj)

    scene = bpy.context.scene
    scene.render.engine = args.engine
    scene.render.resolution_x, scene.render.resolution_y = args.size
    scene.render.film_transparent = False
    scene.view_settings.view_transform = "Standard"  # show the colormap's colors as they are
    if args.engine == "CYCLES":
        scene.cycles.device = "CPU"
        scene.cycles.samples = args.samples
        scene.cycles.use_denoising = True
    else:
        scene.eevee.taa_render_samples = args.samples
    scene.render.image_settings.color_mode = "RGB"
    scene.render.filepath = str(Path(args.output).resolve())
    bpy.ops.render.render(write_still=True)
    print(f"wrote {scene.render.filepath}")
    addon.unregister()


if __name__ == "__main__":
    main()
