"""Operator ``mesh.heat_geodesic_distance``: the button, and ``bpy.ops`` for scripts.

From the button (``invoke`` with a window) a solver that is not cached is
built in a background thread (:class:`~.background.BackgroundBuild`) while a
modal timer shows its stages (:class:`~.display.ProgressDisplay`): the header
of the area it was started from says what runs and how far it is, the status
bar that Esc cancels, the window manager's progress indicator follows, the
UI stays usable, and Esc cancels (nothing is written). Meanwhile a first
answer on a cheaper mesh (a small mesh unrefined, a large one coarsened) is
drawn, never written (:mod:`.preview`). The query and the writes then
run on the main thread, as one undo step. A second click while a
build runs is refused with a message. A cached solver, ``execute`` (scripts,
*Adjust Last Operation*) and background Blender (``bpy.app.background``) run
synchronously, as :func:`~.api.compute_geodesic_distance` does.

Examples
--------
>>> bpy.ops.mesh.heat_geodesic_distance(isolines=8)                   # doctest: +SKIP
>>> bpy.ops.mesh.heat_geodesic_distance("INVOKE_DEFAULT")             # doctest: +SKIP
"""

import bpy

from ._heatcore import heatcore
from .adapters import AddonError
from .api import compute_geodesic_distance
from .background import CANCELLED, FAILED, RUNNING, BackgroundBuild, Busy
from .display import ProgressDisplay
from .legend import format_distance
from .preview import Preview, PreviewWork, preview_kind, preview_title, wants_preview
from .properties import GeodesicOptions
from .redo import draw_run_options
from .stages import (
    BUILD_RANGE,
    build_solver,
    check_unchanged,
    find_object,
    finish_run,
    prepare_run,
)
from .targets import skipped_message, target_objects

#: Errors reported as messages (anything else is a bug: it propagates, with its traceback).
REPORTED_ERRORS = (AddonError, heatcore.HeatcoreError, MemoryError)
#: From this many vertices the query and writes after a background build take long enough (0.6 s at
#: 126k vertices, 1.1 s at 504k; 0.05 s at 51k) that the message saying so is drawn first, one timer step earlier.
SHOWN_FINISH_VERTICES = 100_000


def _status(context, text):
    workspace = getattr(context, "workspace", None)
    if workspace is not None:
        workspace.status_text_set(text)


def show_color_attribute(context, outputs):
    """Make the result visible in the 3D views: Solid shading shows the attribute colors (with Flat lighting
    for the flat isoline style), and a Solid view switches to Material Preview when the isoline material is on
    (a material shows only there and in Rendered shading). ``outputs``: the run's output options."""
    screen = getattr(context, "screen", None)
    for area in screen.areas if screen else ():
        if area.type == "VIEW_3D":
            shading = area.spaces.active.shading
            shading.color_type = "VERTEX"  # "Attribute" in the UI: what Solid shading shows
            if outputs["isoline_material"] and outputs["isoline_style"] == "FLAT":
                shading.light = "FLAT"
            if shading.type == "SOLID" and outputs["isoline_material"]:
                shading.type = "MATERIAL"


def report_result(context, result, report, obj, outputs, space="WORLD"):
    """Statistics for the panel, the result shown in the viewport (``outputs``: the run's output options), and the
    INFO (and WARNING) reports of a run on ``obj`` (its largest distance in the scene's units in World ``space``)."""
    stats = context.window_manager.heat_geodesic_stats
    stats.valid = True
    stats.object_name = result.object.name
    stats.vertices = result.n_vertices
    stats.sources = result.sources.size
    stats.max_distance = result.max_distance
    stats.space = space
    stats.seconds = result.seconds
    stats.solver_seconds = result.solver_seconds
    stats.cached = result.cached
    show_color_attribute(context, outputs)
    for note in result.warnings:
        report({"WARNING"}, note)
    how = "cached solver" if result.cached else f"solver built in {result.solver_seconds:.2f} s"
    where = f" (written to {result.object.name!r})" if result.object != obj else ""
    report(
        {"INFO"},
        f"Geodesic distance on {result.n_vertices:,} vertices{where} from {result.sources.size:,} sources: "
        f"max {format_distance(result.max_distance, space, context.scene)}, {result.seconds:.2f} s ({how})",
    )
    return {"FINISHED"}


class ModalRun:
    """One click whose solver is built in the background: the modal operator's logic, without the operator.

    Parameters
    ----------
    run : PreparedRun
        From :func:`~.stages.prepare_run` (its solver not cached).
    display : ProgressDisplay or an object with ``progress(fraction, message)`` and ``end()``
    report : callable
        ``report(type, message)``, as ``Operator.report``.

    Attributes
    ----------
    preview_work : PreviewWork or None
        The first answer being computed (:meth:`start` with the object), until it is shown or the run ends.
    preview : Preview or None
        The first answer drawn while the solver builds (at the first timer event after ``preview_work`` is
        done), until the run ends.
    """

    def __init__(self, run, display, report):
        self.run = run
        self.display = display
        self.report = report
        label = f"the heat solver of {run.object_name!r} ({len(run.V):,} vertices)"
        self.build = BackgroundBuild(self.work, label)
        self.finishing = False
        self.result = None  # the GeodesicResult once written
        self.preview_work = None
        self.preview = None

    def start(self, obj=None):
        """Start the worker (raises :class:`~.background.Busy` while another build runs).

        Given the run's object, a run that :func:`~.preview.wants_preview` also gets a preview
        (:class:`~.preview.PreviewWork`), drawn over the object once computed, taken down when the run ends:
        on the unrefined mesh it takes a few milliseconds and is drawn at once, before the build starts; a
        coarse one is computed by the worker before the solver (:meth:`work`).
        """
        if obj is not None and wants_preview(self.run):
            self.preview_work = PreviewWork(self.run)
            if preview_kind(self.run) == "unrefined":
                self.preview_work.compute()
                self.show_preview()
        try:
            self.build.start()
        except Busy:
            self.end()
            raise
        self.display.progress(*self.build.progress())

    def work(self, progress):
        """The worker thread's work: a coarse preview first where one is pending, then the solver (any thread)."""
        work = self.preview_work
        if work is not None and not work.done():
            progress(BUILD_RANGE[0], "computing a coarse preview")
            work.compute()
        return build_solver(self.run, progress)

    def end(self):
        """Take the display and the preview down (idempotent); a preview still being computed is never shown."""
        self.display.end()
        self.preview_work = None
        if self.preview is not None:
            self.preview.remove()

    def handle(self, context, event_type, event_value="NOTHING"):
        """Handle one event: the operator's ``modal`` result set.

        Esc cancels; a timer event polls the build and, once it is done,
        says so, and at the next timer event checks that the object is
        unchanged, queries and writes the result (on the main thread: the
        message is on screen while it runs); below ``SHOWN_FINISH_VERTICES``
        vertices, where that is over in a blink, it does so at once. Every
        other event passes through to the rest of Blender.
        """
        if event_type == "ESC" and event_value == "PRESS":
            return self.cancel(f"Geodesic distance cancelled at: {self.build.message}; nothing was written")
        if event_type != "TIMER":
            return {"PASS_THROUGH"}
        state = self.build.poll()
        if state == RUNNING:
            self.display.progress(*self.build.progress())
            self.show_preview()
            return {"PASS_THROUGH"}
        if state != CANCELLED and not self.finishing:
            self.finishing = True
            self.display.progress(BUILD_RANGE[1], "solving for the distance and writing the attributes")
            if len(self.run.V) >= SHOWN_FINISH_VERTICES:
                return {"PASS_THROUGH"}
        try:
            if state == CANCELLED:
                return {"CANCELLED"}
            try:
                if state == FAILED:
                    self.build.result()  # raises the worker's error
                obj = check_unchanged(self.run)
                result = self.result = finish_run(self.run, obj=obj)
            except REPORTED_ERRORS as exc:
                self.report({"ERROR"}, str(exc) or type(exc).__name__)
                return {"CANCELLED"}
        finally:
            self.end()
        return report_result(context, result, self.report, obj, self.run.outputs, self.run.space)

    def show_preview(self):
        """Draw the preview once its work is done (a timer event while the build runs), over the object as it is."""
        work = self.preview_work
        if work is None or not work.done():
            return
        self.preview_work = None
        obj = find_object(self.run) if work.distance is not None else None
        if obj is not None:
            self.preview = Preview.show(obj, self.run, work.distance, work.triangles)

    def cancel(self, message=None):
        """Cancel the build (the worker stops at its next stage), take the display down: ``{"CANCELLED"}``."""
        self.build.cancel()
        self.end()
        if message:
            self.report({"WARNING"}, message)
        return {"CANCELLED"}


def options_from_panel(operator, context, names):
    """Give each option in ``names`` that the call left unset the panel's value (the scene's settings).

    The operators' ``invoke``: from the UI an operator runs with what the panel
    shows, while a script's call keeps the options it passes.

    Parameters
    ----------
    operator : bpy.types.Operator
    context : bpy.types.Context
    names : iterable of str
        Properties of both the operator and ``context.scene.heat_geodesic``.

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> op = NS(properties=NS(is_property_set=lambda name: name == "m"), m=4.0, boundary="robin")
    >>> context = NS(scene=NS(heat_geodesic=NS(m=1.0, boundary="neumann")))
    >>> options_from_panel(op, context, ("m", "boundary"))
    >>> op.m, op.boundary
    (4.0, 'neumann')
    """
    panel = context.scene.heat_geodesic
    for name in names:
        if not operator.properties.is_property_set(name):
            setattr(operator, name, getattr(panel, name))


class PanelOptionsOperator:
    """What the operators that take the panel's options share: ``invoke`` fills the options the call left unset
    from the panel (:func:`options_from_panel`), ``draw`` shows the redo panel's rows ``SHOWN``."""

    SHOWN = ()

    def invoke(self, context, event):
        options_from_panel(self, context, GeodesicOptions.__annotations__)
        return self.execute(context)

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        for name in self.SHOWN:
            layout.prop(self, name)


def poll_editable_mesh(cls, context):
    """``poll`` of the operators that write to the active mesh: a mesh, not linked from a library
    (in Edit Mode it is editable anyway); says why not in the tooltip (``poll_message_set``)."""
    obj = context.active_object
    if obj is None or obj.type != "MESH":
        cls.poll_message_set("The active object must be a mesh")
        return False
    if not obj.visible_get():
        cls.poll_message_set("The active object is hidden")
        return False
    if not obj.data.is_editmode and (obj.library or obj.data.library):
        cls.poll_message_set("Linked (library) meshes cannot be modified")
        return False
    return True


class MESH_OT_heat_geodesic_distance(GeodesicOptions, bpy.types.Operator):
    """Geodesic distance from the selected vertices (heat method), stored as attributes and colors"""

    bl_idname = "mesh.heat_geodesic_distance"
    bl_label = "Geodesic Distance"
    bl_options = {"REGISTER", "UNDO", "PRESET"}  # presets: .presets (mask, falloff weights, isolines)

    poll = classmethod(poll_editable_mesh)

    def draw(self, context):
        draw_run_options(self.layout, self)  # the redo panel: grouped, without path_edges

    def invoke(self, context, event):
        options_from_panel(self, context, GeodesicOptions.__annotations__)
        targets, skipped = target_objects(context)
        if bpy.app.background or context.window is None or len(targets) != 1:
            return self.execute(context)  # several objects: one after the other, each with its progress
        if skipped:
            self.report({"WARNING"}, skipped_message(skipped))
        running = BackgroundBuild.running()
        if running is not None:
            self.report({"WARNING"}, f"Geodesic distance: {running.busy_message()}")
            return {"CANCELLED"}
        try:
            run = prepare_run(targets[0], **self.call_options())
            if run.solver is not None:  # cached: only the query is left, no thread needed
                obj = targets[0]
                return report_result(context, finish_run(run, obj=obj), self.report, obj, run.outputs, self.space)
        except REPORTED_ERRORS as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        title = "Geodesic distance" + preview_title(run)
        self._modal = ModalRun(run, ProgressDisplay(context, title), self.report)
        try:
            self._modal.start(targets[0])
        except Busy as exc:  # pragma: no cover - checked above; another build started in between
            self.report({"WARNING"}, f"Geodesic distance: {exc}")
            return {"CANCELLED"}
        context.window_manager.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        return self._modal.handle(context, event.type, event.value)

    def cancel(self, context):
        # Blender ends the operator without an event (a file is loaded, the window closes).
        modal = getattr(self, "_modal", None)
        if modal is not None:
            modal.cancel()

    def execute(self, context):
        """Measure every target (:func:`~.targets.target_objects`) on its own; name those left out."""
        targets, skipped = target_objects(context)
        wm = context.window_manager
        done = []
        for obj in targets:
            wm.progress_begin(0, 100)

            def progress(fraction, message, name=obj.name):
                wm.progress_update(int(100 * fraction))
                _status(context, f"Geodesic distance ({name}): {message}")

            try:
                done.append((obj, compute_geodesic_distance(obj, progress=progress, **self.call_options())))
            except REPORTED_ERRORS as exc:
                if len(targets) == 1 and not skipped:
                    self.report({"ERROR"}, str(exc))
                    return {"CANCELLED"}
                skipped.append((obj.name, str(exc)))
            finally:
                wm.progress_end()
                _status(context, None)
        for obj, result in done:
            report_result(context, result, self.report, obj, self.call_options(), self.space)
        if skipped:
            self.report({"WARNING"} if done else {"ERROR"}, skipped_message(skipped))
        return {"FINISHED"} if done else {"CANCELLED"}
