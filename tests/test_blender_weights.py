"""Blender add-on: vertex-group weights for modifiers, and output names that never collide.

Weights against heatcore's own distance (float32 storage precision) and
against the analytic great-circle distance on an ico sphere (within what
heatcore's distance error allows, vertex by vertex) for every falloff;
invert; 0 on a part no source reaches; every vertex a member; the active
group; re-runs replace the weights (a Displace modifier keeps its group);
collisions between the weight group, attributes and vertex groups refused
before anything is modified.
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
    select_only,
    snapshot,
)

import heatcore as hc
from heatcore.weights import distance_weights

__all__ = ["addon", "empty_scene"]  # fixtures

RADIUS = 1.5  # sphere radius
#: Largest slope of each falloff curve on [0, 1] (ROOT has none: |sqrt(a) - sqrt(b)| <= sqrt(|a - b|) instead).
SLOPE = {"LINEAR": 1.0, "SMOOTH": 1.5, "SHARP": 2.0}


def coords(obj):
    co = np.empty(3 * len(obj.data.vertices))
    obj.data.vertices.foreach_get("co", co)
    return co.reshape(-1, 3)


def group_weights(obj, name):
    """Weight of every vertex in group ``name`` (NaN where a vertex is not a member)."""
    index = obj.vertex_groups[name].index
    out = np.full(len(obj.data.vertices), np.nan)
    for v in obj.data.vertices:
        for element in v.groups:
            if element.group == index:
                out[v.index] = element.weight
    return out


def great_circle(V, source, radius):
    cos = V @ V[source] / (np.linalg.norm(V, axis=1) * np.linalg.norm(V[source]))
    return radius * np.arccos(np.clip(cos, -1.0, 1.0))


def api(addon, obj, **options):
    return addon.compute_geodesic_distance(obj, **options)


@pytest.fixture
def sphere():
    obj = ico_sphere(subdivisions=5, radius=RADIUS)  # 2,562 vertices (refined twice inside heatcore)
    pole = int(np.argmax(coords(obj)[:, 2]))
    return obj, pole


@pytest.mark.parametrize("invert", [False, True])
def test_each_falloff_against_heatcore_and_the_great_circle(addon, sphere, invert):
    obj, pole = sphere
    V = coords(obj)
    exact = great_circle(V, pole, RADIUS)
    radius = 2.0  # reaches 76 degrees down from the pole
    for falloff in ("LINEAR", "SMOOTH", "SHARP", "ROOT"):
        result = api(addon, obj, sources=[pole], weight_group="w", weight_radius=radius,
                     weight_falloff=falloff, weight_invert=invert)
        w = group_weights(obj, "w")
        assert not np.isnan(w).any(), "every vertex is a member"
        # the weights are heatcore.weights of the add-on's own distance, to float32 precision
        np.testing.assert_allclose(w, distance_weights(result.distance, radius, falloff, invert), rtol=0, atol=1e-7)
        assert w[pole] == (0.0 if invert else 1.0)
        assert (w[result.distance >= radius] == (1.0 if invert else 0.0)).all()
        # ... and the analytic weights, as far as heatcore's distance error allows at each vertex
        d_error = np.abs(result.distance - exact) / radius
        bound = np.sqrt(d_error) if falloff == "ROOT" else SLOPE[falloff] * d_error
        w_exact = distance_weights(exact, radius, falloff, invert)
        assert (np.abs(w - w_exact) <= bound + 1e-6).all(), falloff
        inside = exact < 0.9 * radius
        assert np.abs(w - w_exact)[inside].mean() < 0.01, falloff
        assert result.cached or falloff == "LINEAR"  # the weight options do not rebuild the solver


def test_default_radius_is_the_largest_distance_and_the_group_becomes_active(addon, sphere):
    obj, pole = sphere
    user = obj.vertex_groups.new(name="pin")
    user.add([0, 1, 2], 0.5, "REPLACE")
    mesh = obj.data
    mesh.attributes.new("temperature", "FLOAT", "POINT")
    mesh.attributes.active = mesh.attributes["temperature"]
    select_only(obj, [pole])
    with bpy.context.temp_override(active_object=obj, object=obj):
        assert bpy.ops.mesh.heat_geodesic_distance(write_weights=True) == {"FINISHED"}
    d = attribute(mesh, "geodesic_distance")
    w = group_weights(obj, "geodesic_weight")
    np.testing.assert_allclose(w, 1.0 - d / d.max(), rtol=0, atol=1e-6)  # radius 0 in Blender: the largest
    assert obj.vertex_groups.active.name == "geodesic_weight"
    assert mesh.attributes.active.name == "temperature"  # the user's active attribute is kept
    assert mesh.attributes.get("geodesic_weight") is None and obj.vertex_groups.get("geodesic_distance") is None
    assert group_weights(obj, "pin")[[0, 1, 2]].tolist() == [0.5] * 3

    settings = bpy.context.scene.heat_geodesic  # the panel's settings: radius 0 stands for "the largest"
    assert (settings.weight_radius, settings.weight_falloff, settings.weight_invert) == (0.0, "LINEAR", False)
    assert settings.weight_group == "geodesic_weight" and not settings.write_weights
    settings.write_weights, settings.weight_falloff, settings.weight_invert = True, "ROOT", True
    call = settings.call_options()
    assert (call["weight_group"], call["weight_radius"], call["weight_falloff"], call["weight_invert"]) == (
        "geodesic_weight", None, "ROOT", True)
    settings.weight_radius = 2.5
    assert settings.call_options()["weight_radius"] == 2.5

    bpy.ops.object.mode_set(mode="EDIT")  # a run from Edit Mode with other weight options
    bpy.ops.mesh.select_all(action="DESELECT")
    bm = bmesh.from_edit_mesh(mesh)
    bm.verts.ensure_lookup_table()
    bm.verts[pole].select_set(True)
    bmesh.update_edit_mesh(mesh)
    with bpy.context.temp_override(active_object=obj, object=obj):
        assert bpy.ops.mesh.heat_geodesic_distance(write_weights=True, weight_radius=1.0,
                                                   weight_falloff="SHARP") == {"FINISHED"}
    assert obj.mode == "EDIT"
    bpy.ops.object.mode_set(mode="OBJECT")
    w = group_weights(obj, "geodesic_weight")
    np.testing.assert_allclose(w, np.clip(1.0 - d / 1.0, 0.0, 1.0) ** 2, rtol=0, atol=1e-6)


def test_unreachable_part_gets_weight_zero(addon):
    a = ico_sphere(subdivisions=3, radius=1.0)
    b = ico_sphere(subdivisions=3, radius=1.0)
    b.location = (4.0, 0.0, 0.0)
    with bpy.context.temp_override(active_object=a, selected_editable_objects=[a, b]):
        bpy.ops.object.join()
    obj = bpy.context.view_layer.objects.active = a
    n = len(obj.data.vertices)
    far_part = coords(obj)[:, 0] > 2.0
    assert far_part.sum() == n // 2
    for invert in (False, True):
        result = api(addon, obj, sources=[0], weight_group="w", weight_invert=invert, refine=0)
        w = group_weights(obj, "w")
        assert np.isinf(result.distance[far_part]).all() and np.isfinite(result.distance[~far_part]).all()
        assert not np.isnan(w).any(), "unreachable vertices are members, with weight 0"
        assert (w[far_part] == 0.0).all()
        np.testing.assert_allclose(w[~far_part], distance_weights(result.distance[~far_part], invert=invert),
                                   rtol=0, atol=1e-7)


def test_rerun_replaces_the_weights_and_the_modifier_keeps_its_group(addon, sphere):
    obj, pole = sphere
    south = int(np.argmin(coords(obj)[:, 2]))
    api(addon, obj, sources=[pole], weight_group="w", weight_radius=1.0)
    displace = obj.modifiers.new("Displace", "DISPLACE")
    displace.vertex_group = "w"
    obj.vertex_groups["w"].lock_weight = True
    obj.vertex_groups.new(name="after")  # a user group made after ours
    result = api(addon, obj, sources=[south], weight_group="w", weight_radius=2.0, weight_falloff="SMOOTH")
    w = group_weights(obj, "w")
    np.testing.assert_allclose(w, distance_weights(result.distance, 2.0, "SMOOTH"), rtol=0, atol=1e-7)
    assert w[south] == 1.0 and w[pole] == 0.0
    assert [g.name for g in obj.vertex_groups].count("w") == 1 and "after" in obj.vertex_groups
    assert displace.vertex_group == "w" and obj.vertex_groups["w"].lock_weight
    assert obj.vertex_groups.active.name == "w"


def test_fallback_writer_gives_the_same_group(addon, sphere, monkeypatch):
    obj, pole = sphere
    adapters = __import__("sys").modules["blender_addon.adapters"]
    weights = np.linspace(0.0, 1.0, len(obj.data.vertices)) ** 2
    fast = group_weights(adapters.write_vertex_group(obj, "fast", weights).id_data, "fast")
    monkeypatch.setattr(adapters, "_convert_to_vertex_group", lambda: False)  # as if Convert could not run
    adapters.write_vertex_group(obj, "slow", weights)
    np.testing.assert_array_equal(group_weights(obj, "slow"), fast)
    np.testing.assert_array_equal(fast, weights.astype(np.float32))
    assert obj.data.attributes.get("slow") is None and obj.data.attributes.get("fast") is None


COLLISIONS = [
    ({"weight_group": "temperature"}, "has an attribute 'temperature'"),
    ({"weight_group": "UVMap"}, "has an attribute 'UVMap'"),
    ({"weight_group": "geodesic_distance"}, "weight group and the distance attribute are both named"),
    ({"weight_group": "c", "color_attribute": "c"}, "weight group and the color attribute are both named"),
    ({"weight_group": "pin", "vertex_group": "pin", "sources": None}, "is the source group"),
    ({"weight_group": ""}, None),  # empty: no weights (not an error)
    ({"attribute": "pin"}, "has a vertex group 'pin'"),
    ({"color_attribute": "pin"}, "has a vertex group 'pin'"),
    ({"attribute": "x", "color_attribute": "x"}, "both named 'x'"),
    ({"weight_group": "g" * 64}, "at most 63 bytes"),
]


@pytest.mark.parametrize(("options", "message"), COLLISIONS)
def test_colliding_names_are_refused_before_anything_changes(addon, options, message):
    obj = ico_sphere(subdivisions=2)
    mesh = obj.data
    mesh.attributes.new("temperature", "FLOAT", "POINT").data.foreach_set("value", np.arange(len(mesh.vertices)))
    obj.vertex_groups.new(name="pin").add([0, 1], 1.0, "REPLACE")
    options = {"sources": [3], "refine": 0, **options}
    before = snapshot(obj)
    if message is None:
        api(addon, obj, **options)
        assert [g.name for g in obj.vertex_groups] == ["pin"]
        return
    with pytest.raises(addon.AddonError, match=message):
        api(addon, obj, **options)
    assert_same_snapshot(before, snapshot(obj))
    assert [g.name for g in obj.vertex_groups] == ["pin"]


def test_operator_refuses_a_colliding_weight_group_in_edit_mode(addon):
    obj = ico_sphere(subdivisions=2)
    obj.data.attributes.new("temperature", "FLOAT", "POINT")
    select_only(obj, [0])
    before = snapshot(obj)
    bpy.ops.object.mode_set(mode="EDIT")
    with bpy.context.temp_override(active_object=obj, object=obj), \
            pytest.raises(RuntimeError, match="has an attribute 'temperature'"):
        bpy.ops.mesh.heat_geodesic_distance(write_weights=True, weight_group="temperature")
    assert obj.mode == "EDIT" and len(obj.vertex_groups) == 0
    bpy.ops.object.mode_set(mode="OBJECT")
    # (Edit Mode itself flushes the fresh primitive's face selection to every vertex)
    assert_same_snapshot(before, snapshot(obj), ignore=("selection",))


@pytest.mark.parametrize(("options", "error"), [
    ({"weight_radius": -1.0}, "weight_radius must be a positive number"),
    ({"weight_radius": 0.0}, "weight_radius must be a positive number"),
    ({"weight_falloff": "SPHERE"}, "weight_falloff must be one of LINEAR, SMOOTH, SHARP, ROOT"),
    ({"weight_invert": "yes"}, "weight_invert must be True or False"),
])
def test_bad_weight_options_are_refused_before_anything_changes(addon, options, error):
    obj = ico_sphere(subdivisions=2)
    before = snapshot(obj)
    with pytest.raises(hc.InvalidOptionError, match=error):
        api(addon, obj, sources=[0], weight_group="w", refine=0, **options)
    assert_same_snapshot(before, snapshot(obj))
    assert len(obj.vertex_groups) == 0


def test_edit_mode_clicks_reuse_the_solver_until_an_edge_is_rotated(addon):
    """The cache key holds the topology, read in Edit Mode too: an edge rotation (same positions, same
    counts) makes a new solver, whose distances are heatcore's on the new triangles."""
    obj = ico_sphere(subdivisions=3)
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="DESELECT")  # (deselecting vertices through bmesh leaves faces selected)
    bm = bmesh.from_edit_mesh(obj.data)
    bm.verts.ensure_lookup_table()
    bm.verts[0].select_set(True)
    bmesh.update_edit_mesh(obj.data)
    first = api(addon, obj, refine=0, color_attribute=None)
    again = api(addon, obj, refine=0, color_attribute=None)
    assert not first.cached and again.cached and obj.mode == "EDIT"
    np.testing.assert_array_equal(first.sources, [0])
    bm = bmesh.from_edit_mesh(obj.data)
    far = max(bm.edges, key=lambda e: min(v.co.z for v in e.verts))  # an edge near the south pole
    bmesh.ops.rotate_edges(bm, edges=[far], use_ccw=True)
    bmesh.update_edit_mesh(obj.data)
    rotated = api(addon, obj, refine=0, color_attribute=None)
    assert not rotated.cached
    bpy.ops.object.mode_set(mode="OBJECT")
    V = coords(obj)
    obj.data.calc_loop_triangles()
    F = np.array([t.vertices[:] for t in obj.data.loop_triangles])
    expected = hc.HeatSolver(hc.TriangleMesh(V, F, refine=0)).distance([0])
    np.testing.assert_allclose(rotated.distance, expected, rtol=1e-9, atol=1e-12)
    assert not np.allclose(rotated.distance, first.distance)
