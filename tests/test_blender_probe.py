"""The interactive geodesic probe (issue 20) with the real ``bpy`` (Blender 5.0 headless).

A headless ``bpy`` has no window, no event loop and no GPU: the probe's logic
is :class:`blender_addon.probe.GeodesicProbe`, driven here directly, and the
modal operator's is :class:`blender_addon.probe_tool.ProbeSession`, fed
event-like objects with a ``locate`` that casts a straight-down ray through
the real ray-casting tree (mouse x, y -> world x, y). The overlay's draw
callback cannot run; the data it draws is checked instead.
"""

import importlib
import tracemalloc
from dataclasses import dataclass

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
    names = ("probe", "probe_tool", "probe_surface", "overlay", "path_curve", "adapters", "api", "background")
    return {name: importlib.import_module(f"blender_addon.{name}") for name in names}


@dataclass
class Event:
    """What the operator's ``modal`` reads of a ``bpy.types.Event``."""

    type: str
    value: str = "PRESS"
    mouse_x: int = 0
    mouse_y: int = 0
    shift: bool = False
    ctrl: bool = False


class RecordingDisplay:
    """Stands in for ProbeDisplay (header, status bar, build progress)."""

    def __init__(self):
        self.texts, self.progresses, self.ended, self.readied = [], [], 0, 0

    def text(self, message, keys):
        self.texts.append(message)

    def progress(self, fraction, message):
        self.progresses.append((fraction, message))

    def ready(self):
        self.readied += 1

    def end(self):
        self.ended += 1


#: Mouse pixels per world unit of the straight-down view used by the tests (mouse (500, 500) is x = y = 0).
PIXELS = 200.0


def to_mouse(x, y):
    return int(round(500 + PIXELS * x)), int(round(500 + PIXELS * y))


def session(mods, probe, **kw):
    reports = []

    def locate(event):
        origin = ((event.mouse_x - 500) / PIXELS, (event.mouse_y - 500) / PIXELS, 10.0)
        hit = probe.ray_cast(origin, (0.0, 0.0, -1.0))
        return hit if hit is not None else f"the cursor is not on {probe.run.object_name!r}"

    s = mods["probe_tool"].ProbeSession(probe, RecordingDisplay(), locate, lambda k, m: reports.append((k, m)), **kw)
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
        local = lambda p: (inverse @ np.r_[p, 1.0])[:3]  # noqa: E731
        direction = (inverse[:3, :3] @ -normal)
        found, _, _, polygon = obj.evaluated_get(depsgraph).ray_cast(local(centroid + 2 * normal), direction)
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
    options = dict(isolines=6, colormap="magma", weight_group="weights", weight_falloff="SMOOTH", refine=0)
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
    faces = rng.integers(0, len(probe.triangles), size=110)
    barys = rng.dirichlet(np.ones(3), size=110)
    tracemalloc.start()
    try:
        for f, b in zip(faces[:10], barys[:10]):
            probe.move_to(f, b)
        probe.overlay_data()
        settled = tracemalloc.get_traced_memory()[0]
        for f, b in zip(faces[10:], barys[10:]):
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
