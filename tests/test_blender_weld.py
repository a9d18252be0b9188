"""Blender measures a mesh as it is connected in Blender: no merging of coincident vertices by default (issue 32).

Blender meshes carry their topology: nothing is split at seams, and islands
that touch at a coincident vertex are separate on purpose (Suzanne's eyes
touch her head at one vertex each). heatcore's core welds exactly coincident
vertices by default (``weld=0.0``, right for STL soup and OBJ seams); the
add-on does not (``weld=None``) and offers *Merge Coincident Vertices*
(Advanced, off; ``weld=0.0`` in scripts) for meshes imported as soup. A run
that reaches almost nothing of such a soup says so and names the option.

Measured on stock Suzanne from head vertex 66 (the head's first vertex),
against exact geodesics on the head's own triangles: 3.22% mean error
merged (the eyes joined to the head through one vertex each, so measured
as triangles), 2.57% as connected in Blender (polygons).
"""

import importlib

import blender_required  # noqa: F401 (first: without bpy, the module is skipped)
import bpy
import numpy as np
import pytest
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components
from test_blender import addon, attribute, empty_scene, select_only  # noqa: F401 (fixtures)

import heatcore as hc
from heatcore.reference import exact_distance, mean_relative_error

CUBE = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], float)
CUBE_FACES = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]


def mesh_object(V, faces, name="mesh"):
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(np.asarray(V, float).tolist(), [], [list(map(int, f)) for f in faces])
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    bpy.context.view_layer.objects.active = obj
    return obj


def touching_cubes():
    """Two unit cubes, (0,0,0)-(1,1,1) and (1,1,1)-(2,2,2): they share the corner (1, 1, 1), as two vertices."""
    return mesh_object(np.vstack([CUBE, CUBE + 1.0]), CUBE_FACES + [[i + 8 for i in f] for f in CUBE_FACES],
                       "cubes")


def loop_triangles(mesh):
    mesh.calc_loop_triangles()
    tris = np.empty(3 * len(mesh.loop_triangles), dtype=np.int64)
    mesh.loop_triangles.foreach_get("vertices", tris)
    return tris.reshape(-1, 3)


def islands(V, F):
    n = len(V)
    A = sp.coo_matrix((np.ones(F.size), (F.ravel(), F[:, [1, 2, 0]].ravel())), shape=(n, n))
    return connected_components(A, directed=False)[1]


@pytest.fixture
def suzanne():
    bpy.ops.mesh.primitive_monkey_add()
    obj = bpy.context.active_object
    bpy.ops.object.select_all(action="DESELECT")
    V = np.array([v.co[:] for v in obj.data.vertices])
    F = loop_triangles(obj.data)
    label = islands(V, F)
    head = np.flatnonzero(label == np.argmax(np.bincount(label)))
    return obj, V, F, label, head


def test_suzanne_is_measured_as_connected_in_blender(addon, suzanne):  # noqa: F811
    obj, V, F, label, head = suzanne
    assert len(np.unique(label)) == 3 and len(V) - len(np.unique(V, axis=0)) == 2  # the eyes touch the head
    source = int(head[0])
    result = addon.compute_geodesic_distance(obj, sources=[source], space="LOCAL", color_attribute=None)
    eyes = label != label[source]
    assert np.isinf(result.distance[eyes]).all() and np.isfinite(result.distance[~eyes]).all()
    assert (attribute(obj.data, "geodesic_distance")[eyes] == -1.0).all()  # unreachable: -1, as everywhere
    assert not result.warnings  # polygons as they are: no "measured as triangles" note
    remap = np.full(len(V), -1)
    remap[head] = np.arange(len(head))
    exact = exact_distance(V[head], remap[F[np.isin(F[:, 0], head)]], [remap[source]])
    error = mean_relative_error(result.distance[head], exact)
    merged = addon.compute_geodesic_distance(obj, sources=[source], space="LOCAL", color_attribute=None, weld=0.0)
    merged_error = mean_relative_error(merged.distance[head], exact)
    assert np.isfinite(merged.distance).all()  # merged: the eyes hang on the head by one vertex each
    assert any("measured as triangles, not polygons" in note for note in merged.warnings)  # as before the issue
    expected = hc.HeatSolver(hc.TriangleMesh(V, F, weld=0.0)).distance([source])
    np.testing.assert_allclose(merged.distance, expected, rtol=1e-9, atol=1e-12)
    # measured 3.10% and 3.22% (2026-11-29: the polygons as heatcore triangulates them; 2.57% unmerged with
    # virtual refinement, the default until then)
    assert error < 0.033 and error <= 1.01 * merged_error, (error, merged_error)


def test_an_eye_gets_its_own_distance_only_from_a_source_on_it(addon, suzanne):  # noqa: F811
    obj, V, F, label, head = suzanne
    eye = int(np.flatnonzero(label != label[head[0]])[0])
    result = addon.compute_geodesic_distance(obj, sources=[int(head[0]), eye], color_attribute=None)
    other_eye = (label != label[head[0]]) & (label != label[eye])
    assert np.isfinite(result.distance[~other_eye]).all() and np.isinf(result.distance[other_eye]).all()
    assert result.distance[eye] == 0.0


def test_touching_cubes_are_joined_only_when_merging(addon):  # noqa: F811
    obj = touching_cubes()
    apart = addon.compute_geodesic_distance(obj, sources=[0], color_attribute=None)
    assert np.isfinite(apart.distance[:8]).all() and np.isinf(apart.distance[8:]).all()
    assert apart.distance[7] == pytest.approx(np.sqrt(5.0), rel=0.05)  # across two faces to the shared corner
    merged = addon.compute_geodesic_distance(obj, sources=[0], color_attribute=None, weld=0.0)
    assert np.isfinite(merged.distance).all()
    assert merged.distance[8] == pytest.approx(merged.distance[7])  # the two copies of the shared corner
    assert merged.distance[15] == pytest.approx(2.0 * np.sqrt(5.0), rel=0.05)  # through the shared corner
    assert not merged.cached  # the option is part of the cache key


def test_the_option_is_a_switch_in_the_panel_and_the_operator(addon):  # noqa: F811
    settings = bpy.context.scene.heat_geodesic
    prop = settings.bl_rna.properties["weld"]
    assert prop.type == "BOOLEAN" and prop.name == "Merge Coincident Vertices" and prop.default is False
    assert "weld" in importlib.import_module("blender_addon.panel").VIEW3D_PT_heat_geodesic_advanced.PROPERTIES
    assert settings.call_options()["weld"] is None
    settings.weld = True
    try:
        assert settings.call_options()["weld"] == 0.0 and settings.solver_options()["weld"] == 0.0
    finally:
        settings.weld = False
    obj = touching_cubes()
    select_only(obj, [0])
    assert bpy.ops.mesh.heat_geodesic_distance() == {"FINISHED"}  # the operator's own default: off
    assert (attribute(obj.data, "geodesic_distance")[8:] == -1.0).all()
    assert bpy.ops.mesh.heat_geodesic_distance(weld=True) == {"FINISHED"}  # in the redo panel (F9) too
    assert (attribute(obj.data, "geodesic_distance")[8:] > 1.0).all()


def test_a_soup_says_that_merging_would_join_it(addon):  # noqa: F811
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=3)
    ico = bpy.context.active_object
    V = np.array([v.co[:] for v in ico.data.vertices])
    F = loop_triangles(ico.data)
    soup = mesh_object(V[F].reshape(-1, 3), np.arange(F.size).reshape(-1, 3), "soup")  # as an STL import
    with pytest.warns(UserWarning, match="Merge Coincident Vertices"):
        result = addon.compute_geodesic_distance(soup, sources=[0], color_attribute=None)
    assert np.isfinite(result.distance).sum() == 3
    [note] = [w for w in result.warnings if "Merge Coincident Vertices" in w]
    assert "reaches 3 of 960 vertices" in note and "weld=0.0" in note
    merged = addon.compute_geodesic_distance(soup, sources=[0], color_attribute=None, weld=0.0)
    assert np.isfinite(merged.distance).all() and not merged.warnings
    # a mesh merely in touching pieces (Suzanne's eyes) gets no such note, even from a source on a small piece
    obj = touching_cubes()
    assert not addon.compute_geodesic_distance(obj, sources=[9], color_attribute=None).warnings


def test_uv_map_and_probe_follow_the_option(addon):  # noqa: F811
    obj = touching_cubes()
    up = (0.0, 0.0, 1.0)
    assert addon.geodesic_uv_map(obj, 0, unit=4.0, up=up).unreached == 8
    assert addon.geodesic_uv_map(obj, 0, unit=4.0, up=up, weld=0.0).unreached == 0
    assert "weld" in importlib.import_module("blender_addon.uv_operator").SHARED  # invoked: the panel's setting
    assert bpy.ops.mesh.heat_geodesic_uv_map(vertex=0, uv_up="VECTOR", weld=True) == {"FINISHED"}
    uv = np.array([loop.uv[:] for loop in obj.data.uv_layers["geodesic_uv"].data])
    assert not (uv == 0.0).all(axis=1).any()  # unreached corners would be at (0, 0)
    probe = addon.GeodesicProbe(obj)
    assert probe.run.settings.mesh.weld is None
    assert np.isinf(probe.move_to(0, (0.2, 0.3, 0.5))[8:]).all()
    probe.cancel()
    probe = addon.GeodesicProbe(obj, weld=0.0)
    assert np.isfinite(probe.move_to(0, (0.2, 0.3, 0.5))).all()
    probe.cancel()

