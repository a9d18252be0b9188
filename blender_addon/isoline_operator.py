"""Operator ``mesh.heat_geodesic_isoline_curves``: the isolines of the distance as one curve object.

Reads the FLOAT point attribute written by *Geodesic Distance* (the panel's
*Attribute*, ``geodesic_distance`` by default, or a named one) of the active
mesh object, computes its isolines with :func:`heatcore.isolines` on the
shape the user sees (the evaluated positions in object coordinates, the
mesh's triangles) and writes one curve object, ``"<object> Geodesic Isolines"``
(the name the probe's isolines have: one object), with one POLY spline per
isoline (cyclic when the isoline is closed), parented to the mesh object so
that it sits on it. Running it again, or confirming the probe with *Isoline
Curves*, replaces that object's curve (our objects carry the custom property
:data:`MARKER` and the probe's :data:`~.curves.CURVE_MARKER`). The number of
lines is the panel's *Isolines* when invoked (the curves lie on the stripes
of the distance colors and on the isoline material's lines). Levels are in
the attribute's units: with *Normalize* on, 0..1.

Examples
--------
>>> bpy.ops.mesh.heat_geodesic_isoline_curves(count=8)          # doctest: +SKIP
>>> bpy.ops.mesh.heat_geodesic_isoline_curves(spacing=0.1)      # doctest: +SKIP
"""

import importlib

import bpy
import numpy as np
from bpy.props import FloatProperty, IntProperty, StringProperty

from ._heatcore import heatcore
from .adapters import AddonError, mesh_arrays, stored
from .curves import CURVE_MARKER, fill_splines
from .shape import measured_positions

#: The isoline count's default: the panel's *Isolines* (heatcore's ``isolines`` option, Blender's default).
DEFAULT_COUNT = importlib.import_module(heatcore.__name__ + ".options").OPTIONS["isolines"].default_for("blender")

#: Custom property of the curve objects this operator made (value: the mesh object's name).
MARKER = "heat_geodesic_isolines_of"


def read_distance(obj, name):
    """The values of the FLOAT point attribute ``name`` of ``obj``'s mesh (AddonError when missing or of another kind).

    Examples
    --------
    >>> read_distance(bpy.context.object, "geodesic_distance")  # doctest: +SKIP
    array([0.  , 0.31, ...])
    """
    with stored(obj.data) as mesh:  # Edit Mode: a synced copy holds the data
        attr = mesh.attributes.get(name)
        if attr is None:
            raise AddonError(f"{obj.name!r} has no attribute {name!r}: run Geodesic Distance first")
        if attr.domain != "POINT" or attr.data_type != "FLOAT":
            raise AddonError(f"attribute {name!r} of {obj.name!r} is {attr.data_type} on {attr.domain}, "
                             "not a FLOAT point attribute (the distance)")
        values = np.empty(len(attr.data), dtype=np.float32)
        attr.data.foreach_get("value", values)
    return values.astype(np.float64)


def curve_levels(values, count, spacing):
    """The levels: every multiple of ``spacing`` below the largest finite value when ``spacing > 0``, else ``count`` evenly spaced ones.

    Examples
    --------
    >>> curve_levels(np.array([0.0, 1.0]), 3, 0.0).tolist()
    [0.25, 0.5, 0.75]
    >>> curve_levels(np.array([0.0, 1.0, np.inf]), 3, 0.3).tolist()
    [0.3, 0.6, 0.8999999999999999]
    """
    if spacing <= 0:
        return heatcore.contours.isoline_levels(values, int(count))
    finite = values[np.isfinite(values)]
    if finite.size == 0:
        return np.zeros(0)
    return spacing * np.arange(1, int(np.ceil(finite.max() / spacing)))


def write_curve(obj, curves, name):
    """Put ``curves`` (a list of :class:`heatcore.Isoline`) in the curve object ``name`` parented to ``obj``; returns it.

    Our object of that name gets a new curve (the old one is removed when unused);
    another object of that name is left alone (Blender picks a new name).

    Examples
    --------
    >>> write_curve(obj, heatcore.isolines(V, F, d, 8), "Cube Geodesic Isolines")  # doctest: +SKIP
    bpy.data.objects['Cube Geodesic Isolines']
    """
    data = bpy.data.curves.new(name, type="CURVE")
    data.dimensions = "3D"
    fill_splines(data, [iso.points for iso in curves], [iso.closed for iso in curves])
    target = bpy.data.objects.get(name)
    probe_mark = f"{obj.name}\nIsolines"  # the probe's isolines of obj: the same object
    if target is not None and target.type == "CURVE" and (target.get(MARKER) is not None
                                                         or target.get(CURVE_MARKER) == probe_mark):
        old = target.data
        target.data = data
        if old.users == 0:
            bpy.data.curves.remove(old)
            data.name = name  # the name the removed curve had
    else:
        target = bpy.data.objects.new(name, data)
        collections = obj.users_collection or (bpy.context.scene.collection,)
        collections[0].objects.link(target)
    target[MARKER] = obj.name
    target[CURVE_MARKER] = probe_mark
    target.parent = obj
    target.matrix_parent_inverse.identity()
    target.matrix_basis.identity()
    return target


def isoline_curves(obj, attribute, count=DEFAULT_COUNT, spacing=0.0, name=""):
    """Compute the isolines of ``obj``'s ``attribute`` on its displayed shape and write them as a curve object.

    Returns
    -------
    target : bpy.types.Object
    n : int
        Number of isolines (splines).

    Examples
    --------
    >>> isoline_curves(bpy.context.object, "geodesic_distance", count=8)  # doctest: +SKIP
    (bpy.data.objects['Cube Geodesic Isolines'], 9)
    """
    if obj is None or obj.type != "MESH":
        raise AddonError("the active object must be a mesh")
    if obj.mode == "EDIT":
        obj.update_from_editmode()
    values = read_distance(obj, attribute)
    V, _ = measured_positions(obj, "LOCAL", "EVALUATED")
    _, F = mesh_arrays(obj.data)
    if len(V) != len(values):
        raise AddonError(f"attribute {attribute!r} has {len(values)} values for {len(V)} vertices")
    curves = heatcore.isolines(V, F, values, curve_levels(values, count, spacing))
    return write_curve(obj, curves, name or f"{obj.name} Geodesic Isolines"), len(curves)


class MESH_OT_heat_geodesic_isoline_curves(bpy.types.Operator):
    """Isolines of the geodesic distance as a curve object (one spline per isoline) on the mesh"""

    bl_idname = "mesh.heat_geodesic_isoline_curves"
    bl_label = "Isoline Curves"
    bl_options = {"REGISTER", "UNDO"}

    attribute: StringProperty(name="Attribute", default="",
                              description="FLOAT point attribute with the distance (empty: the panel's Attribute)")
    count: IntProperty(name="Isolines", default=DEFAULT_COUNT, min=1, soft_max=100,
                       description="Number of evenly spaced levels, when Spacing is 0 (from the button: the "
                                   "panel's Isolines, so that the curves lie on the stripes)")
    spacing: FloatProperty(name="Spacing", default=0.0, min=0.0, subtype="DISTANCE",
                           description="Distance between levels in the attribute's units (0: use the number)")
    name: StringProperty(name="Name", default="",
                         description="Curve object (empty: \"<object> Geodesic Isolines\")")

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        if obj is not None and obj.type == "MESH" and not obj.visible_get():
            cls.poll_message_set("The active object is hidden")
            return False
        return obj is not None and obj.type == "MESH"

    def invoke(self, context, event):
        isolines = context.scene.heat_geodesic.isolines
        if not self.properties.is_property_set("count") and isolines > 0:
            self.count = isolines  # the panel's count: the curves lie on the stripes
        return self.execute(context)

    def execute(self, context):
        obj = context.active_object
        attribute = self.attribute or context.scene.heat_geodesic.attribute
        try:
            target, n = isoline_curves(obj, attribute, self.count, self.spacing, self.name)
        except (AddonError, heatcore.HeatcoreError) as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        self.report({"INFO"} if n else {"WARNING"}, f"{n} isolines in {target.name!r}")
        return {"FINISHED"}
