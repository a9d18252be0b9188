"""From the UI (``invoke``) each operator takes the panel's value of every option the call leaves unset.

The operators share one helper (``operator.options_from_panel``). A
headless Blender never calls ``invoke`` (``bpy.ops`` runs ``execute``), so each
operator's ``invoke`` runs here on a stand-in for the operator: one option
given, the panel holding other values.
"""

import importlib

import blender_required  # noqa: F401 (first: without bpy, the module is skipped)
import bpy
import pytest
from test_blender import addon, empty_scene  # noqa: F401 (fixtures)

#: (module, operator class)
OPERATORS = [
    ("operator", "MESH_OT_heat_geodesic_distance"),
    ("path_operator", "MESH_OT_heat_geodesic_path"),
    ("uv_operator", "MESH_OT_heat_geodesic_uv_map"),
    ("signed_operator", "MESH_OT_heat_signed_distance"),
]


class StandIn:
    """An operator with ``given`` set by its call; ``execute`` records that it ran."""

    def __init__(self, **given):
        self.__dict__.update(given)
        self.properties = type("Properties", (), {"is_property_set": staticmethod(lambda name: name in given)})()
        self.executed = False

    def execute(self, context):
        self.executed = True
        return {"FINISHED"}


@pytest.mark.parametrize("module, name", OPERATORS)
def test_invoke_takes_the_panel_for_options_left_unset(addon, module, name):  # noqa: F811 (fixture)
    cls = getattr(importlib.import_module(f"blender_addon.{module}"), name)
    panel = bpy.context.scene.heat_geodesic
    panel.m, panel.boundary, panel.robust = 3.5, "neumann", False
    op = StandIn(boundary="dirichlet")
    assert bpy.app.background  # the distance operator's invoke runs execute too
    assert cls.invoke(op, bpy.context, None) == {"FINISHED"} and op.executed
    assert op.m == 3.5 and op.robust is False  # the panel's
    assert op.boundary == "dirichlet"  # the call's
