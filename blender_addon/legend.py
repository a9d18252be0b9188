"""The colour legend of the isoline material: a sub-panel of the sidebar panel.

Shown when the active object has the add-on's "Geodesic Isolines" modifier.
It reads what the material draws from the material itself
(:func:`~.material.isoline_legend`): the colour bar is the material's
ColorRamp, the range is 0 to the distance at its top, and the spacing is the
distance between isolines, in scene units (World space) or object units.

Examples
--------
>>> format_distance(2.5, "WORLD", bpy.context.scene)   # doctest: +SKIP
'2.5 m'
"""

import bpy

from .material import isoline_legend


def format_distance(value, space, scene):
    """A distance as text: with the scene's length unit in World space, else in object units.

    Examples
    --------
    >>> format_distance(0.25, "LOCAL", bpy.context.scene)   # doctest: +SKIP
    '0.25 (object units)'
    """
    units = scene.unit_settings
    if space != "WORLD":
        return f"{value:.4g} (object units)"
    if units.system == "NONE":
        return f"{value:.4g}"
    return bpy.utils.units.to_string(units.system, "LENGTH", value * units.scale_length, precision=4,
                                     split_unit=units.use_separate)


class VIEW3D_PT_heat_geodesic_legend(bpy.types.Panel):
    """Colour bar, range and isoline spacing of the active object's isoline material."""

    bl_label = "Legend"
    bl_idname = "VIEW3D_PT_heat_geodesic_legend"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Geodesic"
    bl_parent_id = "VIEW3D_PT_heat_geodesic"

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and isoline_legend(obj) is not None

    def draw(self, context):
        layout = self.layout
        obj = context.active_object
        legend = isoline_legend(obj)
        if legend is None:
            return
        row = layout.row()
        row.label(text=obj.name, icon="MATERIAL")
        row.prop(legend.modifier, "show_viewport", text="")
        row.prop(legend.modifier, "show_render", text="")
        layout.template_color_ramp(legend.ramp, "color_ramp", expand=False)
        row = layout.row()
        row.label(text="0")
        right = row.row()
        right.alignment = "RIGHT"
        right.label(text=format_distance(legend.max_distance, legend.space, context.scene))
        if legend.count:
            spacing = format_distance(legend.spacing, legend.space, context.scene)
            layout.label(text=f"Isolines every {spacing} ({legend.count} lines)")
        else:
            layout.label(text="No isolines")
        layout.label(text="Grey: not reached from the sources")
