"""Operator ``mesh.heat_geodesic_path``: the geodesic path between selected vertices as a curve object.

In Edit Mode with exactly two vertices selected, the active one (selected
last) is the source and the other the target; with three or more,
shift-clicked one by one, the path visits them in the order they were
clicked, and *Closed Loop* returns to the first. The path is measured on the
shape the user sees (the panel's *Space* and *Shape*, the solver options:
the cached solver of *Geodesic Distance* is reused) and written as the curve
object ``"<name> Geodesic Path"`` (one poly spline in world coordinates,
reused on re-runs); with *Select Path Edges* the mesh edges along the path
are selected too. The length is in the INFO report. One undo step.

Examples
--------
>>> bpy.ops.mesh.heat_geodesic_path()                        # doctest: +SKIP
>>> bpy.ops.mesh.heat_geodesic_path(path_edges=True)         # doctest: +SKIP
"""

import bpy
from bpy.props import BoolProperty

from ._heatcore import heatcore
from .adapters import AddonError
from .legend import format_distance
from .operator import PanelOptionsOperator, poll_editable_mesh
from .path_api import geodesic_path
from .properties import GeodesicOptions


class MESH_OT_heat_geodesic_path(PanelOptionsOperator, GeodesicOptions, bpy.types.Operator):
    """Shortest path on the surface from the active vertex to the other selected one, or through the vertices in the order they were clicked, as a curve object"""

    bl_idname = "mesh.heat_geodesic_path"
    bl_label = "Geodesic Path"
    bl_options = {"REGISTER", "UNDO"}

    closed: BoolProperty(name="Closed Loop", default=False,
                         description="Return from the last selected vertex to the first: a closed loop through them")

    SHOWN = ("closed", "path_edges", "space", "shape", "m", "accuracy")  # what the redo panel shows
    poll = classmethod(poll_editable_mesh)  # it may select edges

    def execute(self, context):
        obj = context.active_object
        try:
            result = geodesic_path(obj, closed=self.closed, select_edges=self.path_edges, space=self.space,
                                   shape=self.shape, **self.solver_options())
        except (AddonError, heatcore.HeatcoreError, MemoryError) as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        for note in result.warnings:
            self.report({"WARNING"}, note)
        length = format_distance(result.length, self.space, context.scene)
        edges = f", {len(result.edges):,} edges selected" if self.path_edges else ""
        route = (f"Geodesic path through {len(result.waypoints)} vertices{' and back to the first' * self.closed}"
                 if len(result.waypoints) > 2 or self.closed else
                 f"Geodesic path from vertex {result.source} to {result.target}")
        self.report({"INFO"}, f"{route}: length "
                              f"{length}, {len(result.points):,} points in {result.curve.name!r}"
                              f"{edges} ({result.seconds:.2f} s)")
        return {"FINISHED"}
