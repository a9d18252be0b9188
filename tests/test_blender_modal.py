"""The button's background build (issue 18: never freeze, always say what is happening), with the real ``bpy``.

Blender runs no event loop in background mode and calls ``execute`` even for
``INVOKE_DEFAULT``, so the modal operator itself cannot run here. Its logic
lives in :class:`blender_addon.operator.ModalRun` (the operator's ``modal`` is
one call to ``ModalRun.handle``), which these tests drive with timer and Esc
events on the main thread while the worker thread builds the solver, and a
recording display in place of the status bar. A gate in the worker's progress
callback holds the build at a chosen stage, so that "while it builds" is
deterministic.
"""

import importlib
import threading
import time

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

import heatcore as hc


@pytest.fixture(scope="module")
def modules(addon):  # noqa: F811
    names = ("api", "stages", "background", "operator", "cache", "display")
    return {name: importlib.import_module(f"blender_addon.{name}") for name in names}


class RecordingDisplay:
    """Stands in for the ProgressDisplay (status bar, header, progress indicator, timer)."""

    def __init__(self):
        self.shown = []
        self.ended = 0

    def progress(self, fraction, message):
        self.shown.append((fraction, message))

    def end(self):
        self.ended += 1


def modal_run(modules, obj, **options):
    reports = []
    run = modules["stages"].prepare_run(obj, **options)
    assert run.solver is None, "the tests build: the cache must miss"
    modal = modules["operator"].ModalRun(run, RecordingDisplay(), lambda kind, text: reports.append((kind, text)))
    return modal, reports


def gate(modal, modules, stage):
    """Hold the worker when it reports ``stage`` until ``release`` is set; ``reached`` is set there."""
    reached, release = threading.Event(), threading.Event()

    def work(progress):
        def gated(fraction, message):
            progress(fraction, message)
            if message.startswith(stage):
                reached.set()
                assert release.wait(60)

        return modal.work(gated)

    modal.build.work = work
    return reached, release


def drive(modal, timeout=60.0):
    """Timer events every 10 ms until the run ends; the operator's ``modal`` return value."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        state = modal.handle(bpy.context, "TIMER")
        if state != {"PASS_THROUGH"}:
            return state
        time.sleep(0.01)
    raise AssertionError("the background build did not end")


def rising(fractions):
    return all(b >= a for a, b in zip(fractions, fractions[1:]))


def test_background_build_reports_real_stages_and_writes_what_the_script_api_writes(modules):
    stages, background = modules["stages"], modules["background"]
    obj = ico_sphere(5)  # 2,562 vertices
    select_only(obj, [0])
    modal, reports = modal_run(modules, obj, isolines=10, m=1.0)
    modal.start()
    assert background.BackgroundBuild.running() is modal.build
    assert drive(modal) == {"FINISHED"}
    assert background.BackgroundBuild.running() is None

    updates = modal.build.updates
    fractions = [f for _, f, _ in updates]
    assert rising(fractions) and fractions[0] == stages.BUILD_RANGE[0] and fractions[-1] == stages.BUILD_RANGE[1]
    messages = [m for _, _, m in updates]
    for stage in ("intrinsic Delaunay flips", "factoring the heat matrix", "factoring the Poisson matrix"):
        assert stage in messages
    shown = [f for f, _ in modal.display.shown]
    assert rising(shown) and shown[-1] == stages.BUILD_RANGE[1]
    assert modal.display.shown[-1][1] == "solving for the distance and writing the attributes"
    assert modal.display.ended == 1
    assert reports[-1][0] == {"INFO"} and "solver built in" in reports[-1][1]
    assert modal.result.cached is False and modal.result.solver_seconds > 0
    assert bpy.context.window_manager.heat_geodesic_stats.object_name == obj.name

    # the same object and options through the script API (synchronous), on a twin mesh
    twin = ico_sphere(5)
    seen = []
    expected = modules["api"].compute_geodesic_distance(twin, sources=[0], isolines=10, m=1.0,
                                         progress=lambda f, message: seen.append((f, message)))
    np.testing.assert_allclose(modal.result.distance, expected.distance, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(attribute(obj.data, "geodesic_distance"), attribute(twin.data, "geodesic_distance"),
                               rtol=1e-12, atol=1e-12)
    # the great-circle distance from vertex 0 (the pole, (0, 0, 1)) to the equator is pi / 2: within 1%
    V = np.array([v.co for v in obj.data.vertices])
    equator = np.abs(V[:, 2]) < 1e-6
    assert np.mean(modal.result.distance[equator]) == pytest.approx(np.pi / 2, rel=0.01)
    # the script API's own progress rises to 1 through the same build stages
    fractions = [f for f, _ in seen]
    assert rising(fractions) and fractions[-1] == 1.0
    assert "factoring the Poisson matrix" in [m for _, m in seen]

    # the next click finds the solver in the cache: no thread is needed
    again = stages.prepare_run(obj, sources=[5], isolines=10, m=1.0)
    assert again.cached and again.solver is modal.run.solver


def test_esc_mid_build_writes_nothing_and_caches_nothing(modules):
    background, cache = modules["background"], modules["cache"]
    obj = ico_sphere(4)
    select_only(obj, [3])
    modules["api"].compute_geodesic_distance(obj, m=2.0)  # a solver with other options is cached ...
    assert obj.data.session_uid in cache.SOLVERS
    before = snapshot(obj)
    modal, reports = modal_run(modules, obj, m=1.0)  # ... and dropped as stale when this build begins
    assert obj.data.session_uid not in cache.SOLVERS
    reached, release = gate(modal, modules, "factoring the heat matrix")
    modal.start()
    assert reached.wait(60)
    assert modal.handle(bpy.context, "ESC", "PRESS") == {"CANCELLED"}
    assert modal.display.ended == 1
    assert reports == [({"WARNING"}, "Geodesic distance cancelled at: factoring the heat matrix; nothing was written")]
    # the worker is finishing its stage: a new build is refused until it is gone
    other, _ = modal_run(modules, obj, m=3.0)
    with pytest.raises(background.Busy, match="cancelled build .* finishing its current stage"):
        other.start()
    release.set()
    assert modal.build.wait(60)
    assert background.BackgroundBuild.running() is None
    assert modal.build.poll() == "cancelled" and modal.run.solver is None
    assert modal.build.updates[-1][2] == "factoring the heat matrix"  # it stopped at the next stage
    with pytest.raises(background.Cancelled):
        modal.build.result()
    assert obj.data.session_uid not in cache.SOLVERS
    assert_same_snapshot(before, snapshot(obj))
    assert "geodesic_distance" in obj.data.attributes  # the m=2 run's, untouched
    other.start()  # now it may run
    assert drive(other) == {"FINISHED"}


def test_new_object_is_made_only_when_the_result_is_written(modules):
    obj = ico_sphere(2)  # 42 vertices, 120 edges, 80 triangles
    obj.modifiers.new("Subdivision", "SUBSURF").levels = 1
    select_only(obj, [0])
    cancelled, _ = modal_run(modules, obj, new_object=True)
    reached, release = gate(cancelled, modules, "factoring the heat matrix")
    cancelled.start()
    assert reached.wait(60)
    assert cancelled.handle(bpy.context, "ESC", "PRESS") == {"CANCELLED"}
    release.set()
    assert cancelled.build.wait(60)
    assert [o.name for o in bpy.data.objects] == [obj.name]  # no copy
    finished, _ = modal_run(modules, obj, new_object=True)
    finished.start()
    assert drive(finished) == {"FINISHED"}
    copy = finished.result.object
    assert copy.name == f"{obj.name} Geodesic" and len(copy.data.vertices) == 42 + 120 + 80  # vertices, edges, faces
    expected = modules["api"].compute_geodesic_distance(obj, sources=[0], new_object=True)
    assert expected.object == copy
    np.testing.assert_array_equal(finished.result.sources, expected.sources)
    np.testing.assert_allclose(finished.result.distance, expected.distance, rtol=1e-12, atol=1e-12)


def test_second_build_is_refused_while_one_runs_and_edit_mode_is_respected(modules):
    background = modules["background"]
    first_obj, second_obj = ico_sphere(3), ico_sphere(3)
    select_only(first_obj, [0])
    select_only(second_obj, [0])
    first, _ = modal_run(modules, first_obj)
    reached, release = gate(first, modules, "factoring the Poisson matrix")
    first.start()
    assert reached.wait(60)
    second, _ = modal_run(modules, second_obj)
    with pytest.raises(background.Busy, match=r"already building the heat solver of 'Icosphere' \(162 vertices\) "
                                               r"\(factoring the Poisson matrix, \d+%\)"):
        second.start()
    # the user goes on working: makes the object active and goes into Edit Mode on it
    bpy.context.view_layer.objects.active = first_obj
    bpy.ops.object.mode_set(mode="EDIT")
    release.set()
    assert drive(first) == {"FINISHED"}
    assert first_obj.mode == "EDIT"  # the result was written in Object Mode, and the mode restored
    bpy.ops.object.mode_set(mode="OBJECT")
    np.testing.assert_allclose(attribute(first_obj.data, "geodesic_distance"), first.result.distance, rtol=1e-6)
    second.start()
    assert drive(second) == {"FINISHED"}


def test_mesh_changed_while_building_is_reported_and_not_written(modules):
    cache = modules["cache"]
    obj = ico_sphere(3)
    select_only(obj, [0])
    modal, reports = modal_run(modules, obj)
    reached, release = gate(modal, modules, "factoring the heat matrix")
    modal.start()
    assert reached.wait(60)
    obj.data.vertices[7].co.x += 0.25  # the user moves a vertex meanwhile
    obj.data.update()
    before = snapshot(obj)
    release.set()
    assert drive(modal) == {"CANCELLED"}
    assert modal.display.ended == 1
    assert reports == [({"ERROR"}, f"{obj.name!r} changed while its solver was being built (its shape or its "
                                   "vertices); nothing was written: run it again")]
    assert_same_snapshot(before, snapshot(obj))
    assert "geodesic_distance" not in obj.data.attributes
    assert obj.data.session_uid not in cache.SOLVERS


def test_object_deleted_while_building_is_reported(modules):
    obj = ico_sphere(3)
    select_only(obj, [0])
    name = obj.name
    modal, reports = modal_run(modules, obj)
    reached, release = gate(modal, modules, "intrinsic Delaunay flips")
    modal.start()
    assert reached.wait(60)
    bpy.data.objects.remove(obj)
    release.set()
    assert drive(modal) == {"CANCELLED"}
    assert reports == [({"ERROR"}, f"{name!r} was deleted while its solver was being built; nothing was written")]
    assert modal.display.ended == 1


@pytest.mark.filterwarnings("ignore:ignored 1 faces with repeated vertices")
def test_a_failing_build_is_reported_and_writes_nothing(modules):
    mesh = bpy.data.meshes.new("collapsed")
    mesh.from_pydata([(0, 0, 0)] * 3, [], [(0, 1, 2)])  # three vertices at one point: no area
    obj = bpy.data.objects.new("collapsed", mesh)
    bpy.context.collection.objects.link(obj)
    select_only(obj, [0])
    before = snapshot(obj)
    modal, reports = modal_run(modules, obj, space="LOCAL")
    modal.start()
    assert drive(modal) == {"CANCELLED"}
    assert modal.build.poll() == "failed"
    with pytest.raises(hc.InvalidMeshError):
        modal.build.result()
    [(kind, text)] = reports
    assert kind == {"ERROR"} and "the mesh has no area" in text  # nothing merged in Blender
    assert modal.display.ended == 1
    assert_same_snapshot(before, snapshot(obj))


def test_headless_operator_stays_synchronous_and_the_display_calls_exist(modules, monkeypatch):
    background = modules["background"]
    obj = ico_sphere(3)
    select_only(obj, [0])

    def no_thread(self):
        raise AssertionError("bpy.app.background: no background build")

    monkeypatch.setattr(background.BackgroundBuild, "start", no_thread)
    with bpy.context.temp_override(active_object=obj, object=obj):
        assert bpy.ops.mesh.heat_geodesic_distance("INVOKE_DEFAULT") == {"FINISHED"}
    assert "geodesic_distance" in obj.data.attributes  # written before the call returned
    # the status bar, header, timer and progress calls of the ProgressDisplay exist in this Blender
    window = bpy.context.window_manager.windows[0]
    area = next(a for a in window.screen.areas if a.type == "VIEW_3D")
    with bpy.context.temp_override(window=window, area=area):
        display = modules["display"].ProgressDisplay(bpy.context, "Geodesic distance")
        assert display.timer.time_step == pytest.approx(modules["display"].QUICK_STEP)  # quick looks first
        display.progress(0.42, "factoring the heat matrix")
        assert display.timer.time_step == pytest.approx(modules["display"].QUICK_STEP)  # still within QUICK_SPAN
        later = display.started + modules["display"].QUICK_SPAN + 0.01
        monkeypatch.setattr(modules["display"].time, "monotonic", lambda: later)
        display.progress(0.5, "factoring the heat matrix")  # a long build: the timer slows down
        assert display.timer.time_step == pytest.approx(modules["display"].TIMER_STEP)
        display.text("Geodesic probe: click on the surface", "Esc: cancel")
        display.ready()
        display.end()
        display.end()  # every exit path ends it; twice is harmless
    assert display.ended
