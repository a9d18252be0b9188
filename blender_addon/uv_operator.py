"""Operator ``mesh.heat_geodesic_uv_map``: a decal UV map from the logarithmic map around the active vertex.

The button, the menu entries and ``bpy.ops`` run :func:`~.uvmap.geodesic_uv_map`
on the active mesh object, from its active vertex in Edit Mode (or the
``vertex`` given), as one undo step. Options not set by the caller come from
the panel (the scene settings): the UV options of the *UV Map* sub-panel (its
own *Accuracy*, High by default), and *Space*, *Shape*, *Time Factor* and the
*Advanced* solver settings of the distance. *Up: View Up* takes the 3D View's up direction when the
operator is invoked there; from a script or without a 3D View, the *Up Vector*
(with a warning).

Examples
--------
>>> bpy.ops.mesh.heat_geodesic_uv_map(uv_unit=0.5)                                   # doctest: +SKIP
>>> bpy.ops.mesh.heat_geodesic_uv_map(vertex=12, uv_up="VECTOR", uv_up_vector=(0, 1, 0))   # doctest: +SKIP
"""

import bpy
import numpy as np
from bpy.props import EnumProperty, FloatVectorProperty, IntProperty
from mathutils import Vector

from ._heatcore import heatcore
from .adapters import AddonError
from .legend import format_distance
from .operator import options_from_panel, poll_editable_mesh
from .properties import (
    SHAPE_HELP,
    SHAPE_ITEMS,
    SPACE_HELP,
    SPACE_ITEMS,
    UVMapOptions,
    option_property,
    option_value,
)
from .uvmap import VECTOR_OPTIONS, geodesic_uv_map

#: The UV map's solver and mesh options that are the distance's (all but ``accuracy``: ``uv_accuracy``).
SOLVER_SHARED = tuple(name for name in VECTOR_OPTIONS if name != "accuracy")
#: Settings of the distance that the UV map shares (copied from the panel when not set).
SHARED = ("space", "shape", *SOLVER_SHARED)


def view_up(context):
    """The world-space up direction of the 3D View of ``context`` (None without one).

    Examples
    --------
    >>> view_up(bpy.context)   # doctest: +SKIP
    array([0., 0., 1.])
    """
    rv3d = getattr(context, "region_data", None)
    if not isinstance(rv3d, bpy.types.RegionView3D):
        space = getattr(context, "space_data", None)
        rv3d = getattr(space, "region_3d", None) if getattr(space, "type", None) == "VIEW_3D" else None
    if rv3d is None:
        return None
    return np.array((rv3d.view_rotation @ Vector((0.0, 1.0, 0.0)))[:], dtype=np.float64)


class MESH_OT_heat_geodesic_uv_map(UVMapOptions, bpy.types.Operator):
    """UV map from geodesic polar coordinates around the active vertex (vector heat method): a decal placed with the least distortion"""

    bl_idname = "mesh.heat_geodesic_uv_map"
    bl_label = "Geodesic UV Map"
    bl_options = {"REGISTER", "UNDO"}

    vertex: IntProperty(name="Vertex", default=-1, min=-1,
                        description="Source vertex (-1: the active vertex in Edit Mode)")
    space: EnumProperty(name="Space", items=SPACE_ITEMS, default="WORLD", description=SPACE_HELP)
    shape: EnumProperty(name="Shape", items=SHAPE_ITEMS, default="EVALUATED", description=SHAPE_HELP)
    view_up: FloatVectorProperty(name="View Up", size=3, default=(0.0, 0.0, 0.0), options={"HIDDEN", "SKIP_SAVE"},
                                 description="The 3D View's up direction when invoked (zero: none)")

    poll = classmethod(poll_editable_mesh)

    def invoke(self, context, event):
        options_from_panel(self, context, (*UVMapOptions.__annotations__, *SHARED))
        up = view_up(context)
        if up is not None and not self.properties.is_property_set("view_up"):
            self.view_up = up
        return self.execute(context)

    def up_direction(self, context):
        """The ``up`` of :func:`geodesic_uv_map` for these options (with a warning when View Up has no view)."""
        if self.uv_up == "EDGE":
            return "EDGE"
        if self.uv_up == "VIEW":
            up = np.array(self.view_up[:]) if any(self.view_up) else view_up(context)
            if up is not None:
                return up
            self.report({"WARNING"}, "Up: View Up without a 3D View; the Up Vector was used")
        return np.array(self.uv_up_vector[:])

    def execute(self, context):
        obj = context.active_object
        try:
            result = geodesic_uv_map(
                obj, None if self.vertex < 0 else self.vertex, name=self.uv_map, unit=self.uv_unit or None,
                up=self.up_direction(context), space=self.space, shape=self.shape, accuracy=self.uv_accuracy,
                **{name: option_value(name, getattr(self, name)) for name in SOLVER_SHARED},
            )
        except (AddonError, heatcore.HeatcoreError) as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        missed = f", {result.unreached:,} vertices unreached (UV 0, 0)" if result.unreached else ""
        unit, far = (format_distance(value, self.space, context.scene) for value in (result.unit, result.max_distance))
        self.report({"INFO"}, f"UV map {result.name!r}: 1 UV unit = {unit}, farthest vertex "
                              f"{far} from the source{missed}, {result.seconds:.2f} s")
        return {"FINISHED"}


# The distance's options the UV map shares, one property each, generated from their declarations.
MESH_OT_heat_geodesic_uv_map.__annotations__.update({name: option_property(name) for name in SOLVER_SHARED})
