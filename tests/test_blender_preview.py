"""The button's first answer (issue 34): a preview drawn while the solver builds, never written.

A small mesh is previewed unrefined, a large one coarsened
(``heatcore.CoarsePreview.of_arrays``). Driven as ``test_blender_modal.py``
drives the button (``ModalRun`` with timer and Esc events, a gate holding the
worker at a stage): while the solver builds, the preview is drawn at the first
timer event after it is computed and nothing is written; at the end the written
result is the solver's, the script API's; Esc takes it down with nothing
written. A quick finish is written at the timer event that sees the build done.
"""

import importlib

import blender_required  # noqa: F401 (first: without bpy, the module is skipped)
import bpy
import numpy as np
import pytest
from test_blender import (  # noqa: F401
    addon,
    assert_same_snapshot,
    attribute,
    empty_scene,
    ico_sphere,
    select_only,
    snapshot,
)
from test_blender_modal import drive, gate, modal_run

import heatcore as hc
from heatcore.reference import mean_relative_error


@pytest.fixture(scope="module")
def modules(addon):  # noqa: F811
    names = ("api", "stages", "background", "operator", "overlay", "preview")
    return {name: importlib.import_module(f"blender_addon.{name}") for name in names}


def great_circle(obj, source):
    V = np.array([v.co for v in obj.data.vertices])
    V /= np.linalg.norm(V, axis=1, keepdims=True)
    return np.arccos(np.clip(V @ V[source], -1.0, 1.0))


def held_build(modules, obj, source, **options):
    """A button click from ``source`` whose worker is held at the heat factorization: ``(modal, release)``."""
    select_only(obj, [source])
    modal, _ = modal_run(modules, obj, **options)
    reached, release = gate(modal, modules, "factoring the heat matrix")
    modal.start(obj)
    assert reached.wait(60)
    return modal, release


def shown_preview(modal):
    """The preview drawn while the build is held at a gate: a coarse one once computed, at the next timer event; an
    unrefined one at once."""
    if importlib.import_module("blender_addon.preview").preview_kind(modal.run) == "unrefined":
        assert modal.preview_work is None and modal.preview is not None
        return modal.preview
    assert modal.preview_work.wait(60)
    assert modal.preview is None  # not before a timer event
    assert modal.handle(bpy.context, "TIMER") == {"PASS_THROUGH"}
    assert modal.preview_work is None
    return modal.preview


def test_preview_is_drawn_at_once_and_the_refined_result_is_written(modules):
    overlay = modules["overlay"]
    obj = ico_sphere(3)  # 162 vertices: its solver is built on 40,962
    modal, release = held_build(modules, obj, 0, isolines=10)
    assert modules["preview"].preview_kind(modal.run) == "unrefined"
    preview = shown_preview(modal)
    assert preview is not None and preview.overlay in overlay.Overlay.live  # drawn while the solver builds
    assert "geodesic_distance" not in obj.data.attributes  # and nothing written
    # the preview is heatcore's distance on the mesh as it is (its 162 vertices, refine=0)
    V = np.array([v.co for v in obj.data.vertices])
    coarse = hc.HeatSolver(hc.TriangleMesh(V, modal.run.F, refine=0, weld=None)).distance([0])
    np.testing.assert_allclose(preview.distance, coarse, rtol=1e-12, atol=1e-12)
    assert preview.data.colors.shape == (162, 4) and preview.data.sources.shape == (1, 3)
    exact = great_circle(obj, 0)
    release.set()
    assert mean_relative_error(preview.distance, exact) == pytest.approx(0.0274, abs=0.0005)  # measured 2.74%
    assert drive(modal) == {"FINISHED"}
    assert preview.overlay is None and not overlay.Overlay.live  # taken down
    written = attribute(obj.data, "geodesic_distance")
    assert mean_relative_error(written, exact) == pytest.approx(0.0099, abs=0.0005)  # refined: measured 0.99% (1.25% with one heat step)
    # the default's result, as a script gets it
    twin = ico_sphere(3)
    expected = modules["api"].compute_geodesic_distance(twin, sources=[0], isolines=10)
    np.testing.assert_allclose(modal.result.distance, expected.distance, rtol=1e-12, atol=1e-12)
    np.testing.assert_array_equal(written, attribute(twin.data, "geodesic_distance"))


def test_esc_takes_the_preview_down_and_writes_nothing(modules):
    overlay = modules["overlay"]
    obj = ico_sphere(3)
    modal, release = held_build(modules, obj, 5)
    before = snapshot(obj)  # selected, nothing written yet
    assert shown_preview(modal).overlay in overlay.Overlay.live
    release.set()  # the worker goes on to the next stage, where it sees the cancel
    assert modal.handle(bpy.context, "ESC", "PRESS") == {"CANCELLED"}
    assert modal.build.wait(60)
    assert modal.preview.overlay is None and not overlay.Overlay.live
    assert_same_snapshot(before, snapshot(obj))
    assert "geodesic_distance" not in obj.data.attributes


@pytest.mark.parametrize("options", [{"refine": 0}, {"selected": "FACES"}])
def test_no_preview_where_the_mesh_is_not_refined_or_the_sources_are_not_vertices(modules, options):
    obj = ico_sphere(3)
    select_only(obj, [0, 1, 2])
    modal, _ = modal_run(modules, obj, **options)
    assert not modules["preview"].wants_preview(modal.run)
    modal.start(obj)
    assert modal.preview_work is None
    assert drive(modal) == {"FINISHED"}
    assert modal.preview is None


@pytest.mark.parametrize("shown_from, events", [(100_000, 1), (0, 2)])
def test_a_quick_finish_is_written_at_the_timer_event_that_sees_the_build_done(modules, monkeypatch, shown_from,
                                                                              events):
    # below SHOWN_FINISH_VERTICES the query and writes run at once (0.1 s earlier); above, the message is drawn first
    monkeypatch.setattr(modules["operator"], "SHOWN_FINISH_VERTICES", shown_from)
    obj = ico_sphere(3)
    select_only(obj, [0])
    modal, _ = modal_run(modules, obj)
    modal.start(obj)
    assert modal.build.wait(60)
    states = [modal.handle(bpy.context, "TIMER") for _ in range(events)]
    assert states == [{"PASS_THROUGH"}] * (events - 1) + [{"FINISHED"}]
    assert modal.display.shown[-1][1] == "solving for the distance and writing the attributes"
    assert "geodesic_distance" in obj.data.attributes


@pytest.fixture
def coarse_from_2000(modules, monkeypatch):
    """A 2,562-vertex icosphere counts as large: previewed coarsened, to 256 clusters (a tenth)."""
    monkeypatch.setattr(modules["preview"], "COARSE_PREVIEW_FROM", 2000)


def test_a_large_mesh_is_previewed_coarse_and_its_own_result_written(modules, coarse_from_2000):
    overlay = modules["overlay"]
    obj = ico_sphere(5)
    modal, release = held_build(modules, obj, 0, isolines=10)
    assert modules["preview"].preview_kind(modal.run) == "coarse"
    preview = shown_preview(modal)
    assert preview.overlay in overlay.Overlay.live and "geodesic_distance" not in obj.data.attributes
    V = np.array([v.co for v in obj.data.vertices])
    coarse = hc.CoarsePreview.of_arrays(V, modal.run.F, vertices=256, only_parts_of=[0])
    np.testing.assert_array_equal(preview.distance, coarse.distance([0]))
    exact = great_circle(obj, 0)
    assert mean_relative_error(preview.distance, exact) == pytest.approx(0.0591, abs=0.002)  # measured 5.91% (256 clusters)
    release.set()
    assert drive(modal) == {"FINISHED"}
    assert preview.overlay is None and not overlay.Overlay.live
    twin = ico_sphere(5)
    expected = modules["api"].compute_geodesic_distance(twin, sources=[0], isolines=10)
    np.testing.assert_array_equal(attribute(obj.data, "geodesic_distance"), attribute(twin.data, "geodesic_distance"))
    np.testing.assert_allclose(modal.result.distance, expected.distance, rtol=1e-12, atol=1e-12)


def test_a_preview_computed_but_not_drawn_before_esc_is_never_drawn(modules, coarse_from_2000):
    overlay = modules["overlay"]
    obj = ico_sphere(5)
    modal, release = held_build(modules, obj, 7)
    before = snapshot(obj)  # selected, nothing written yet
    work = modal.preview_work
    assert work.done() and work.distance is not None  # computed by the worker, not yet drawn
    assert modal.handle(bpy.context, "ESC", "PRESS") == {"CANCELLED"}
    release.set()
    assert modal.build.wait(60)
    assert modal.preview is None and not overlay.Overlay.live
    assert_same_snapshot(before, snapshot(obj))


def test_a_preview_of_another_vertex_count_is_not_drawn(modules, coarse_from_2000):
    # the object edited while the preview was computed: its distance no longer fits the mesh, and the build says so
    obj = ico_sphere(5)
    modal, release = held_build(modules, obj, 0)
    assert modal.preview_work.wait(60)
    modal.preview_work.distance = modal.preview_work.distance[:-1]
    modal.show_preview()
    assert modal.preview is None
    release.set()
    assert drive(modal) == {"FINISHED"}


def test_a_quad_mesh_is_previewed_from_its_polygons_and_drawn_on_their_triangles(modules, coarse_from_2000):
    bpy.ops.mesh.primitive_torus_add(major_segments=64, minor_segments=40)  # 2,560 quads: measured as polygons
    obj = bpy.context.active_object
    modal, release = held_build(modules, obj, 0)
    assert modal.run.F is None and modal.run.polygons is not None
    preview = shown_preview(modal)
    offsets, indices = modal.run.polygons
    fan = np.stack([indices[offsets[:-1]], indices[offsets[:-1] + 1], indices[offsets[:-1] + 2],
                    indices[offsets[:-1]], indices[offsets[:-1] + 2], indices[offsets[:-1] + 3]], axis=1).reshape(-1, 3)
    np.testing.assert_array_equal(preview.data.triangles, fan)  # convex quads: their fans cover them
    V = np.array([v.co for v in obj.data.vertices])
    expected = hc.CoarsePreview.of_arrays(V, fan, vertices=256, only_parts_of=[0]).distance([0])
    np.testing.assert_array_equal(preview.distance, expected)
    assert np.isfinite(preview.distance).all()
    release.set()
    assert drive(modal) == {"FINISHED"}
    assert preview.overlay is None
