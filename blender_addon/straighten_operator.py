"""Operator ``mesh.heat_straighten_edges``: *Straighten Edges*, a selected edge path or loop shortened to a geodesic.

In Edit Mode, select an edge path (its ends stay) or an edge loop (it
shrinks to the closed geodesic of its class: around a cylinder, its waist),
or several. :func:`~.straighten.straighten_edges` writes the geodesics as
the curve object ``"<name> Geodesic Straightened"``; with *Select Path Edges*
the edges nearest to each straightened path replace its selection. The
lengths before and after are in the info report. One undo step.

Examples
--------
>>> bpy.ops.mesh.heat_straighten_edges()                   # doctest: +SKIP
>>> bpy.ops.mesh.heat_straighten_edges(path_edges=True)    # doctest: +SKIP
"""

import bpy

from ._heatcore import heatcore
from .adapters import AddonError
from .operator import PanelOptionsOperator, poll_editable_mesh
from .properties import GeodesicOptions
from .straighten import straighten_edges


class MESH_OT_heat_straighten_edges(PanelOptionsOperator, GeodesicOptions, bpy.types.Operator):
    """Shorten the selected edge path or loop to a geodesic on the surface (ends kept), as a curve object"""

    bl_idname = "mesh.heat_straighten_edges"
    bl_label = "Straighten Edges"
    bl_options = {"REGISTER", "UNDO"}

    SHOWN = ("path_edges", "space", "shape")  # what the redo panel shows
    poll = classmethod(poll_editable_mesh)  # it may select edges

    def execute(self, context):
        obj = context.active_object
        try:
            result = straighten_edges(obj, select_edges=self.path_edges, space=self.space, shape=self.shape,
                                      **self.solver_options())
        except (AddonError, heatcore.HeatcoreError, MemoryError) as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        for note in result.warnings:
            self.report({"WARNING"}, note)
        units = "scene units" if self.space == "WORLD" else "object units"
        shapes = ", ".join(f"{'loop' if c else 'path'} {b:.4g} -> {a:.4g}"
                           for c, b, a in zip(result.closed, result.before, result.lengths))
        self.report({"INFO"}, f"Straightened in {result.curve.name!r} ({units}): {shapes} ({result.seconds:.2f} s)")
        return {"FINISHED"}
