"""Sidebar panel: View3D > Sidebar > Geodesic, with a closed *Advanced* sub-panel.

The main panel holds what a user chooses (sources, how to measure, the time
factor, the accuracy, the outputs); the solver's technical settings
(boundary condition, robust operators, linear-algebra backend, polygons, refinement,
*Merge Coincident Vertices*) are in the *Advanced* sub-panel, closed by default.
"""

import bpy

from .legend import VIEW3D_PT_heat_geodesic_legend, format_distance


class VIEW3D_PT_heat_geodesic(bpy.types.Panel):
    """Button, options and last result of the geodesic distance operator."""

    bl_label = "Geodesic Distance"
    bl_idname = "VIEW3D_PT_heat_geodesic"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Geodesic"

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        settings = context.scene.heat_geodesic
        obj = context.active_object

        row = layout.row(align=True)
        row.operator("mesh.heat_geodesic_distance", icon="DRIVER_DISTANCE")
        row.operator("mesh.heat_geodesic_isoline_curves", text="Curves", icon="OUTLINER_OB_CURVE")
        layout.operator("mesh.heat_geodesic_probe", icon="CURSOR")
        layout.operator("mesh.heat_geodesic_path", icon="CURVE_PATH")
        layout.operator("mesh.heat_straighten_edges", icon="IPO_LINEAR")
        layout.operator("mesh.heat_signed_distance", icon="MOD_MASK")

        col = layout.column(heading="Sources")
        col.prop(settings, "source", text="Sources")
        if settings.source == "VERTEX_GROUP":
            if obj is not None and obj.type == "MESH":
                col.prop_search(settings, "vertex_group", obj, "vertex_groups", text="Group")
            else:
                col.prop(settings, "vertex_group", text="Group")

        col = layout.column(heading="Measure")
        col.prop(settings, "space")
        col.prop(settings, "shape")
        row = col.row()
        row.enabled = settings.shape == "EVALUATED"
        row.prop(settings, "new_object")

        col = layout.column(heading="Solver")
        col.prop(settings, "m")
        col.prop(settings, "accuracy")

        col = layout.column(heading="Output")
        col.prop(settings, "attribute")
        col.prop(settings, "normalize")
        col.prop(settings, "color_attribute", text="Colors")
        col.prop(settings, "colormap")
        col.prop(settings, "isolines")
        col.prop(settings, "isoline_material")
        sub = col.column()
        sub.enabled = settings.isoline_material
        sub.prop(settings, "isoline_spacing")
        sub.prop(settings, "isoline_width")
        sub.prop(settings, "isoline_style")
        col.prop(settings, "write_weights")
        if settings.write_weights:
            col.prop(settings, "weight_group")
            col.prop(settings, "weight_radius")
            col.prop(settings, "weight_falloff")
            col.prop(settings, "weight_invert")
        col.prop(settings, "path_edges")

        stats = context.window_manager.heat_geodesic_stats
        if stats.valid:
            box = layout.box()
            box.label(text=f"Last: {stats.object_name}", icon="INFO")
            box.label(text=f"{stats.vertices:,} vertices, {stats.sources:,} sources")
            box.label(text=f"Max distance {format_distance(stats.max_distance, stats.space, context.scene)}")
            solver = "cached solver" if stats.cached else f"solver {stats.solver_seconds:.2f} s"
            box.label(text=f"{stats.seconds:.2f} s ({solver})")


class VIEW3D_PT_heat_geodesic_advanced(bpy.types.Panel):
    """Solver settings most users never change (closed by default)."""

    bl_label = "Advanced"
    bl_idname = "VIEW3D_PT_heat_geodesic_advanced"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Geodesic"
    bl_parent_id = VIEW3D_PT_heat_geodesic.bl_idname
    bl_options = {"DEFAULT_CLOSED"}

    #: The settings shown here, in order.
    PROPERTIES = ("boundary", "robust", "backend", "polygons", "refine", "weld")

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        settings = context.scene.heat_geodesic
        col = layout.column()
        for name in self.PROPERTIES:
            col.prop(settings, name)


class VIEW3D_PT_heat_geodesic_uv_map(bpy.types.Panel):
    """The *Geodesic UV Map* button and its options (it measures with the distance's Space, Shape and solver)."""

    bl_label = "UV Map"
    bl_idname = "VIEW3D_PT_heat_geodesic_uv_map"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Geodesic"
    bl_parent_id = VIEW3D_PT_heat_geodesic.bl_idname
    bl_options = {"DEFAULT_CLOSED"}

    #: The settings shown here, in order (``properties.UVMapOptions``).
    PROPERTIES = ("uv_map", "uv_unit", "uv_accuracy", "uv_up", "uv_up_vector")

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        settings = context.scene.heat_geodesic
        layout.operator("mesh.heat_geodesic_uv_map", icon="UV")
        col = layout.column()
        for name in self.PROPERTIES:
            row = col.row()
            row.enabled = name != "uv_up_vector" or settings.uv_up != "EDGE"
            row.prop(settings, name)


CLASSES = (VIEW3D_PT_heat_geodesic, VIEW3D_PT_heat_geodesic_legend, VIEW3D_PT_heat_geodesic_advanced,
           VIEW3D_PT_heat_geodesic_uv_map)


def register():
    for cls in CLASSES:
        bpy.utils.register_class(cls)


def unregister():
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
