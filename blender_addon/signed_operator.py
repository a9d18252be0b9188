"""Operator ``mesh.heat_signed_distance``: *Signed Distance from Edges*, the selected edges as signed curves.

In Edit Mode, select the edges of one or more curves (closed loops, open
chains); selected faces, if any, mark the inside of the loops. The field
(positive inside, on the loops' left) is written by
:func:`~.signed.signed_distance_from_edges`: the attribute
``signed_distance``, blue-to-red colors, and with *Write Weights* a vertex
group (inside 1). It is measured on the shape the user sees (the panel's
*Space*, *Shape* and solver options). One undo step.

Examples
--------
>>> bpy.ops.mesh.heat_signed_distance()                                      # doctest: +SKIP
>>> bpy.ops.mesh.heat_signed_distance(write_weights=True, weight_band=0.1)  # doctest: +SKIP
"""

import bpy
from bpy.props import (
    BoolProperty,
    EnumProperty,
    FloatProperty,
    IntProperty,
    StringProperty,
)

from ._heatcore import heatcore
from .adapters import AddonError
from .operator import options_from_panel, poll_editable_mesh
from .properties import SHAPE_ITEMS, SPACE_ITEMS, option_property, option_value
from .signed import (
    DEFAULT_SIGNED_ATTRIBUTE,
    DEFAULT_SIGNED_COLOR,
    SIGNED_OPTIONS,
    signed_distance_from_edges,
)

#: Options taken from the panel when the operator is invoked from the interface.
FROM_PANEL = ("space", "shape", *SIGNED_OPTIONS)


class MESH_OT_heat_signed_distance(bpy.types.Operator):
    """Signed geodesic distance to the selected edges (signed heat method): positive inside loops, negative outside"""

    bl_idname = "mesh.heat_signed_distance"
    bl_label = "Signed Distance from Edges"
    bl_options = {"REGISTER", "UNDO"}

    attribute: StringProperty(name="Attribute", default=DEFAULT_SIGNED_ATTRIBUTE,
                              description="Point attribute that receives the signed distance")
    color_attribute: StringProperty(name="Color Attribute", default=DEFAULT_SIGNED_COLOR,
                                    description="Color attribute showing it: blue outside, red inside")
    isolines: IntProperty(name="Isolines", default=0, min=0, max=100,
                          description="Dark stripes in the colors: at the curve and this many levels on each side")
    write_weights: BoolProperty(name="Write Weights", default=False,
                                description="Also write a vertex group: 1 inside the loops, 0 outside")
    weight_group: StringProperty(name="Weight Group", default="signed_inside",
                                 description="Vertex group written with Write Weights")
    weight_band: FloatProperty(name="Soft Edge", default=0.0, min=0.0, subtype="DISTANCE",
                               description="Width of the weights' soft edge across the curve (0: a hard mask)")
    space: EnumProperty(name="Space", items=SPACE_ITEMS, default="WORLD",
                        description="Measure in scene units (World) or in the object's own coordinates (Local)")
    shape: EnumProperty(name="Shape", items=SHAPE_ITEMS, default="EVALUATED",
                        description="Measure the shape as displayed, or the mesh data as stored")

    poll = classmethod(poll_editable_mesh)

    def invoke(self, context, event):
        options_from_panel(self, context, FROM_PANEL)
        return self.execute(context)

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        for name in ("attribute", "color_attribute", "isolines", "write_weights"):
            layout.prop(self, name)
        if self.write_weights:
            layout.prop(self, "weight_group")
            layout.prop(self, "weight_band")
        for name in ("space", "shape", "m"):
            layout.prop(self, name)

    def execute(self, context):
        obj = context.active_object
        try:
            result = signed_distance_from_edges(
                obj, attribute=self.attribute or None, color_attribute=self.color_attribute or None,
                weight_group=self.weight_group if self.write_weights else None, weight_band=self.weight_band,
                isolines=self.isolines, space=self.space, shape=self.shape,
                **{name: option_value(name, getattr(self, name)) for name in SIGNED_OPTIONS},
            )
        except (AddonError, heatcore.HeatcoreError, MemoryError) as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        missed = f", {result.unreached:,} vertices in parts no curve reaches (0, gray)" if result.unreached else ""
        self.report({"INFO"}, f"Signed distance from {result.curves} curve{'s' * (result.curves != 1)}: inside up to "
                              f"{result.max_distance:.4g}, outside down to {result.min_distance:.4g}{missed} "
                              f"({result.seconds:.2f} s)")
        return {"FINISHED"}


# The solver and mesh options, one property each, generated from their declarations.
MESH_OT_heat_signed_distance.__annotations__.update({name: option_property(name) for name in SIGNED_OPTIONS})
