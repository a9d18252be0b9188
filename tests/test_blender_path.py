"""The *Geodesic Path* operator and ``geodesic_path`` (real ``bpy``): a curve object on the shape the user sees."""

import blender_required  # noqa: F401 (first: without bpy, the module is skipped)
import bmesh
import bpy
import numpy as np
import pytest
from test_blender import addon, assert_same_snapshot, empty_scene, ico_sphere, snapshot  # noqa: F401 (fixtures)

import heatcore as hc

MARKER = "heat_geodesic_curve_of"


def curve_points(curve):
    """World-space points of the curve object's only spline."""
    (spline,) = curve.data.splines
    co = np.empty(4 * len(spline.points))
    spline.points.foreach_get("co", co)
    M = np.array(curve.matrix_world)
    return co.reshape(-1, 4)[:, :3] @ M[:3, :3].T + M[:3, 3]


def world_mesh(obj):
    """World positions and triangles of the displayed shape (read here independently of the add-on)."""
    ev = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = ev.to_mesh()
    V = np.array([v.co for v in mesh.vertices], dtype=np.float64)
    mesh.calc_loop_triangles()
    F = np.array([t.vertices[:] for t in mesh.loop_triangles])
    ev.to_mesh_clear()
    M = np.array(obj.matrix_world)
    return V @ M[:3, :3].T + M[:3, 3], F


def off_surface(P, faces, V, F):
    """For each segment ``k`` (in face ``faces[k]``), how far its two ends are from that triangle."""
    worst = 0.0
    for k, f in enumerate(faces):
        A, B, C = V[F[f]]
        for X in (P[k], P[k + 1]):
            M = np.column_stack([B - A, C - A])
            uv, *_ = np.linalg.lstsq(M, X - A, rcond=None)
            inside = min(uv[0], uv[1], 1 - uv.sum()) >= -1e-6
            worst = max(worst, np.linalg.norm(A + M @ uv - X) if inside else np.inf)
    return worst


def select_ends(obj, source, target):
    """Edit Mode with ``target`` then ``source`` selected (the source active)."""
    bpy.context.view_layer.objects.active = obj
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="DESELECT")
    bm = bmesh.from_edit_mesh(obj.data)
    bm.verts.ensure_lookup_table()
    for i in (target, source):
        bm.verts[i].select_set(True)
        bm.select_history.add(bm.verts[i])
    bmesh.update_edit_mesh(obj.data)


def path_operator(obj, **options):
    with bpy.context.temp_override(active_object=obj, object=obj, edit_object=obj if obj.mode == "EDIT" else None):
        return bpy.ops.mesh.heat_geodesic_path(**options)


def test_scaled_sphere_path_is_a_great_circle_arc_on_the_surface(addon):
    obj = ico_sphere(subdivisions=4, radius=1.0)
    obj.scale = (2.0, 2.0, 2.0)
    obj.location = (1.0, 0.0, -3.0)
    bpy.context.view_layer.update()
    V, F = world_mesh(obj)
    source, target = 0, int(np.argmin(V[:, 0]))  # a top vertex and one on the far side
    result = addon.geodesic_path(obj, source, target)
    centre = np.array([1.0, 0.0, -3.0])
    a, b = V[source] - centre, V[target] - centre
    arc = 2.0 * np.arccos(np.clip(a @ b / (np.linalg.norm(a) * np.linalg.norm(b)), -1, 1))
    exact = hc.reference.exact_distance(V, F, source)[target]  # MMP on the polyhedron
    assert result.length >= exact * (1 - 1e-9)  # a path on the surface is never shorter than the geodesic
    assert result.length <= exact * 1.005
    assert abs(result.length / arc - 1) < 0.01  # the polyhedron's geodesic is within 1% of the sphere's arc
    P = curve_points(result.curve)
    np.testing.assert_allclose(P[0], V[source], atol=1e-5)
    np.testing.assert_allclose(P[-1], V[target], atol=1e-5)
    assert off_surface(P, result.path.faces, V, F) < 1e-5  # on the displayed (scaled, moved) surface
    np.testing.assert_allclose(np.linalg.norm(np.diff(P, axis=0), axis=1).sum(), result.length, rtol=1e-6)
    assert result.curve.name == f"{obj.name} Geodesic Path" and result.curve[MARKER].startswith(obj.name)


def test_operator_uses_the_active_vertex_as_source_and_reruns_update_one_curve(addon):
    obj = ico_sphere(subdivisions=3)
    source, target = 5, 120
    select_ends(obj, source, target)
    assert path_operator(obj) == {"FINISHED"}
    curves = [o for o in bpy.data.objects if o.type == "CURVE"]
    assert len(curves) == 1
    forward = curve_points(curves[0])
    V, _ = world_mesh(obj)
    np.testing.assert_allclose(forward[0], V[source], atol=1e-5)
    select_ends(obj, target, source)  # the other one active: the path reversed
    assert path_operator(obj) == {"FINISHED"}
    curves = [o for o in bpy.data.objects if o.type == "CURVE"]
    assert len(curves) == 1  # updated, not a second object
    backward = curve_points(curves[0])
    np.testing.assert_allclose(backward[0], V[target], atol=1e-5)
    length = lambda P: np.linalg.norm(np.diff(P, axis=0), axis=1).sum()  # noqa: E731
    assert length(backward) == pytest.approx(length(forward), rel=1e-6)
    assert obj.mode == "EDIT"


def test_select_edges_selects_a_chain_from_source_to_target(addon):
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=10, y_subdivisions=10, size=2.0)
    obj = bpy.context.active_object
    V = np.array([v.co for v in obj.data.vertices])
    source = int(np.argmin(V[:, 0] + V[:, 1]))  # corner (-1, -1)
    target = int(np.argmin(np.abs(V[:, 0] - 1) + np.abs(V[:, 1] - 0.0)))  # on the opposite side
    result = addon.geodesic_path(obj, source, target, select_edges=True)
    assert result.length == pytest.approx(np.linalg.norm(V[target] - V[source]), rel=1e-6)  # a straight segment (float32 co)
    E = np.array([e.vertices[:] for e in obj.data.edges])
    chain = E[result.edges]
    assert chain[0].tolist().count(source) == 1 and target in chain[-1]
    assert all(set(a) & set(b) for a, b in zip(chain[:-1], chain[1:]))  # consecutive edges share a vertex
    selected = np.array([e.select for e in obj.data.edges])
    assert selected[result.edges].all()


def test_bad_input_is_refused_and_changes_nothing(addon):
    obj = ico_sphere(subdivisions=2)
    bpy.context.view_layer.objects.active = obj
    bpy.ops.object.mode_set(mode="EDIT")
    bpy.ops.mesh.select_all(action="DESELECT")
    bpy.ops.object.mode_set(mode="OBJECT")
    before = snapshot(obj)
    with pytest.raises(addon.AddonError, match="Edit Mode"):
        addon.geodesic_path(obj)  # Object Mode, no ends given
    select_ends(obj, 3, 7)
    bm = bmesh.from_edit_mesh(obj.data)
    bm.verts.ensure_lookup_table()
    bm.verts[9].select_set(True)  # three selected, the third not clicked: no order to visit them in
    bmesh.update_edit_mesh(obj.data)
    with pytest.raises(addon.AddonError, match="not all one by one"):
        addon.geodesic_path(obj)
    with pytest.raises(RuntimeError, match="not all one by one"):
        path_operator(obj)  # the operator reports the same as an error
    bpy.ops.object.mode_set(mode="OBJECT")
    with pytest.raises(addon.AddonError, match="give both"):
        addon.geodesic_path(obj, 3)
    with pytest.raises(addon.AddonError):
        addon.geodesic_path(obj, 3, 10_000)  # no such vertex
    assert not [o for o in bpy.data.objects if o.type == "CURVE"]
    assert_same_snapshot(before, snapshot(obj), ignore=("selection",))


def test_target_in_another_part_names_both_parts(addon):
    obj = ico_sphere(subdivisions=2)
    other = ico_sphere(subdivisions=2)
    other.location = (5, 0, 0)
    bpy.ops.object.select_all(action="DESELECT")
    obj.select_set(True)
    other.select_set(True)
    bpy.context.view_layer.objects.active = obj
    bpy.ops.object.join()
    n = len(obj.data.vertices) // 2
    with pytest.raises(addon.AddonError, match="part"):
        addon.geodesic_path(obj, 0, n + 3)
    assert not [o for o in bpy.data.objects if o.type == "CURVE"]


def test_same_vertex_is_a_one_point_path(addon):
    obj = ico_sphere(subdivisions=2)
    result = addon.geodesic_path(obj, 4, 4)
    assert result.length == 0.0 and len(result.points) == 1


def test_undo_removes_the_curve(addon):
    obj = ico_sphere(subdivisions=3)
    select_ends(obj, 0, 50)
    bpy.ops.ed.undo_push(message="before")
    assert path_operator(obj) == {"FINISHED"}
    bpy.ops.ed.undo_push(message="geodesic path")  # what the UI does after an operator with UNDO
    assert len([o for o in bpy.data.objects if o.type == "CURVE"]) == 1
    bpy.ops.ed.undo()
    assert not [o for o in bpy.data.objects if o.type == "CURVE"]


def test_an_orphan_curve_of_the_same_name_does_not_rename_the_object(addon):
    obj = ico_sphere(subdivisions=2)
    bpy.data.curves.new(f"{obj.name} Geodesic Path", "CURVE")  # left by a deleted curve object (no users)
    result = addon.geodesic_path(obj, 0, 20)
    assert result.curve.name == f"{obj.name} Geodesic Path"
