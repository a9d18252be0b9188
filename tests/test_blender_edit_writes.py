"""Blender add-on: a click in Edit Mode writes into the edit mesh and never leaves Edit Mode (issue 34).

Leaving Edit Mode to write and coming back cost two conversions of the whole
mesh (0.38-0.5 s at 504k vertices, more than the query). The outputs now go
into the edit mesh's layers (``blender_addon/edit_layers.py``). Checked: the
values are those an Object Mode click writes (bit for bit: both store
float32), the object never leaves Edit Mode (no mode switch is made), what
the user had is untouched, a weight group of that name is replaced and keeps
its lock, and one undo removes the outputs.
"""

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
    run,
    snapshot,
)
from test_blender_weights import group_weights

__all__ = ["addon", "empty_scene"]  # fixtures

OUTPUTS = ("geodesic_distance", "geodesic_distance_color", "geodesic_weight")


def _select_in_edit_mode(obj, vertex):
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="DESELECT")
    bm = bmesh.from_edit_mesh(obj.data)
    bm.verts.ensure_lookup_table()
    bm.verts[vertex].select = True
    bm.select_flush_mode()
    bmesh.update_edit_mesh(obj.data)


def _outputs(obj):
    mesh = obj.data
    return attribute(mesh, OUTPUTS[0]).copy(), attribute(mesh, OUTPUTS[1]).copy(), group_weights(obj, OUTPUTS[2])


@pytest.fixture
def mode_switches(addon, monkeypatch):
    """The objects ``adapters.object_mode`` was entered with outside Object Mode (it leaves their mode)."""
    entered, inner = [], addon.adapters.object_mode

    def counted(obj):
        if obj.mode != "OBJECT":
            entered.append(obj.name)
        return inner(obj)

    monkeypatch.setattr(addon.adapters, "object_mode", counted)
    return entered


def test_an_edit_mode_click_writes_what_an_object_mode_click_writes_without_leaving_edit_mode(addon, mode_switches):
    obj = ico_sphere(subdivisions=4)
    mesh = obj.data
    mesh.attributes.new("user_value", "FLOAT", "POINT").data.foreach_set("value", np.arange(len(mesh.vertices), dtype=np.float32))
    user = obj.vertex_groups.new(name="user_group")
    user.add([1, 2, 3], 0.25, "REPLACE")

    _select_in_edit_mode(obj, 7)
    bpy.ops.object.mode_set(mode="OBJECT")
    before = snapshot(obj)
    assert run(obj, write_weights=True, isoline_material=False) == {"FINISHED"}
    in_object_mode = _outputs(obj)
    for name in OUTPUTS[:2]:
        mesh.attributes.remove(mesh.attributes[name])
    obj.vertex_groups.remove(obj.vertex_groups[OUTPUTS[2]])
    assert mode_switches == []

    bpy.ops.object.mode_set(mode="EDIT")
    assert run(obj, write_weights=True, isoline_material=False) == {"FINISHED"}
    assert obj.mode == "EDIT" and mode_switches == []  # written in Edit Mode: no switch to Object Mode and back
    assert mesh.color_attributes.active_color_name == OUTPUTS[1]
    assert obj.vertex_groups.active.name == OUTPUTS[2]
    bpy.ops.object.mode_set(mode="OBJECT")  # the edit mesh's layers become the mesh's attributes
    in_edit_mode = _outputs(obj)
    for ours, theirs in zip(in_edit_mode, in_object_mode):
        np.testing.assert_array_equal(ours, theirs)
    assert not np.isnan(in_edit_mode[2]).any()  # every vertex a member of the weight group
    assert in_edit_mode[0][7] == 0.0 and in_edit_mode[0].max() > 1.0
    assert_same_snapshot(before, snapshot(obj), ignore=OUTPUTS)


def test_a_weight_group_of_that_name_is_replaced_in_edit_mode_and_keeps_its_lock(addon, mode_switches):
    obj = ico_sphere(subdivisions=3)
    old = obj.vertex_groups.new(name=OUTPUTS[2])
    old.add([0, 1, 2], 0.5, "REPLACE")
    old.lock_weight = True
    _select_in_edit_mode(obj, 5)
    assert run(obj, write_weights=True, isoline_material=False) == {"FINISHED"}
    assert mode_switches == [] and [g.name for g in obj.vertex_groups] == [OUTPUTS[2]]
    assert obj.vertex_groups[OUTPUTS[2]].lock_weight
    bpy.ops.object.mode_set(mode="OBJECT")
    w = group_weights(obj, OUTPUTS[2])
    assert w[5] == 1.0 and not np.isnan(w).any() and w.min() == 0.0  # the old 0.5 weights are gone


def test_one_undo_removes_what_an_edit_mode_click_wrote(addon):
    obj = ico_sphere(subdivisions=3)
    _select_in_edit_mode(obj, 5)
    bpy.ops.ed.undo_push(message="before")
    assert bpy.ops.mesh.heat_geodesic_distance(isoline_material=False) == {"FINISHED"}
    bpy.ops.ed.undo_push(message="geodesic distance")
    assert obj.data.attributes.get(OUTPUTS[0]) is not None
    bpy.ops.ed.undo()
    obj = bpy.context.active_object
    assert obj.mode == "EDIT"
    assert obj.data.attributes.get(OUTPUTS[0]) is None and obj.data.attributes.get(OUTPUTS[1]) is None
    bpy.ops.ed.redo()
    bpy.ops.object.mode_set(mode="OBJECT")
    assert attribute(bpy.context.active_object.data, OUTPUTS[0])[5] == 0.0
