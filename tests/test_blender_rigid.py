"""Moving the object keeps its solver (issue 34: "rigid motions never rebuild; a uniform scale rescales").

In World space the cache keys the geometry by the object's own coordinates
and the metric of its world matrix (``blender_addon/cache.py``): a
translation, a rotation (of the object or of a parent) reuses the solver and
gives the same distances bit for bit; a uniform scale reuses it and scales the
answer; a non-uniform scale or a shear rebuilds it. In Object (Local) space the
transform plays no part. Edits to the mesh still rebuild.

A rebuild is told by the run's ``cached`` and by counting the heat solvers the
add-on makes (:func:`builds`), never by the clock. Against a fresh solve after
a rotation the distances agree to the precision of Blender's float32 world
matrix (its rotation is orthogonal to about 1e-7), and to 1e-12 against
heatcore on the mesh turned by an exact rotation.
"""

import doctest
import importlib

import blender_required  # noqa: F401 (first: without bpy, the module is skipped)
import bpy
import numpy as np
import pytest
from test_blender import (  # noqa: F401 (fixtures)
    addon,
    attribute,
    coords,
    empty_scene,
    ico_sphere,
    loop_triangles,
    run,
    select_only,
)

import heatcore as hc


@pytest.fixture
def builds(addon, monkeypatch):  # noqa: F811
    """The heat solvers made from now on (their domains; the add-on's and this test's), by wrapping ``HeatSolver``."""
    heatcore = importlib.import_module("blender_addon._heatcore").heatcore
    made, original = [], heatcore.HeatSolver

    def counted(domain, *args, **kwargs):
        made.append(domain)
        return original(domain, *args, **kwargs)

    monkeypatch.setattr(heatcore, "HeatSolver", counted)
    return made


@pytest.fixture
def sphere(addon):  # noqa: F811
    """A 642-vertex ico sphere (its first click made: the solver is cached) and that first result."""
    obj = ico_sphere(subdivisions=4, radius=1.0)
    addon.SOLVERS.clear()
    first = distance(addon, obj)
    assert not first.cached
    return obj, first


def distance(addon, obj, **options):  # noqa: F811
    return addon.compute_geodesic_distance(obj, sources=[0], attribute="d", color_attribute=None, **options)


def update():
    bpy.context.view_layer.update()


def fresh(addon, obj, **options):  # noqa: F811
    """The distance of a solver built now (the cache emptied first)."""
    addon.SOLVERS.clear()
    result = distance(addon, obj, **options)
    assert not result.cached
    return result.distance


def exact_rotation(seed=3):
    Q, R = np.linalg.qr(np.random.default_rng(seed).normal(size=(3, 3)))
    return Q * np.sign(np.diag(R))


def test_translation_reuses_the_solver_bit_for_bit(addon, sphere, builds):  # noqa: F811
    obj, first = sphere
    obj.location = (3.0, -2.0, 1.0)
    update()
    moved = distance(addon, obj)
    assert moved.cached and moved.solver_seconds == 0.0 and not builds
    np.testing.assert_array_equal(moved.distance, first.distance)
    np.testing.assert_allclose(fresh(addon, obj), first.distance, rtol=1e-12)


def test_rotation_reuses_the_solver_bit_for_bit(addon, sphere, builds):  # noqa: F811
    obj, first = sphere
    obj.rotation_euler = (0.4, -0.3, 1.1)
    update()
    turned = distance(addon, obj)
    assert turned.cached and not builds
    np.testing.assert_array_equal(turned.distance, first.distance)
    V, F = coords(obj.data), loop_triangles(obj.data)
    exact = hc.HeatSolver(hc.TriangleMesh(V @ exact_rotation().T, F)).distance([0])  # distances are rigid-invariant
    np.testing.assert_allclose(turned.distance, exact, rtol=1e-12)
    # a fresh solve on the world positions: as close as the float32 world matrix is to a rotation
    np.testing.assert_allclose(fresh(addon, obj), first.distance, rtol=1e-6)
    obj.scale = (-1.0, 1.0, 1.0)  # mirrored: an isometry too
    update()
    made = len(builds)
    mirrored = distance(addon, obj)
    assert mirrored.cached and len(builds) == made
    np.testing.assert_allclose(mirrored.distance, first.distance, rtol=1e-6)


def test_translation_and_rotation_through_the_button(addon, sphere, builds):  # noqa: F811
    obj, first = sphere
    select_only(obj, [0])
    for k in range(3):
        obj.location = (k, -2.0 * k, 0.5)
        obj.rotation_euler = (0.3 * k, 1.0, -0.2 * k)
        update()
        assert run(obj) == {"FINISHED"}
        np.testing.assert_array_equal(attribute(obj.data, "geodesic_distance"), first.distance.astype(np.float32))
    assert not builds


def test_a_parent_rotation_reuses_the_solver(addon, sphere, builds):  # noqa: F811
    obj, first = sphere
    parent = bpy.data.objects.new("Rig", None)
    bpy.context.scene.collection.objects.link(parent)
    obj.parent = parent
    parent.rotation_euler = (1.2, 0.0, -0.7)
    parent.location = (0.0, 5.0, 0.0)
    update()
    assert not np.allclose(np.array(obj.matrix_world), np.eye(4))
    child = distance(addon, obj)
    assert child.cached and not builds
    np.testing.assert_array_equal(child.distance, first.distance)


def test_a_uniform_scale_rescales_the_cached_answer(addon, sphere, builds):  # noqa: F811
    obj, first = sphere
    obj.scale = (1.7, 1.7, 1.7)
    update()
    scaled = distance(addon, obj)
    assert scaled.cached and not builds
    factor = float(np.float32(1.7))  # Blender's scale is float32
    np.testing.assert_allclose(scaled.distance, factor * first.distance, rtol=1e-15)
    np.testing.assert_allclose(attribute(obj.data, "d"), scaled.distance, rtol=1e-6)  # the written answer too
    np.testing.assert_allclose(scaled.distance, fresh(addon, obj), rtol=1e-9)  # heat method: scale-covariant
    obj.rotation_euler = (0.0, 0.5, 0.0)  # and turned: as exact as the float32 rotation
    update()
    turned = distance(addon, obj)
    assert turned.cached and len(builds) == 1
    np.testing.assert_allclose(turned.distance, scaled.distance, rtol=1e-6)


def test_a_weld_tolerance_is_a_length_so_a_uniform_scale_rebuilds(addon, builds):  # noqa: F811
    obj = ico_sphere(subdivisions=3, radius=1.0)
    distance(addon, obj, weld=1e-6)
    obj.rotation_euler = (0.3, 0.2, 0.1)
    update()
    assert distance(addon, obj, weld=1e-6).cached  # rigid: the tolerance means the same
    obj.scale = (2.0, 2.0, 2.0)
    update()
    assert not distance(addon, obj, weld=1e-6).cached


def test_a_non_uniform_scale_or_a_shear_rebuilds(addon, sphere, builds):  # noqa: F811
    obj, first = sphere
    obj.scale = (1.0, 1.0, 2.0)
    update()
    stretched = distance(addon, obj)
    assert not stretched.cached and len(builds) == 1
    world = coords(obj.data) * [1.0, 1.0, 2.0]
    expected = hc.HeatSolver(hc.TriangleMesh(world, loop_triangles(obj.data))).distance([0])
    np.testing.assert_allclose(stretched.distance, expected, rtol=1e-9)
    ratio = stretched.distance[1:] / first.distance[1:]
    assert np.ptp(ratio) > 0.1  # not a rescaled answer
    parent = bpy.data.objects.new("Stretch", None)  # a rotation under a non-uniform parent: a shear
    bpy.context.scene.collection.objects.link(parent)
    obj.scale = (1.0, 1.0, 1.0)
    obj.parent, parent.scale = parent, (1.0, 1.0, 2.0)
    update()
    assert distance(addon, obj).cached  # the same world matrix
    obj.rotation_euler = (0.7, 0.0, 0.0)
    update()
    made = len(builds)
    sheared = distance(addon, obj)
    assert not sheared.cached and len(builds) == made + 1
    np.testing.assert_allclose(sheared.distance, fresh(addon, obj), rtol=1e-9)


def test_object_space_ignores_the_transform(addon, builds):  # noqa: F811
    obj = ico_sphere(subdivisions=4, radius=1.0)
    first = distance(addon, obj, space="LOCAL")
    obj.location, obj.rotation_euler, obj.scale = (1.0, 2.0, 3.0), (0.1, 0.2, 0.3), (1.0, 3.0, 0.5)
    update()
    moved = distance(addon, obj, space="LOCAL")
    assert moved.cached and len(builds) == 1
    np.testing.assert_array_equal(moved.distance, first.distance)


def test_edits_still_rebuild_after_a_move(addon, sphere, builds):  # noqa: F811
    obj, _ = sphere
    obj.rotation_euler = (0.5, 0.0, 0.2)
    update()
    assert distance(addon, obj).cached
    co = coords(obj.data)
    co[3] *= 1.05  # a vertex moved
    obj.data.vertices.foreach_set("co", co.ravel())
    update()
    edited = distance(addon, obj)
    assert not edited.cached and len(builds) == 1
    np.testing.assert_allclose(edited.distance, fresh(addon, obj), rtol=1e-9)
    obj.shape_key_add(name="Basis")
    key = obj.shape_key_add(name="Tall")
    key.data.foreach_set("co", (co * [1.0, 1.0, 1.5]).astype(np.float32).ravel())
    key.value = 1.0
    update()
    assert not distance(addon, obj).cached  # a shape key
    obj.modifiers.new("Cast", "CAST").factor = 0.5
    update()
    assert not distance(addon, obj).cached  # a deform modifier


def test_a_uniform_scale_during_a_background_build_scales_the_answer(addon):  # noqa: F811
    stages = importlib.import_module("blender_addon.stages")
    obj = ico_sphere(subdivisions=3, radius=1.0)
    addon.SOLVERS.clear()
    prepared = stages.prepare_run(obj, sources=[0], attribute="d", color_attribute=None)
    stages.build_solver(prepared)
    unscaled = prepared.solver.distance([0])
    obj.scale, obj.location = (2.0, 2.0, 2.0), (1.0, 0.0, 0.0)  # the user goes on working meanwhile
    update()
    stages.check_unchanged(prepared)
    result = stages.finish_run(prepared)
    np.testing.assert_allclose(result.distance, 2.0 * unscaled, rtol=1e-12)


def test_paths_and_the_probe_follow_the_moved_object(addon, sphere, builds):  # noqa: F811
    obj, _ = sphere
    obj.scale, obj.rotation_euler, obj.location = (2.0, 2.0, 2.0), (0.3, 1.0, 0.0), (0.0, 0.0, 4.0)
    update()
    moved = addon.geodesic_path(obj, 0, 400)
    assert moved.cached and not builds
    addon.SOLVERS.clear()
    built = addon.geodesic_path(obj, 0, 400)
    assert not built.cached
    np.testing.assert_allclose(moved.points, built.points, atol=1e-5)
    assert moved.length == pytest.approx(built.length, rel=1e-6)
    probe = addon.GeodesicProbe(obj, overlay=False)
    try:
        assert probe.run.cached
        np.testing.assert_allclose(probe.add(0), distance(addon, obj).distance, rtol=1e-12)
    finally:
        probe.cancel()


def test_the_uv_map_takes_no_domain_built_in_another_frame(addon, sphere):  # noqa: F811
    obj, _ = sphere
    obj.rotation_euler = (0.0, 0.0, 1.0)
    update()
    assert distance(addon, obj).cached  # the distance's solver is reused; the UV map's directions turn
    uv = addon.geodesic_uv_map(obj, 0, up=(1.0, 0.0, 0.0), accuracy="smooth").uv
    addon.SOLVERS.clear()
    np.testing.assert_allclose(uv, addon.geodesic_uv_map(obj, 0, up=(1.0, 0.0, 0.0), accuracy="smooth").uv,
                               atol=1e-9)


def test_the_cache_examples_run(addon):  # noqa: F811
    result = doctest.testmod(importlib.import_module("blender_addon.cache"))
    assert result.attempted and not result.failed
