"""Render a checker decal on spot's flank: the Geodesic UV Map against Blender's Project from View and Smart UV Project.

One picture for docs/blender.md and docs/vector-heat.md, a headless Workbench
render through ``bpy`` (texture colors, studio light). Three copies of spot
(one level of subdivision, 17,570 vertices), seen from the side, each with
one UV map and the same decal image (8 × 8 checker squares, the top row red:
the decal's up; a grey border, so that outside the decal the mesh is grey):

- left: *Geodesic UV Map* (``geodesic_uv_map``, ``accuracy="high"``) from a
  vertex on the flank, up = +z (the cow's up);
- middle: *Project from View* from the side (orthographic, along -x):
  the mapping Blender's operator makes from that view, computed here with
  numpy because headless ``bpy`` has no 3D View to run the operator in;
- right: Blender's own *Smart UV Project* (``bpy.ops.uv.smart_project``).

The camera looks from the side and 37 degrees above, so that the back, which
a projection from the side stretches, is in sight. The two projections are moved and scaled so that the source vertex is at the
decal's centre and one UV unit is the same surface length as the geodesic
map's (Smart UV Project: its mean scale, from the UV and 3D areas).

Examples
--------
::

    python scripts/render_blender_decal.py                       # docs/images/blender_decal.png
    python scripts/render_blender_decal.py --meshes ../shared/meshes --out decal.png
"""

import argparse
import math
from pathlib import Path

import bpy
import numpy as np
from blender_addon_loader import load_addon

REPO = Path(__file__).resolve().parents[1]
#: Surface length of the decal's side (one UV unit), in spot's units (it is about 1.9 long).
UNIT = 0.8
SQUARES = 8
#: Where the copies stand along y (the camera looks along -x at their flanks).
OFFSETS = (-2.2, 0.0, 2.2)


def positions(obj, world=True):
    co = np.empty(3 * len(obj.data.vertices))
    obj.data.vertices.foreach_get("co", co)
    V = co.reshape(-1, 3)
    if world:
        M = np.array(obj.matrix_world)
        V = V @ M[:3, :3].T + M[:3, 3]
    return V


def decal_image(pixels=512):
    """The decal: a checker of ``SQUARES`` × ``SQUARES`` (white and blue, the top row white and red), grey border."""
    i = np.arange(pixels) * SQUARES // pixels
    odd = (i[:, None] + i[None, :]) % 2 == 1  # rows: v (bottom first), columns: u
    rgba = np.ones((pixels, pixels, 4))
    rgba[odd, :3] = (0.1, 0.25, 0.8)
    top = i[:, None].repeat(pixels, axis=1) == SQUARES - 1
    rgba[odd & top, :3] = (0.85, 0.1, 0.1)
    border = max(2, pixels // 128)
    grey = np.zeros((pixels, pixels), dtype=bool)
    grey[:border], grey[-border:], grey[:, :border], grey[:, -border:] = True, True, True, True
    rgba[grey, :3] = 0.6
    image = bpy.data.images.new("decal", pixels, pixels, alpha=False)
    image.pixels.foreach_set(rgba.astype(np.float32).ravel())
    image.pack()
    return image


def material(image):
    mat = bpy.data.materials.new("decal")
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    tex = nodes.new("ShaderNodeTexImage")
    tex.image, tex.extension, tex.interpolation = image, "EXTEND", "Closest"
    bsdf = nodes.get("Principled BSDF")
    mat.node_tree.links.new(tex.outputs["Color"], bsdf.inputs["Base Color"])
    nodes.active = tex  # Workbench's Texture color shows the active image node
    return mat


def only_uv_map(obj, name, uv_corners):
    """Make ``name`` (values per face corner) the mesh's only UV map."""
    mesh = obj.data
    for layer in [layer for layer in mesh.uv_layers if layer.name != name]:
        mesh.uv_layers.remove(layer)
    layer = mesh.uv_layers.get(name) or mesh.uv_layers.new(name=name)
    if uv_corners is not None:
        layer.uv.foreach_set("vector", np.asarray(uv_corners, dtype=np.float32).ravel())
    mesh.uv_layers.active = layer
    layer.active_render = True


def corners(mesh):
    out = np.empty(len(mesh.loops), dtype=np.int64)
    mesh.loops.foreach_get("vertex_index", out)
    return out


def corner_uv(mesh, name):
    out = np.empty(2 * len(mesh.loops))
    mesh.uv_layers[name].uv.foreach_get("vector", out)
    return out.reshape(-1, 2)


def smart_uv(obj, source, V):
    """Blender's Smart UV Project, rescaled to one UV unit = ``UNIT`` (mean scale) and centred on ``source``."""
    bpy.context.view_layer.objects.active = obj
    for other in bpy.context.view_layer.objects:
        other.select_set(other == obj)
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="SELECT")
    bpy.ops.uv.smart_project(angle_limit=math.radians(66.0), island_margin=0.02, scale_to_bounds=False)
    bpy.ops.object.mode_set(mode="OBJECT")
    mesh = obj.data
    uv = corner_uv(mesh, mesh.uv_layers.active.name)
    mesh.calc_loop_triangles()
    tri = np.empty(3 * len(mesh.loop_triangles), dtype=np.int64)
    mesh.loop_triangles.foreach_get("loops", tri)
    tri = tri.reshape(-1, 3)
    C = corners(mesh)
    P = V[C]
    area3 = 0.5 * np.linalg.norm(np.cross(P[tri[:, 1]] - P[tri[:, 0]], P[tri[:, 2]] - P[tri[:, 0]]), axis=1).sum()
    e1, e2 = uv[tri[:, 1]] - uv[tri[:, 0]], uv[tri[:, 2]] - uv[tri[:, 0]]
    area2 = 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]).sum()
    scale = math.sqrt(area3 / area2) / UNIT  # UV units per Smart-UV unit, so that 1 UV unit = UNIT
    centre = uv[C == source].mean(axis=0)
    only_uv_map(obj, mesh.uv_layers.active.name, 0.5 + (uv - centre) * scale)


def build(addon, mesh_path):
    bpy.ops.wm.obj_import(filepath=str(mesh_path))
    spot = bpy.context.selected_objects[0]
    bpy.context.view_layer.objects.active = spot
    mod = spot.modifiers.new("subdivision", "SUBSURF")
    mod.levels = 1
    bpy.ops.object.modifier_apply(modifier=mod.name)
    bpy.ops.object.shade_smooth()
    bpy.context.view_layer.update()
    V0 = positions(spot)  # the importer turns the OBJ's y (spot's up) to z and its z (the length) to -y
    flank = np.flatnonzero((np.abs(V0[:, 2] - 0.1) < 0.08) & (np.abs(V0[:, 1] + 0.3) < 0.08))
    source = int(flank[np.argmax(V0[flank, 0])])
    image = decal_image()
    mat = material(image)
    copies = [spot] + [spot.copy() for _ in (1, 2)]
    for obj, y in zip(copies, OFFSETS):
        if obj is not spot:
            obj.data = spot.data.copy()
            bpy.context.collection.objects.link(obj)
        obj.location = (0.0, y, 0.0)
        obj.data.materials.clear()
        obj.data.materials.append(mat)
    bpy.context.view_layer.update()
    geodesic, projected, smart = copies
    result = addon.geodesic_uv_map(geodesic, source, unit=UNIT, up=(0.0, 0.0, 1.0), accuracy="high")
    only_uv_map(geodesic, result.name, None)
    V = positions(projected)
    # Project from View along -x (camera right = +y, up = +z), source at the centre, one UV unit = UNIT.
    view = 0.5 + (V[:, 1:] - V[source, 1:]) / UNIT
    only_uv_map(projected, "project_from_view", view[corners(projected.data)])
    smart_uv(smart, source, positions(smart))
    captions = ("Geodesic UV Map", "Project from View (from the side)", "Smart UV Project")
    for obj, text in zip(copies, captions):
        label(text, (0.6, obj.location.y, -0.95))
    print(f"source vertex {source}, {len(V):,} vertices, farthest {result.max_distance:.3f}, "
          f"{result.seconds:.2f} s")
    return copies


def label(text, location, size=0.16):
    """A dark text object lying on the floor in front of the cows, facing up and towards +x."""
    curve = bpy.data.curves.new(text, "FONT")
    curve.body, curve.size, curve.align_x = text, size, "CENTER"
    obj = bpy.data.objects.new(text, curve)
    obj.location = location
    obj.rotation_euler = (math.radians(37.0), 0.0, math.pi / 2)  # facing the camera (from +x, 37 degrees up)
    text_mat = bpy.data.materials.get("label") or bpy.data.materials.new("label")
    text_mat.diffuse_color = (0.05, 0.05, 0.05, 1.0)
    curve.materials.append(text_mat)
    bpy.context.collection.objects.link(obj)


def render(path, direction=(1.0, 0.0, 0.75), size=(1500, 500), color_type="TEXTURE"):
    """Render from ``direction`` (orthographic, at the scene's centre), on white, with Workbench colors
    ``color_type`` (``"TEXTURE"``: the active image node's; ``"MATERIAL"``: the materials' viewport colors)."""
    direction = np.asarray(direction, dtype=float) / np.linalg.norm(direction)
    cam_data = bpy.data.cameras.new("camera")
    cam_data.type, cam_data.ortho_scale = "ORTHO", 6.6
    cam = bpy.data.objects.new("camera", cam_data)
    bpy.context.collection.objects.link(cam)
    centre = np.array([0.0, 0.0, -0.1])
    cam.location = centre + 8.0 * direction
    look = -direction
    cam.rotation_euler = (math.atan2(math.hypot(look[0], look[1]), -look[2]), 0.0,
                          math.atan2(look[1], look[0]) - math.pi / 2)
    scene = bpy.context.scene
    scene.camera = cam
    scene.render.engine = "BLENDER_WORKBENCH"
    scene.render.resolution_x, scene.render.resolution_y = size
    scene.view_settings.view_transform = "Standard"
    scene.display.shading.light = "STUDIO"
    scene.display.shading.color_type = color_type
    scene.world = bpy.data.worlds.new("white")
    scene.world.color = (1.0, 1.0, 1.0)
    scene.display.shading.background_type = "WORLD"
    scene.render.image_settings.color_mode = "RGB"
    scene.render.image_settings.compression = 100
    scene.render.filepath = str(path)
    bpy.ops.render.render(write_still=True)
    print(f"wrote {path}")


def parse_arguments(doc, image, mesh="spot", argv=None):
    """``--meshes`` and ``--out`` of a render script: the mesh file and the picture's path."""
    parser = argparse.ArgumentParser(description=doc.split("\n\n")[0])
    parser.add_argument("--meshes", type=Path, default=REPO.parent / "shared" / "meshes",
                        help=f"folder holding {mesh}.obj (default: ../shared/meshes; else heatcore's own copy)")
    parser.add_argument("--out", type=Path, default=REPO / "docs" / "images" / image)
    args = parser.parse_args(argv)
    path = args.meshes / f"{mesh}.obj"
    if not path.exists() and (REPO / "heatcore" / "data" / f"{mesh}.obj").exists():
        path = REPO / "heatcore" / "data" / f"{mesh}.obj"
    return path, args.out.resolve()


def render_scene(build, mesh_path, out, **render_options):
    """An empty scene, the add-on, ``build(addon, mesh_path)``, then :func:`render` into ``out``."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    addon = load_addon()
    build(addon, mesh_path)
    render(out, **render_options)
    addon.unregister()


def main(argv=None):
    render_scene(build, *parse_arguments(__doc__, "blender_decal.png", argv=argv))


if __name__ == "__main__":
    main()
