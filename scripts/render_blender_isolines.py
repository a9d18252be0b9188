"""Render the add-on's isoline material headless: ogre, per-vertex stripes beside per-pixel isolines.

Imports the mesh, runs ``mesh.heat_geodesic_distance`` from the top of the
head, then again with ``isoline_material=True`` on a linked duplicate beside
it (the same mesh, moved, so measured anew in world space), and renders both with EEVEE (what
the viewport's Material Preview shows; software OpenGL through EGL works) or,
with ``--engine CYCLES``, Cycles on the CPU: on the left the vertex colors
with their isoline stripes (what exporters get), on the right the generated
material, isolines drawn per pixel from the distance attribute. The picture
in docs/blender.md.

The ogre (62,194 vertices) is ``data/ogre.obj`` of the public repository
alecjacobson/common-3d-test-models; pass its path with ``--mesh``.

Examples
--------
::

    python scripts/render_blender_isolines.py docs/images/blender_isolines_ogre.png --mesh ../shared/meshes/ogre.obj
"""

import argparse
import math
import time
from pathlib import Path

import bpy
import numpy as np
from blender_addon_loader import load_addon
from render_blender_example import color_material

REPO = Path(__file__).resolve().parents[1]


def import_mesh(path, name, offset):
    """Import an OBJ as object ``name`` moved by ``offset`` (world units), smooth shaded."""
    bpy.ops.wm.obj_import(filepath=str(path))
    obj = bpy.context.selected_objects[0]
    obj.name = obj.data.name = name
    obj.location = offset
    bpy.context.view_layer.objects.active = obj
    bpy.ops.object.shade_smooth()
    bpy.context.view_layer.update()
    return obj


def select(obj, vertex):
    flags = np.zeros(len(obj.data.vertices), dtype=bool)
    flags[vertex] = True
    obj.data.vertices.foreach_set("select", flags)


def world_box(objects):
    points = np.concatenate([np.array([o.matrix_world @ v.co for v in o.data.vertices]) for o in objects])
    return points.min(axis=0), points.max(axis=0)


def camera_and_light(objects):
    """Orthographic front camera (-Y looking +Y) framing ``objects``, a sun and a light grey world."""
    low, high = world_box(objects)
    center = 0.5 * (low + high)
    cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    cam.data.type = "ORTHO"
    scene = bpy.context.scene
    aspect = scene.render.resolution_x / scene.render.resolution_y
    cam.data.ortho_scale = 1.06 * max(high[0] - low[0], (high[2] - low[2]) * aspect)
    cam.location = (center[0], low[1] - 2.0 * (high[1] - low[1]), center[2])
    cam.rotation_euler = (math.pi / 2, 0.0, 0.0)
    cam.data.clip_end = 10.0 * float(np.linalg.norm(high - low))
    bpy.context.collection.objects.link(cam)
    scene.camera = cam
    sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
    sun.data.energy = 2.5
    sun.rotation_euler = (math.radians(60), math.radians(-20), math.radians(-25))
    bpy.context.collection.objects.link(sun)
    world = bpy.data.worlds.new("world")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.6, 0.6, 0.6, 1.0)
    scene.world = world


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("output", nargs="?", default=str(REPO / "docs" / "images" / "blender_isolines_ogre.png"))
    parser.add_argument("--mesh", default=str(REPO.parent / "shared" / "meshes" / "ogre.obj"))
    parser.add_argument("--isolines", type=int, default=16)
    parser.add_argument("--width", type=float, default=1.5, help="isoline width in pixels")
    parser.add_argument("--engine", default="BLENDER_EEVEE", choices=["CYCLES", "BLENDER_EEVEE"])
    parser.add_argument("--samples", type=int, default=16)
    parser.add_argument("--size", type=int, nargs=2, default=[920, 520])
    args = parser.parse_args(argv)

    start = time.perf_counter()
    addon = load_addon()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y = args.size
    left = import_mesh(args.mesh, "ogre", (0.0, 0.0, 0.0))
    low, high = world_box([left])
    right = left.copy()  # a linked duplicate: the same mesh
    right.name = "ogre isoline material"
    right.location.x += 1.05 * (high[0] - low[0])
    bpy.context.collection.objects.link(right)
    V = np.array([v.co for v in left.data.vertices])
    source = int(np.argmax(V[:, 1]))  # the top of the head (the OBJ is Y-up; the importer rotates the object)
    select(left, source)
    for obj, material in ((left, False), (right, True)):
        with bpy.context.temp_override(active_object=obj, object=obj, selected_objects=[obj]):
            bpy.ops.mesh.heat_geodesic_distance(isolines=args.isolines, colormap="viridis",
                                                isoline_material=material, isoline_width=args.width)
    left.data.materials.append(color_material("geodesic_distance_color"))  # the right one's modifier overrides it
    camera_and_light([left, right])

    scene.render.engine = args.engine
    scene.render.film_transparent = False
    scene.view_settings.view_transform = "Standard"  # show the colormap's colors as they are
    if args.engine == "CYCLES":
        scene.cycles.device = "CPU"
        scene.cycles.samples = args.samples
        scene.cycles.use_denoising = False
    else:
        scene.eevee.taa_render_samples = args.samples
    scene.render.image_settings.color_mode = "RGB"
    scene.render.image_settings.compression = 100
    scene.render.filepath = str(Path(args.output).resolve())
    bpy.ops.render.render(write_still=True)
    print(f"wrote {scene.render.filepath} in {time.perf_counter() - start:.1f} s "
          f"({len(V):,} vertices, source {source})")
    addon.unregister()


if __name__ == "__main__":
    main()
