"""Blender add-on: the isoline material is what a click shows, in a shaded or a flat (unlit) style.

What is checked, and how (real ``bpy``):

- the *Geodesic Distance* operator and the panel have the material on by
  default; a click with the defaults adds the "Geodesic Isolines" modifier
  whose material reads the distance attribute and draws the isolines
  (Attribute -> bands -> Bump line mask -> darkening -> Principled BSDF with
  a faint glow of the same color); the vertex colors are still written and
  active (what Solid shading shows); the user's materials, slots and
  attributes are unchanged; one undo step removes the modifier, its node
  group and material, and the outputs;
- ``isoline_style="FLAT"`` rebuilds the same material in place with an
  Emission shader; rendered (Cycles, no isolines) its pixels are the
  colormap's colors whatever the light: the same under a white and a dark
  world, within 1% of heatcore's colormap at the pixel's distance;
- an unknown style is refused before anything is written;
- the viewport: after a run, Solid views show the attribute colors (Flat
  lighting for the flat style) and switch to Material Preview when the
  material is on (stand-in 3D views: headless Blender has no screen).
"""

from types import SimpleNamespace

import blender_required  # noqa: F401 (first: without bpy, the module is skipped)
import bpy
import numpy as np
import pytest
from test_blender import (
    addon,
    assert_same_snapshot,
    empty_scene,
    ico_sphere,
    select_only,
    snapshot,
)
from test_blender_material import (
    clean_data,
    linked_from,
    material_module,
    material_state,
    render,
    square,
    srgb_to_linear,
    user_materials,
)

from heatcore.viz.colormap import colorize

__all__ = ["addon", "clean_data", "empty_scene"]  # fixtures


def test_a_click_with_the_defaults_shows_the_isoline_material(addon):
    material = material_module()
    op_props = bpy.ops.mesh.heat_geodesic_distance.get_rna_type().properties
    assert op_props["isoline_material"].default is True and op_props["isoline_style"].default == "SHADED"
    assert bpy.context.scene.heat_geodesic.isoline_material is True
    obj = ico_sphere(subdivisions=3)
    user_materials(obj)  # Red and Blue, faces split between them
    mine = obj.data.attributes.new("my_mask", "FLOAT", "POINT")
    mine.data.foreach_set("value", np.arange(len(obj.data.vertices), dtype=np.float32))
    select_only(obj, [0])
    before, before_materials = snapshot(obj), material_state(obj)
    with bpy.context.temp_override(active_object=obj, object=obj, selected_objects=[obj]):
        assert bpy.ops.mesh.heat_geodesic_distance() == {"FINISHED"}

    outputs = ("geodesic_distance", "geodesic_distance_color")
    assert_same_snapshot(before, snapshot(obj), ignore=outputs)  # my_mask and the material indices included
    assert material_state(obj) == before_materials and [m.name for m in obj.data.materials] == ["Red", "Blue"]
    assert obj.data.color_attributes.active_color.name == "geodesic_distance_color"  # Solid shading's colors
    legend = material.isoline_legend(obj)
    assert legend is not None and legend.count == 10  # the panel's 10 isolines
    nodes = legend.material.node_tree.nodes
    assert nodes["Distance Attribute"].attribute_name == "geodesic_distance"
    assert linked_from(nodes["Band Change"], "Height") == "Band Index"
    assert linked_from(nodes["Isolines"], 0) == "Isoline Mask"
    assert linked_from(nodes["Isoline Color"], nodes["Isoline Color"].inputs[0]) == "Isolines"
    shading = nodes["Shading"]
    assert shading.bl_idname == "ShaderNodeBsdfPrincipled"
    assert linked_from(shading, "Base Color") == linked_from(shading, "Emission Color") == "Isoline Color"
    assert shading.inputs["Emission Strength"].default_value == pytest.approx(material.SHADED_GLOW)
    assert linked_from(nodes["Output"], "Surface") == "Shading"


def test_one_undo_step_takes_the_material_away(addon):
    obj = ico_sphere(subdivisions=2)
    name = obj.name
    select_only(obj, [0])
    counts = {kind: len(getattr(bpy.data, kind)) for kind in ("materials", "node_groups")}
    bpy.ops.ed.undo_push(message="before")
    with bpy.context.temp_override(active_object=obj, object=obj, selected_objects=[obj]):
        assert bpy.ops.mesh.heat_geodesic_distance() == {"FINISHED"}
    bpy.ops.ed.undo_push(message="geodesic distance")
    assert [m.name for m in bpy.data.objects[name].modifiers] == ["Geodesic Isolines"]
    bpy.ops.ed.undo()
    obj = bpy.data.objects[name]
    assert len(obj.modifiers) == 0 and "geodesic_distance" not in obj.data.attributes
    assert {kind: len(getattr(bpy.data, kind)) for kind in counts} == counts


def test_flat_style_rebuilds_the_material_in_place(addon):
    material = material_module()
    obj = ico_sphere(subdivisions=2)
    addon.compute_geodesic_distance(obj, sources=[0], isolines=4, isoline_material=True)
    ours = material.isoline_legend(obj).material
    addon.compute_geodesic_distance(obj, sources=[0], isolines=4, isoline_material=True, isoline_style="FLAT")
    assert material.isoline_legend(obj).material == ours and len(obj.modifiers) == 1
    shading = ours.node_tree.nodes["Shading"]
    assert shading.bl_idname == "ShaderNodeEmission" and shading.inputs["Strength"].default_value == 1.0
    assert linked_from(shading, "Color") == "Isoline Color"
    assert linked_from(ours.node_tree.nodes["Output"], "Surface") == "Shading"
    addon.compute_geodesic_distance(obj, sources=[0], isolines=4, isoline_material=True)  # and back
    assert ours.node_tree.nodes["Shading"].bl_idname == "ShaderNodeBsdfPrincipled"


def test_flat_style_renders_the_colormap_in_any_light(addon, tmp_path):
    """d = x on the unit square, no isolines: each pixel is viridis(x) (linear) under a white and a dark world;
    the shaded style, lit by the world, is not."""
    material = material_module()
    obj, co = square(65)
    obj.data.attributes.new("d", "FLOAT", "POINT").data.foreach_set("value", co[:, 0].astype(np.float32))
    x = (np.arange(64) + 0.5) / 64
    want = srgb_to_linear(colorize(x, colormap="viridis", vmax=1.0))  # a row of pixels, left to right
    rows = {}
    for style in ("FLAT", "SHADED"):
        material.show_isoline_material(obj, "d", colormap="viridis", max_distance=1.0, spacing=0.0, style=style)
        for light in (1.0, 0.1):
            rows[style, light] = render(obj, tmp_path, size=64, world_color=(light,) * 3)[32]
    np.testing.assert_allclose(rows["FLAT", 1.0], want, atol=0.01)
    np.testing.assert_allclose(rows["FLAT", 0.1], want, atol=0.01)
    assert np.abs(rows["SHADED", 1.0] - rows["SHADED", 0.1]).max() > 0.1  # lit: it depends on the light


def test_an_unknown_style_is_refused_before_any_work(addon):
    obj = ico_sphere(subdivisions=2)
    before = snapshot(obj)
    with pytest.raises(addon.AddonError, match="isoline_style must be one of SHADED, FLAT"):
        addon.compute_geodesic_distance(obj, sources=[0], isoline_material=True, isoline_style="GLOSSY")
    assert_same_snapshot(before, snapshot(obj))
    assert len(obj.modifiers) == 0
    assert "geodesic_distance" not in obj.data.attributes


def view(kind="SOLID"):
    """A stand-in 3D view area (headless Blender has no screen): its shading settings."""
    shading = SimpleNamespace(type=kind, color_type="MATERIAL", light="STUDIO")
    return SimpleNamespace(type="VIEW_3D", spaces=SimpleNamespace(active=SimpleNamespace(shading=shading))), shading


@pytest.mark.parametrize("material_on, style, want", [
    (False, "SHADED", ("SOLID", "VERTEX", "STUDIO")),  # the vertex colors, in Solid shading
    (True, "SHADED", ("MATERIAL", "VERTEX", "STUDIO")),
    (True, "FLAT", ("MATERIAL", "VERTEX", "FLAT")),  # Solid shading later: unlit attribute colors
])
def test_a_run_shows_its_result_in_the_3d_views(addon, material_on, style, want):
    solid, shading = view()
    rendered, rendered_shading = view("RENDERED")
    context = SimpleNamespace(screen=SimpleNamespace(areas=[solid, rendered]))
    addon.operator.show_color_attribute(context, {"isoline_material": material_on, "isoline_style": style})
    assert (shading.type, shading.color_type, shading.light) == want
    assert rendered_shading.type == "RENDERED"  # a Rendered view stays as it is
