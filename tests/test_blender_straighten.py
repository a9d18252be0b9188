"""*Straighten Edges* (``mesh.heat_straighten_edges``, ``straighten_edges``) with the real ``bpy`` (issue 36).

An L of edges on a flat grid becomes the straight diagonal between its ends (with *Select Path Edges*, a
staircase along it replaces the L); a square-wave loop of edges around a cylinder becomes its waist (the
32-gon's perimeter); no edge is an error; one undo step.
"""

import blender_required  # noqa: F401 (first: without bpy, the module is skipped)
import bmesh
import bpy
import numpy as np
import pytest
from test_blender import addon, empty_scene  # noqa: F401 (fixtures)
from test_blender_path import curve_points


@pytest.fixture(autouse=True)
def keep_select_mode():
    """These tests select edges in Edge select mode: the scene's mode is put back (other tests draw menus by it)."""
    before = bpy.context.scene.tool_settings.mesh_select_mode[:]
    yield
    bpy.context.scene.tool_settings.mesh_select_mode = before  # the scene anew: an undo replaces it


def select_edges(obj, pairs):
    bpy.context.view_layer.objects.active = obj
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_mode(type="EDGE")
    bpy.ops.mesh.select_all(action="DESELECT")
    bm = bmesh.from_edit_mesh(obj.data)
    for e in bm.edges:
        if tuple(sorted(v.index for v in e.verts)) in pairs:
            e.select_set(True)
    bmesh.update_edit_mesh(obj.data)


def grid(n=11):
    """A flat n x n grid of quads (size 2) and its vertex index at each lattice point ``(i, j)``."""
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=n - 1, y_subdivisions=n - 1, size=2.0)
    obj = bpy.context.active_object
    co = np.array([v.co[:] for v in obj.data.vertices])
    step = 2.0 / (n - 1)
    return obj, co, {(round((x + 1) / step), round((y + 1) / step)): i for i, (x, y, _) in enumerate(co)}


def edges_of(vertices):
    return {tuple(sorted(p)) for p in zip(vertices[:-1], vertices[1:])}


def test_an_l_of_edges_on_a_grid_becomes_the_straight_diagonal(addon):
    n = 11
    obj, co, index = grid(n)
    corner = [index[i, 0] for i in range(n)] + [index[n - 1, j] for j in range(1, n)]  # along the bottom, then up
    pairs = edges_of(corner)
    select_edges(obj, pairs)
    assert bpy.ops.mesh.heat_straighten_edges(path_edges=True) == {"FINISHED"}
    bpy.ops.object.mode_set(mode="OBJECT")
    selected = np.zeros(len(obj.data.edges), dtype=bool)
    obj.data.edges.foreach_get("select", selected)
    E = np.sort(np.array([e.vertices[:] for e in obj.data.edges]), axis=1)
    chosen = E[selected]
    assert not any(tuple(e) in pairs for e in chosen.tolist())  # the L gave way to a staircase along the diagonal
    assert len(chosen) == 2 * (n - 1) and np.abs(co[chosen.ravel(), 0] - co[chosen.ravel(), 1]).max() < 0.2 + 1e-6  # float32
    result = addon.straighten_edges(obj, edges=list(pairs))
    assert result.closed == [False]
    np.testing.assert_allclose(result.before[0], 4.0, rtol=1e-6)  # two sides of 2
    np.testing.assert_allclose(result.lengths[0], 2 * np.sqrt(2), rtol=1e-6)
    P = curve_points(result.curve)
    np.testing.assert_allclose(P[[0, -1]], co[[corner[0], corner[-1]]], atol=1e-6)


def cylinder(around=32, rings=9, radius=1.0):
    """An open cylinder of quads (radius 1, z from -1 to 1) and its vertex grid ``[ring, k]``."""
    t = 2 * np.pi * np.arange(around) / around
    z = np.linspace(-1, 1, rings)
    V = [(radius * np.cos(a), radius * np.sin(a), h) for h in z for a in t]
    grid_ = np.arange(rings * around).reshape(rings, around)
    faces = [(grid_[r, k], grid_[r, (k + 1) % around], grid_[r + 1, (k + 1) % around], grid_[r + 1, k])
             for r in range(rings - 1) for k in range(around)]
    bm = bmesh.new()  # not Mesh.from_pydata: in bpy 5.0 its selection layers do not fit the edges it makes
    verts = [bm.verts.new(v) for v in V]
    for f in faces:
        bm.faces.new([verts[int(i)] for i in f])
    mesh = bpy.data.meshes.new("cylinder")
    bm.to_mesh(mesh)
    bm.free()
    obj = bpy.data.objects.new("cylinder", mesh)
    bpy.context.collection.objects.link(obj)
    return obj, grid_


def test_square_wave_loop_around_a_cylinder_becomes_its_waist(addon):
    obj, ring = cylinder()
    low, high = ring[4], ring[5]  # z = 0 and z = 0.25
    wave = []
    for k in range(0, 32, 2):  # up, across, down, across: a square wave round the cylinder
        wave += [low[k], high[k], high[k + 1], low[k + 1]]
    pairs = edges_of(wave + [wave[0]])
    result = addon.straighten_edges(obj, edges=list(pairs), space="LOCAL", select_edges=True)
    assert result.closed == [True]
    E = np.sort(np.array([e.vertices[:] for e in obj.data.edges]), axis=1)
    ring = {tuple(e) for e in E[result.edges].tolist()}
    z = np.array([v.co.z for v in obj.data.vertices])
    assert len(ring) == 32 and np.ptp(z[E[result.edges].ravel()]) < 1e-6  # one ring of the cylinder, whole
    waist = 32 * 2 * np.sin(np.pi / 32)  # the 32-gon's perimeter: the polyhedral cylinder's shortest loop
    np.testing.assert_allclose(result.lengths[0], waist, rtol=0.005)
    assert result.before[0] > 1.5 * waist


def test_no_edge_is_refused_and_undo_removes_the_curve(addon):
    obj, co, index = grid(6)
    pairs = edges_of([index[i, 0] for i in range(6)] + [index[5, j] for j in range(1, 6)])
    select_edges(obj, set())
    with pytest.raises(addon.AddonError, match="no edge selected"):
        addon.straighten_edges(obj)
    select_edges(obj, pairs)
    bpy.ops.ed.undo_push(message="before")
    assert bpy.ops.mesh.heat_straighten_edges() == {"FINISHED"}
    bpy.ops.ed.undo_push(message="straightened")
    assert any(o.type == "CURVE" for o in bpy.data.objects)
    bpy.ops.ed.undo()
    assert not any(o.type == "CURVE" for o in bpy.data.objects)
