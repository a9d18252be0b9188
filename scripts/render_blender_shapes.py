"""Render what "the shape on screen" means: a scaled object and a shape-keyed one, each measured two ways.

Two pictures for docs/blender.md, headless EEVEE renders through ``bpy`` of
the add-on's isoline material (isolines drawn per pixel from the distance
attribute, as Material Preview shows them):

- ``ellipsoid``: an ico sphere (40,962 vertices) scaled (1, 1, 3), distance
  from the top pole with Space *Local* (left: the unit sphere's distance drawn
  on the ellipsoid, the add-on's old answer) and *World* (right: the default);
- ``shape_key``: spot (46,754 vertices) with a shape key that makes its legs
  twice as long, distance from the top of a horn with Shape *Mesh Data* (left) and
  *As Displayed* (right: the default), measured on its loop triangles.

Both halves of a picture share one color scale and isoline spacing (scene
units: the material of each is shown with the larger maximum), so colors and
lines show where the two answers differ.

Examples
--------
::

    python scripts/render_blender_shapes.py                 # both pictures into docs/images/
    python scripts/render_blender_shapes.py --only ellipsoid
"""

import argparse
import math
import subprocess
import sys
from pathlib import Path

import bpy
import numpy as np
from blender_addon_loader import load_addon
from blender_render_scene import camera_looking_at, render_still

REPO = Path(__file__).resolve().parents[1]
IMAGES = REPO / "docs" / "images"


def positions(obj):
    co = np.empty(3 * len(obj.data.vertices))
    obj.data.vertices.foreach_get("co", co)
    return co.reshape(-1, 3)


def label(text, location, size):
    """A flat dark-grey text object facing the camera's side of the scene (-y)."""
    curve = bpy.data.curves.new(text, "FONT")
    curve.body, curve.size, curve.align_x = text, size, "CENTER"
    ink = bpy.data.materials.new("ink")
    ink.diffuse_color = (0.08, 0.08, 0.08, 1.0)
    if ink.node_tree is None:
        ink.use_nodes = True
    ink.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (0.08, 0.08, 0.08, 1.0)
    curve.materials.append(ink)
    obj = bpy.data.objects.new(text, curve)
    obj.location = location
    obj.rotation_euler = (math.pi / 2, 0.0, 0.0)
    bpy.context.collection.objects.link(obj)
    return obj


def paint_on_one_scale(addon, objects, spacing, captions, z, size):
    """Show ``(object, distance)`` pairs with the isoline material on one scale (up to the larger maximum),
    isolines every ``spacing``, and put a caption (formatted with the object's maximum) under each; the objects."""
    vmax = max(d.max() for _, d in objects)
    for (obj, d), caption in zip(objects, captions):
        addon.material.show_isoline_material(obj, "geodesic_distance", colormap="viridis", max_distance=vmax,
                                             spacing=spacing, line_width=2.0)
        label(caption.format(d.max()), (obj.location.x, 0.0, z), size)
    return [obj for obj, _ in objects]


def ellipsoid_scene(addon):
    """Two ico spheres scaled (1, 1, 3): Local on the left, World on the right, one color scale."""
    objects = []
    for x, space in ((-1.6, "LOCAL"), (1.6, "WORLD")):
        bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=7, radius=1.0, location=(x, 0.0, 0.0))
        obj = bpy.context.active_object
        obj.scale = (1.0, 1.0, 3.0)  # the object's scale: the mesh stays a unit sphere
        bpy.context.view_layer.update()
        bpy.ops.object.shade_smooth()
        top = int(np.argmax(positions(obj)[:, 2]))
        result = addon.compute_geodesic_distance(obj, sources=[top], space=space, color_attribute=None)
        objects.append((obj, result.distance))
    captions = ("Local (old): {:.2f} pole to pole", "World (default): {:.2f}")
    return paint_on_one_scale(addon, objects, 0.5, captions, -3.5, 0.28), (0.0, -1.0, 0.1)


def shape_key_scene(addon):
    """spot with a long-legs shape key at 1: Mesh Data on the left, As Displayed on the right, one color scale."""
    objects = []
    for x, shape in ((-1.4, "BASIS"), (1.4, "EVALUATED")):
        bpy.ops.wm.obj_import(filepath=str(REPO / "heatcore" / "data" / "spot.obj"))
        obj = bpy.context.selected_objects[0]
        bpy.context.view_layer.objects.active = obj
        mod = obj.modifiers.new("subdivision", "SUBSURF")
        mod.levels = 2
        bpy.ops.object.modifier_apply(modifier=mod.name)
        bpy.ops.object.shade_smooth()
        obj.location.x = x
        obj.rotation_euler.z = math.pi / 2  # the cow's length (the OBJ's z) along the picture's width
        obj.shape_key_add(name="Basis")
        key = obj.shape_key_add(name="Long legs")
        V = positions(obj)
        legs = V[:, 1] < -0.35  # mesh data are the OBJ's (Y up): legs twice as long
        long = V.copy()
        long[legs, 1] = -0.35 + 2.0 * (V[legs, 1] + 0.35)
        key.data.foreach_set("co", long.astype(np.float32).ravel())
        key.value = 1.0
        bpy.context.view_layer.update()
        top = int(np.argmax(V[:, 1]))  # the top of a horn
        # loop triangles, as when the picture was made: the polygons (heatcore's triangulation) give 2.603 for
        # the farthest point where these give 2.611 and the eikonal pass 2.62 (virtual refinement gave 2.39)
        result = addon.compute_geodesic_distance(obj, sources=[top], shape=shape, color_attribute=None,
                                                 polygons="TRIANGULATE")
        objects.append((obj, result.distance))
    captions = ("Mesh Data (old): farthest {:.2f}", "As Displayed (default): {:.2f}")
    return paint_on_one_scale(addon, objects, 0.15, captions, -1.45, 0.16), (0.0, -1.0, 0.3)


def render(objects, direction, path, size):
    """Frame ``objects`` from ``direction``, light them with a sun and a light grey world, render with EEVEE."""
    corners = np.vstack([positions(obj) @ np.array(obj.matrix_world)[:3, :3].T + np.array(obj.matrix_world)[:3, 3]
                         for obj in objects])
    center = 0.5 * (corners.min(axis=0) + corners.max(axis=0))
    extent = float(np.linalg.norm(corners.max(axis=0) - corners.min(axis=0)))
    direction = np.asarray(direction, dtype=float) / np.linalg.norm(direction)
    camera_looking_at(center + 2.0 * extent * direction, center)
    render_still(path, size)
    print(f"wrote {path}")


SCENES = {"ellipsoid": (ellipsoid_scene, (960, 640)), "shape_key": (shape_key_scene, (960, 480))}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--only", choices=sorted(SCENES), help="render one picture")
    parser.add_argument("--out", default=str(IMAGES), help="folder of the PNGs (blender_<scene>.png)")
    args = parser.parse_args(argv)
    if args.only is None:  # one process per picture: a second render in a process may fail (EGL)
        for name in SCENES:
            subprocess.run([sys.executable, __file__, "--only", name, "--out", args.out], check=True)
        return
    bpy.ops.wm.read_factory_settings(use_empty=True)
    addon = load_addon()
    build, size = SCENES[args.only]
    objects, direction = build(addon)
    render(objects, direction, Path(args.out).resolve() / f"blender_{args.only}.png", size)
    addon.unregister()

if __name__ == "__main__":
    main()
