"""The probe's geodesic path as a curve object, and whether this heatcore computes paths.

Geodesic paths are ``HeatSolver.geodesic_path`` (heatcore's paths); a copy
of heatcore without them makes the probe refuse paths with a message, and
everything else works. :func:`write_path_curve` makes (or updates) one
curve object per probed object, ``"<name> Geodesic Path"``, a poly spline
through the path's points in world coordinates.

Examples
--------
>>> path_available(solver)                              # doctest: +SKIP
True
>>> write_path_curve(obj, path_points).name             # doctest: +SKIP
'Suzanne Geodesic Path'
"""

import bpy
import numpy as np
from mathutils import Matrix

#: Custom property marking the curve objects made here (value: the probed object's name).
PATH_MARKER = "heat_geodesic_path_of"


def path_available(solver):
    """Whether ``solver`` computes geodesic paths (``HeatSolver.geodesic_path``).

    Examples
    --------
    >>> path_available(object())
    False
    """
    return callable(getattr(solver, "geodesic_path", None))


def write_path_curve(obj, points):
    """The curve object of ``obj``'s path, made or updated to a poly spline through ``points`` (world).

    Placed in ``obj``'s collections, at the identity matrix; marked with
    :data:`PATH_MARKER` so that the next confirm updates it.

    Examples
    --------
    >>> write_path_curve(obj, [[0, 0, 0], [1, 0, 0]]).data.splines[0].type   # doctest: +SKIP
    'POLY'
    """
    points = np.asarray(points, dtype=np.float32).reshape(-1, 3)
    curve = next((o for o in bpy.data.objects if o.get(PATH_MARKER) == obj.name and o.type == "CURVE"), None)
    if curve is None:
        data = bpy.data.curves.new(f"{obj.name} Geodesic Path", "CURVE")
        data.dimensions = "3D"
        curve = bpy.data.objects.new(data.name, data)
        curve[PATH_MARKER] = obj.name
        for collection in obj.users_collection or (bpy.context.scene.collection,):
            collection.objects.link(curve)
    data = curve.data
    data.splines.clear()
    spline = data.splines.new("POLY")
    spline.points.add(len(points) - 1)
    co = np.ones((len(points), 4), dtype=np.float32)
    co[:, :3] = points
    spline.points.foreach_set("co", co.ravel())
    curve.matrix_world = Matrix.Identity(4)
    return curve
