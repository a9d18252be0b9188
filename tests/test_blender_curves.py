"""The *Isoline Curves* operator (real ``bpy``): one curve object, a spline per isoline of the distance attribute."""

import blender_required  # noqa: F401 (first: without bpy, the module is skipped)
import bpy
import numpy as np
import pytest
from test_blender import addon, assert_same_snapshot, empty_scene, ico_sphere, snapshot  # noqa: F401 (fixtures)

import heatcore as hc

MARKER = "heat_geodesic_isolines_of"


def set_distance(obj, values, name="geodesic_distance"):
    attr = obj.data.attributes.new(name, "FLOAT", "POINT")
    attr.data.foreach_set("value", np.asarray(values, dtype=np.float32))
    return np.asarray(values, dtype=np.float32).astype(np.float64)  # what the attribute holds


def curves(obj, **options):
    with bpy.context.temp_override(active_object=obj, object=obj):
        return bpy.ops.mesh.heat_geodesic_isoline_curves(**options)


def splines(target):
    """[(world-space points, cyclic)] of a curve object."""
    M = np.array(target.matrix_world)
    out = []
    for spline in target.data.splines:
        co = np.empty(4 * len(spline.points))
        spline.points.foreach_get("co", co)
        P = co.reshape(-1, 4)[:, :3]
        out.append((P @ M[:3, :3].T + M[:3, 3], spline.use_cyclic_u))
    return out


def evaluated_arrays(obj):
    """Local positions of the displayed shape, and the triangles (read here independently of the add-on)."""
    ev = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = ev.to_mesh()
    V = np.array([v.co for v in mesh.vertices], dtype=np.float64)
    ev.to_mesh_clear()
    obj.data.calc_loop_triangles()
    F = np.array([t.vertices[:] for t in obj.data.loop_triangles])
    return V, F


def ours():
    return [o for o in bpy.data.objects if o.get(MARKER) is not None]


def test_grid_curves_lie_at_the_levels_on_the_displayed_scaled_shape(addon):
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=12, y_subdivisions=9, size=2.0)
    obj = bpy.context.active_object
    obj.scale = (2.0, 3.0, 0.5)
    obj.location = (1.0, -2.0, 4.0)
    mod = obj.modifiers.new("lift", "DISPLACE")  # no texture: every vertex moves 0.4 along its normal (+z)
    mod.strength, mod.mid_level = 0.4, 0.0
    V0 = np.array([v.co for v in obj.data.vertices])
    d = set_distance(obj, np.linalg.norm(V0[:, :2] - V0[0, :2], axis=1))  # exact distance from a corner
    assert curves(obj, count=5) == {"FINISHED"}
    (target,) = ours()
    assert target.name == f"{obj.name} Geodesic Isolines" and target.parent is obj and target[MARKER] == obj.name

    V, F = evaluated_arrays(obj)
    np.testing.assert_allclose(V[:, 2], 0.4, atol=1e-6)  # the displayed shape is not the base one
    expected = hc.isolines(V, F, d, 5)
    got = splines(target)
    assert len(got) == len(expected) == 5
    M = np.array(obj.matrix_world)
    levels = hc.contours.isoline_levels(d, 5)
    for iso, (P, cyclic), level in zip(expected, got, levels):
        assert iso.level == pytest.approx(level)
        a, b = iso.edges.T
        np.testing.assert_allclose((1 - iso.t) * d[a] + iso.t * d[b], level, atol=1e-6)  # on the level
        np.testing.assert_allclose(P, iso.points @ M[:3, :3].T + M[:3, 3], atol=1e-5)  # world space
        np.testing.assert_allclose(P[:, 2], 4.0 + 0.5 * 0.4, atol=1e-5)  # on the lifted, scaled shape
        assert not cyclic and not iso.closed  # quarter circles end on the border


def test_spacing_gives_multiples_in_the_attribute_units(addon):
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=10, y_subdivisions=10, size=2.0)
    obj = bpy.context.active_object
    V0 = np.array([v.co for v in obj.data.vertices])
    d = set_distance(obj, V0[:, 0] + 1.0)  # 0..2 along x
    assert curves(obj, spacing=0.5) == {"FINISHED"}
    got = splines(ours()[0])
    assert len(got) == 3
    np.testing.assert_allclose(sorted(P[:, 0].mean() for P, _ in got), [-0.5, 0.0, 0.5], atol=1e-6)
    assert d.max() == pytest.approx(2.0)


def test_sphere_latitudes_are_cyclic_splines_and_a_rerun_replaces_the_curve(addon):
    obj = ico_sphere(subdivisions=3)
    V0 = np.array([v.co for v in obj.data.vertices])
    set_distance(obj, np.arccos(np.clip(V0[:, 2] / np.linalg.norm(V0, axis=1), -1, 1)))  # from the north pole
    assert curves(obj, count=4) == {"FINISHED"}
    got = splines(ours()[0])
    assert len(got) == 4 and all(cyclic for _, cyclic in got)
    names = sorted(bpy.data.curves.keys())
    assert curves(obj, count=2) == {"FINISHED"}
    assert len(ours()) == 1 and len(ours()[0].data.splines) == 2
    assert sorted(bpy.data.curves.keys()) == names  # the old curve is gone, the new one has its name
    assert ours()[0].data.name == "Icosphere Geodesic Isolines"


def test_missing_attribute_is_refused_and_nothing_changes(addon):
    obj = ico_sphere(subdivisions=2)
    before, n_curves = snapshot(obj), len(bpy.data.curves)
    with pytest.raises(RuntimeError, match="run Geodesic Distance first"):
        curves(obj)
    with pytest.raises(addon.AddonError, match="Geodesic Distance first"):
        addon.isoline_operator.isoline_curves(obj, "nope")
    assert not ours() and len(bpy.data.curves) == n_curves
    assert_same_snapshot(before, snapshot(obj))


def test_edit_mode_run_stays_in_edit_mode(addon):
    """From the Edit Mode context menu: the curve is made and the mesh stays in Edit Mode, unchanged."""
    obj = ico_sphere(subdivisions=2)
    V0 = np.array([v.co for v in obj.data.vertices])
    set_distance(obj, V0[:, 2] + 1.0)
    before = snapshot(obj)
    with bpy.context.temp_override(active_object=obj, object=obj):
        bpy.ops.object.mode_set(mode="EDIT")
    try:
        assert curves(obj, count=3) == {"FINISHED"}
        assert obj.mode == "EDIT" and len(ours()[0].data.splines) == 3
    finally:
        with bpy.context.temp_override(active_object=obj, object=obj):
            bpy.ops.object.mode_set(mode="OBJECT")
    assert_same_snapshot(before, snapshot(obj))


def test_an_attribute_of_another_kind_is_refused(addon):
    obj = ico_sphere(subdivisions=2)
    obj.data.attributes.new("corner", "FLOAT", "CORNER")
    before, n_curves = snapshot(obj), len(bpy.data.curves)
    with pytest.raises(RuntimeError, match="not a FLOAT point attribute"):
        curves(obj, attribute="corner")
    assert not ours() and len(bpy.data.curves) == n_curves
    assert_same_snapshot(before, snapshot(obj))
