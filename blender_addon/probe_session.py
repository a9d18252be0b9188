"""The probe tool's event logic: :class:`ProbeSession`, events in, probe calls and header text out.

The modal operator of :mod:`.probe_tool` builds a session from the context and
forwards each ``modal`` event to :meth:`ProbeSession.handle`; tests feed it
event-like objects (no ``bpy`` window needed). While a large mesh's solver
builds, the session places and drags sources on the probe's coarse preview
(:attr:`~.probe.GeodesicProbe.preview_ready`) and shows the solver's field once
it is there.

Examples
--------
>>> session = ProbeSession(probe, display, locate, operator.report)   # doctest: +SKIP
>>> session.handle(event)                                            # doctest: +SKIP
{'RUNNING_MODAL'}
"""

import time

import bpy

from ._heatcore import heatcore
from .adapters import AddonError
from .background import DONE, RUNNING
from .legend import format_distance
from .probe_surface import Hit
from .probe_trace import start_trace, trace_to, write_trace

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
        state = self.probe.poll()
        if state == RUNNING:
            self.display.progress(*self.probe.progress())
            if self.probe.preview_ready:  # a large mesh: its coarse preview answers while the solver builds
                return self._previewing(event)
            if event.type == "LEFTMOUSE" and event.value == "RELEASE":
                self.released = True
            return {"PASS_THROUGH"}
        if event.type == "LEFTMOUSE" and event.value == "RELEASE":
            self.released = True
        if state != DONE:
            return self.cancel("Geodesic probe: the solver build was cancelled")
        self._ready()
        if self.probe.ended:  # the tool's click was off the mesh
            return {"CANCELLED"}
        return self._release() if self.release_confirms and self.released else {"PASS_THROUGH"}

    def _previewing(self, event):
        """An event while the solver builds, with the coarse preview ready: sources are placed and dragged on the
        preview; Enter (and the tool's release) waits for the solver, which then replaces the preview."""
        if self.pending is not None and not (self.pending.alt or self.pending.ctrl):  # those wait for the solver
            self._place_pending()
        kind, value = event.type, event.value
        if kind.startswith("TIMER") or kind in NAVIGATION:
            return {"PASS_THROUGH"}
        try:
            if self.probe.changed:
                self.probe.check()
        except REPORTED_ERRORS as exc:
            return self.cancel(str(exc), "ERROR")
        try:
            if kind in MOVES:
                self._move(event)
            elif kind == "LEFTMOUSE" and value == "PRESS" and (event.alt or event.ctrl):
                self.display.text("paths and traces need the solver: once it is built", self.keys)
            elif kind == "LEFTMOUSE" and value == "PRESS":
                self.released = False
                return self._press(event)
            elif kind == "LEFTMOUSE" and value == "RELEASE":
                self.dragging = self.probe.dragging = self.tracing = False
                self.released = True  # the tool's release: confirmed once the solver is there
            elif kind in CONFIRM and value == "PRESS":
                self.display.text("the coarse preview is shown while the solver builds: Enter once it is ready",
                                  self.keys)
        except REPORTED_ERRORS as exc:
            self.display.text(str(exc), self.keys)
        return {"RUNNING_MODAL"}

    def _ready(self):
        """The solver is there: say so, place the tool's click if it started the probe, and show the solver's
        field where sources were placed on the coarse preview meanwhile."""
        self.display.ready()
        self.display.text(f"{self.probe.run.object_name}: click on the surface", self.keys)
        if self.pending is not None:
            self._place_pending()
        elif not self.probe.exact and not self.dragging:
            self.probe.settle()
            self.display.wake(False)
            self._say_field()

    def _place_pending(self):
        """Place the tool's click that started the probe (Shift or Ctrl: from the tool's last sources)."""
        press, self.pending = self.pending, None
        try:
            solver = self.probe.run.solver if self.probe.ready else None
            last = solver.domain.derived.get(SOURCES_KEY) if solver is not None else None
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
