"""The add-on's options (shared by the operator and the panel) and last-run statistics.

:class:`GeodesicOptions` declares every option once; the operator and the
scene settings shown in the panel both inherit it.
"""

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty, StringProperty

from ._heatcore import colormap as colormaps
from .api import DEFAULT_ATTRIBUTE, DEFAULT_COLOR_ATTRIBUTE

SOURCE_ITEMS = [
    ("SELECTED", "Selected Vertices", "Use the selected vertices as sources"),
    ("VERTEX_GROUP", "Vertex Group", "Use the members of a vertex group as sources"),
]
BOUNDARY_ITEMS = [
    ("robin", "Robin", "Mean of the Neumann and Dirichlet heat solutions (recommended)"),
    ("neumann", "Neumann", "Zero-flux boundary: distance bends less near holes"),
    ("dirichlet", "Dirichlet", "Zero heat on the boundary"),
]
COLORMAP_ITEMS = [(name, name.capitalize(), f"Perceptual colormap {name}") for name in colormaps.COLORMAPS]


class GeodesicOptions:
    """Options of one run (mixin for the operator and the scene settings)."""

    source: EnumProperty(name="Sources", items=SOURCE_ITEMS, default="SELECTED")
    vertex_group: StringProperty(name="Source Group", description="Vertex group whose members are the sources")
    time_factor: FloatProperty(
        name="Time Factor",
        description="Heat time t = m h² (h: mean edge length); larger values give a smoother distance",
        default=1.0,
        min=1e-3,
        soft_max=1000.0,
    )
    boundary: EnumProperty(name="Boundary", items=BOUNDARY_ITEMS, default="robin")
    accuracy: EnumProperty(
        name="Accuracy",
        items=[
            ("smooth", "Smooth", "The heat method: smooth distance, about 1-2% error"),
            ("high", "High", "Heat method plus an ordered eikonal pass: about 0.1-0.3% error, slower"),
        ],
        default="smooth",
    )
    robust: BoolProperty(
        name="Robust",
        description="Intrinsic Delaunay operators: accurate on badly shaped triangles",
        default=True,
    )
    attribute: StringProperty(
        name="Attribute", description="FLOAT point attribute that receives the distance", default=DEFAULT_ATTRIBUTE
    )
    normalize: BoolProperty(name="Normalize", description="Store distance / max distance (0..1)", default=False)
    color_attribute: StringProperty(
        name="Color Attribute",
        description="Color attribute that receives the colored distance (made active)",
        default=DEFAULT_COLOR_ATTRIBUTE,
    )
    colormap: EnumProperty(name="Colormap", items=COLORMAP_ITEMS, default="viridis")
    isolines: IntProperty(name="Isolines", description="Number of isoline stripes (0: none)", default=10, min=0, soft_max=50)
    write_weights: BoolProperty(
        name="Vertex Group Output",
        description="Also write the normalized distance as vertex-group weights (for modifiers)",
        default=False,
    )
    weight_group: StringProperty(name="Weight Group", default=DEFAULT_ATTRIBUTE)

    def call_options(self):
        """Keyword arguments of :func:`compute_geodesic_distance` for these options."""
        return dict(
            vertex_group=self.vertex_group if self.source == "VERTEX_GROUP" else None,
            attribute=self.attribute,
            color_attribute=self.color_attribute,
            colormap=self.colormap,
            isolines=self.isolines,
            normalize=self.normalize,
            weight_group=self.weight_group if self.write_weights else None,
            **self.solver_options(),
        )

    def solver_options(self):
        """Options passed through to heatcore (``TriangleMesh`` / ``HeatSolver``)."""
        return dict(m=self.time_factor, boundary=self.boundary, accuracy=self.accuracy, robust=self.robust)


class HeatGeodesicSettings(GeodesicOptions, bpy.types.PropertyGroup):
    """Panel options, stored in the scene (``Scene.heat_geodesic``)."""


class HeatGeodesicStats(bpy.types.PropertyGroup):
    """Statistics of the last run (``WindowManager.heat_geodesic_stats``, not saved)."""

    valid: BoolProperty(default=False)
    object_name: StringProperty()
    vertices: IntProperty()
    sources: IntProperty()
    max_distance: FloatProperty()
    seconds: FloatProperty()
    solver_seconds: FloatProperty()
    cached: BoolProperty()


CLASSES = (HeatGeodesicSettings, HeatGeodesicStats)


def register():
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.Scene.heat_geodesic = PointerProperty(type=HeatGeodesicSettings)
    bpy.types.WindowManager.heat_geodesic_stats = PointerProperty(type=HeatGeodesicStats)


def unregister():
    del bpy.types.WindowManager.heat_geodesic_stats
    del bpy.types.Scene.heat_geodesic
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
