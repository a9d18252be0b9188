"""The add-on's options (shared by the operator and the panel) and last-run statistics.

:class:`GeodesicOptions` declares every option once; the operator and the
scene settings shown in the panel both inherit it. heatcore's options, those
the Blender front end offers (``heatcore.settings.FRONT_END_OPTIONS["blender"]``:
``m``, ``boundary``, ``accuracy``, ``backend``, ``robust``, ``refine``,
``weld``, ``colormap``, ``isolines``, ``weight_radius``, ``weight_falloff``,
``weight_invert``), are generated from ``heatcore.options`` by
:func:`option_property`, one property per name of that table: the property
name is the option's name, and its description, default, range and choices
are the declared ones (the label may be friendlier). A number that also takes
words (``refine``: ``"auto"`` or 0..8) is a menu of the words and the
numbers. An option that may be None (``weight_radius``) declares the
Blender value standing for None as its Blender default (0: the largest
distance); :func:`option_value` turns it back into None. One declared as a
switch (``weld``, *Merge Coincident Vertices*) is a Boolean: off is None (the
Blender default: the mesh as connected in Blender), on its core default
(``weld=0.0``: exactly coincident vertices merged). The add-on's own options
(sources, output names) are declared here.
"""

import importlib

import bpy
from bpy.props import (
    BoolProperty,
    EnumProperty,
    FloatProperty,
    FloatVectorProperty,
    IntProperty,
    PointerProperty,
    StringProperty,
)

from ._heatcore import heatcore
from .api import (
    DEFAULT_ATTRIBUTE,
    DEFAULT_COLOR_ATTRIBUTE,
    DEFAULT_WEIGHT_GROUP,
    options,
)
from .material import ISOLINE_STYLES
from .stages import FRONT_END_OPTIONS
from .tooltips import choice_help, option_help
from .uvmap import DEFAULT_UV_MAP

#: ``heatcore.linalg`` (the bundled copy's): which factorization backends are usable here.
linalg = importlib.import_module(heatcore.__name__ + ".linalg")
#: heatcore options that are properties here: those the Blender front end offers, in the table's order.
HEATCORE_OPTIONS = FRONT_END_OPTIONS["blender"]
#: Of those, the ones that shape the domain and the solver (the others are outputs).
SOLVER_OPTIONS = tuple(name for name in HEATCORE_OPTIONS if options.OPTIONS[name].target in ("mesh", "solver"))

#: Enum labels that are not the choice capitalized (library names).
CHOICE_LABELS = {"qdldl": "QDLDL", "cholmod": "CHOLMOD", "superlu": "SuperLU", "gpu": "GPU"}

SPACE_ITEMS = [
    ("WORLD", "World", "Measure in scene units: the object's scale, rotation and parents applied"),
    ("LOCAL", "Local", "Measure in the object's own coordinates"),
]
SHAPE_ITEMS = [
    ("EVALUATED", "As Displayed", "Shape keys and deform modifiers applied (modifiers that change the vertices are "
                                  "left out, with a warning)"),
    ("BASIS", "Mesh Data", "The mesh as stored, without shape keys or modifiers"),
]

POLYGON_ITEMS = [
    ("AUTO", "Keep Polygons", ("Measure quads and n-gons as faces: each on its own Delaunay triangulation, "
                               "concave ones included; triangle meshes, High accuracy and Robust off use the loop "
                               "triangles")),
    ("TRIANGULATE", "Triangulate", "Always measure the mesh's loop triangles (Blender's own split of each face)"),
]

SPACE_HELP = "Coordinates the distance is measured in: with the object's transform (scene units) or without"
SHAPE_HELP = "Which shape of the mesh is measured: as displayed (shape keys, deform modifiers) or as stored"

SOURCE_ITEMS = [
    ("SELECTED", "Selected Vertices", "Use the selected vertices as sources"),
    ("EDGES", "Selected Edges", "Distance to the selected edges: 0 all along them, not only at their vertices"),
    ("FACES", "Selected Faces", "Distance to the selected faces (a region): 0 inside it, measured from its border"),
    ("VERTEX_GROUP", "Vertex Group", "Use the members of a vertex group as sources"),
]


def option_property(name, front_end="blender"):
    """The bpy property of heatcore option ``name`` (``heatcore.options.OPTIONS[name]``), with ``front_end``'s default.

    Examples
    --------
    >>> option_property("m").keywords["default"]  # doctest: +SKIP
    1.0
    """
    opt = options.OPTIONS[name]
    kw = {"name": opt.ui_label or opt.label.title(), "description": option_help(name, opt.help),
          "default": opt.default_for(front_end)}
    if opt.switch_help:  # on: the core's default; off: None
        return BoolProperty(**{**kw, "description": option_help(name, opt.switch_help),
                               "default": kw["default"] is not None})
    if opt.choices:
        items = [(c, CHOICE_LABELS.get(c, c.capitalize()), choice_help(name, c, text))
                 for c, text in zip(opt.choices, opt.choice_help) if usable_choice(name, c)]
        return EnumProperty(items=items, **kw)
    if opt.specials:  # words or whole numbers in a range (refine: "auto" or 0..8): a menu of them
        return EnumProperty(items=special_items(opt), **kw)
    if opt.type is bool:
        return BoolProperty(**kw)
    low = _none_stand_in(opt) if opt.default is None else opt.ui_min if opt.low_open else opt.low
    limits = {"min": low, "max": opt.high, "soft_max": opt.soft_max}
    limits = {k: v for k, v in limits.items() if v is not None}
    if opt.type is int:
        return IntProperty(**kw, **limits)
    if "a length" in (opt.unit or ""):  # shown in the scene's units (weight_radius)
        limits["subtype"] = "DISTANCE"
    return FloatProperty(**kw, **limits)


def usable_choice(name, choice):
    """Whether the menu of option ``name`` offers ``choice`` here: the GPU backend only where Blender's Python has
    its CUDA libraries and a GPU (a Blender user cannot install them from the menu's error); no "auto" accuracy
    (it is "high" for one query with numba only: in Blender, interactive and without numba, always "smooth").

    Examples
    --------
    >>> usable_choice("backend", "auto"), usable_choice("colormap", "magma"), usable_choice("accuracy", "auto")  # doctest: +SKIP
    (True, True, False)
    """
    if (name, choice) == ("accuracy", "auto"):
        return False
    if (name, choice) != ("backend", "gpu"):
        return True
    return choice in linalg.available_backends()


def special_items(opt):
    """Enum items of an integer option that also takes words: the words, then ``low``..``high`` as text.

    Examples
    --------
    >>> [item[0] for item in special_items(options.OPTIONS["refine"])][:3]  # doctest: +SKIP
    ['auto', '0', '1']
    """
    label = opt.ui_label or opt.label.title()
    words = [(word, word.capitalize(), f"{label}: {word} (see the description)") for word in opt.specials]
    return words + [(str(k), str(k), f"{label}: {k} level{'s' * (k != 1)}") for k in range(opt.low, opt.high + 1)]


def _none_stand_in(opt):
    """The Blender value of an option that stands for None: its declared Blender default, if its default is None."""
    return opt.default_for("blender") if opt.default is None and opt.none_means else None


def option_value(name, value):
    """The heatcore value of property ``name``: None where Blender holds the stand-in for None (a switch: off).

    Examples
    --------
    >>> option_value("weight_radius", 0.0), option_value("weight_radius", 2.5)  # doctest: +SKIP
    (None, 2.5)
    >>> option_value("weld", False), option_value("weld", True)  # doctest: +SKIP
    (None, 0.0)
    >>> option_value("refine", "auto"), option_value("refine", "3")  # doctest: +SKIP
    ('auto', 3)
    """
    opt = options.OPTIONS[name]
    if opt.switch_help:
        return opt.default if value else None
    if opt.specials and isinstance(value, str) and value not in opt.specials:  # a menu's number ("3")
        return int(value)
    stand_in = _none_stand_in(opt)
    return None if stand_in is not None and value == stand_in else value


class GeodesicOptions:
    """Options of one run (mixin for the operator and the scene settings)."""

    source: EnumProperty(name="Sources", items=SOURCE_ITEMS, default="SELECTED",
                         description="Where the distance is measured from")
    vertex_group: StringProperty(name="Source Group", description="Vertex group whose members are the sources")
    polygons: EnumProperty(name="Polygons", items=POLYGON_ITEMS, default="AUTO",
                           description="How quads and n-gons are measured: as polygons or as their triangles")
    attribute: StringProperty(
        name="Attribute", description="Float point attribute that receives the distance", default=DEFAULT_ATTRIBUTE
    )
    normalize: BoolProperty(name="Normalize", description="Store distance / max distance (0..1)", default=False)
    color_attribute: StringProperty(
        name="Color Attribute",
        description="Color attribute that receives the colored distance (made active)",
        default=DEFAULT_COLOR_ATTRIBUTE,
    )
    write_weights: BoolProperty(
        name="Vertex Group Output",
        description="Also write weights to a vertex group (for modifiers): 1 at the sources falling to 0 at the "
                    "radius; the group becomes the active one",
        default=False,
    )
    weight_group: StringProperty(
        name="Weight Group",
        description="Vertex group that receives the weights; it must not share its name with an attribute",
        default=DEFAULT_WEIGHT_GROUP,
    )
    space: EnumProperty(name="Space", items=SPACE_ITEMS, default="WORLD", description=SPACE_HELP)
    shape: EnumProperty(name="Shape", items=SHAPE_ITEMS, default="EVALUATED", description=SHAPE_HELP)
    new_object: BoolProperty(
        name="Apply All Modifiers (New Object)",
        description="Measure the whole evaluated mesh, Subdivision, Mirror and other modifiers that change the "
                    "vertices included, on a new object '<name> Geodesic' (reused on re-runs); the original is "
                    "not modified",
        default=False,
    )
    isoline_material: BoolProperty(
        name="Isoline Material",
        description="Show the distance per pixel with a generated material: colormap colors and smooth isolines "
                    "of even width, independent of the mesh density, in Material Preview and renders (a 'Geodesic "
                    "Isolines' modifier sets it; the mesh's own materials are not modified)",
        default=True,
    )
    isoline_style: EnumProperty(
        name="Style", items=[(key, label, tip) for key, (label, tip) in ISOLINE_STYLES.items()], default="SHADED",
        description="How the isoline material is lit: by the scene, or not at all (the colors exactly)",
    )
    isoline_spacing: FloatProperty(
        name="Spacing",
        description="Distance between the material's isolines (0: the largest distance / (Isolines + 1), the "
                    "spacing of the stripes in the distance colors)",
        default=0.0, min=0.0, soft_max=10.0, subtype="DISTANCE",
    )
    path_edges: BoolProperty(
        name="Select Path Edges",
        description="Geodesic Path also selects the mesh edges along the path: the shortest chain of edges from the "
                    "source to the target among the faces the path crosses",
        default=False,
    )
    isoline_width: FloatProperty(
        name="Line Width",
        description="Width of the material's isolines in screen pixels, at any zoom (0.7 to 1 times it, by the "
                    "line's direction)",
        default=1.5, min=0.1, max=20.0,
    )

    def call_options(self):
        """Keyword arguments of :func:`compute_geodesic_distance` for these options."""
        return dict(
            vertex_group=self.vertex_group if self.source == "VERTEX_GROUP" else None,
            selected=self.source if self.source in ("EDGES", "FACES") else "VERTICES",
            attribute=self.attribute,
            color_attribute=self.color_attribute,
            colormap=self.colormap,
            isolines=self.isolines,
            normalize=self.normalize,
            weight_group=self.weight_group if self.write_weights else None,
            weight_radius=option_value("weight_radius", self.weight_radius),
            weight_falloff=self.weight_falloff,
            weight_invert=self.weight_invert,
            space=self.space,
            shape=self.shape,
            new_object=self.new_object,
            isoline_material=self.isoline_material,
            isoline_spacing=self.isoline_spacing,
            isoline_width=self.isoline_width,
            isoline_style=self.isoline_style,
            polygons=self.polygons,
            **self.solver_options(),
        )

    def solver_options(self):
        """The domain's and the solver's options (:data:`SOLVER_OPTIONS`) as keywords of the script API."""
        return {name: option_value(name, getattr(self, name)) for name in SOLVER_OPTIONS}


# Every option the Blender front end offers, one property each, generated from its declaration.
GeodesicOptions.__annotations__.update({name: option_property(name) for name in HEATCORE_OPTIONS})


UV_UP_ITEMS = [
    ("VIEW", "View Up", "The 3D View's up direction (from a script or without a 3D View: the Up Vector)"),
    ("EDGE", "Selected Edge", "Along the source vertex's selected edge (the first by index), else its first edge"),
    ("VECTOR", "Vector", "The Up Vector, in world coordinates"),
]


class UVMapOptions:
    """Options of the *Geodesic UV Map* (mixin for its operator and the scene settings)."""

    uv_map: StringProperty(
        name="UV Map", default=DEFAULT_UV_MAP,
        description="UV map that receives the coordinates (one made by an earlier run is overwritten; any other "
                    "attribute or UV map of that name is refused)",
    )
    uv_unit: FloatProperty(
        name="UV Unit", default=0.0, min=0.0, soft_max=10.0, subtype="DISTANCE",
        description="Length on the surface of one UV unit, in the units of Space (0: twice the largest distance, "
                    "so that the map fills the 0..1 square)",
    )
    uv_accuracy: option_property("accuracy", front_end="vector heat")  # the radii: the eikonal pass by default
    uv_up: EnumProperty(name="Up", items=UV_UP_ITEMS, default="VIEW",
                        description="Direction at the source that becomes +V (up in the image)")
    uv_up_vector: FloatVectorProperty(
        name="Up Vector", size=3, default=(0.0, 0.0, 1.0), subtype="XYZ",
        description="World-space up direction (Up: Vector, or View Up without a 3D View); its part along the "
                    "surface normal is dropped",
    )


class HeatGeodesicSettings(GeodesicOptions, UVMapOptions, bpy.types.PropertyGroup):
    """Panel options, stored in the scene (``Scene.heat_geodesic``)."""


class HeatGeodesicStats(bpy.types.PropertyGroup):
    """Statistics of the last run (``WindowManager.heat_geodesic_stats``, not saved)."""

    valid: BoolProperty(default=False)
    object_name: StringProperty()
    vertices: IntProperty()
    sources: IntProperty()
    max_distance: FloatProperty()
    space: StringProperty(default="WORLD")
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
