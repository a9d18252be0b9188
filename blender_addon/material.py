"""Isolines drawn per pixel: a generated material shown through a Geometry Nodes modifier.

Per-vertex color stripes are only as sharp as the mesh is fine. This module
draws the distance attribute per pixel instead: a material (colormap colors
and dark isolines) that the shader computes from the *interpolated* distance
attribute, so the lines do not depend on the mesh density. It is shown by a
Geometry Nodes modifier ("Geodesic Isolines") whose node group sets that
material on the evaluated geometry only: the mesh's own materials and face
material indices are never modified, and disabling or removing the modifier
restores the object's look. The vertex colors are still written, for
exporters and Solid shading. The material is *Shaded* (a Principled BSDF lit
by the scene, the color glowing faintly) or *Flat* (an Emission shader: the
colormap's colors exactly, in any light): :data:`ISOLINE_STYLES`.

The isolines have an even width **in screen pixels**, whatever the zoom: a
line pixel is one where the isoline band ``floor(d / spacing)`` changes within
``width`` pixels. Shader nodes have no screen-space derivative node, but the
Bump node evaluates its height one "Filter Width" of pixel footprint away in
two directions (EEVEE: screen x and y; Cycles: two perpendicular tangents);
with the band index as its height, its normal tilts exactly on those pixels
and stays the surface normal everywhere else. A line is 0.7 to 1 times
``width`` pixels wide, depending on its direction on screen. Blender 4.2 and
4.3 have no *Filter Width*: there the lines are :data:`SURFACE_LINE_WIDTH` of
the spacing wide on the surface, the width of the vertex-color stripes.

Re-runs update the modifier, its node group and the material in place. The
add-on's datablocks carry the custom property :data:`MARKER`; a datablock of
the user's is never reused (a name the user took gets Blender's unique
suffix), and an object duplicated with its modifier gets its own copies on
its next run.

Examples
--------
>>> show_isoline_material(obj, "geodesic_distance", colormap="viridis",
...                       max_distance=2.0, spacing=0.2)          # doctest: +SKIP
>>> isoline_legend(obj).spacing                                    # doctest: +SKIP
0.2
"""

from dataclasses import dataclass

import bpy
import numpy as np

from ._heatcore import colormap as colormaps
from .adapters import srgb_to_linear

#: Name of the modifier (Blender adds a suffix if the object has a modifier of that name that is not ours).
ISOLINE_MODIFIER = "Geodesic Isolines"
#: Custom property on the add-on's node groups and materials (value: the space the distance was measured in).
MARKER = "heat_geodesic_isolines"
#: Elements of the ColorRamp (Blender's limit) sampled from heatcore's colormap.
RAMP_SAMPLES = 32
#: Isolines darken the color to this fraction (linear), as heatcore's stripes do (0.25 in sRGB).
LINE_DARKNESS = 0.05
#: Bump distance: large, so that a band change tilts the bump normal far from the surface normal.
BUMP_DISTANCE = 1000.0
#: Before Blender 4.4 (no Bump *Filter Width*): line width on the surface, as a fraction of the spacing.
SURFACE_LINE_WIDTH = 0.08
#: How the material is lit, name -> (label, tooltip): the one declaration of the ``isoline_style`` choices.
ISOLINE_STYLES = {
    "SHADED": ("Shaded", ("Lit by the scene (Principled BSDF), the colors also glowing faintly so that the sides "
                          "away from the light keep them")),
    "FLAT": ("Flat", ("Unlit (Emission): the colormap's colors exactly, in any light; in Solid shading the "
                      "attribute colors are shown with Flat lighting")),
}
#: Shaded style: the color is also emitted at this strength (the shadowed side keeps a readable color).
SHADED_GLOW = 0.25


@dataclass
class IsolineLegend:
    """What the isoline material of an object shows (read back from its nodes).

    Attributes
    ----------
    ramp : bpy.types.ShaderNodeValToRGB
        The colormap (0 at the sources, ``max_distance`` at the top).
    max_distance : float
        Distance at the top of the colormap.
    spacing : float
        Distance between isolines (0: no isolines).
    count : int
        Isolines between 0 and ``max_distance``.
    space : str
        "WORLD" (scene units) or "LOCAL" (object units).
    modifier : bpy.types.NodesModifier
    material : bpy.types.Material
    """

    ramp: object
    max_distance: float
    spacing: float
    count: int
    space: str
    modifier: object
    material: object


def is_isoline_modifier(modifier):
    """Whether ``modifier`` is this add-on's isoline modifier (it sets a material, no vertex changes).

    Examples
    --------
    >>> any(is_isoline_modifier(m) for m in obj.modifiers)   # doctest: +SKIP
    True
    """
    group = getattr(modifier, "node_group", None)
    return modifier.type == "NODES" and group is not None and MARKER in group


def isoline_modifier(obj):
    """The add-on's isoline modifier on ``obj``, or None.

    Examples
    --------
    >>> isoline_modifier(obj).name   # doctest: +SKIP
    'Geodesic Isolines'
    """
    return next((m for m in obj.modifiers if is_isoline_modifier(m)), None)


def _socket(sockets, identifier):
    return next(s for s in sockets if s.identifier == identifier)


def _node(nodes, kind, name, location, **settings):
    node = nodes.new(kind)
    node.name = node.label = name
    node.location = location
    for key, value in settings.items():
        setattr(node, key, value)
    return node


def _fill_ramp(ramp, colormap):
    """ColorRamp elements: heatcore's colormap sampled at RAMP_SAMPLES positions, in linear color."""
    x = np.linspace(0.0, 1.0, RAMP_SAMPLES)
    rgb = srgb_to_linear(colormaps.colorize(x, colormap=colormap, vmax=1.0))
    elements = ramp.color_ramp.elements
    while len(elements) > 1:
        elements.remove(elements[-1])
    elements[0].position, elements[0].color = 0.0, (*rgb[0], 1.0)
    for position, color in zip(x[1:], rgb[1:]):
        elements.new(float(position)).color = (*color, 1.0)
    ramp.color_ramp.interpolation = "LINEAR"
    ramp.color_ramp.color_mode = "RGB"


def _build_shader(material, attribute, colormap, max_distance, spacing, attribute_scale, line_width, style):
    """(Re)build the material's nodes: colormap colors and pixel-width isolines of the distance attribute."""
    tree = material.node_tree
    nodes, links = tree.nodes, tree.links
    nodes.clear()
    math = "ShaderNodeMath"
    attr = _node(nodes, "ShaderNodeAttribute", "Distance Attribute", (-1000, 0),
                 attribute_type="GEOMETRY", attribute_name=attribute)
    dist = _node(nodes, math, "Distance", (-800, 0), operation="MULTIPLY")
    dist.inputs[1].default_value = attribute_scale  # attribute value -> distance (normalized attributes)
    links.new(attr.outputs["Fac"], dist.inputs[0])

    position = _node(nodes, math, "Colormap Position", (-600, 200), operation="DIVIDE")
    position.inputs[1].default_value = max_distance
    ramp = _node(nodes, "ShaderNodeValToRGB", "Colormap", (-400, 250))
    _fill_ramp(ramp, colormap)
    unreachable = _node(nodes, math, "Unreachable", (-400, 400), operation="LESS_THAN")
    unreachable.inputs[1].default_value = 0.0
    grey = _node(nodes, "ShaderNodeMix", "Unreachable Color", (-100, 300), data_type="RGBA", blend_type="MIX")
    _socket(grey.inputs, "B_Color").default_value = (*srgb_to_linear(colormaps.UNREACHABLE_COLOR), 1.0)
    links.new(dist.outputs[0], position.inputs[0])
    links.new(position.outputs[0], ramp.inputs["Fac"])
    links.new(dist.outputs[0], unreachable.inputs[0])
    links.new(unreachable.outputs[0], _socket(grey.inputs, "Factor_Float"))
    links.new(ramp.outputs["Color"], _socket(grey.inputs, "A_Color"))

    band = _node(nodes, math, "Isoline Band", (-600, -200), operation="DIVIDE")
    band.inputs[1].default_value = spacing if spacing > 0 else 1.0
    links.new(dist.outputs[0], band.inputs[0])
    lines = _node(nodes, math, "Isolines", (400, -250), operation="MULTIPLY")
    lines.inputs[1].default_value = 1.0 if spacing > 0 else 0.0
    mask = _pixel_lines(tree, band, line_width) if pixel_lines_supported(tree) else _surface_lines(tree, band)
    links.new(mask, lines.inputs[0])

    color = _node(nodes, "ShaderNodeMix", "Isoline Color", (400, 200), data_type="RGBA", blend_type="MULTIPLY")
    _socket(color.inputs, "B_Color").default_value = (LINE_DARKNESS,) * 3 + (1.0,)
    links.new(lines.outputs[0], _socket(color.inputs, "Factor_Float"))
    links.new(_socket(grey.outputs, "Result_Color"), _socket(color.inputs, "A_Color"))
    _shading(tree, _socket(color.outputs, "Result_Color"), style)


def _shading(tree, color, style):
    """The "Shading" node of ``style`` (:data:`ISOLINE_STYLES`) fed ``color``, into the material output."""
    nodes, links = tree.nodes, tree.links
    output = _node(nodes, "ShaderNodeOutputMaterial", "Output", (950, 200))
    if style == "FLAT":
        shader = _node(nodes, "ShaderNodeEmission", "Shading", (650, 200))
        links.new(color, shader.inputs["Color"])
        shader.inputs["Strength"].default_value = 1.0
    else:
        shader = _node(nodes, "ShaderNodeBsdfPrincipled", "Shading", (650, 200))
        shader.inputs["Roughness"].default_value = 0.6
        shader.inputs["Emission Strength"].default_value = SHADED_GLOW
        links.new(color, shader.inputs["Base Color"])
        links.new(color, shader.inputs["Emission Color"])
    links.new(shader.outputs[0], output.inputs["Surface"])


def pixel_lines_supported(tree):
    """Whether this Blender's Bump node has a *Filter Width* input (4.4 and later): lines a width in pixels.

    Examples
    --------
    >>> pixel_lines_supported(material.node_tree)   # doctest: +SKIP
    True
    """
    probe = tree.nodes.new("ShaderNodeBump")
    try:
        return "Filter Width" in probe.inputs
    finally:
        tree.nodes.remove(probe)


def _pixel_lines(tree, band, line_width):
    """Isoline mask: 1 where the band index changes within ``line_width`` pixels on screen (the Bump test)."""
    nodes, links, math = tree.nodes, tree.links, "ShaderNodeMath"
    floor = _node(nodes, math, "Band Index", (-400, -200), operation="FLOOR")
    bump = _node(nodes, "ShaderNodeBump", "Band Change", (-200, -200))
    bump.inputs["Filter Width"].default_value = line_width  # pixel footprints on screen
    bump.inputs["Distance"].default_value = BUMP_DISTANCE
    geometry = _node(nodes, "ShaderNodeNewGeometry", "Geometry", (-200, -450))
    tilt = _node(nodes, "ShaderNodeVectorMath", "Normal Tilt", (0, -250), operation="DOT_PRODUCT")
    mask = _node(nodes, "ShaderNodeMapRange", "Isoline Mask", (200, -250), clamp=True)
    for key, value in (("From Min", 0.999), ("From Max", 0.5), ("To Min", 0.0), ("To Max", 1.0)):
        mask.inputs[key].default_value = value
    links.new(band.outputs[0], floor.inputs[0])
    links.new(floor.outputs[0], bump.inputs["Height"])
    links.new(bump.outputs["Normal"], tilt.inputs[0])
    links.new(geometry.outputs["Normal"], tilt.inputs[1])
    links.new(tilt.outputs["Value"], mask.inputs["Value"])
    return mask.outputs["Result"]


def _surface_lines(tree, band):
    """Isoline mask before Blender 4.4: 1 within SURFACE_LINE_WIDTH of the spacing of a nonzero multiple."""
    nodes, links, math = tree.nodes, tree.links, "ShaderNodeMath"
    shifted = _node(nodes, math, "Band Phase", (-400, -200), operation="ADD")
    shifted.inputs[1].default_value = 0.5
    fract = _node(nodes, math, "Band Fraction", (-250, -200), operation="FRACT")
    centred = _node(nodes, math, "Band Offset", (-100, -200), operation="SUBTRACT")
    centred.inputs[1].default_value = 0.5
    near = _node(nodes, math, "Isoline Mask", (50, -200), operation="LESS_THAN", use_clamp=False)
    away = _node(nodes, math, "Away From Sources", (50, -400), operation="GREATER_THAN")
    away.inputs[1].default_value = 0.5
    both = _node(nodes, math, "Surface Isolines", (200, -250), operation="MULTIPLY")
    absolute = _node(nodes, math, "Band Distance", (-100, -350), operation="ABSOLUTE")
    near.inputs[1].default_value = 0.5 * SURFACE_LINE_WIDTH
    links.new(band.outputs[0], shifted.inputs[0])
    links.new(shifted.outputs[0], fract.inputs[0])
    links.new(fract.outputs[0], centred.inputs[0])
    links.new(centred.outputs[0], absolute.inputs[0])
    links.new(absolute.outputs[0], near.inputs[0])
    links.new(band.outputs[0], away.inputs[0])
    links.new(near.outputs[0], both.inputs[0])
    links.new(away.outputs[0], both.inputs[1])
    return both.outputs[0]


def _build_group(group, material):
    """(Re)build the modifier's node group: geometry in, Set Material, geometry out."""
    if not group.interface.items_tree:
        group.interface.new_socket(name="Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
        group.interface.new_socket(name="Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    group.is_modifier = True
    nodes = group.nodes
    nodes.clear()
    group_in = _node(nodes, "NodeGroupInput", "Group Input", (-300, 0))
    set_material = _node(nodes, "GeometryNodeSetMaterial", "Set Material", (0, 0))
    set_material.inputs["Material"].default_value = material
    group_out = _node(nodes, "NodeGroupOutput", "Group Output", (300, 0))
    group.links.new(group_in.outputs[0], set_material.inputs["Geometry"])
    group.links.new(set_material.outputs["Geometry"], group_out.inputs[0])


def _material_of(group):
    node = group.nodes.get("Set Material")
    material = node.inputs["Material"].default_value if node is not None else None
    return material if material is not None and MARKER in material else None


def show_isoline_material(obj, attribute, *, colormap, max_distance, spacing, attribute_scale=1.0,
                          line_width=1.5, space="WORLD", style="SHADED"):
    """Show ``obj`` with the isoline material: add or update its "Geodesic Isolines" modifier.

    Parameters
    ----------
    obj : bpy.types.Object
        A mesh object holding the FLOAT POINT attribute ``attribute``.
    attribute : str
        The distance attribute the shader reads (interpolated per pixel).
    colormap : str
        One of ``heatcore.viz.colormap.COLORMAPS``; the ColorRamp holds
        :data:`RAMP_SAMPLES` samples of it (linear color, as the vertex colors).
    max_distance : float
        Distance at the top of the colormap.
    spacing : float
        Distance between isolines, in the units of ``max_distance`` (0: none).
    attribute_scale : float
        Attribute value times this is the distance (``max_distance`` when the
        attribute was normalized, else 1).
    line_width : float
        Isoline width in screen pixels (0.7 to 1 times it, by the line's direction).
    space : str
        The space the distance was measured in (shown by the legend).
    style : str
        How the material is lit, a key of :data:`ISOLINE_STYLES`: "SHADED"
        (Principled BSDF) or "FLAT" (Emission, the colors as they are).

    Returns
    -------
    bpy.types.NodesModifier

    Examples
    --------
    >>> show_isoline_material(obj, "geodesic_distance", colormap="magma",
    ...                       max_distance=3.3, spacing=0.33).name      # doctest: +SKIP
    'Geodesic Isolines'
    """
    modifier = isoline_modifier(obj)
    group = modifier.node_group if modifier is not None else None
    material = _material_of(group) if group is not None else None
    if group is not None and group.users > 1:  # shared with a duplicated object: this one gets its own
        group, material = group.copy(), material.copy() if material is not None else None
    if group is None:
        group = bpy.data.node_groups.new(f"{ISOLINE_MODIFIER} ({obj.name})", "GeometryNodeTree")
    if material is None:
        material = bpy.data.materials.new(f"{ISOLINE_MODIFIER} ({obj.name})")
    group[MARKER] = material[MARKER] = space
    if material.node_tree is None:  # Blender before 5.0: nodes are opt-in
        material.use_nodes = True
    _build_shader(material, attribute, colormap, max(max_distance, 1e-30), spacing, attribute_scale, line_width,
                  style)
    _build_group(group, material)
    if modifier is None:
        modifier = obj.modifiers.new(ISOLINE_MODIFIER, "NODES")
    if modifier.node_group != group:
        modifier.node_group = group
    return modifier


def isoline_legend(obj):
    """Range, spacing and colormap of ``obj``'s isoline material, read from its nodes; None without one.

    Examples
    --------
    >>> legend = isoline_legend(bpy.context.object)             # doctest: +SKIP
    >>> legend.max_distance, legend.spacing, legend.count       # doctest: +SKIP
    (3.3, 0.33, 10)
    """
    modifier = isoline_modifier(obj) if obj is not None else None
    material = _material_of(modifier.node_group) if modifier is not None else None
    nodes = material.node_tree.nodes if material is not None and material.node_tree else None
    if nodes is None or not all(n in nodes for n in ("Colormap", "Colormap Position", "Isoline Band", "Isolines")):
        return None
    top = nodes["Colormap Position"].inputs[1].default_value
    spacing = nodes["Isoline Band"].inputs[1].default_value if nodes["Isolines"].inputs[1].default_value else 0.0
    count = int(np.ceil(top / spacing * (1 - 1e-6))) - 1 if spacing > 0 else 0  # lines below the top
    return IsolineLegend(nodes["Colormap"], top, spacing, count, material[MARKER], modifier, material)
