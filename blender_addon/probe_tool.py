"""The interactive geodesic tool: a modal operator and toolbar tools over :class:`~.probe.GeodesicProbe`.

``mesh.heat_geodesic_probe`` (menus, F3, the sidebar panel): move the mouse
over the mesh and the header shows the geodesic distance under the cursor;
click places the source at the surface point, drag moves it and the field
follows (drawn as an overlay), Shift+click adds a source, Ctrl+click sets a
target and draws the geodesic path, Alt+drag traces the straightest geodesic
from the press towards the mouse (:mod:`.probe_trace`); Enter writes the
result and the trace (one undo step),
Esc or right-click cancels and leaves the mesh as it was. The toolbar tool
*Geodesic Probe* (Object and Edit Mode) runs the same operator from each
click, and releasing the button confirms; Shift+click and Ctrl+click there
start from the sources of the tool's last click on the same (unchanged) mesh.

:class:`ProbeSession` is the operator's logic, event by event, without
``bpy`` windows (tests feed it event-like objects); the operator only builds
it from the context and forwards ``modal`` to :meth:`ProbeSession.handle`.

Examples
--------
>>> bpy.ops.mesh.heat_geodesic_probe("INVOKE_DEFAULT")    # doctest: +SKIP
"""


import os
import time

import bpy
from bpy.app.handlers import persistent
from bpy.props import BoolProperty
from mathutils import Vector

from . import probe as probes
from ._heatcore import heatcore
from .adapters import AddonError
from .background import DONE, RUNNING, Busy
from .display import ProgressDisplay
from .legend import format_distance
from .operator import poll_editable_mesh, show_color_attribute
from .probe import GeodesicProbe
from .probe_surface import Hit
from .probe_trace import start_trace, trace_to, write_trace

OPERATOR = "mesh.heat_geodesic_probe"
#: Errors shown to the user (anything else is a bug: it propagates with its traceback).
REPORTED_ERRORS = (AddonError, heatcore.HeatcoreError, MemoryError)
#: Events left to the 3D View while the probe runs (navigation).
NAVIGATION = frozenset({
    "MIDDLEMOUSE", "WHEELUPMOUSE", "WHEELDOWNMOUSE", "WHEELINMOUSE", "WHEELOUTMOUSE", "TRACKPADPAN",
    "TRACKPADZOOM", "MOUSEROTATE", "MOUSESMARTZOOM", "NDOF_MOTION", "HOME", "NUMPAD_PERIOD", "NUMPAD_PLUS",
    "NUMPAD_MINUS", "NUMPAD_SLASH", "NUMPAD_ASTERIX", *(f"NUMPAD_{i}" for i in range(10)),
})
MOVES = frozenset({"MOUSEMOVE", "INBETWEEN_MOUSEMOVE"})
#: A drag's mouse at rest this long (seconds): the solver's field replaces the coarse preview.
REST_SECONDS = 0.08
CONFIRM = frozenset({"RET", "NUMPAD_ENTER"})
CANCEL = frozenset({"ESC", "RIGHTMOUSE"})
KEYS = ("click: source · drag: move it · Shift+click: add · Ctrl+click: path to · Alt+drag: trace · Enter: apply · "
        "Esc: cancel")
TOOL_KEYS = "release: apply · Esc / right-click: cancel"

#: Where the sources of the tool's last click on a mesh are kept: the cache of its solver's domain (so per unchanged
#: mesh, dropped with the solver); Shift/Ctrl+click start from them.
SOURCES_KEY = ("probe sources", None)


class ProbeSession:
    """The modal operator's logic: events in, probe calls and text out.

    Parameters
    ----------
    probe : GeodesicProbe
    display : object
        ``text(message, keys)``, ``progress(fraction, message)``, ``end()``
        (the header and status bar; :class:`~.display.ProgressDisplay` in Blender).
    locate : callable
        ``locate(event)``: the :data:`~.probe_surface.Hit` under the mouse, or
        a text saying why there is none (off the mesh, another object in front).
    report : callable
        ``report(type, message)``, as ``Operator.report``.
    release_confirms : bool
        The toolbar tool: the press that started it (``press``) places the
        source and the release confirms.
    press : event, optional
        That press; with Shift or Ctrl it starts from the tool's last sources.
    """

    def __init__(self, probe, display, locate, report, release_confirms=False, press=None):
        self.probe, self.display, self.locate, self.report = probe, display, locate, report
        self.release_confirms = release_confirms
        self.pending = press
        self.dragging = False
        self.tracing = False  # Alt+drag: the trace follows the mouse (:mod:`.probe_trace`)
        self.moved_at = 0.0  # time.perf_counter() of the drag's last move
        self.released = False  # the tool's button released while the solver was being built
        self.result = None
        self.keys = TOOL_KEYS if release_confirms else KEYS
        if probe.ready:
            self._ready()
        else:
            display.progress(*probe.progress())

    def handle(self, event):
        """One event: the operator's ``modal`` result (``RUNNING_MODAL``, ``PASS_THROUGH``, ``FINISHED``, ``CANCELLED``)."""
        kind, value = event.type, event.value
        if kind in CANCEL and value == "PRESS":
            return self.cancel("Geodesic probe cancelled; nothing was written")
        try:  # the solver ready, the object there and unchanged: or the probe ends
            if not self.probe.ready:
                return self._building(event)
            if self.probe.changed:
                self.probe.check()
        except REPORTED_ERRORS as exc:
            return self.cancel(str(exc), "ERROR")
        if kind.startswith("TIMER") and self.dragging and not self.probe.exact:
            self._rest()
        if kind.startswith("TIMER") or kind in NAVIGATION:
            return {"PASS_THROUGH"}
        try:
            if kind in MOVES:
                self._move(event)
            elif kind == "LEFTMOUSE" and value == "PRESS":
                return self._press(event)
            elif kind == "LEFTMOUSE" and value == "RELEASE" and (self.dragging or self.tracing or self.release_confirms):
                return self._release()
            elif kind in CONFIRM and value == "PRESS":
                return self.confirm()
        except REPORTED_ERRORS as exc:  # a point the solver refuses: say so, the field stays
            self.display.text(str(exc), self.keys)
        return {"RUNNING_MODAL"}

    # ---- the build

    def _building(self, event):
        if event.type == "LEFTMOUSE" and event.value == "RELEASE":
            self.released = True
        state = self.probe.poll()
        if state == RUNNING:
            self.display.progress(*self.probe.progress())
            return {"PASS_THROUGH"}
        if state != DONE:
            return self.cancel("Geodesic probe: the solver build was cancelled")
        self._ready()
        if self.probe.ended:  # the tool's click was off the mesh
            return {"CANCELLED"}
        return self._release() if self.release_confirms and self.released else {"PASS_THROUGH"}

    def _ready(self):
        """The solver is there: say so, and place the tool's click if it started the probe."""
        self.display.ready()
        self.display.text(f"{self.probe.run.object_name}: click on the surface", self.keys)
        press, self.pending = self.pending, None
        if press is None:
            return
        try:
            last = self.probe.run.solver.domain.derived.get(SOURCES_KEY)
            if last and (press.shift or press.ctrl):
                self.probe.place(last)
            self._press(press)
        except REPORTED_ERRORS as exc:
            self.display.text(str(exc), self.keys)

    # ---- the mouse

    def _hit(self, event):
        hit = self.locate(event)
        if not isinstance(hit, Hit):
            self.display.text(str(hit), self.keys)
            return None
        return hit

    def _move(self, event):
        hit = self._hit(event)
        if hit is None:
            return
        if self.tracing:
            traced = trace_to(self.probe, hit.face, hit.barycentric)
            if traced is not None:
                self.display.text(f"Trace: {self._format(traced.length)} (stopped: {traced.stopped})", self.keys)
            return
        if self.dragging:  # on a large mesh the coarse preview, until the mouse rests (_rest)
            self.probe.move_to(hit.face, hit.barycentric, preview=True)
            self.moved_at = time.perf_counter()
            self.display.wake(not self.probe.exact)
            self._say_field()
            return
        d = self.probe.distance_at(hit.face, hit.barycentric)
        if d is None:
            self.display.text(f"{self.probe.run.object_name}: click on the surface to place the source", self.keys)
        else:
            self.display.text(f"Distance under the cursor: {self._format(d)}", self.keys)

    def _rest(self):
        """The mouse at rest for ``REST_SECONDS`` during a drag: the solver's field replaces the coarse preview."""
        if time.perf_counter() - self.moved_at >= REST_SECONDS:
            try:
                self.probe.settle()
            except REPORTED_ERRORS as exc:
                self.display.text(str(exc), self.keys)
            self.display.wake(False)
            self._say_field()

    def _press(self, event):
        self.probe.check()  # every press: never a stale field
        hit = self._hit(event)
        if hit is None:
            return self.cancel(None) if self.release_confirms else {"RUNNING_MODAL"}
        if event.alt:
            start_trace(self.probe, hit.face, hit.barycentric)
            self.tracing = True
            self.display.text("Trace: drag towards where it should go", self.keys)
            return {"RUNNING_MODAL"}
        if event.ctrl:
            path = self.probe.path_to(hit.face, hit.barycentric)
            self.display.text(f"Path to the target: {self._format(path.length)} long", self.keys)
        elif event.shift or not self.probe.sources:
            self.probe.add(hit.face, hit.barycentric)
            self._say_field()
        else:
            self.probe.move_to(hit.face, hit.barycentric)
            self._say_field()
        self.dragging = self.probe.dragging = True
        return {"RUNNING_MODAL"}

    def _release(self):
        if self.tracing:
            self.tracing = False
            return self.confirm() if self.release_confirms else {"RUNNING_MODAL"}
        self.dragging = False
        self.probe.end_drag()  # the solver's field (no preview), the path follows, the isoline curves come back
        self.display.wake(False)
        return self.confirm() if self.release_confirms else {"RUNNING_MODAL"}

    def _format(self, value):
        return "not reachable" if value == float("inf") else format_distance(value, self.probe.run.space,
                                                                              bpy.context.scene)

    def _say_field(self):
        probe = self.probe
        finite = probe.distance[probe.distance < float("inf")]
        farthest = self._format(float(finite.max())) if finite.size else "-"
        self.display.text(f"{len(probe.sources)} source{'s' * (len(probe.sources) > 1)}, farthest {farthest} "
                          f"({1000 * probe.timings['update']:.0f} ms)", self.keys)

    # ---- the end

    def confirm(self):
        """Write the result: ``{"FINISHED"}``; with no source placed, say so and go on (or end, for the tool).

        A trace (Alt+drag) is written as a curve object too; with no source placed, only it is written.
        """
        if self.probe.distance is None and self.probe.trace is not None:
            return self._confirm_trace()
        try:
            self.result = self.probe.confirm(push_undo=False)  # the operator's FINISHED pushes the undo step
        except REPORTED_ERRORS as exc:
            if self.probe.distance is None and not self.release_confirms:
                self.display.text(str(exc), self.keys)
                return {"RUNNING_MODAL"}
            return self.cancel(str(exc), "ERROR")
        self.probe.run.solver.domain.derived[SOURCES_KEY] = list(self.probe.sources)
        write_trace(self.probe, self.result.object)
        self.display.end()
        sources = len(self.probe.sources)
        self.report({"INFO"}, f"Geodesic probe: distance from {sources} source{'s' * (sources > 1)} written to "
                              f"{self.result.object.name!r} (farthest {self._format(self.result.max_distance)})")
        return {"FINISHED"}

    def _confirm_trace(self):
        """Write the trace alone (no source was placed) as its curve object."""
        try:
            obj = self.probe.check()
        except REPORTED_ERRORS as exc:
            return self.cancel(str(exc), "ERROR")
        curve = write_trace(self.probe, obj)
        length = self._format(self.probe.trace.length)
        self.probe.end()
        self.display.end()
        self.report({"INFO"}, f"Geodesic probe: trace of length {length} written to {curve.name!r}")
        return {"FINISHED"}

    def cancel(self, message=None, kind="WARNING"):
        """End without writing: the probe's overlay goes, the header and status bar are restored."""
        self.probe.cancel()
        self.display.end()
        if message:
            self.report({kind}, message)
        return {"CANCELLED"}


def occluder(depsgraph, obj_name, origin, direction, depth):
    """The name of another object the ray hits before ``depth`` (in front of the probed object), or None.

    Examples
    --------
    >>> occluder(bpy.context.evaluated_depsgraph_get(), "Suzanne", (0, 0, 5), (0, 0, -1), 4.0)   # doctest: +SKIP
    'Cube'
    """
    direction = Vector(direction).normalized()
    hit, location, _, _, other, _ = bpy.context.scene.ray_cast(depsgraph, Vector(origin), direction)
    closer = hit and (Vector(location) - Vector(origin)).length < depth * (1 - 1e-6)
    return other.original.name if closer and other is not None and other.original.name != obj_name else None


def view_locate(region, rv3d, probe):
    """``locate(event)`` for a 3D View's main region: a ray from the mouse through the view."""
    from bpy_extras import view3d_utils

    def locate(event):
        coord = (event.mouse_x - region.x, event.mouse_y - region.y)
        if not (0 <= coord[0] < region.width and 0 <= coord[1] < region.height):
            return "the cursor is outside the 3D Viewport"
        origin = view3d_utils.region_2d_to_origin_3d(region, rv3d, coord)
        direction = view3d_utils.region_2d_to_vector_3d(region, rv3d, coord)
        hit = probe.ray_cast(origin, direction)
        name = probe.run.object_name
        if hit is None:
            return f"the cursor is not on {name!r}"
        other = occluder(bpy.context.evaluated_depsgraph_get(), name, origin, direction, hit.depth)
        return f"the cursor is on {other!r}, in front of {name!r}" if other else hit

    return locate


class MESH_OT_heat_geodesic_probe(bpy.types.Operator):
    """Click on the mesh to see the geodesic distance live: drag the source, Shift+click adds one, Ctrl+click draws the path to a target, Alt+drag traces a straight line on the surface; Enter writes the result"""

    bl_idname = OPERATOR
    bl_label = "Geodesic Probe"
    bl_options = {"REGISTER", "UNDO"}

    release_confirms: BoolProperty(name="Release Confirms", default=False, options={"HIDDEN", "SKIP_SAVE"},
                                   description="Apply the distance when the mouse button is released (the toolbar "
                                               "tool's click-and-drag)")
    path_curve: BoolProperty(
        name="Path Curve",
        description="When applied, also write the geodesic path to the target as a curve object "
                    "'<name> Geodesic Path'",
        default=False,
    )
    isoline_curves: BoolProperty(
        name="Isoline Curves",
        description="When applied, also write the isolines as a curve object '<name> Geodesic Isolines'",
        default=False,
    )

    poll = classmethod(poll_editable_mesh)  # it writes to the mesh when applied

    def invoke(self, context, event):
        area = context.area
        if bpy.app.background or context.window is None or area is None or area.type != "VIEW_3D":
            self.report({"ERROR"}, "the geodesic probe is interactive: start it in a 3D Viewport "
                                   "(scripts: GeodesicProbe)")
            return {"CANCELLED"}
        region = next(r for r in area.regions if r.type == "WINDOW")
        settings = context.scene.heat_geodesic
        options = settings.call_options()
        options.pop("vertex_group")
        options.pop("selected")  # the probe's sources are the points clicked
        if options.pop("new_object"):
            self.report({"WARNING"}, "Geodesic probe: measured on the object itself (Apply All Modifiers is off "
                                     "for the probe)")
        try:
            probe = GeodesicProbe(context.active_object, background=True, path_curve=self.path_curve,
                                  isoline_curves=self.isoline_curves, **options)
        except (Busy, *REPORTED_ERRORS) as exc:
            self.report({"ERROR"}, f"Geodesic probe: {exc}")
            return {"CANCELLED"}
        for note in probe.notes:
            self.report({"WARNING"}, note)
        press = event if self.release_confirms else None
        display = ProgressDisplay(context, "Geodesic probe")
        self._session = ProbeSession(probe, display, view_locate(region, area.spaces.active.region_3d, probe),
                                     self.report, self.release_confirms, press)
        if self._session.probe.ended:  # the tool's click was off the mesh
            return {"CANCELLED"}
        context.window_manager.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        state = self._session.handle(event)
        if state == {"FINISHED"}:
            session = self._session
            result, stats = session.result, context.window_manager.heat_geodesic_stats
            stats.valid, stats.object_name, stats.vertices = True, result.object.name, result.n_vertices
            stats.sources, stats.max_distance = len(session.probe.sources), result.max_distance
            stats.seconds, stats.solver_seconds, stats.cached = result.seconds, result.solver_seconds, result.cached
            show_color_attribute(context, session.probe.run.outputs)
        return state

    def cancel(self, context):
        session = getattr(self, "_session", None)
        if session is not None:
            session.cancel()

    def execute(self, context):
        self.report({"ERROR"}, "the geodesic probe is interactive: start it in a 3D Viewport (scripts: GeodesicProbe)")
        return {"CANCELLED"}


#: The tool's own toolbar icon (a source point and its isolines; ``scripts/make_probe_icon.py`` draws it): the
#: path of its ``.dat`` file without the extension, as Blender takes it.
ICON = os.path.join(os.path.dirname(__file__), "icons", "ops.mesh.heat_geodesic_probe")


class _ProbeTool:
    bl_space_type = "VIEW_3D"
    bl_label = "Geodesic Probe"
    bl_description = ("Click on a mesh to see the geodesic distance from that point; drag to move it, release to "
                      "apply. Shift+click adds a source, Ctrl+click draws the path to a target")
    bl_icon = ICON
    bl_widget = None
    bl_keymap = tuple(
        (OPERATOR, {"type": "LEFTMOUSE", "value": "PRESS", **modifier}, {"properties": [("release_confirms", True)]})
        for modifier in ({}, {"shift": True}, {"ctrl": True})
    )

    def draw_settings(context, layout, tool):
        props = tool.operator_properties(OPERATOR)
        layout.prop(props, "path_curve")
        layout.prop(props, "isoline_curves")


class VIEW3D_WT_heat_geodesic_probe_object(_ProbeTool, bpy.types.WorkSpaceTool):
    bl_context_mode = "OBJECT"
    bl_idname = "heat_geodesics.probe_object"


class VIEW3D_WT_heat_geodesic_probe_edit(_ProbeTool, bpy.types.WorkSpaceTool):
    bl_context_mode = "EDIT_MESH"
    bl_idname = "heat_geodesics.probe_edit"


TOOLS = (VIEW3D_WT_heat_geodesic_probe_object, VIEW3D_WT_heat_geodesic_probe_edit)


@persistent
def flag_changes(scene, depsgraph):
    """Handler of ``depsgraph_update_post``: any update flags the running probes (checked at their next step).

    Examples
    --------
    >>> bpy.app.handlers.depsgraph_update_post.append(flag_changes)   # doctest: +SKIP
    """
    for probe in probes.running():
        probe.changed = True


def register():
    """Register the operator, the toolbar tools (after *Measure*) and the change handler."""
    bpy.utils.register_class(MESH_OT_heat_geodesic_probe)
    for tool in TOOLS:
        bpy.utils.register_tool(tool, after={"builtin.measure"}, separator=True)
    if flag_changes not in bpy.app.handlers.depsgraph_update_post:
        bpy.app.handlers.depsgraph_update_post.append(flag_changes)


def unregister():
    """End running probes; unregister the handler, the tools and the operator."""
    for probe in probes.running():
        probe.end()
    while flag_changes in bpy.app.handlers.depsgraph_update_post:
        bpy.app.handlers.depsgraph_update_post.remove(flag_changes)
    for tool in reversed(TOOLS):
        bpy.utils.unregister_tool(tool)
    bpy.utils.unregister_class(MESH_OT_heat_geodesic_probe)
