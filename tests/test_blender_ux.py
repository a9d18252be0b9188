"""What an artist meets first (issue 37): tooltips, selection, one isoline count, units, the redo panel, sources.

With the real ``bpy`` (Blender 5.0 headless). Every registered property of
the add-on (operators, scene settings) is walked for its tooltip; runs on
several selected objects, faces and edges as sources are checked against
heatcore called on the same arrays.
"""

import bpy
import numpy as np
import pytest
from test_blender import addon, attribute, empty_scene, ico_sphere, run, select_only  # noqa: F401 (fixtures)

#: The add-on's operators (``bpy.ops.mesh.<name>``).
OPERATORS = ("heat_geodesic_distance", "heat_geodesic_isoline_curves", "heat_geodesic_probe", "heat_geodesic_path",
             "heat_geodesic_uv_map")
#: Properties every Blender property group has, with Blender's own tooltip.
BUILT_IN = {"rna_type", "name"}


def registered_properties():
    """(owner, property) of every property a user can meet: the operators' and the scene settings'."""
    owners = [(op, getattr(bpy.ops.mesh, op).get_rna_type()) for op in OPERATORS]
    owners.append(("scene.heat_geodesic", bpy.context.scene.heat_geodesic.bl_rna))
    return [(owner, prop) for owner, rna in owners for prop in rna.properties if prop.identifier not in BUILT_IN]


# ---------------------------------------------------------------- tooltips


def test_every_property_has_a_tooltip_for_a_blender_user(addon):
    foreign = addon.tooltips.FOREIGN_WORDS
    props = registered_properties()
    assert len(props) > 80
    for owner, prop in props:
        texts = [prop.description] + [item.description for item in getattr(prop, "enum_items", ())]
        where = f"{owner}.{prop.identifier}"
        assert prop.description.strip(), f"{where} has no tooltip"
        for text in texts:
            assert text[:1].isupper() or not text[:1].isalpha(), f"{where}: {text!r} starts lower-case"
            assert not any(word in text.lower() for word in foreign), f"{where}: {text!r} names another front end"


def test_spacing_tooltip_is_the_spacing_the_material_uses(addon):
    settings = bpy.context.scene.heat_geodesic
    assert "(Isolines + 1)" in settings.bl_rna.properties["isoline_spacing"].description
    obj = ico_sphere(3)
    select_only(obj, [0])
    result = addon.compute_geodesic_distance(obj, isolines=9, isoline_material=True)
    legend = addon.material.isoline_legend(obj)
    assert legend.spacing == pytest.approx(result.max_distance / 10, rel=1e-5)
