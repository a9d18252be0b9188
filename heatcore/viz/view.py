"""The default camera of a picture: facing a source, so that its marker is in view.

:func:`view_facing` turns the camera of :func:`heatcore.viz.render.render_distance`
(azimuth about the up axis, elevation above the horizon) towards the outside of
the surface at a vertex: along its area-weighted normal, taken on the side away
from the mesh's centroid (whatever the faces' winding), turned by
``THREE_QUARTER`` (a three-quarter view keeps the shape's depth; the source stays
in view) and with the elevation kept within ``MAX_ELEVATION``, so that the up
axis stays up in the picture.

Examples
--------
>>> import numpy as np
>>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
>>> F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
>>> view_facing(V, F, 3)   # the corner on +z: seen from the front (+z), three-quarter
{'azimuth': 25.0, 'elevation': 15.0}
>>> view_facing(V, F, 1)   # the corner on +x: from the side
{'azimuth': 115.0, 'elevation': 15.0}
"""

import numpy as np

from .render import UP_AXES

#: Largest elevation of a default view, in degrees (a camera straight along the up axis has no up direction).
MAX_ELEVATION = 75.0
#: (azimuth, elevation) added to the normal's direction, in degrees: a three-quarter view of the source.
THREE_QUARTER = (25.0, 15.0)


def view_facing(V, F, vertex, up="y"):
    """``{"azimuth", "elevation"}`` in degrees: the camera looking at ``vertex`` from outside the surface.

    Parameters
    ----------
    V : (n, 3) float array
    F : (m, 3) int array
    vertex : int
    up : {"x", "y", "z"}

    Returns
    -------
    dict
        The keywords of :func:`~heatcore.viz.render.render_distance`'s camera; ``{}`` (its default) where the
        vertex has no face or no normal.

    Examples
    --------
    >>> view_facing(np.eye(3), [[0, 1, 2]], 0, up="z")   # a triangle facing (1, 1, 1), z up
    {'azimuth': 70.0, 'elevation': 50.26438968275466}
    """
    V, F = np.asarray(V, dtype=float), np.asarray(F, dtype=np.int64).reshape(-1, 3)
    around = F[(F == vertex).any(axis=1)]
    if around.size == 0:
        return {}
    normal = np.cross(V[around[:, 1]] - V[around[:, 0]], V[around[:, 2]] - V[around[:, 0]]).sum(axis=0)
    size = np.linalg.norm(normal)
    if not size > 0:
        return {}
    normal /= size
    if normal @ (V[vertex] - V.mean(axis=0)) < 0:
        normal = -normal
    k = UP_AXES[up]
    u, f0 = np.eye(3)[k], np.eye(3)[(k + 1) % 3]
    r0 = np.cross(u, f0)
    elevation = np.degrees(np.arcsin(np.clip(normal @ u, -1.0, 1.0))) + THREE_QUARTER[1]
    azimuth = np.degrees(np.arctan2(normal @ r0, normal @ f0)) + THREE_QUARTER[0]
    return {"azimuth": float(azimuth), "elevation": float(np.clip(elevation, -MAX_ELEVATION, MAX_ELEVATION))}
