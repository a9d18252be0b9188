"""*Geodesic Path* through waypoints (issue 36): vertices clicked one by one, visited in that order, closed or not."""

import blender_required  # noqa: F401 (first: without bpy, the module is skipped)
import bmesh
import bpy
import numpy as np
import pytest
from test_blender import addon, empty_scene, ico_sphere  # noqa: F401 (fixtures)
from test_blender_path import curve_points, path_operator, world_mesh

import heatcore as hc


def click(obj, vertices, box=()):
    """Edit Mode with ``vertices`` shift-clicked in order (in the selection history) and ``box`` selected without."""
    bpy.context.view_layer.objects.active = obj
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="DESELECT")
    bm = bmesh.from_edit_mesh(obj.data)
    bm.verts.ensure_lookup_table()
    bm.select_history.clear()
    for i in vertices:
        bm.verts[i].select_set(True)
        bm.select_history.add(bm.verts[i])
    for i in box:
        bm.verts[i].select_set(True)
    bmesh.update_edit_mesh(obj.data)


def waypoints_of(V):
    """Three vertices far apart on a sphere: the top, and two on the equator a quarter turn apart."""
    return [int(np.argmax(V[:, 2])), int(np.argmax(V[:, 0])), int(np.argmax(V[:, 1]))]


def test_clicked_vertices_are_visited_in_order(addon):
    obj = ico_sphere(4)
    V, F = world_mesh(obj)
    stops = waypoints_of(V)
    click(obj, stops)
    assert path_operator(obj) == {"FINISHED"}
    result = addon.geodesic_path(obj)  # the same selection, through the script API
    expected = hc.HeatSolver(hc.TriangleMesh(V, F)).geodesic_path(points=stops)
    assert result.waypoints == stops and result.source == stops[0] and result.target == stops[-1]
    np.testing.assert_allclose(result.leg_lengths, expected.leg_lengths, rtol=1e-6)
    np.testing.assert_allclose(result.length, expected.length, rtol=1e-6)
    P = curve_points(result.curve)
    np.testing.assert_allclose(P[0], V[stops[0]], atol=1e-6)
    np.testing.assert_allclose(P[-1], V[stops[-1]], atol=1e-6)
    assert min(np.linalg.norm(P - V[stops[1]], axis=1)) < 1e-6  # through the middle one


def test_closed_loop_returns_to_the_first(addon):
    obj = ico_sphere(4)
    V, F = world_mesh(obj)
    stops = waypoints_of(V)
    click(obj, stops)
    assert path_operator(obj, closed=True) == {"FINISHED"}
    result = addon.geodesic_path(obj, closed=True)
    assert len(result.leg_lengths) == 3 and result.target == stops[0]
    # an octant's three sides on the unit sphere: each a quarter great circle (the icosphere's is a little shorter)
    np.testing.assert_allclose(result.leg_lengths, np.pi / 2, rtol=0.01)
    P = curve_points(result.curve)
    np.testing.assert_allclose(P[0], P[-1], atol=1e-6)


def test_selected_edges_follow_every_leg(addon):
    obj = ico_sphere(3)
    V, _ = world_mesh(obj)
    stops = waypoints_of(V)
    result = addon.geodesic_path(obj, waypoints=stops, select_edges=True)
    E = np.array([e.vertices[:] for e in obj.data.edges])[result.edges]
    assert set(stops) <= set(E.ravel().tolist())
    selected = np.zeros(len(obj.data.edges), dtype=bool)
    obj.data.edges.foreach_get("select", selected)
    assert selected[result.edges].all()


def test_waypoints_not_clicked_one_by_one_are_refused(addon):
    obj = ico_sphere(3)
    V, _ = world_mesh(obj)
    stops = waypoints_of(V)
    click(obj, stops[:2], box=stops[2:])
    with pytest.raises(addon.AddonError, match="one by one"):
        addon.geodesic_path(obj)
    with pytest.raises(addon.AddonError, match="not both"):
        addon.geodesic_path(obj, 0, 5, waypoints=stops)
