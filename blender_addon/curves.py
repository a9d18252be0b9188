"""The probe's geodesic path and isolines as curve objects, and whether this heatcore computes paths.

Geodesic paths are ``HeatSolver.geodesic_path`` (heatcore's paths); a copy
of heatcore without them makes the probe refuse paths with a message, and
everything else works. :func:`write_curves` makes (or updates) one curve
object per probed object and kind, ``"<name> Geodesic Path"`` (a poly
spline through the path's points) or ``"<name> Geodesic Isolines"`` (one
spline per isoline of ``heatcore.isolines``, closed ones cyclic), in world
coordinates.

Examples
--------
>>> path_available(solver)                                    # doctest: +SKIP
True
>>> write_curves(obj, "Path", [path_points]).name             # doctest: +SKIP
'Suzanne Geodesic Path'
"""

import bpy
import numpy as np
from mathutils import Matrix

from ._heatcore import heatcore

#: Custom property marking the curve objects made here (value: the probed object's name and the kind).
CURVE_MARKER = "heat_geodesic_curve_of"


def path_available(solver):
    """Whether ``solver`` computes geodesic paths (``HeatSolver.geodesic_path``).

    Examples
    --------
    >>> path_available(object())
    False
    """
    return callable(getattr(solver, "geodesic_path", None))


def write_curves(obj, kind, polylines, closed=None):
    """The curve object ``"<name> Geodesic <kind>"`` of ``obj``, made or updated to hold ``polylines`` (world).

    One poly spline per polyline (cyclic where ``closed`` says so), placed
    in ``obj``'s collections at the identity matrix, and marked with
    :data:`CURVE_MARKER` so that the next confirm updates it.

    Examples
    --------
    >>> write_curves(obj, "Path", [[[0, 0, 0], [1, 0, 0]]]).data.splines[0].type   # doctest: +SKIP
    'POLY'
    """
    mark = f"{obj.name}\n{kind}"
    curve = next((o for o in bpy.data.objects if o.get(CURVE_MARKER) == mark and o.type == "CURVE"), None)
    if curve is None:
        name = f"{obj.name} Geodesic {kind}"
        data = bpy.data.curves.new(name, "CURVE")
        data.dimensions = "3D"
        curve = bpy.data.objects.new(name, data)  # not data.name: an orphan curve of that name renames the data
        curve[CURVE_MARKER] = mark
        for collection in obj.users_collection or (bpy.context.scene.collection,):
            collection.objects.link(curve)
    curve.data.splines.clear()
    fill_splines(curve.data, polylines, closed)
    curve.matrix_world = Matrix.Identity(4)
    return curve


def fill_splines(data, polylines, closed=None):
    """Add one poly spline per polyline (``(k, 3)`` points) to the curve ``data``, cyclic where ``closed`` says so.

    Examples
    --------
    >>> fill_splines(bpy.data.curves.new("c", "CURVE"), [[[0, 0, 0], [1, 0, 0]]])   # doctest: +SKIP
    """
    for k, line in enumerate(polylines):
        points = np.asarray(line, dtype=np.float32).reshape(-1, 3)
        spline = data.splines.new("POLY")
        spline.points.add(len(points) - 1)
        co = np.ones((len(points), 4), dtype=np.float32)
        co[:, :3] = points
        spline.points.foreach_set("co", co.ravel())
        spline.use_cyclic_u = bool(closed[k]) if closed is not None else False


def write_probe_curves(probe, obj):
    """The curve objects a confirmed probe asked for: its path (``path_curve``) and its isolines (``isoline_curves``).

    Examples
    --------
    >>> write_probe_curves(probe, obj)                         # doctest: +SKIP
    """
    if probe.path_curve and probe.path is not None:
        write_curves(obj, "Path", [probe.overlay_data().path])
    count = int(probe.run.outputs["isolines"])
    if probe.isoline_curves and count:
        lines = heatcore.isolines(probe.surface.positions, probe.triangles, probe.distance, count)
        write_curves(obj, "Isolines", [c.points for c in lines], [c.closed for c in lines])
