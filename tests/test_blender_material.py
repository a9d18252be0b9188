"""Blender add-on: the isoline material (per-pixel isolines, independent of the mesh density) and its legend.

What is checked, and how:

- the modifier, node group and material are created, re-runs update them in
  place (same datablocks, no ``.001`` copies), and the user's materials, slots
  and face material indices are unchanged (snapshots); a user material with
  our name is never reused;
- the shader's logic read from its nodes and links: distance = attribute x
  scale (normalized attributes too), colormap position = distance / max,
  isoline bands = floor(distance / spacing) with spacing = max / (isolines + 1);
  the ColorRamp equals heatcore's colormap (linear color);
- rendered with Cycles (CPU, 128 x 128 pixels, a few samples): on a flat
  square with the exact distance from one corner (Euclidean) or from one
  side, written as the attribute, dark pixels occur only within 1.5 pixels
  of a multiple of the spacing, every isoline is drawn along its whole
  length, and its width in pixels is the same for every isoline, on a mesh of
  4 vertices or 4,225, and when the camera zooms in; the fallback for Blender
  before 4.4 (no Bump *Filter Width*, forced here) darkens exactly the pixels
  within 4% of the spacing of a nonzero multiple;
- the measure is not affected: the modifier changes no vertices, so it is
  never named among the skipped modifiers;
- the legend sub-panel: range, spacing and the material's ColorRamp.
"""

from types import SimpleNamespace

import blender_required  # noqa: F401 (first: without bpy, the module is skipped)
import bmesh
import bpy
import numpy as np
import pytest
from test_blender import (
    addon,
    assert_same_snapshot,
    attribute,
    empty_scene,
    ico_sphere,
    select_only,
    snapshot,
)

from heatcore.viz.colormap import colorize

__all__ = ["addon", "empty_scene"]  # fixtures

SAMPLES = 4
DATA = ("materials", "node_groups", "cameras", "lights", "worlds", "images")


@pytest.fixture(autouse=True)
def clean_data():
    """Remove the materials, node groups, cameras, ... a test made (empty_scene removes objects and meshes)."""
    before = {kind: set(getattr(bpy.data, kind)) for kind in DATA}
    yield
    for kind in DATA:
        for block in set(getattr(bpy.data, kind)) - before[kind]:
            getattr(bpy.data, kind).remove(block)


def material_module():
    import blender_addon.material as material

    return material


def srgb_to_linear(c):
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def user_materials(obj):
    """An object with two materials of the user's and faces split between them."""
    red, blue = bpy.data.materials.new("Red"), bpy.data.materials.new("Blue")
    obj.data.materials.append(red)
    obj.data.materials.append(blue)
    index = (np.arange(len(obj.data.polygons)) % 2).astype(np.int32)
    obj.data.polygons.foreach_set("material_index", index)
    obj.data.update()
    return red, blue


def material_state(obj):
    """The user's material setup: slots, mesh materials, their node trees."""
    return (
        [(s.link, s.material.name if s.material else None) for s in obj.material_slots],
        [m.name for m in obj.data.materials],
        {m.name: sorted(n.bl_idname for n in m.node_tree.nodes) for m in bpy.data.materials
         if m.node_tree and material_module().MARKER not in m},
    )


def evaluated_face_materials(obj):
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    index = np.empty(len(evaluated.data.polygons), dtype=np.int32)
    evaluated.data.polygons.foreach_get("material_index", index)
    slots = evaluated.material_slots
    return {slots[i].material.name for i in np.unique(index)}


def linked_from(node, socket):
    """Name of the node feeding input ``socket`` of ``node``."""
    links = node.inputs[socket].links if isinstance(socket, (str, int)) else socket.links
    return links[0].from_node.name


# ---------------------------------------------------------------- datablocks


def test_material_modifier_created_and_rerun_updates_in_place(addon):
    material = material_module()
    obj = ico_sphere(subdivisions=3)
    red, blue = user_materials(obj)
    taken = bpy.data.materials.new(f"Geodesic Isolines ({obj.name})")  # the user took our name
    before, before_materials = snapshot(obj), material_state(obj)

    result = addon.compute_geodesic_distance(obj, sources=[0], isolines=8, isoline_material=True)
    outputs = ("geodesic_distance", "geodesic_distance_color")
    assert_same_snapshot(before, snapshot(obj), ignore=outputs)  # material_index values included
    assert material_state(obj) == before_materials
    assert [m.name for m in obj.modifiers] == ["Geodesic Isolines"]
    mod = obj.modifiers[0]
    assert mod.type == "NODES" and material.is_isoline_modifier(mod)
    ours = mod.node_group.nodes["Set Material"].inputs["Material"].default_value
    assert ours != taken and material.MARKER in ours and material.MARKER not in taken
    assert ours.name.startswith(f"Geodesic Isolines ({obj.name})")  # Blender's unique suffix (leftovers of
    assert ours.name != taken.name  # earlier test files' default runs may hold lower suffixes)
    assert evaluated_face_materials(obj) == {ours.name}  # every face, on screen only

    legend = material.isoline_legend(obj)
    assert legend.max_distance == pytest.approx(result.max_distance, rel=1e-6)
    assert legend.spacing == pytest.approx(result.max_distance / 9, rel=1e-6)
    assert legend.count == 8 and legend.space == "WORLD"

    counts = {kind: len(getattr(bpy.data, kind)) for kind in ("materials", "node_groups")}
    pointers = (mod.as_pointer(), mod.node_group.as_pointer(), ours.as_pointer())
    result = addon.compute_geodesic_distance(obj, sources=[7], isolines=5, colormap="magma", isoline_material=True)
    assert {kind: len(getattr(bpy.data, kind)) for kind in counts} == counts
    mod = obj.modifiers[0]
    ours = mod.node_group.nodes["Set Material"].inputs["Material"].default_value
    assert len(obj.modifiers) == 1 and (mod.as_pointer(), mod.node_group.as_pointer(), ours.as_pointer()) == pointers
    assert material.isoline_legend(obj).spacing == pytest.approx(result.max_distance / 6, rel=1e-6)
    assert material_state(obj) == before_materials
    assert_same_snapshot(before, snapshot(obj), ignore=outputs)

    obj.modifiers.remove(mod)  # the user's look is back
    assert evaluated_face_materials(obj) == {red.name, blue.name}


def test_object_linked_slots_and_duplicates(addon):
    material = material_module()
    obj = ico_sphere(subdivisions=2)
    user = bpy.data.materials.new("Object Linked")
    obj.data.materials.append(None)
    obj.material_slots[0].link = "OBJECT"
    obj.material_slots[0].material = user
    addon.compute_geodesic_distance(obj, sources=[0], isolines=4, isoline_material=True)
    assert evaluated_face_materials(obj) == {material.isoline_legend(obj).material.name}
    assert obj.material_slots[0].link == "OBJECT" and obj.material_slots[0].material == user

    twin = obj.copy()  # Shift-D: the modifier is copied and shares the node group
    bpy.context.collection.objects.link(twin)
    twin.scale = (2.0, 2.0, 2.0)
    bpy.context.view_layer.update()
    first = material.isoline_legend(obj).max_distance
    addon.compute_geodesic_distance(twin, sources=[0], isolines=4, isoline_material=True)
    assert material.isoline_modifier(twin).node_group != material.isoline_modifier(obj).node_group
    assert material.isoline_legend(twin).max_distance == pytest.approx(2 * first, rel=1e-5)
    assert material.isoline_legend(obj).max_distance == first  # the original's material is its own


def test_bad_isoline_options_change_nothing(addon):
    obj = ico_sphere(subdivisions=2)
    select_only(obj, [0])
    before, materials = snapshot(obj), len(bpy.data.materials)
    AddonError = addon.AddonError
    with pytest.raises(AddonError, match="attribute name"):
        addon.compute_geodesic_distance(obj, attribute=None, isoline_material=True)
    with pytest.raises(AddonError, match="isoline_width"):
        addon.compute_geodesic_distance(obj, isoline_material=True, isoline_width=0.0)
    with pytest.raises(AddonError, match="isoline_spacing"):
        addon.compute_geodesic_distance(obj, isoline_material=True, isoline_spacing=-1.0)
    assert_same_snapshot(before, snapshot(obj))
    assert len(obj.modifiers) == 0 and len(bpy.data.materials) == materials


def test_modifier_is_not_a_skipped_modifier(addon):
    obj = ico_sphere(subdivisions=2)
    addon.compute_geodesic_distance(obj, sources=[0], isoline_material=True, color_attribute=None)
    with_ours = attribute(obj.data, "geodesic_distance")
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no warning: the modifier changes no vertex
        result = addon.compute_geodesic_distance(obj, sources=[0], isoline_material=True, color_attribute=None)
    assert result.skipped_modifiers == []
    obj.modifiers.new("Subdivision", "SUBSURF")
    with pytest.warns(UserWarning, match="Subdivision") as caught:
        result = addon.compute_geodesic_distance(obj, sources=[0], isoline_material=True, color_attribute=None)
    assert result.skipped_modifiers == ["Subdivision"]
    assert not any("Geodesic Isolines" in str(w.message) for w in caught)
    assert obj.modifiers["Geodesic Isolines"].show_viewport
    np.testing.assert_allclose(attribute(obj.data, "geodesic_distance"), with_ours, rtol=1e-6)


# ---------------------------------------------------------------- the shader's logic


@pytest.mark.parametrize("normalize", [False, True])
def test_shader_nodes_compute_colormap_and_bands(addon, normalize):
    material = material_module()
    obj = ico_sphere(subdivisions=3, radius=2.0)
    result = addon.compute_geodesic_distance(obj, sources=[0], isolines=6, colormap="plasma",
                                             normalize=normalize, isoline_material=True)
    legend = material.isoline_legend(obj)
    nodes = legend.ramp.id_data.nodes
    dmax = result.max_distance
    # wiring: attribute -> distance -> colormap / bands -> bump -> mask -> darkening -> BSDF
    assert nodes["Distance Attribute"].attribute_name == "geodesic_distance"
    assert linked_from(nodes["Distance"], 0) == "Distance Attribute"
    assert linked_from(nodes["Colormap Position"], 0) == "Distance"
    assert linked_from(nodes["Colormap"], "Fac") == "Colormap Position"
    assert linked_from(nodes["Isoline Band"], 0) == "Distance"
    assert linked_from(nodes["Band Index"], 0) == "Isoline Band"
    assert linked_from(nodes["Band Change"], "Height") == "Band Index"
    assert linked_from(nodes["Isoline Mask"], "Value") == "Normal Tilt"
    assert linked_from(nodes["Shading"], "Base Color") == "Isoline Color"
    assert nodes["Band Index"].operation == "FLOOR" and nodes["Isoline Band"].operation == "DIVIDE"

    # the math, evaluated with the node values on the attribute's own values
    value = attribute(obj.data, "geodesic_distance")
    distance = value * nodes["Distance"].inputs[1].default_value
    np.testing.assert_allclose(distance, result.distance, rtol=1e-5, atol=1e-6)
    assert nodes["Colormap Position"].inputs[1].default_value == pytest.approx(dmax, rel=1e-6)
    spacing = nodes["Isoline Band"].inputs[1].default_value
    assert spacing == pytest.approx(dmax / 7, rel=1e-6) and legend.count == 6
    bands = np.floor(distance / spacing)
    assert set(np.unique(bands)) <= set(range(8))
    # the ramp is heatcore's colormap in linear color (32 samples of its 33-entry table)
    x = np.linspace(0.0, 1.0, 101)
    ramp = np.array([legend.ramp.color_ramp.evaluate(float(t))[:3] for t in x])
    np.testing.assert_allclose(ramp, srgb_to_linear(colorize(x, colormap="plasma", vmax=1.0)), atol=0.01)


# ---------------------------------------------------------------- rendered


def square(n):
    """The unit square [0, 1]^2 (z = 0) as an n x n grid (n = 2: one quad, 4 vertices)."""
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=n - 1, y_subdivisions=n - 1, size=1.0)
    obj = bpy.context.active_object
    co = np.empty(3 * len(obj.data.vertices))
    obj.data.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    co[:, :2] += 0.5
    obj.data.vertices.foreach_set("co", co.ravel())
    obj.data.update()
    return obj, co


def render(obj, tmp_path, ortho_scale=1.0, center=(0.5, 0.5), size=128, world_color=(1.0, 1.0, 1.0)):
    """Cycles, orthographic from above, a uniform world (white): linear RGB, rows bottom-up."""
    scene = bpy.context.scene
    camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    camera.data.type, camera.data.ortho_scale = "ORTHO", ortho_scale
    camera.location = (*center, 2.0)
    scene.collection.objects.link(camera)
    world = bpy.data.worlds.new("uniform")
    world.color = world_color
    if world.node_tree is not None:  # Blender 5.0: a new world has nodes; its Background node is the light
        world.node_tree.nodes["Background"].inputs["Color"].default_value = (*world_color, 1.0)
    saved = scene.camera, scene.world, scene.render.engine
    scene.camera, scene.world = camera, world
    scene.render.engine = "CYCLES"
    scene.cycles.device, scene.cycles.use_denoising = "CPU", False
    scene.cycles.samples = SAMPLES
    scene.cycles.seed = 0
    scene.cycles.filter_width = 0.01  # every sample at the pixel centre: one mask value per pixel
    scene.render.resolution_x = scene.render.resolution_y = size
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.filepath = str(tmp_path / "render.exr")
    try:
        bpy.ops.render.render(write_still=True)
    finally:
        scene.camera, scene.world, scene.render.engine = saved
        bpy.data.objects.remove(camera)
    image = bpy.data.images.load(scene.render.filepath)
    pixels = np.array(image.pixels[:], dtype=np.float64).reshape(size, size, 4)[:, :, :3]
    bpy.data.images.remove(image)
    return pixels


def dark_pixels(obj, distance, spacing, tmp_path, **view):
    """Pixels the isolines darken: the render with lines over the same render without (same samples)."""
    material = material_module()
    obj.data.attributes.new("d", "FLOAT", "POINT").data.foreach_set("value", distance.astype(np.float32))
    show = dict(colormap="viridis", max_distance=float(distance.max()), line_width=1.5)
    material.show_isoline_material(obj, "d", spacing=spacing, **show)
    lined = render(obj, tmp_path, **view)
    material.show_isoline_material(obj, "d", spacing=0.0, **show)
    plain = render(obj, tmp_path, **view)
    return lined.sum(axis=2) / plain.sum(axis=2) < 0.6  # lines: 0.05 of the diffuse, the specular stays


def pixel_centers(size, ortho_scale=1.0, center=(0.5, 0.5)):
    t = (np.arange(size) + 0.5) / size - 0.5
    x, y = np.meshgrid(center[0] + ortho_scale * t, center[1] + ortho_scale * t)  # rows bottom-up
    return x, y


def check_isolines(dark, d, spacing, pixel, length):
    """Dark pixels only near multiples of the spacing; every isoline drawn, 1 to 2 pixels wide.

    The shader marks a pixel whose isoline band changes within the line width
    (1.5) times the pixel footprint along two tangent directions (Cycles:
    screen diagonals; EEVEE: screen x and y), so a line is 0.7 to 1 times 1.5
    pixels wide depending on its direction; sampled at pixel centres that is
    1 or 2 pixels.
    """
    k = np.round(d / spacing)
    off = np.abs(d - k * spacing) / pixel  # pixels from the nearest isoline (|grad d| = 1)
    assert dark.any()
    assert off[dark].max() < 1.5, "a dark pixel away from every isoline"
    assert not dark[k == 0].any(), "a line at distance 0"
    grown = dark.copy()  # a dark pixel next to each pixel the isoline crosses: no gaps
    grown[1:] |= dark[:-1]
    grown[:-1] |= dark[1:]
    grown[:, 1:] |= dark[:, :-1]
    grown[:, :-1] |= dark[:, 1:]
    widths = []
    for j in np.unique(k[(k > 0) & (off < 0.5)]):
        along = (k == j) & (off < 0.5)
        assert grown[along].mean() > 0.95, f"isoline {j} has gaps"
        widths.append(np.count_nonzero(dark & (k == j)) / length(j))
    widths = np.array(widths)
    assert len(widths) >= 4
    assert 0.9 < widths.min() and widths.max() < 2.1, widths  # pixels across each line
    assert 0.95 < widths.mean() < 1.8, widths
    return widths


@pytest.mark.parametrize("n", [2, 65])
def test_rendered_isolines_of_the_distance_from_a_side(addon, tmp_path, n):
    """d = x (exact on any mesh: linear): straight isolines at x = 0.12 k, on 4 or 4,225 vertices."""
    obj, co = square(n)
    dark = dark_pixels(obj, co[:, 0], 0.12, tmp_path)
    x, _ = pixel_centers(128)
    widths = check_isolines(dark, x, 0.12, 1 / 128, lambda k: 128)
    zoomed = dark_pixels(obj, co[:, 0], 0.12, tmp_path, ortho_scale=0.5, center=(0.4, 0.5))
    xz, _ = pixel_centers(128, 0.5, (0.4, 0.5))
    zoomed_widths = check_isolines(zoomed, xz, 0.12, 0.5 / 128, lambda k: 128)
    assert abs(zoomed_widths.mean() - widths.mean()) < 0.25  # the same width in pixels at twice the zoom


def test_rendered_isolines_of_the_distance_from_a_corner(addon, tmp_path):
    """d = |p| (Euclidean from the corner (0, 0), exact at the 4,225 vertices): quarter circles r = k / 10."""
    obj, co = square(65)
    dark = dark_pixels(obj, np.hypot(co[:, 0], co[:, 1]), 0.1, tmp_path)
    x, y = pixel_centers(128)
    r = np.hypot(x, y)
    arc = lambda k: 128 * k * 0.1 * (np.pi / 2 if k * 0.1 <= 1 else np.pi / 2 - 2 * np.arccos(1 / (k * 0.1)))
    check_isolines(dark, r, 0.1, 1 / 128, arc)


def test_before_blender_4_4_lines_have_a_width_on_the_surface(addon, tmp_path, monkeypatch):
    """Without the Bump node's Filter Width: dark exactly where |d - k s| < 0.04 s, k >= 1 (d = x, 4 vertices)."""
    material = material_module()
    monkeypatch.setattr(material, "pixel_lines_supported", lambda tree: False)
    obj, co = square(2)
    for scale, center in ((1.0, (0.5, 0.5)), (0.5, (0.4, 0.5))):
        dark = dark_pixels(obj, co[:, 0], 0.12, tmp_path, ortho_scale=scale, center=center)
        obj.data.attributes.remove(obj.data.attributes["d"])
        x, _ = pixel_centers(128, scale, center)
        k = np.round(x / 0.12)
        off = np.abs(x - 0.12 * k)
        half = 0.5 * material.SURFACE_LINE_WIDTH * 0.12
        clear = np.abs(off - half) > 0.05 * scale / 128  # pixel centres not on the line's edge
        np.testing.assert_array_equal(dark[clear], ((off < half) & (k >= 1))[clear])
        assert dark.any()


# ---------------------------------------------------------------- operator and legend


class Recorder:
    """A stand-in for ``UILayout`` that records what a panel draws."""

    def __init__(self, log=None):
        self.log = [] if log is None else log

    def __getattr__(self, name):
        def call(*args, **kwargs):
            self.log.append((name, args, kwargs))
            return Recorder(self.log)

        return call


def test_operator_option_and_legend_panel(addon):
    obj = ico_sphere(subdivisions=3)
    legend_panel = bpy.types.VIEW3D_PT_heat_geodesic_legend
    context = SimpleNamespace(active_object=obj, scene=bpy.context.scene)
    assert not legend_panel.poll(context)
    bpy.context.scene.unit_settings.system = "METRIC"
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="DESELECT")
    mesh = bmesh.from_edit_mesh(obj.data)
    mesh.verts.ensure_lookup_table()
    mesh.verts[0].select_set(True)
    bmesh.update_edit_mesh(obj.data)
    with bpy.context.temp_override(active_object=obj, object=obj):
        assert bpy.ops.mesh.heat_geodesic_distance(isolines=4, isoline_material=True, isoline_width=2.0) == {"FINISHED"}
    assert obj.mode == "EDIT"
    bpy.ops.object.mode_set(mode="OBJECT")
    nodes = material_module().isoline_legend(obj).ramp.id_data.nodes
    assert nodes["Band Change"].inputs["Filter Width"].default_value == 2.0
    assert legend_panel.poll(context)
    log = []
    legend_panel.draw(SimpleNamespace(layout=Recorder(log)), context)
    texts = [kw.get("text") for name, _, kw in log if name == "label"]
    dmax = bpy.context.window_manager.heat_geodesic_stats.max_distance
    assert f"{dmax:.4g} m" in texts  # the range 0 .. max
    assert f"Isolines every {dmax / 5 * 100:.4g} cm (4 lines)" in texts
    ramps = [args for name, args, _ in log if name == "template_color_ramp"]
    assert ramps == [(nodes["Colormap"], "color_ramp")]
