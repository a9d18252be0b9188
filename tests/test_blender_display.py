"""Blender add-on: the shape the user sees, in the cases the first tests of tests/test_blender.py leave out.

Edit Mode with an active shape key, modifiers applied on a new object (Mirror
on a flat grid: exact Euclidean distances), undo of an Edit Mode run, and the
source selections that deserve a warning (a whole fresh primitive, loose
vertices).
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
    coords,
    empty_scene,
    ico_sphere,
    loop_triangles,
    select_only,
    snapshot,
)

import heatcore as hc

__all__ = ["addon", "empty_scene"]  # fixtures


def _api(addon, obj, **options):
    return addon.compute_geodesic_distance(obj, color_attribute=None, **options)


def grid(n=21, size=1.0):
    """A flat n x n grid on [0, size]^2 in the xy plane (z = 0), nothing selected."""
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=n - 1, y_subdivisions=n - 1, size=size)
    obj = bpy.context.active_object
    V = coords(obj.data)
    V[:, :2] -= V[:, :2].min(axis=0)
    obj.data.vertices.foreach_set("co", V.ravel())
    select_only(obj, [])
    return obj


def test_edit_mode_measures_the_active_shape_key_as_displayed(addon):
    obj = ico_sphere(subdivisions=4)
    obj.shape_key_add(name="Basis")
    tall = obj.shape_key_add(name="Tall")
    co = coords(obj.data) * [1.0, 1.0, 2.0]
    tall.data.foreach_set("co", co.astype(np.float32).ravel())
    tall.value = 0.25  # Object Mode shows a quarter of the key; Edit Mode shows the active key itself
    obj.active_shape_key_index = 1
    pole = int(np.argmax(co[:, 2]))
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="DESELECT")
    bm = bmesh.from_edit_mesh(obj.data)
    bm.verts.ensure_lookup_table()
    bm.verts[pole].select = True
    bmesh.update_edit_mesh(obj.data)
    result = _api(addon, obj)
    assert obj.mode == "EDIT"
    np.testing.assert_array_equal(result.sources, [pole])
    shown = co.astype(np.float32).astype(np.float64)
    np.testing.assert_allclose(result.distance, hc.geodesic_distance(shown, loop_triangles(obj.data), [pole]),
                               rtol=1e-6, atol=1e-9)
    assert result.max_distance > 1.4 * np.pi  # pole to pole on the tall shape, not the unit sphere's pi


def test_new_object_measures_the_mirrored_mesh_and_leaves_the_original_alone(addon):
    obj = grid(n=21)
    mirror = obj.modifiers.new("Mirror", "MIRROR")
    mirror.use_axis = (True, False, False)  # x -> -x: [-1, 1] x [0, 1], seam merged
    corner = int(np.argmin(np.linalg.norm(coords(obj.data) - [1.0, 0.0, 0.0], axis=1)))
    before = snapshot(obj)
    cage = _api(addon, obj, sources=[corner], attribute="d")
    far = int(np.argmin(np.linalg.norm(coords(obj.data) - [0.0, 1.0, 0.0], axis=1)))
    assert cage.skipped_modifiers == ["Mirror"] and cage.object == obj
    assert abs(cage.distance[far] - np.sqrt(2.0)) < 0.02 * np.sqrt(2.0)  # on the cage: one half only

    before = snapshot(obj)
    result = _api(addon, obj, sources=[corner], attribute="d", new_object=True)
    assert_same_snapshot(before, snapshot(obj))
    copy = result.object
    assert copy != obj and copy.name == f"{obj.name} Geodesic" and len(copy.data.vertices) == 21 * 41
    V = coords(copy.data)
    np.testing.assert_allclose(V[result.sources], [[1.0, 0.0, 0.0]], atol=1e-6)  # the selected side's corner
    exact = np.linalg.norm(V - [1.0, 0.0, 0.0], axis=1)
    d = attribute(copy.data, "d")
    np.testing.assert_allclose(d, result.distance, rtol=1e-6)
    quads = hc.PolygonMesh(V, [list(p.vertices) for p in copy.data.polygons])  # quads: measured as polygons
    np.testing.assert_allclose(d, hc.HeatSolver(quads).distance(result.sources), rtol=1e-6, atol=1e-9)
    assert np.abs(d - exact).max() < 0.03 * exact.max()  # the mirrored half too: up to 2.24 away
    assert d[np.argmin(np.linalg.norm(V - [-1.0, 0.0, 0.0], axis=1))] > 1.9  # the mirrored corner is not a source

    mirror.use_axis = (True, True, False)  # a re-run replaces the copy's mesh: one copy, 41 x 41 vertices
    again = _api(addon, obj, sources=[corner], attribute="d", new_object=True)
    assert again.object == copy and len(copy.data.vertices) == 41 * 41
    assert sum(o.name.startswith(obj.name) for o in bpy.data.objects) == 2
    with pytest.raises(addon.AddonError, match="shape='EVALUATED'"):
        _api(addon, obj, sources=[corner], new_object=True, shape="BASIS")


def test_new_object_maps_sources_through_subdivision(addon):
    obj = ico_sphere(subdivisions=2)
    obj.modifiers.new("Subdivision", "SUBSURF").levels = 2
    result = _api(addon, obj, sources=[0], new_object=True, space="LOCAL")
    V = coords(result.object.data)
    assert len(V) > 10 * len(obj.data.vertices)
    assert np.linalg.norm(V[result.sources[0]] - coords(obj.data)[0]) < 0.1  # vertex 0's child, moved inwards
    quads = hc.PolygonMesh(V, [list(p.vertices) for p in result.object.data.polygons])  # subdivided: quads
    np.testing.assert_allclose(result.distance, hc.HeatSolver(quads).distance(result.sources), rtol=1e-6)


def test_edit_mode_undo_restores_the_active_color(addon):
    obj = ico_sphere(subdivisions=2)
    colors = obj.data.color_attributes
    colors.new("user_colors", "BYTE_COLOR", "CORNER")
    colors.active_color = colors["user_colors"]
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="DESELECT")
    bm = bmesh.from_edit_mesh(obj.data)
    bm.verts.ensure_lookup_table()
    bm.verts[0].select = True
    bmesh.update_edit_mesh(obj.data)
    bpy.ops.ed.undo_push(message="before")
    assert bpy.ops.mesh.heat_geodesic_distance() == {"FINISHED"}
    bpy.ops.ed.undo_push(message="geodesic distance")
    assert obj.data.color_attributes.active_color_name == "geodesic_distance_color"
    bpy.ops.ed.undo()
    colors = bpy.context.active_object.data.color_attributes
    assert colors.get("geodesic_distance_color") is None  # the run is undone ...
    assert colors.active_color_name == "user_colors" and colors.active_color.name == "user_colors"  # ... and active
    assert colors.render_color_index == colors.active_color_index


def test_whole_fresh_primitive_selected_warns(addon):
    obj = ico_sphere(subdivisions=2)  # a new primitive: every vertex selected
    with pytest.warns(UserWarning, match="all 42 vertices .* are selected"):
        result = _api(addon, obj)
    assert result.max_distance == 0.0 and "Edit Mode" in result.warnings[0]


def test_loose_source_vertices_are_dropped_with_a_warning(addon):
    obj = ico_sphere(subdivisions=3)  # 162 vertices
    obj.data.vertices.add(2)  # two loose vertices: 162 and 163
    obj.data.vertices[162].co = (3.0, 0.0, 0.0)
    obj.data.update()
    with pytest.warns(UserWarning, match="2 of the sources are loose vertices .*162, 163.*from the other 1"):
        result = _api(addon, obj, sources=[5, 162, 163])
    np.testing.assert_array_equal(result.sources, [5])
    d = _api(addon, obj, sources=[5]).distance
    np.testing.assert_array_equal(result.distance, d)
    select_only(obj, [162])
    before = snapshot(obj)
    with pytest.raises(addon.AddonError, match="only vertices no face uses .*162"):
        _api(addon, obj)
    assert_same_snapshot(before, snapshot(obj))
