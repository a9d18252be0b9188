"""Operator ``mesh.heat_geodesic_select_within``: *Select › Within Geodesic Distance* (Edit Mode).

Grows the selection along the surface: every vertex whose geodesic
distance from the selected vertices is at most *Distance* is selected
(edges and faces follow, as Blender's own selection tools do). The distance
is measured as *Geodesic Distance* measures it (the panel's *Space*,
*Shape* and solver options; the cached solver is reused); nothing is
written to the mesh but the selection. One undo step.

Examples
--------
>>> bpy.ops.mesh.heat_geodesic_select_within(distance=0.3)       # doctest: +SKIP
"""

import bmesh
import bpy
import numpy as np
from bpy.props import FloatProperty

from ._heatcore import heatcore
from .adapters import AddonError
from .api import compute_geodesic_distance
from .legend import format_distance


def select_within(obj, distance, **options):
    """Select the vertices of ``obj`` (in Edit Mode) within ``distance`` of the selected ones; their count.

    ``options`` are keywords of :func:`~.api.compute_geodesic_distance`
    (``space``, ``shape``, the solver's); no attribute is written.

    Examples
    --------
    >>> select_within(bpy.context.object, 0.3)  # doctest: +SKIP
    412
    """
    if obj is None or obj.type != "MESH" or obj.mode != "EDIT":
        raise AddonError("Within Geodesic Distance works on a mesh in Edit Mode")
    result = compute_geodesic_distance(obj, attribute=None, color_attribute=None, **options)
    within = np.flatnonzero(result.distance <= distance)
    bm = bmesh.from_edit_mesh(obj.data)
    bm.verts.ensure_lookup_table()
    for i in within.tolist():
        bm.verts[i].select = True
    bm.select_flush(True)
    bmesh.update_edit_mesh(obj.data, loop_triangles=False, destructive=False)
    return len(within)


class MESH_OT_heat_geodesic_select_within(bpy.types.Operator):
    """Select every vertex within a geodesic distance of the selected ones (grow the selection along the surface)"""

    bl_idname = "mesh.heat_geodesic_select_within"
    bl_label = "Within Geodesic Distance"
    bl_options = {"REGISTER", "UNDO"}

    distance: FloatProperty(
        name="Distance", default=0.5, min=0.0, soft_max=10.0, subtype="DISTANCE",
        description="Largest geodesic distance from the selected vertices of the vertices selected, in the units "
                    "of the panel's Space (scene units in World space)",
    )

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        if obj is None or obj.type != "MESH" or obj.mode != "EDIT":
            cls.poll_message_set("Needs a mesh in Edit Mode")
            return False
        return True

    def execute(self, context):
        settings = context.scene.heat_geodesic
        obj = context.active_object
        try:
            n = select_within(obj, self.distance, space=settings.space, shape=settings.shape,
                              polygons=settings.polygons, **settings.solver_options())
        except (AddonError, heatcore.HeatcoreError, MemoryError) as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        radius = format_distance(self.distance, settings.space, context.scene)
        self.report({"INFO"}, f"{n:,} vertices within {radius} of the selection")
        return {"FINISHED"}
