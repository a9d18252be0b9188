"""The *Geodesic Distance* operator's redo panel (*Adjust Last Operation*, F9): what matters for the run.

Grouped as the sidebar panel is (Sources, Measure, Solver, Output), with
the rows that depend on a switch (the group of *Vertex Group* sources, the
isoline material's spacing and width, the weight group's radius and
falloff) shown only when it is on, and the solver's technical settings in a
closed *Advanced* section. *Select Path Edges* (``path_edges``), an option of
*Geodesic Path* that does nothing here, is not shown.

Examples
--------
>>> draw_run_options(self.layout, self)   # doctest: +SKIP
"""

#: The solver's technical settings, in the closed *Advanced* section (as the sidebar's *Advanced* sub-panel).
ADVANCED = ("boundary", "robust", "backend", "polygons", "refine", "weld")
#: Options of the run's properties that the redo panel leaves out (they do nothing in this operator).
HIDDEN = ("path_edges",)


def draw_run_options(layout, props):
    """Draw ``props`` (the operator's properties) into ``layout``, grouped, without :data:`HIDDEN`."""
    layout.use_property_split = True
    layout.use_property_decorate = False

    col = layout.column(heading="Sources")
    col.prop(props, "source")
    if props.source == "VERTEX_GROUP":
        col.prop(props, "vertex_group", text="Group")

    col = layout.column(heading="Measure")
    col.prop(props, "space")
    col.prop(props, "shape")
    if props.shape == "EVALUATED":
        col.prop(props, "new_object")

    col = layout.column(heading="Solver")
    col.prop(props, "m")
    col.prop(props, "accuracy")

    col = layout.column(heading="Output")
    col.prop(props, "attribute")
    col.prop(props, "normalize")
    col.prop(props, "color_attribute", text="Colors")
    col.prop(props, "colormap")
    col.prop(props, "isolines")
    col.prop(props, "isoline_material")
    if props.isoline_material:
        col.prop(props, "isoline_spacing")
        col.prop(props, "isoline_width")
        col.prop(props, "isoline_style")
    col.prop(props, "write_weights")
    if props.write_weights:
        for name in ("weight_group", "weight_radius", "weight_falloff", "weight_invert"):
            col.prop(props, name)

    header, body = layout.panel("heat_geodesic_redo_advanced", default_closed=True)
    header.label(text="Advanced")
    if body is not None:
        for name in ADVANCED:
            body.prop(props, name)
