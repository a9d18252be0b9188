"""Quads measured as polygons: the solver built in the background (the button's path), and the notes of its build (issue 22).

The operator, invoked from a window, builds the solver in a worker thread and
checks, before writing, that the object still has the geometry and options
the solver was built for (``stages.check_unchanged``). A mesh measured as
polygons must pass that check (its cache key holds the domain kind) and get
the same distance as the script API. What the build has to tell the user (a
bowtie measured as its fan triangles; coincident vertices merged, so the mesh
measured as triangles) is a note of the run: raised in the worker thread as a
warning, it would reach no one; as a note it is in the operator's report and
the script API's warnings.
"""

import importlib

import blender_required  # noqa: F401 (first: without bpy, the module is skipped)
import bpy
import numpy as np
import pytest
from test_blender import addon, attribute, empty_scene, select_only  # noqa: F401 (fixtures)
from test_blender_modal import RecordingDisplay, drive

import heatcore as hc


def modules():
    return {name: importlib.import_module(f"blender_addon.{name}") for name in ("stages", "operator", "api")}


def quad_grid(n=12):
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=n, y_subdivisions=n, size=2.0)
    return bpy.context.active_object


def modal_run(obj, **options):
    mods = modules()
    reports = []
    run = mods["stages"].prepare_run(obj, **options)
    assert run.solver is None, "the tests build: the cache must miss"
    modal = mods["operator"].ModalRun(run, RecordingDisplay(), lambda kind, text: reports.append((kind, text)))
    return modal, reports


def polygons(mesh):
    sizes = [len(p.vertices) for p in mesh.polygons]
    return np.concatenate([[0], np.cumsum(sizes)]), np.concatenate([list(p.vertices) for p in mesh.polygons])


def test_a_background_build_of_polygons_is_kept_and_written(addon):  # noqa: F811
    obj = quad_grid()
    select_only(obj, [7])
    modal, reports = modal_run(obj)
    assert modal.run.polygons is not None  # measured as polygons
    modal.start()
    assert drive(modal) == {"FINISHED"}, reports
    assert reports[-1][0] == {"INFO"} and "solver built in" in reports[-1][1]
    V = np.array([v.co for v in obj.data.vertices])
    expected = hc.HeatSolver(hc.PolygonMesh(V, polygons(obj.data))).distance([7])
    np.testing.assert_allclose(modal.result.distance, expected, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(attribute(obj.data, "geodesic_distance"), expected, rtol=1e-6, atol=1e-7)
    again = modules()["stages"].prepare_run(obj, sources=[7])
    assert again.cached and again.solver is modal.run.solver


def test_a_bowtie_warning_from_the_worker_reaches_the_report(addon):  # noqa: F811
    mesh = bpy.data.meshes.new("bowtie")
    V = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0], [2, 1, 0]]
    mesh.from_pydata(V, [], [[0, 1, 2, 3], [1, 4, 2, 5]])  # the second quad's sides cross
    obj = bpy.data.objects.new("bowtie", mesh)
    bpy.context.scene.collection.objects.link(obj)
    select_only(obj, [0])
    modal, reports = modal_run(obj)
    modal.start()
    assert drive(modal) == {"FINISHED"}, reports
    warned = [text for kind, text in reports if kind == {"WARNING"}]
    assert any("cross" in text for text in warned), reports
    assert any(text.startswith("1 face(s) cross themselves, as a bowtie does: 1 (sides") for text in warned), warned
    # the distance: heatcore's PolygonMesh with the bowtie split into its fan triangles
    expected = hc.HeatSolver(hc.PolygonMesh(np.array(V, float), polygons(mesh), split_crossing=True)).distance([0])
    np.testing.assert_allclose(modal.result.distance, expected, rtol=1e-9, atol=1e-12)


def test_coincident_vertices_are_welded_as_triangles_with_a_note(addon):  # noqa: F811
    # two quads side by side, their shared edge duplicated: merged (weld=0, Merge Coincident Vertices; off by
    # default in Blender), TriangleMesh welds it, PolygonMesh would not
    mesh = bpy.data.meshes.new("seam")
    V = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [1, 0, 0], [2, 0, 0], [2, 1, 0], [1, 1, 0]]
    mesh.from_pydata(V, [], [[0, 1, 2, 3], [4, 5, 6, 7]])
    obj = bpy.data.objects.new("seam", mesh)
    bpy.context.scene.collection.objects.link(obj)
    api = modules()["api"]
    with pytest.warns(UserWarning, match="measured as triangles, not polygons: 2 vertices share their position"):
        result = api.compute_geodesic_distance(obj, sources=[0], color_attribute=None, weld=0.0)
    assert any("welded" in note for note in result.warnings)
    mesh.calc_loop_triangles()
    F = np.array([t.vertices[:] for t in mesh.loop_triangles])
    np.testing.assert_allclose(result.distance, hc.HeatSolver(hc.TriangleMesh(np.array(V, float), F)).distance([0]),
                               rtol=1e-9, atol=1e-12)
    assert result.distance[5] == pytest.approx(2.0, rel=0.05)  # across the welded seam (measured 1.94)
    apart = api.compute_geodesic_distance(obj, sources=[0], color_attribute=None)  # the default: polygons, two parts
    assert np.isinf(apart.distance[4:]).all() and apart.distance[2] == pytest.approx(np.sqrt(2), rel=0.05)


def test_new_object_measures_the_evaluated_quads_as_polygons(addon):  # noqa: F811
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=1, radius=1.0)  # triangles; the Subdivision makes quads
    obj = bpy.context.active_object
    obj.modifiers.new("Subdivision", "SUBSURF").levels = 2
    obj.location = (2.0, 0.0, 0.0)
    bpy.context.view_layer.update()
    api = modules()["api"]
    result = api.compute_geodesic_distance(obj, sources=[0], color_attribute=None, new_object=True)
    copy = result.object
    assert copy is not obj and all(len(p.vertices) == 4 for p in copy.data.polygons)
    V = np.array([v.co for v in copy.data.vertices]) + [2.0, 0.0, 0.0]  # World space: the copy sits where obj is
    expected = hc.HeatSolver(hc.PolygonMesh(V, polygons(copy.data))).distance(result.sources)
    np.testing.assert_allclose(result.distance, expected, rtol=1e-9, atol=1e-12)
    entry = addon.SOLVERS._entries[(modules()["stages"].COPY_MARKER, obj.session_uid)]
    assert isinstance(entry[1].domain, hc.PolygonMesh)
    triangles = api.compute_geodesic_distance(obj, sources=[0], color_attribute=None, new_object=True,
                                              polygons="TRIANGULATE")
    copy.data.calc_loop_triangles()
    F = np.array([t.vertices[:] for t in copy.data.loop_triangles])
    np.testing.assert_allclose(triangles.distance, hc.HeatSolver(hc.TriangleMesh(V, F)).distance(result.sources),
                               rtol=1e-9, atol=1e-12)


def test_a_polygon_build_reports_its_stages(addon):  # noqa: F811
    """Issue 34: the polygon build sat at one fraction for 7.5 s of 10.8 s (126k vertices); now each stage shows."""
    obj = quad_grid(20)
    select_only(obj, [0])
    stages = modules()["stages"]
    run = stages.prepare_run(obj)
    assert run.polygons is not None  # quads: measured as polygons
    seen = []
    stages.build_solver(run, lambda fraction, message: seen.append((fraction, message)))
    messages = [m for _, m in seen]
    assert "checking the polygons' shapes (crossing sides, concave corners)" in messages
    # every quad triangulated: the triangles are built as heatcore.TriangleMesh builds them, stage by stage
    assert "intrinsic Delaunay flips" in messages and "factoring the Poisson matrix" in messages
    fractions = [f for f, _ in seen]
    assert all(b >= a for a, b in zip(fractions, fractions[1:])) and len(set(fractions)) >= 6
