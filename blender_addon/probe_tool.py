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

:class:`~.probe_session.ProbeSession` is the operator's logic, event by event,
without ``bpy`` windows (tests feed it event-like objects); the operator only
builds it from the context and forwards ``modal`` to its ``handle``.

Examples
--------
>>> bpy.ops.mesh.heat_geodesic_probe("INVOKE_DEFAULT")    # doctest: +SKIP
"""


import os

import bpy
from bpy.app.handlers import persistent
from bpy.props import BoolProperty
from mathutils import Vector

from . import probe as probes
from .background import Busy
from .display import ProgressDisplay
from .operator import poll_editable_mesh, show_color_attribute
from .probe import GeodesicProbe
from .probe_session import REPORTED_ERRORS, ProbeSession

OPERATOR = "mesh.heat_geodesic_probe"


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
