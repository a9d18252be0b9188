"""Blender: a click builds only the connected parts its sources are on (issue 34: many-part models).

A model of many loose parts (a character's eyes, teeth, buttons) was built
whole on the first click: every small part refined and factored though no
source is on it. Now a click builds the parts its sources are on; a click on
another part builds that one; the probe and paths (sources placed later)
build every part.
"""

import blender_required  # noqa: F401 (first: without bpy, the module is skipped)
import bpy
import numpy as np
import pytest
from test_blender import addon, attribute, empty_scene, select_only  # noqa: F401 (fixtures)

import heatcore as hc


def three_spheres():
    """One mesh object of three separate ico spheres (642 vertices each), x = 0, 3, 6."""
    for k in range(3):
        bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=3, location=(3.0 * k, 0, 0))
    objs = list(bpy.context.scene.objects)
    with bpy.context.temp_override(active_object=objs[0], selected_editable_objects=objs):
        bpy.ops.object.join()
    obj = bpy.context.view_layer.objects.active = objs[0]
    return obj


def click(obj, **options):
    with bpy.context.temp_override(active_object=obj, object=obj):
        return bpy.ops.mesh.heat_geodesic_distance(**options)


def cached_domain(addon, obj):
    (_, solver), = [e for k, e in addon.SOLVERS._entries.items() if k == obj.data.session_uid]
    return solver.domain


def part_of(obj):
    x = np.array([v.co.x for v in obj.data.vertices])
    return np.round(x / 3.0).astype(int)


def test_a_click_builds_the_sources_part_and_a_click_elsewhere_builds_that_one(addon):
    obj = three_spheres()
    part = part_of(obj)
    first = int(np.flatnonzero(part == 1)[0])
    select_only(obj, [first])
    assert click(obj) == {"FINISHED"}
    domain = cached_domain(addon, obj)
    assert domain.parts_left_out == 2 and domain.n_parts == 1
    d = attribute(obj.data, "geodesic_distance")
    V = np.array([v.co for v in obj.data.vertices])
    obj.data.calc_loop_triangles()
    F = np.array([t.vertices[:] for t in obj.data.loop_triangles])
    whole = hc.HeatSolver(hc.TriangleMesh(V, F, weld=None)).distance([first])
    np.testing.assert_allclose(d[part == 1], whole[part == 1], rtol=1e-5, atol=1e-6)  # float32 attribute
    assert np.isinf(whole[part != 1]).all()
    assert (d[part != 1] == d[part != 1][0]).all()  # the unreachable value, as before

    second = int(np.flatnonzero(part == 2)[0])
    select_only(obj, [second])
    assert click(obj) == {"FINISHED"}
    assert not bpy.context.window_manager.heat_geodesic_stats.cached  # another part: built now
    d = attribute(obj.data, "geodesic_distance")
    assert cached_domain(addon, obj).parts_left_out == 2
    assert d[second] == 0 and np.isfinite(d[part == 2]).all() and d[part == 2].max() > 2

    select_only(obj, [int(np.flatnonzero(part == 2)[5])])  # the same part again: the cached solver
    assert click(obj) == {"FINISHED"}
    assert bpy.context.window_manager.heat_geodesic_stats.cached


def test_sources_on_two_parts_build_both(addon):
    obj = three_spheres()
    part = part_of(obj)
    select_only(obj, [int(np.flatnonzero(part == 0)[0]), int(np.flatnonzero(part == 2)[0])])
    assert click(obj) == {"FINISHED"}
    assert cached_domain(addon, obj).parts_left_out == 1


@pytest.mark.parametrize("polygons", ["AUTO", "TRIANGULATE"])
def test_a_partial_solver_is_not_reused_where_every_part_is_needed(addon, polygons):
    """After a click on one part, a run whose sources come later (probe, path) builds every part."""
    from blender_addon.stages import build_solver, prepare_run

    obj = three_spheres()
    select_only(obj, [0])
    assert click(obj, polygons=polygons) == {"FINISHED"}
    assert cached_domain(addon, obj).parts_left_out == 2
    run = prepare_run(obj, sources_later=True, polygons=polygons)
    assert not run.cached
    assert build_solver(run).domain.parts_left_out == 0
