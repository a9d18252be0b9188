"""*Signed Distance from Edges* (``mesh.heat_signed_distance``, ``signed_distance_from_edges``) with the real ``bpy``.

On a flat grid (scaled and moved, measured in world space) a square loop of selected edges gives the signed
distance to the square: positive inside, exact up to the heat method's error. Then: selected faces mark the
inside, the weights, no edge, other attributes untouched, Edit Mode kept, one undo step.
"""

import blender_required  # noqa: F401 (first: without bpy, the module is skipped)
import bmesh
import bpy
import numpy as np
import pytest
from test_blender import addon, assert_same_snapshot, empty_scene, snapshot  # noqa: F401 (fixtures)

from heatcore import weights as hc_weights

HALF = 0.5  # the square's half side, in the grid's own coordinates (the grid spans -1..1)
SCALE = 2.0


@pytest.fixture(autouse=True)
def keep_select_mode():
    """These tests select edges in Edge select mode: the scene's mode is put back (other tests draw menus by it)."""
    before = bpy.context.scene.tool_settings.mesh_select_mode[:]
    yield
    bpy.context.scene.tool_settings.mesh_select_mode = before  # the scene anew: an undo replaces it


def grid(n=21):
    """A flat grid of ``n`` x ``n`` vertices (spacing 2 / (n - 1)), scaled by SCALE and moved."""
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=n - 1, y_subdivisions=n - 1, size=2.0)  # n - 1 cuts
    obj = bpy.context.active_object
    obj.scale = (SCALE, SCALE, SCALE)
    obj.location = (1.0, -0.5, 0.3)
    bpy.context.view_layer.update()
    return obj


def local(obj):
    co = np.empty(3 * len(obj.data.vertices))
    obj.data.vertices.foreach_get("co", co)
    return co.reshape(-1, 3)


def square_distance(X):
    """Signed distance to the square |x|, |y| <= HALF (positive inside), in world units."""
    qx, qy = np.abs(X[:, 0]) - HALF, np.abs(X[:, 1]) - HALF
    outside = np.hypot(np.maximum(qx, 0), np.maximum(qy, 0))
    inside = np.minimum(np.maximum(qx, qy), 0)
    return -(outside + inside) * SCALE


def select_square(obj, faces=None):
    """In Edit Mode: select the edges of the square's boundary (and the faces ``"inside"``/``"outside"``)."""
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_mode(type="EDGE")
    bpy.ops.mesh.select_all(action="DESELECT")
    bm = bmesh.from_edit_mesh(obj.data)
    on = lambda v: max(abs(v.co.x), abs(v.co.y)) == pytest.approx(HALF)
    for e in bm.edges:
        a, b = e.verts
        if on(a) and on(b) and (a.co.x == pytest.approx(b.co.x) or a.co.y == pytest.approx(b.co.y)):
            e.select = True
    if faces:
        for f in bm.faces:
            c = f.calc_center_median()
            if (max(abs(c.x), abs(c.y)) < HALF) == (faces == "inside"):
                f.select = True
    bmesh.update_edit_mesh(obj.data)


def attribute(mesh, name):
    out = np.empty(len(mesh.vertices))
    mesh.attributes[name].data.foreach_get("value", out)
    return out


def test_square_loop_on_a_grid_is_the_signed_distance_to_the_square(addon):
    obj = grid()
    X = local(obj)
    other = obj.data.attributes.new("mine", "FLOAT", "POINT")
    other.data.foreach_set("value", np.arange(len(X), dtype=np.float32))
    select_square(obj)
    bpy.ops.object.mode_set(mode="OBJECT")
    before = snapshot(obj)
    bpy.ops.object.mode_set(mode="EDIT")
    assert bpy.ops.mesh.heat_signed_distance() == {"FINISHED"}
    assert obj.mode == "EDIT"
    bpy.ops.object.mode_set(mode="OBJECT")
    assert_same_snapshot(before, snapshot(obj), ignore=("signed_distance", "signed_distance_color"))
    phi, exact = attribute(obj.data, "signed_distance"), square_distance(X)
    assert np.abs(phi - exact).mean() < 0.02 * SCALE  # the smaller side: the square is positive
    off = np.abs(exact) > 0.15 * SCALE
    assert (np.sign(phi[off]) == np.sign(exact[off])).all()
    colors = np.empty(4 * len(X))
    obj.data.attributes["signed_distance_color"].data.foreach_get("color", colors)
    colors = colors.reshape(-1, 4)
    centre, corner = np.argmin(np.abs(X).sum(axis=1)), np.argmax(np.abs(X).sum(axis=1))
    assert colors[centre, 0] > colors[centre, 2] and colors[corner, 2] > colors[corner, 0]


def test_selected_faces_mark_the_inside_and_weights_follow(addon):
    obj = grid()
    X = local(obj)
    select_square(obj, faces="outside")
    result = addon.signed_distance_from_edges(obj, weight_group="inside", weight_band=0.2)
    assert result.curves == 1 and result.unreached == 0
    exact = -square_distance(X)  # the selected outside is now positive
    assert np.abs(result.distance - exact).mean() < 0.02 * SCALE
    bpy.ops.object.mode_set(mode="OBJECT")
    group = obj.vertex_groups["inside"].index
    w = np.array([next((g.weight for g in v.groups if g.group == group), 0.0) for v in obj.data.vertices])
    np.testing.assert_allclose(w, hc_weights.signed_weights(result.distance, 0.2), atol=1e-6)
    assert w[np.argmax(np.abs(X).sum(axis=1))] == 1.0 and w[np.argmin(np.abs(X).sum(axis=1))] == 0.0


def test_no_edge_or_a_taken_name_changes_nothing(addon):
    obj = grid(n=9)
    obj.data.attributes.new("taken", "INT", "POINT")
    for elements in (obj.data.vertices, obj.data.edges, obj.data.polygons):
        elements.foreach_set("select", np.zeros(len(elements), dtype=bool))
    before = snapshot(obj)
    with pytest.raises(addon.AddonError, match="no edge selected"):
        addon.signed_distance_from_edges(obj)
    select_square(obj)
    with pytest.raises(addon.AddonError):
        addon.signed_distance_from_edges(obj, attribute="taken")
    with pytest.raises(addon.AddonError, match="options"):
        addon.signed_distance_from_edges(obj, accuracy="high")
    bpy.ops.mesh.select_all(action="DESELECT")
    bpy.ops.object.mode_set(mode="OBJECT")
    assert_same_snapshot(before, snapshot(obj))


def test_one_undo_step(addon):
    obj = grid(n=9)
    select_square(obj)
    bpy.ops.ed.undo_push(message="before")
    assert bpy.ops.mesh.heat_signed_distance(write_weights=True) == {"FINISHED"}
    bpy.ops.ed.undo_push(message="signed")
    bpy.ops.ed.undo()
    obj = bpy.context.active_object
    bpy.ops.object.mode_set(mode="OBJECT")
    assert "signed_distance" not in obj.data.attributes and "signed_inside" not in obj.vertex_groups
