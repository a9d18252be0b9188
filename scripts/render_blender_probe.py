"""Render a drag of the geodesic probe as a short GIF for docs/blender.md (headless Workbench through ``bpy``).

spot (two levels of subdivision, 46,754 vertices) is probed with
:class:`GeodesicProbe`: the source is dragged along the cow's back, from the
neck to the tail, by straight-down rays through the probe's own ray casting
(``probe.ray_cast``, ``probe.move_to``, as the tool does for each mouse move).
Each frame shows what the probe draws at that moment: the overlay's colors
(``OverlayData.colors``: the field with 10 isoline stripes, the colors the
probe writes when applied), the source (a red dot at ``OverlayData.sources``)
and, in the caption, the update's time. A headless ``bpy`` cannot draw the
overlay itself (no GPU), so each frame's colors go to a copy of the mesh,
shown only in its frame, and the frames are rendered as one animation.

Examples
--------
::

    python scripts/render_blender_probe.py                     # docs/images/blender_probe_drag.gif
    python scripts/render_blender_probe.py --frames 8 --out /tmp/drag.gif
"""

import argparse
import math
import tempfile
from pathlib import Path

import bpy
import numpy as np
from blender_addon_loader import load_addon
from PIL import Image

REPO = Path(__file__).resolve().parents[1]
OUT = REPO / "docs" / "images" / "blender_probe_drag.gif"


def spot():
    bpy.ops.wm.obj_import(filepath=str(REPO / "heatcore" / "data" / "spot.obj"))
    obj = bpy.context.selected_objects[0]
    bpy.context.view_layer.objects.active = obj
    mod = obj.modifiers.new("subdivision", "SUBSURF")
    mod.levels = 2
    bpy.ops.object.modifier_apply(modifier=mod.name)
    bpy.ops.object.shade_smooth()
    obj.rotation_euler = (math.pi / 2, 0.0, math.pi / 2)  # upright (the OBJ is Y up), head towards -x
    bpy.context.view_layer.update()
    return obj


def show_only_in_frame(obj, frame):
    for f, hidden in ((frame - 1, True), (frame, False), (frame + 1, True)):
        obj.hide_render = hidden
        obj.keyframe_insert("hide_render", frame=f)


def frame_objects(obj, data, frame, caption, caption_at):
    """A copy of the mesh with the overlay's colors, a dot at the source and a caption, shown in ``frame`` only."""
    copy = bpy.data.objects.new(f"frame {frame}", obj.data.copy())
    copy.matrix_world = obj.matrix_world
    bpy.context.collection.objects.link(copy)
    colors = copy.data.color_attributes.new("probe", "FLOAT_COLOR", "POINT")
    colors.data.foreach_set("color", data.colors.ravel())
    copy.data.color_attributes.active_color = colors
    copy.data.color_attributes.render_color_index = copy.data.color_attributes.active_color_index
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.05, location=tuple(data.sources[0]))
    dot = bpy.context.active_object
    red = dot.data.color_attributes.new("dot", "FLOAT_COLOR", "POINT")
    red.data.foreach_set("color", np.tile([1.0, 0.0, 0.0, 1.0], len(dot.data.vertices)).astype(np.float32))
    dot.data.color_attributes.active_color = red
    text = bpy.data.curves.new(f"caption {frame}", "FONT")
    text.body, text.size, text.align_x = caption, 0.085, "CENTER"
    label = bpy.data.objects.new(text.name, text)
    label.location, label.rotation_euler = caption_at, (math.pi / 2, 0.0, 0.0)
    bpy.context.collection.objects.link(label)
    for item in (copy, dot, label):
        show_only_in_frame(item, frame)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--frames", type=int, default=14)
    parser.add_argument("--out", default=str(OUT))
    parser.add_argument("--size", type=int, nargs=2, default=(480, 300))
    args = parser.parse_args(argv)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    addon = load_addon()
    obj = spot()
    probe = addon.GeodesicProbe(obj, isolines=10)
    V = probe.surface.positions
    back = V[:, 2].max() + 1.0
    low, high = V.min(axis=0), V.max(axis=0)
    caption_at = (0.5 * (low[0] + high[0]), low[1], low[2] - 0.12)
    xs = np.linspace(V[:, 0].min() + 0.5, V[:, 0].max() - 0.15, args.frames)  # neck to tail, along the back
    for frame, x in enumerate(xs, start=1):
        hit = probe.ray_cast((x, 0.0, back), (0.0, 0.0, -1.0))
        probe.move_to(hit.face, hit.barycentric)
        data = probe.overlay_data()
        farthest = probe.distance[np.isfinite(probe.distance)].max()
        caption = f"drag: source at x = {x:+.2f}, farthest {farthest:.2f} ({1000 * probe.timings['update']:.0f} ms)"
        frame_objects(obj, data, frame, caption, caption_at)
    probe.cancel()
    obj.hide_render = True

    scene = bpy.context.scene
    cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    bpy.context.collection.objects.link(cam)
    center = 0.5 * (low + high) - [0.0, 0.0, 0.08]  # the caption below
    extent = float(np.linalg.norm(high - low))
    direction = np.array([0.0, -1.0, 0.3]) / np.linalg.norm([0.0, -1.0, 0.3])
    cam.location = center + 1.9 * extent * direction
    look = center - np.array(cam.location)
    cam.rotation_euler = (math.atan2(math.hypot(look[0], look[1]), -look[2]), 0.0,
                          math.atan2(look[1], look[0]) - math.pi / 2)
    scene.camera = cam
    scene.render.engine = "BLENDER_WORKBENCH"
    scene.render.resolution_x, scene.render.resolution_y = args.size
    scene.view_settings.view_transform = "Standard"
    scene.display.shading.light = "STUDIO"
    scene.display.shading.color_type = "VERTEX"
    scene.display.shading.background_type = "VIEWPORT"
    scene.frame_start, scene.frame_end = 1, args.frames
    with tempfile.TemporaryDirectory() as folder:
        scene.render.filepath = str(Path(folder) / "frame_")
        scene.render.image_settings.file_format = "PNG"
        bpy.ops.render.render(animation=True)
        frames = [Image.alpha_composite(Image.new("RGBA", args.size, "white"), Image.open(p).convert("RGBA"))
                  .convert("RGB") for p in sorted(Path(folder).glob("frame_*.png"))]
        palette = frames[len(frames) // 2].quantize(colors=255, method=Image.Quantize.MEDIANCUT)
        frames = [f.quantize(palette=palette, dither=Image.Dither.NONE) for f in frames]
        frames[0].save(args.out, save_all=True, append_images=frames[1:], duration=180, loop=0, optimize=True)
    print(f"wrote {args.out} ({Path(args.out).stat().st_size / 1024:.0f} KB, {len(frames)} frames)")
    addon.unregister()


if __name__ == "__main__":
    main()
