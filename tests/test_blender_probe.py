"""The interactive geodesic probe (issue 20) with the real ``bpy`` (Blender 5.0 headless).

A headless ``bpy`` has no window, no event loop and no GPU: the probe's logic
is :class:`blender_addon.probe.GeodesicProbe`, driven here directly, and the
modal operator's is :class:`blender_addon.probe_session.ProbeSession`, fed
event-like objects with a ``locate`` that casts a straight-down ray through
the real ray-casting tree (mouse x, y -> world x, y). The overlay's draw
callback cannot run; the data it draws is checked instead.
"""

import importlib
import threading
import time
import tracemalloc
from dataclasses import dataclass

import blender_required  # noqa: F401 (first: without bpy, the module is skipped)
import bpy
import numpy as np
import pytest
from test_blender import (  # noqa: F401 (fixtures)
    addon,
    assert_same_snapshot,
    attribute,
    empty_scene,
    ico_sphere,
    select_only,
    snapshot,
)

import heatcore as hc
from heatcore.viz.colormap import colorize

HAS_PATHS = hasattr(hc.HeatSolver, "geodesic_path")


@pytest.fixture(scope="module")
def mods(addon):  # noqa: F811
    names = ("probe", "probe_tool", "probe_session", "probe_surface", "overlay", "curves", "adapters", "api",
             "background", "legend")
    return {name: importlib.import_module(f"blender_addon.{name}") for name in names}


@pytest.fixture(autouse=True)
def no_leaks(mods):
    """Every test ends with no probe running and no draw handler left (each test ends its probes)."""
    yield
    running, live = mods["probe"].running(), set(mods["overlay"].Overlay.live)
    for probe in running:
        probe.end()
    assert not running and not live


@dataclass
class Event:
    """What the operator's ``modal`` reads of a ``bpy.types.Event``."""

    type: str
    value: str = "PRESS"
    mouse_x: int = 0
    mouse_y: int = 0
    shift: bool = False
    ctrl: bool = False
    alt: bool = False


class RecordingDisplay:
    """Stands in for the ProgressDisplay (header, status bar, build progress)."""

    def __init__(self):
        self.texts, self.progresses, self.ended, self.readied = [], [], 0, 0
        self.awake = False

    def text(self, message, keys):
        self.texts.append(message)

    def wake(self, on=True):
        self.awake = on

    def progress(self, fraction, message):
        self.progresses.append((fraction, message))

    def ready(self):
        self.readied += 1

    def end(self):
        self.ended += 1


#: Mouse pixels per world unit of the straight-down view used by the tests (mouse (500, 500) is x = y = 0).
PIXELS = 200.0


def to_mouse(x, y):
    return round(500 + PIXELS * x), round(500 + PIXELS * y)


def session(mods, probe, **kw):
    reports = []

    def locate(event):
        origin = ((event.mouse_x - 500) / PIXELS, (event.mouse_y - 500) / PIXELS, 10.0)
        hit = probe.ray_cast(origin, (0.0, 0.0, -1.0))
        return hit if hit is not None else f"the cursor is not on {probe.run.object_name!r}"

    s = mods["probe_session"].ProbeSession(probe, RecordingDisplay(), locate, lambda k, m: reports.append((k, m)), **kw)
    return s, reports


def grid(n=24, size=2.0):
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=n, y_subdivisions=n, size=size)
    return bpy.context.active_object


def loop_triangle_data(mesh):
    mesh.calc_loop_triangles()
    F = np.empty(3 * len(mesh.loop_triangles), dtype=np.int64)
    mesh.loop_triangles.foreach_get("vertices", F)
    polys = np.empty(len(mesh.loop_triangles), dtype=np.int64)
    mesh.loop_triangle_polygons.foreach_get("value", polys)
    return F.reshape(-1, 3), polys


def world(obj):
    co = np.empty(3 * len(obj.data.vertices))
    obj.data.vertices.foreach_get("co", co)
    M = np.array(obj.matrix_world)
    return co.reshape(-1, 3) @ M[:3, :3].T + M[:3, 3]


# ---------------------------------------------------------------- the probe against heatcore


def test_a_face_point_matches_heatcore_and_the_ray_hits_the_loop_triangle(mods):
    bpy.ops.mesh.primitive_uv_sphere_add(segments=24, ring_count=12)  # quads and triangle fans
    obj = bpy.context.active_object
    obj.scale = (1.0, 1.5, 0.8)
    obj.rotation_euler = (0.3, 0.2, 0.1)
    bpy.context.view_layer.update()
    probe = mods["probe"].GeodesicProbe(obj, isolines=8)
    V, (F, polys) = world(obj), loop_triangle_data(obj.data)
    np.testing.assert_array_equal(probe.triangles, F)
    bary = np.array([0.2, 0.3, 0.5])
    d = probe.move_to(100, bary)
    solver = hc.HeatSolver(hc.TriangleMesh(V, F))  # refine="auto", as the add-on
    expected = solver.distance(points=([100], [bary]))
    np.testing.assert_allclose(d, expected, rtol=1e-9, atol=1e-12)
    assert probe.distance_at(300, (1.0, 0.0, 0.0)) == pytest.approx(expected[F[300, 0]], rel=1e-12)
    w = np.array([0.1, 0.6, 0.3])
    assert probe.distance_at(300, w) == pytest.approx(w @ expected[F[300]], rel=1e-12)

    # A ray through a triangle's centroid along its normal hits that triangle at (1/3, 1/3, 1/3), and
    # Blender's own ray cast of the evaluated object names the polygon the loop triangle belongs to.
    depsgraph = bpy.context.evaluated_depsgraph_get()
    inverse = np.linalg.inv(np.array(obj.matrix_world))
    for face in (0, 7, 150, len(F) - 1):
        a, b, c = V[F[face]]
        centroid, normal = (a + b + c) / 3, np.cross(b - a, c - a)
        normal /= np.linalg.norm(normal)
        hit = probe.ray_cast(centroid + 2 * normal, -normal)
        assert hit.face == face and hit.depth == pytest.approx(2.0, rel=1e-5)
        np.testing.assert_allclose(hit.barycentric, [1 / 3] * 3, atol=1e-5)
        origin = (inverse @ np.r_[centroid + 2 * normal, 1.0])[:3]
        found, _, _, polygon = obj.evaluated_get(depsgraph).ray_cast(origin, inverse[:3, :3] @ -normal)
        assert found and polygon == polys[face]
    assert probe.ray_cast((5.0, 5.0, 5.0), (1.0, 0.0, 0.0)) is None
    probe.cancel()


def test_cancel_leaves_attributes_active_color_selection_and_mode_bit_identical(mods):
    obj = ico_sphere(subdivisions=3)
    mesh = obj.data
    mesh.attributes.new("user_float", "FLOAT", "POINT").data.foreach_set("value", np.arange(len(mesh.vertices), dtype=np.float32))
    mesh.color_attributes.new("user_colors", "BYTE_COLOR", "CORNER")
    mesh.color_attributes.active_color = mesh.color_attributes["user_colors"]
    obj.vertex_groups.new(name="group").add([0, 1, 2], 0.5, "REPLACE")
    select_only(obj, [3, 4, 5])
    bpy.ops.object.mode_set(mode="EDIT")  # Edit Mode makes edges and faces agree with the vertex selection
    bpy.ops.object.mode_set(mode="OBJECT")
    for mode in ("OBJECT", "EDIT"):
        before = snapshot(obj)
        active_color, render = mesh.color_attributes.active_color_name, mesh.color_attributes.render_color_index
        bpy.ops.object.mode_set(mode=mode)
        probe = mods["probe"].GeodesicProbe(obj, isolines=5, weight_group="weights", refine=0)
        for face in (3, 40, 77):
            probe.move_to(face, (0.5, 0.25, 0.25))
        probe.add(12, (0.1, 0.1, 0.8))
        assert len(mods["overlay"].Overlay.live) == 1
        probe.cancel()
        assert obj.mode == mode and not mods["overlay"].Overlay.live
        bpy.ops.object.mode_set(mode="OBJECT")
        assert_same_snapshot(before, snapshot(obj))
        assert mesh.color_attributes.active_color_name == active_color
        assert mesh.color_attributes.render_color_index == render
        assert "weights" not in obj.vertex_groups and "geodesic_distance" not in mesh.attributes
        with pytest.raises(mods["adapters"].AddonError, match="has ended"):
            probe.move_to(3, (1.0, 0.0, 0.0))


def test_confirm_writes_what_the_one_shot_operator_writes_as_one_undo_step(mods):
    options = {"isolines": 6, "colormap": "magma", "weight_group": "weights", "weight_falloff": "SMOOTH", "refine": 0}
    twin = ico_sphere(subdivisions=3)
    obj = ico_sphere(subdivisions=3)
    bpy.ops.ed.undo_push(message="before")
    probe = mods["probe"].GeodesicProbe(obj, **options)
    probe.add(7)
    probe.move_to(20, (0.3, 0.3, 0.4))  # dragged elsewhere, then onto a vertex
    probe.move_to(11)
    probe.add(100)
    result = probe.confirm()
    expected = mods["api"].compute_geodesic_distance(twin, sources=[11, 100], **options)
    np.testing.assert_array_equal(result.sources, [11, 100])
    assert result.max_distance == expected.max_distance
    for name in ("geodesic_distance", "geodesic_distance_color"):
        np.testing.assert_array_equal(attribute(obj.data, name), attribute(twin.data, name))
    weights = [[g.weight for g in v.groups] for v in obj.data.vertices]
    assert weights == [[g.weight for g in v.groups] for v in twin.data.vertices]
    assert obj.data.color_attributes.active_color_name == "geodesic_distance_color"
    assert not mods["overlay"].Overlay.live and probe.ended
    name = obj.name
    bpy.ops.ed.undo()
    obj = bpy.data.objects[name]
    assert "geodesic_distance" not in obj.data.attributes and "weights" not in obj.vertex_groups


def test_confirm_in_edit_mode_writes_and_stays_in_edit_mode(mods):
    twin = ico_sphere(subdivisions=2)
    obj = ico_sphere(subdivisions=2)
    bpy.ops.object.mode_set(mode="EDIT")
    probe = mods["probe"].GeodesicProbe(obj, refine=0)
    probe.add(5, (0.2, 0.2, 0.6))
    probe.confirm()
    assert obj.mode == "EDIT"
    bpy.ops.object.mode_set(mode="OBJECT")
    V, (F, _) = world(twin), loop_triangle_data(twin.data)
    expected = hc.HeatSolver(hc.TriangleMesh(V, F, refine=0)).distance(points=([5], [[0.2, 0.2, 0.6]]))
    np.testing.assert_allclose(attribute(obj.data, "geodesic_distance"), expected, rtol=1e-6)


def test_moving_the_source_100_times_grows_no_memory_handlers_or_layers(mods):
    obj = ico_sphere(subdivisions=4)
    probe = mods["probe"].GeodesicProbe(obj, refine=0, isolines=10)
    layers = sorted(a.name for a in obj.data.attributes)
    counts = (len(bpy.data.meshes), len(bpy.data.objects), len(bpy.data.materials), len(bpy.data.curves))
    rng = np.random.default_rng(1)
    faces = rng.integers(0, len(probe.triangles), size=140)
    barys = rng.dirichlet(np.ones(3), size=140)
    tracemalloc.start()
    try:
        for f, b in zip(faces[:40], barys[:40]):  # heatcore keeps the last 64 pinned vertices' responses
            probe.move_to(f, b)
        probe.overlay_data()
        settled = tracemalloc.get_traced_memory()[0]
        for f, b in zip(faces[40:], barys[40:]):
            probe.move_to(f, b)
            assert len(mods["overlay"].Overlay.live) == 1
        probe.overlay_data()
        grown = tracemalloc.get_traced_memory()[0] - settled
    finally:
        tracemalloc.stop()
    assert grown < 200_000, f"{grown} bytes more after 100 moves"
    assert len(probe.sources) == 1
    assert sorted(a.name for a in obj.data.attributes) == layers
    assert counts == (len(bpy.data.meshes), len(bpy.data.objects), len(bpy.data.materials), len(bpy.data.curves))
    probe.cancel()
    assert not mods["overlay"].Overlay.live


def test_the_solver_and_the_ray_tree_are_reused_while_the_mesh_is_unchanged(mods):
    obj = ico_sphere(subdivisions=3)
    first = mods["probe"].GeodesicProbe(obj, refine=0)
    first.cancel()
    second = mods["probe"].GeodesicProbe(obj, refine=0)
    assert second.run.cached and second.run.solver is first.run.solver and second.surface is first.surface
    second.cancel()
    obj.data.vertices[0].co.x += 0.1
    obj.data.update()
    third = mods["probe"].GeodesicProbe(obj, refine=0)
    assert not third.run.cached and third.surface is not first.surface
    third.cancel()


# ---------------------------------------------------------------- the modal operator's events


def test_events_hover_click_drag_shift_ctrl_enter(mods):
    obj = grid()
    probe = mods["probe"].GeodesicProbe(obj, boundary="neumann", isolines=4)  # refined 2 levels: 8,833 vertices
    s, reports = session(mods, probe)
    texts = s.display.texts
    assert texts[-1].endswith("click on the surface")
    assert s.handle(Event("MOUSEMOVE", "NOTHING", *to_mouse(0.1, 0.1))) == {"RUNNING_MODAL"}
    assert "click on the surface" in texts[-1] and probe.distance is None  # nothing placed by hovering
    assert s.handle(Event("MOUSEMOVE", "NOTHING", *to_mouse(3.0, 0.0))) == {"RUNNING_MODAL"}
    assert texts[-1] == "the cursor is not on 'Grid'"

    assert s.handle(Event("LEFTMOUSE", "PRESS", *to_mouse(-0.5, -0.5))) == {"RUNNING_MODAL"}
    assert len(probe.sources) == 1 and s.dragging
    for x in (-0.45, -0.4, -0.3):  # the drag moves the one source
        assert s.handle(Event("MOUSEMOVE", "NOTHING", *to_mouse(x, -0.5))) == {"RUNNING_MODAL"}
    assert len(probe.sources) == 1 and "1 source, farthest" in texts[-1]
    np.testing.assert_allclose(probe.world_point(*probe.sources[0])[:2], [-0.3, -0.5], atol=0.5 / PIXELS)
    np.testing.assert_allclose(probe.overlay_data().sources[0], probe.world_point(*probe.sources[0]), atol=1e-6)
    assert probe.dragging and probe.overlay_data().isolines == []  # no isoline curves while dragging
    assert s.handle(Event("LEFTMOUSE", "RELEASE", *to_mouse(-0.3, -0.5))) == {"RUNNING_MODAL"}
    assert not s.dragging and not probe.dragging and len(probe.overlay_data().isolines) >= 4
    field = probe.distance.copy()
    assert s.handle(Event("MOUSEMOVE", "NOTHING", *to_mouse(0.5, 0.5))) == {"RUNNING_MODAL"}
    np.testing.assert_array_equal(probe.distance, field)  # hovering after the release: no update
    euclid = np.hypot(0.5 + 0.3, 0.5 + 0.5)
    hit = probe.ray_cast((0.5, 0.5, 10.0), (0.0, 0.0, -1.0))
    shown = mods["legend"].format_distance(probe.distance_at(hit.face, hit.barycentric), "WORLD", bpy.context.scene)
    assert texts[-1] == f"Distance under the cursor: {shown}" and shown.endswith(" m")
    assert probe.distance_at(hit.face, hit.barycentric) == pytest.approx(euclid, rel=0.02)

    assert s.handle(Event("LEFTMOUSE", "PRESS", *to_mouse(0.6, -0.6), shift=True)) == {"RUNNING_MODAL"}
    assert s.handle(Event("LEFTMOUSE", "RELEASE", *to_mouse(0.6, -0.6))) == {"RUNNING_MODAL"}
    assert len(probe.sources) == 2 and "2 sources" in texts[-1]
    assert s.handle(Event("MIDDLEMOUSE", "PRESS")) == {"PASS_THROUGH"}  # view navigation
    assert s.handle(Event("WHEELUPMOUSE", "PRESS")) == {"PASS_THROUGH"}
    assert s.handle(Event("TIMER", "NOTHING")) == {"PASS_THROUGH"}
    assert s.handle(Event("A", "PRESS")) == {"RUNNING_MODAL"}  # other keys do nothing while the probe runs

    assert s.handle(Event("LEFTMOUSE", "PRESS", *to_mouse(0.2, 0.7), ctrl=True)) == {"RUNNING_MODAL"}
    s.handle(Event("LEFTMOUSE", "RELEASE", *to_mouse(0.2, 0.7)))
    if HAS_PATHS:
        assert probe.path is not None and texts[-1].startswith("Path to the target")
        np.testing.assert_allclose(probe.path.points[-1][:2], [0.2, 0.7], atol=1e-3)
    else:
        assert "needs heatcore's geodesic paths" in texts[-1] and probe.target is None
    assert len(probe.sources) == 2

    assert s.handle(Event("RET", "PRESS")) == {"FINISHED"}
    assert s.display.ended == 1 and reports[-1][0] == {"INFO"} and "2 sources" in reports[-1][1]
    V, (F, _) = world(obj), loop_triangle_data(obj.data)
    faces = [f for f, _ in probe.sources]
    expected = hc.HeatSolver(hc.TriangleMesh(V, F), boundary="neumann").distance(
        points=(faces, [b for _, b in probe.sources]))
    np.testing.assert_allclose(attribute(obj.data, "geodesic_distance"), expected, rtol=1e-6)
    assert not mods["overlay"].Overlay.live


@pytest.mark.parametrize("key", ["ESC", "RIGHTMOUSE"])
def test_esc_and_right_click_cancel_and_write_nothing(mods, key):
    obj = grid(8)
    before = snapshot(obj)
    s, reports = session(mods, mods["probe"].GeodesicProbe(obj, refine=0))
    s.handle(Event("LEFTMOUSE", "PRESS", *to_mouse(0.1, 0.2)))
    s.handle(Event("MOUSEMOVE", "NOTHING", *to_mouse(0.2, 0.2)))
    assert s.handle(Event(key, "PRESS")) == {"CANCELLED"}
    assert reports == [({"WARNING"}, "Geodesic probe cancelled; nothing was written")]
    assert_same_snapshot(before, snapshot(obj))
    assert s.display.ended == 1 and not mods["overlay"].Overlay.live


def test_enter_with_no_source_says_so_and_goes_on(mods):
    obj = grid(8)
    s, reports = session(mods, mods["probe"].GeodesicProbe(obj, refine=0))
    assert s.handle(Event("RET", "PRESS")) == {"RUNNING_MODAL"}
    assert "no source placed" in s.display.texts[-1] and "geodesic_distance" not in obj.data.attributes
    assert reports == []
    s.cancel()


def test_the_toolbar_tool_places_on_press_and_confirms_on_release_shift_adds_to_its_last_sources(mods):
    obj = grid(10)
    probe = mods["probe"].GeodesicProbe(obj, refine=0)
    s, _ = session(mods, probe, release_confirms=True, press=Event("LEFTMOUSE", "PRESS", *to_mouse(-0.5, 0.0)))
    assert len(probe.sources) == 1 and s.dragging  # the press that started the tool placed the source
    s.handle(Event("MOUSEMOVE", "NOTHING", *to_mouse(-0.4, 0.0)))
    assert s.handle(Event("LEFTMOUSE", "RELEASE", *to_mouse(-0.4, 0.0))) == {"FINISHED"}
    first, first_source = attribute(obj.data, "geodesic_distance").copy(), probe.sources[0]

    probe = mods["probe"].GeodesicProbe(obj, refine=0)  # the next click, with Shift
    s, _ = session(mods, probe, release_confirms=True,
                   press=Event("LEFTMOUSE", "PRESS", *to_mouse(0.5, 0.0), shift=True))
    assert len(probe.sources) == 2
    assert s.handle(Event("LEFTMOUSE", "RELEASE", *to_mouse(0.5, 0.0))) == {"FINISHED"}
    first_point, second_point = probe.sources
    assert first_point[0] == first_source[0] and np.array_equal(first_point[1], first_source[1])
    V, (F, _) = world(obj), loop_triangle_data(obj.data)
    expected = hc.HeatSolver(hc.TriangleMesh(V, F, refine=0)).distance(
        points=([first_point[0], second_point[0]], [first_point[1], second_point[1]]))
    np.testing.assert_allclose(attribute(obj.data, "geodesic_distance"), expected, rtol=1e-6)
    assert expected.max() < 0.8 * first.max()

    probe = mods["probe"].GeodesicProbe(obj, refine=0)  # a click off the mesh ends the tool at once
    s, reports = session(mods, probe, release_confirms=True, press=Event("LEFTMOUSE", "PRESS", *to_mouse(4.0, 0.0)))
    assert probe.ended and s.display.texts[-1] == "the cursor is not on 'Grid'" and reports == []


# ---------------------------------------------------------------- the background build


def test_the_solver_is_built_in_the_background_and_the_tools_click_waits_for_it(mods):
    obj = ico_sphere(subdivisions=3)
    probe = mods["probe"].GeodesicProbe(obj, background=True)  # refine="auto": 642 vertices refined
    assert not probe.ready and mods["background"].BackgroundBuild.running() is probe.build
    with pytest.raises(mods["adapters"].AddonError, match="still being built"):
        probe.move_to(0, (1.0, 0.0, 0.0))
    top = to_mouse(0.05, 0.05)  # the sphere's top, seen from above
    s, reports = session(mods, probe, release_confirms=True, press=Event("LEFTMOUSE", "PRESS", *top))
    assert s.display.progresses and not probe.sources
    assert s.handle(Event("LEFTMOUSE", "RELEASE", *top)) == {"PASS_THROUGH"}  # released during the build
    assert probe.build.wait(120)
    assert s.handle(Event("TIMER", "NOTHING")) == {"FINISHED"}  # placed, then confirmed: it was released
    assert s.display.readied == 1 and len(probe.sources) == 1 and probe.run.cached is False
    messages = [m for _, _, m in probe.build.updates]
    assert "factoring the heat matrix" in messages and messages[-1] == "preparing the ray casting"
    assert s.display.progresses[0][1] in messages and 0 <= s.display.progresses[0][0] < 1
    d = attribute(obj.data, "geodesic_distance")
    assert d.min() < 0.1 and reports[-1][0] == {"INFO"}
    again = mods["probe"].GeodesicProbe(obj)
    assert again.run.cached and again.surface is probe.surface  # kept for the next tool session
    again.cancel()


def test_esc_during_the_build_cancels_it_and_keeps_no_solver(mods):
    obj = ico_sphere(subdivisions=3)
    probe = mods["probe"].GeodesicProbe(obj, background=True)
    s, _ = session(mods, probe)
    assert s.handle(Event("ESC", "PRESS")) == {"CANCELLED"}
    assert probe.build.poll() == "cancelled" and probe.ended and not mods["overlay"].Overlay.live
    probe.build.wait(120)
    assert obj.data.session_uid not in mods["probe"].SOLVERS
    assert "geodesic_distance" not in obj.data.attributes


# ---------------------------------------------------------------- bad input


def test_a_non_mesh_or_a_mesh_without_faces_is_refused(mods):
    AddonError = mods["adapters"].AddonError
    bpy.ops.object.empty_add()
    empty = bpy.context.active_object
    with pytest.raises(AddonError, match="needs a mesh object; 'Empty' is not one"):
        mods["probe"].GeodesicProbe(empty)
    assert not bpy.ops.mesh.heat_geodesic_probe.poll()
    mesh = bpy.data.meshes.new("cloud")
    mesh.from_pydata([(0, 0, 0), (1, 0, 0), (0, 1, 0)], [], [])
    cloud = bpy.data.objects.new("cloud", mesh)
    bpy.context.scene.collection.objects.link(cloud)
    with pytest.raises(AddonError, match="places sources on faces: mesh 'cloud' has none"):
        mods["probe"].GeodesicProbe(cloud)
    with pytest.raises(AddonError, match="new_object is not available"):
        mods["probe"].GeodesicProbe(ico_sphere(1), new_object=True)
    assert not mods["overlay"].Overlay.live and not mods["probe"].running()
    interactive = "the geodesic probe is interactive: start it in a 3D Viewport"
    with bpy.context.temp_override(active_object=cloud, object=cloud), pytest.raises(RuntimeError, match=interactive):
        bpy.ops.mesh.heat_geodesic_probe("INVOKE_DEFAULT")  # headless: no 3D View to run in


def test_an_edit_while_the_tool_runs_ends_it_with_a_message_and_writes_nothing(mods):
    obj = grid(8)
    probe = mods["probe"].GeodesicProbe(obj, refine=0)
    s, reports = session(mods, probe)
    s.handle(Event("LEFTMOUSE", "PRESS", *to_mouse(0.1, 0.1)))
    obj.data.vertices[0].co.z += 0.5
    obj.data.update()
    bpy.context.view_layer.update()  # what Blender does after any edit: the probe is flagged
    assert probe.changed
    assert s.handle(Event("MOUSEMOVE", "NOTHING", *to_mouse(0.2, 0.1))) == {"CANCELLED"}
    assert reports[-1][0] == {"ERROR"} and "'Grid' changed while the geodesic probe ran" in reports[-1][1]
    assert "geodesic_distance" not in obj.data.attributes and not mods["overlay"].Overlay.live


def test_an_edit_the_handler_did_not_see_is_caught_by_confirm(mods):
    obj = grid(8)
    probe = mods["probe"].GeodesicProbe(obj, refine=0)
    probe.add(3, (0.2, 0.3, 0.5))
    obj.data.vertices[0].co.z += 0.5  # no depsgraph update: not flagged
    with pytest.raises(mods["adapters"].AddonError, match="changed while the geodesic probe ran"):
        probe.confirm()
    assert "geodesic_distance" not in obj.data.attributes
    probe.cancel()


def test_a_deleted_object_ends_the_tool(mods):
    obj = grid(8)
    s, reports = session(mods, mods["probe"].GeodesicProbe(obj, refine=0))
    s.handle(Event("LEFTMOUSE", "PRESS", *to_mouse(0.1, 0.1)))
    bpy.data.objects.remove(obj)
    bpy.context.view_layer.update()
    assert s.handle(Event("MOUSEMOVE", "NOTHING", *to_mouse(0.2, 0.1))) == {"CANCELLED"}
    assert reports[-1] == ({"ERROR"}, "'Grid' was deleted while the geodesic probe ran; nothing was written")
    assert not mods["overlay"].Overlay.live


def test_a_second_build_while_one_runs_is_refused_and_leaks_nothing(mods):
    a, b = ico_sphere(3), ico_sphere(3)
    b.location.x = 5
    first = mods["probe"].GeodesicProbe(a, background=True)
    with pytest.raises(mods["background"].Busy, match="already building the heat solver of 'Icosphere'"):
        mods["probe"].GeodesicProbe(b, background=True)
    assert mods["probe"].running() == [first] and len(mods["overlay"].Overlay.live) == 1
    first.cancel()
    first.build.wait(120)


def test_another_object_in_front_of_the_mesh_is_named(mods):
    obj = grid(8)
    bpy.ops.mesh.primitive_cube_add(size=0.5, location=(0.5, 0.5, 1.0))
    depsgraph = bpy.context.evaluated_depsgraph_get()
    occluder = mods["probe_tool"].occluder
    assert occluder(depsgraph, obj.name, (0.5, 0.5, 5.0), (0, 0, -1), 5.0) == "Cube"
    assert occluder(depsgraph, obj.name, (-0.5, -0.5, 5.0), (0, 0, -1), 5.0) is None
    assert occluder(depsgraph, "Cube", (0.5, 0.5, 5.0), (0, 0, -1), 5.0) is None  # itself


# ---------------------------------------------------------------- what the overlay draws


def test_overlay_colors_are_the_written_colors_at_the_tables_steps(mods):
    overlay, adapters = mods["overlay"], mods["adapters"]
    obj = ico_sphere(subdivisions=3)
    obj.data.vertices.add(1)  # a loose vertex: unreachable, grey
    obj.data.update()
    probe = mods["probe"].GeodesicProbe(obj, isolines=7, colormap="plasma", refine=0)
    d = probe.move_to(9, (0.6, 0.2, 0.2))
    data = probe.overlay_data()
    assert data.colors.dtype == np.float32 and data.colors.shape == (len(d), 4)
    steps = np.floor(d[:-1] * ((overlay.COLOR_STEPS - 1) / d[:-1].max()) + 0.5) / (overlay.COLOR_STEPS - 1)
    exact = adapters.srgb_to_linear(colorize(steps, colormap="plasma", isolines=7, vmax=1.0))
    np.testing.assert_array_equal(data.colors[:-1, :3], exact)  # colorize at the nearest of the table's steps
    np.testing.assert_array_equal(data.colors[-1, :3], adapters.srgb_to_linear(colorize(np.array([np.inf]))[0]))
    assert (data.colors[:, 3] == 1).all()
    written = adapters.srgb_to_linear(colorize(d, colormap="plasma", isolines=7))
    near = np.abs(written - data.colors[:, :3]).max(axis=1) < 2e-3  # the step: 1/8190 of the maximum
    assert near.mean() > 0.99  # the others straddle an isoline stripe's edge
    np.testing.assert_array_equal(data.positions, world(obj).astype(np.float32))
    np.testing.assert_array_equal(data.triangles, loop_triangle_data(obj.data)[0])
    assert data.triangles.dtype == np.uint32 and data.positions.dtype == np.float32
    # heatcore's isoline curves (7 closed loops around the source, on the world positions), but not during a drag
    curves = hc.isolines(world(obj), loop_triangle_data(obj.data)[0], d, 7)
    assert len(curves) == len(data.isolines) == 7 and all(c.closed for c in curves)
    for curve, drawn in zip(curves, data.isolines):
        np.testing.assert_array_equal(drawn, curve.points.astype(np.float32))
    probe.dragging = True
    assert probe.overlay_data().isolines == []
    probe.end_drag()
    assert not probe.dragging and len(probe.overlay_data().isolines) == 7
    probe.cancel()


def test_overlay_geometry_helpers(mods):
    from mathutils import Matrix

    overlay = mods["overlay"]
    segments = overlay.line_segments([np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0]]), np.zeros((1, 3))])
    np.testing.assert_array_equal(segments, [[0, 0, 0], [1, 0, 0], [1, 0, 0], [1, 1, 0]])
    assert overlay.line_segments([]).shape == (0, 3)
    # The offset pulls depths towards the viewer by Blender's polygon offset: perspective and orthographic.
    near, far = 0.1, 100.0
    perspective = Matrix(((1, 0, 0, 0), (0, 1, 0, 0), (0, 0, -(far + near) / (far - near), -2 * far * near / (far - near)),
                          (0, 0, -1, 0)))
    orthographic = Matrix(((1, 0, 0, 0), (0, 1, 0, 0), (0, 0, -2 / (far - near), -(far + near) / (far - near)),
                           (0, 0, 0, 1)))
    for P in (perspective, orthographic):
        Q = overlay.offset_projection(P, view_distance=10.0)
        for depth in (0.5, 5.0, 50.0):
            p, q = P @ Matrix.Translation((0, 0, -depth)).col[3], Q @ Matrix.Translation((0, 0, -depth)).col[3]
            z_p, z_q = p.z / p.w, q.z / q.w
            assert z_q < z_p and z_p - z_q < 1e-3
    assert overlay.offset_projection(perspective, 10.0)[2][3] == pytest.approx(perspective[2][3] * 1.00125)
    assert overlay.offset_projection(orthographic, 10.0)[2][3] == pytest.approx(orthographic[2][3] - 5e-5)


def test_the_path_target_and_the_curve_objects(mods):
    obj = grid(10)
    probe = mods["probe"].GeodesicProbe(obj, refine=0, boundary="neumann", path_curve=True, isoline_curves=True,
                                        isolines=5)
    with pytest.raises(mods["adapters"].AddonError, match="place a source first|needs heatcore's geodesic paths"):
        probe.path_to(5, (1 / 3, 1 / 3, 1 / 3))
    probe.add(3, (0.2, 0.3, 0.5))
    if HAS_PATHS:
        path = probe.path_to(150, (0.5, 0.25, 0.25))
        np.testing.assert_allclose(path.points[0], probe.world_point(3, (0.2, 0.3, 0.5)), atol=1e-9)
        np.testing.assert_allclose(path.points[-1], probe.world_point(150, (0.5, 0.25, 0.25)), atol=1e-9)
        straight = np.linalg.norm(path.points[-1] - path.points[0])
        assert path.length == pytest.approx(straight, rel=1e-9)  # a flat grid: a straight line
        np.testing.assert_array_equal(probe.overlay_data().path, path.points.astype(np.float32))
    else:
        with pytest.raises(mods["adapters"].AddonError, match="needs heatcore's geodesic paths"):
            probe.path_to(150, (0.5, 0.25, 0.25))
        assert probe.target is None and probe.overlay_data().path is None
    d = probe.distance
    probe.confirm()
    if HAS_PATHS:
        curve = bpy.data.objects["Grid Geodesic Path"]
        co = np.empty(4 * len(curve.data.splines[0].points))
        curve.data.splines[0].points.foreach_get("co", co)
        np.testing.assert_allclose(co.reshape(-1, 4)[:, :3], path.points, atol=1e-6)
    else:
        assert "Grid Geodesic Path" not in bpy.data.objects  # no path, no curve
    isolines = bpy.data.objects["Grid Geodesic Isolines"]
    expected = hc.isolines(world(obj), loop_triangle_data(obj.data)[0], d, 5)
    assert len(isolines.data.splines) == len(expected) >= 5
    for spline, line in zip(isolines.data.splines, expected):
        co = np.empty(4 * len(spline.points))
        spline.points.foreach_get("co", co)
        np.testing.assert_allclose(co.reshape(-1, 4)[:, :3], line.points, atol=1e-6)
        assert spline.use_cyclic_u == line.closed
    # The curve writer itself: made once, updated in place.
    write = mods["curves"].write_curves
    first = write(obj, "Path", [[[0, 0, 0], [1, 0, 0], [1, 1, 0]]])
    second = write(obj, "Path", [[[0, 0, 1], [2, 0, 1]]])
    assert first == second and first.name == "Grid Geodesic Path" and len(first.data.splines) == 1
    co = np.empty(8)
    second.data.splines[0].points.foreach_get("co", co)
    np.testing.assert_array_equal(co, [0, 0, 1, 1, 2, 0, 1, 1])
    assert first.users_collection[0] == obj.users_collection[0]
    assert not mods["curves"].path_available(object())


def test_edit_mode_checks_do_not_flag_themselves(mods):
    obj = ico_sphere(subdivisions=2)
    bpy.ops.object.mode_set(mode="EDIT")
    probe = mods["probe"].GeodesicProbe(obj, refine=0)
    bpy.context.view_layer.update()
    assert not probe.changed  # syncing the edit mesh at the start was settled before the probe listened
    probe.check()
    bpy.context.view_layer.update()
    assert not probe.changed
    probe.add(0, (1.0, 0.0, 0.0))
    import bmesh

    bm = bmesh.from_edit_mesh(obj.data)
    bm.verts.ensure_lookup_table()
    bm.verts[0].co.z += 0.2
    bmesh.update_edit_mesh(obj.data)
    bpy.context.view_layer.update()
    assert probe.changed
    with pytest.raises(mods["adapters"].AddonError, match="changed while the geodesic probe ran"):
        probe.move_to(1, (1.0, 0.0, 0.0))
    probe.cancel()
    bpy.ops.object.mode_set(mode="OBJECT")


# ---------------------------------------------------------------- findable: menus, panel, toolbar


class Recorder:
    """A stand-in ``layout``: records the operators drawn."""

    def __init__(self):
        self.operators, self.operator_context = [], None

    def separator(self):
        pass

    def operator(self, idname, **kw):
        self.operators.append((idname, kw.get("text"), self.operator_context))
        return type("Props", (), {})()


def test_menus_panel_and_toolbar_have_the_probe(addon, mods):  # noqa: F811
    ico_sphere(1)
    entries = dict(addon.menus.ENTRIES)
    for menu, draw in entries.items():
        holder = type("Menu", (), {"layout": Recorder()})()
        draw(holder, bpy.context)
        ops = holder.layout.operators
        if menu in ("VIEW3D_MT_paint_weight", "VIEW3D_MT_edit_mesh_weights"):
            assert [o[0] for o in ops] == ["mesh.heat_geodesic_distance"], menu
        else:  # the probe just above the distance, both invoked (then Isoline Curves where it is shown)
            curves = [("mesh.heat_geodesic_isoline_curves", "Isoline Curves", "INVOKE_REGION_WIN")
                      ] if menu in addon.menus.CURVE_MENUS else []
            paths = [("mesh.heat_geodesic_path", "Geodesic Path", "INVOKE_REGION_WIN")
                     ] if menu in addon.menus.PATH_MENUS else []
            selects = [("mesh.heat_geodesic_select_within", "Within Geodesic Distance", "INVOKE_REGION_WIN")
                       ] if menu == addon.menus.SELECT_MENU else []
            assert ops == selects + [("mesh.heat_geodesic_probe", "Geodesic Probe", "INVOKE_REGION_WIN"),
                           ("mesh.heat_geodesic_distance", "Geodesic Distance", "INVOKE_REGION_WIN")] + curves + paths, menu
    from bl_ui.space_toolsystem_common import ToolSelectPanelHelper

    tools = ToolSelectPanelHelper._tool_class_from_space_type("VIEW_3D")._tools
    for mode, idname in (("OBJECT", "heat_geodesics.probe_object"), ("EDIT_MESH", "heat_geodesics.probe_edit")):
        names = [getattr(t, "idname", None) for t in tools[mode]]
        tool = tools[mode][names.index(idname)]
        assert names[names.index(idname) - 2] == "builtin.measure"  # after Measure, past a separator
        items = bpy.context.window_manager.keyconfigs.addon.keymaps[tool.keymap[0]].keymap_items
        keys = [(i.idname, i.type, i.value, i.shift, i.ctrl, i.properties.release_confirms) for i in items]
        assert keys == [("mesh.heat_geodesic_probe", "LEFTMOUSE", "PRESS", shift, ctrl, True)
                        for shift, ctrl in ((0, 0), (1, 0), (0, 1))]
    from pathlib import Path

    assert 'layout.operator("mesh.heat_geodesic_probe"' in Path(addon.panel.__file__).read_text()


# ---------------------------------------------------------------- the coarse preview of a drag (large meshes)


def test_a_drag_on_a_large_mesh_shows_the_coarse_preview_until_the_mouse_rests(mods, monkeypatch):
    """Issue 34: 0.56 s per update at 1M vertices; a drag now shows a coarse field (about 40 ms there)
    and the solver's field once the mouse rests (REST_SECONDS) or the button is up; confirm writes the exact one."""
    monkeypatch.setattr(mods["probe"], "PREVIEW_FROM", 100)  # a small grid stands in for a large mesh
    monkeypatch.setattr(mods["probe_session"], "REST_SECONDS", 0.0)
    obj = grid(40)
    probe = mods["probe"].GeodesicProbe(obj, isolines=8)
    s, _ = session(mods, probe)
    s.handle(Event("LEFTMOUSE", "PRESS", *to_mouse(-0.5, -0.5)))
    assert probe.exact  # a press: the solver's field
    s.handle(Event("MOUSEMOVE", "NOTHING", *to_mouse(-0.4, -0.5)))
    assert not probe.exact and s.display.awake  # the preview, and a timer to see the rest
    preview = probe.distance.copy()
    exact = probe.run.solver.distance(points=([probe.sources[0][0]], [probe.sources[0][1]]))
    assert np.isfinite(preview).all() and not np.allclose(preview, exact)
    assert np.abs(preview - exact).mean() < 0.05 * exact.max()  # coarse, not wrong
    assert s.handle(Event("TIMER", "NOTHING")) == {"PASS_THROUGH"}  # the mouse at rest
    assert probe.exact and not s.display.awake
    np.testing.assert_allclose(probe.distance, exact, rtol=1e-12, atol=1e-12)
    s.handle(Event("MOUSEMOVE", "NOTHING", *to_mouse(-0.3, -0.5)))
    assert not probe.exact
    result = probe.confirm()  # never the preview written
    assert probe.exact
    expected = probe.run.solver.distance(points=([probe.sources[0][0]], [probe.sources[0][1]]))
    np.testing.assert_allclose(result.distance, expected, rtol=1e-12, atol=1e-12)


def held_probe(mods, monkeypatch, obj, **options):
    """A probe built in the background whose solver build waits for ``release.set()``: ``(probe, release)``."""
    release, build_solver = threading.Event(), mods["probe"].build_solver

    def held(run, progress=None):
        assert release.wait(120)
        return build_solver(run, progress)

    monkeypatch.setattr(mods["probe"], "build_solver", held)
    probe = mods["probe"].GeodesicProbe(obj, background=True, **options)
    return probe, release


def wait_for(condition, seconds=60):
    deadline = time.monotonic() + seconds
    while not condition():
        assert time.monotonic() < deadline, "timed out"
        time.sleep(0.01)


def test_a_large_mesh_is_probed_on_its_coarse_preview_while_the_solver_builds(mods, monkeypatch):
    """Issue 34: the 1M-vertex probe's first start took 16-19 s; from PREVIEW_FROM vertices sources are placed and
    dragged on the coarse preview (made from the arrays first) while the solver builds, which then replaces it."""
    monkeypatch.setattr(mods["probe"], "PREVIEW_FROM", 100)  # a small grid stands in for a large mesh
    obj = grid(40)
    probe, release = held_probe(mods, monkeypatch, obj, isolines=8)
    s, _ = session(mods, probe)
    wait_for(lambda: probe.preview_ready)
    assert not probe.ready and probe.run.solver is None
    assert s.handle(Event("LEFTMOUSE", "PRESS", *to_mouse(-0.5, -0.5))) == {"RUNNING_MODAL"}
    s.handle(Event("MOUSEMOVE", "NOTHING", *to_mouse(-0.4, -0.5)))
    assert len(probe.sources) == 1 and not probe.exact and np.isfinite(probe.distance).all()
    preview = probe.distance.copy()
    assert s.handle(Event("LEFTMOUSE", "RELEASE", *to_mouse(-0.4, -0.5))) == {"RUNNING_MODAL"}
    assert not probe.exact  # the mouse up: still the preview, no solver yet
    assert s.handle(Event("LEFTMOUSE", "PRESS", *to_mouse(-0.4, -0.5), ctrl=True)) == {"RUNNING_MODAL"}
    assert s.display.texts[-1].startswith("paths and traces need the solver")
    assert s.handle(Event("RET", "PRESS")) == {"RUNNING_MODAL"}  # Enter waits for the solver
    with pytest.raises(mods["adapters"].AddonError, match="still being built"):
        probe.confirm()
    assert "geodesic_distance" not in obj.data.attributes
    release.set()
    assert probe.build.wait(120)
    assert s.handle(Event("TIMER", "NOTHING")) == {"PASS_THROUGH"}  # built: the solver's field replaces the preview
    assert probe.ready and probe.exact and s.display.readied == 1
    exact = probe.run.solver.distance(points=([probe.sources[0][0]], [probe.sources[0][1]]))
    np.testing.assert_allclose(probe.distance, exact, rtol=1e-12, atol=1e-12)
    assert np.abs(preview - exact).mean() < 0.05 * exact.max()  # the preview was coarse, not wrong
    assert probe._preview() is probe.early_preview  # kept for the solver's next probes (its domain's cache)
    assert s.handle(Event("RET", "PRESS")) == {"FINISHED"}
    np.testing.assert_allclose(attribute(obj.data, "geodesic_distance"), exact, rtol=1e-6, atol=1e-6)


def test_the_tools_click_on_a_large_mesh_is_placed_on_the_preview_and_confirmed_once_built(mods, monkeypatch):
    monkeypatch.setattr(mods["probe"], "PREVIEW_FROM", 100)
    obj = grid(40)
    probe, release = held_probe(mods, monkeypatch, obj)
    press = Event("LEFTMOUSE", "PRESS", *to_mouse(0.5, 0.0))
    s, reports = session(mods, probe, release_confirms=True, press=press)
    wait_for(lambda: probe.preview_ready)
    assert s.handle(Event("TIMER", "NOTHING")) == {"PASS_THROUGH"}  # the tool's click placed on the preview
    assert len(probe.sources) == 1 and not probe.exact
    assert s.handle(Event("LEFTMOUSE", "RELEASE", *to_mouse(0.5, 0.0))) == {"RUNNING_MODAL"}  # not yet written
    assert "geodesic_distance" not in obj.data.attributes
    release.set()
    assert probe.build.wait(120)
    assert s.handle(Event("TIMER", "NOTHING")) == {"FINISHED"}  # built, then confirmed: it was released
    exact = probe.run.solver.distance(points=([probe.sources[0][0]], [probe.sources[0][1]]))
    np.testing.assert_allclose(attribute(obj.data, "geodesic_distance"), exact, rtol=1e-6, atol=1e-6)
    assert reports[-1][0] == {"INFO"}


def test_esc_while_dragging_on_the_preview_cancels_the_build_and_writes_nothing(mods, monkeypatch):
    monkeypatch.setattr(mods["probe"], "PREVIEW_FROM", 100)
    obj = grid(40)
    probe, release = held_probe(mods, monkeypatch, obj)
    s, _ = session(mods, probe)
    wait_for(lambda: probe.preview_ready)
    s.handle(Event("LEFTMOUSE", "PRESS", *to_mouse(0.1, 0.2)))
    s.handle(Event("MOUSEMOVE", "NOTHING", *to_mouse(0.2, 0.2)))
    assert s.handle(Event("ESC", "PRESS")) == {"CANCELLED"}
    release.set()
    probe.build.wait(120)
    assert probe.ended and not probe.preview_ready and not mods["overlay"].Overlay.live
    assert obj.data.session_uid not in mods["probe"].SOLVERS
    assert "geodesic_distance" not in obj.data.attributes


def test_small_meshes_drag_with_the_solvers_field(mods):
    obj = grid(12)
    probe = mods["probe"].GeodesicProbe(obj, isolines=8)
    s, _ = session(mods, probe)
    s.handle(Event("LEFTMOUSE", "PRESS", *to_mouse(-0.5, -0.5)))
    s.handle(Event("MOUSEMOVE", "NOTHING", *to_mouse(-0.4, -0.5)))
    assert probe.exact and not s.display.awake
