"""Triangles of a mesh file's faces: heatcore's triangulation of its polygons, not the readers' fans.

The libraries split a polygon into the fan of triangles around its first
corner (trimesh for OBJ and OFF, meshio's polygon cells as heatcore used to
read them). On a concave polygon, as Blender's Dissolve Edges, Limited
Dissolve and text leave them, that fan folds outside the polygon: an L of area
3 came back as 4 triangles of total area 4, one of them flipped, a different
surface with exit status 0. :func:`triangulate_faces` keeps a polygon's fan
where it covers the polygon exactly: where every fan triangle faces the way
the polygon does (along its vector area), by more than ``FLAT`` of the
polygon's area. The other polygons (a concave one whose first corner does not
see all of it, a fan triangle of zero area at a straight corner, a fold out of
a non-planar polygon) are triangulated by
:func:`~heatcore.domains.polygon.triangulate_polygons` (ear clipping and
Delaunay flips in the polygon's plane). The test is a few vectorized cross
products (1M convex quads: a binary PLY reads in 0.8 s instead of 0.45 s); the
ear clipping costs about 0.6 ms a polygon (a Python loop), paid only by
polygons whose fan is wrong (250k folded L-octagons: 140 s).

Examples
--------
>>> V = np.array([[0, 0, 0], [2, 0, 0], [2, 1, 0], [1, 1, 0], [1, 2, 0], [0, 2, 0]], float)
>>> F = triangulate_faces(V, np.array([0, 6]), np.array([2, 3, 4, 5, 0, 1]))
>>> (np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])[:, 2] / 2).tolist()   # the L, area 3
[0.5, 0.5, 1.0, 1.0]
"""

import numpy as np

from ..domains.polygon_shape import fan_triangulate
from ..domains.polygon_triangulate import triangulate_polygons
from ..domains.validate import one_based_hint
from ..errors import InvalidMeshError

#: A fan triangle whose area along its polygon's normal is at most this fraction of the polygon's area
#: (zero at a straight corner, negative where the fan folds) sends the polygon to the triangulation.
FLAT = 1e-9


def triangulate_faces(V, offsets, corners, where="cannot read mesh file"):
    """Triangles of the faces ``corners[offsets[p]:offsets[p + 1]]``, in face order (see the module docstring).

    Parameters
    ----------
    V : (n, 3) float array
        The file's vertices.
    offsets : (m + 1,) int array
    corners : (offsets[-1],) int array
        Vertex indices (0-based) of each face's corners, faces of 3 or more.
    where : str
        The start of an error message ("cannot read mesh file m.obj").

    Returns
    -------
    (sum(k - 2), 3) int64 array
        Face ``p``'s ``k - 2`` triangles follow face ``p - 1``'s, each
        oriented as its face; triangles are kept as they are.

    Raises
    ------
    InvalidMeshError
        A polygon's corner that is not a vertex of the file.

    Examples
    --------
    A dart (reflex at corner 3), whose fan from corner 0 folds out of it, after a triangle:

    >>> V = np.array([[0, 0, 0], [2, 1, 0], [0, 2, 0], [0.5, 1, 0], [3, 3, 0]], float)
    >>> triangulate_faces(V, np.array([0, 3, 7]), np.array([1, 4, 2, 0, 1, 2, 3])).tolist()
    [[1, 4, 2], [0, 1, 3], [1, 2, 3]]
    """
    offsets = np.asarray(offsets, dtype=np.int64)
    corners = np.asarray(corners, dtype=np.int64)
    sizes = np.diff(offsets)
    if sizes.size == 0 or (sizes == 3).all():
        return corners.reshape(-1, 3)
    bad = (corners < 0) | (corners >= len(V))
    if bad.any():
        k = int(np.flatnonzero(bad)[0])
        face = int(np.searchsorted(offsets, k, side="right") - 1)
        raise InvalidMeshError(f"{where}: face {face} references vertex {corners[k]} but the file has "
                               f"{len(V)} vertices{one_based_hint(corners, len(V))}")
    V = np.asarray(V, dtype=float)
    triangles, polygon = fan_triangulate(offsets, corners)
    chosen = np.flatnonzero(folded_fans(V, triangles, polygon))
    if chosen.size:
        pos = np.repeat(offsets[chosen], sizes[chosen]) + _ramps(sizes[chosen])
        own, _ = triangulate_polygons(V, np.r_[0, np.cumsum(sizes[chosen])], corners[pos])
        first = np.r_[0, np.cumsum(sizes - 2)[:-1]]  # each face's first triangle
        triangles[np.repeat(first[chosen], sizes[chosen] - 2) + _ramps(sizes[chosen] - 2)] = own
    return triangles


def folded_fans(V, triangles, polygon):
    """Which polygons' fans do not cover them exactly: a fan triangle against the polygon's vector area, or flat.

    Parameters
    ----------
    V : (n, 3) float array
    triangles : (t, 3) int array
        The fans (:func:`~heatcore.domains.polygon.fan_triangulate`).
    polygon : (t,) int array
        The polygon of each triangle: ``0, 1, ...`` in order, each at least once.

    Returns
    -------
    (polygon[-1] + 1,) bool array

    Examples
    --------
    >>> from heatcore.domains.polygon import fan_triangulate
    >>> V = np.array([[0, 0, 0], [2, 1, 0], [0, 2, 0], [0.5, 1, 0]], float)   # a dart, reflex at 3
    >>> offsets = np.array([0, 4, 8])
    >>> folded_fans(V, *fan_triangulate(offsets, np.array([0, 1, 2, 3, 3, 0, 1, 2]))).tolist()
    [True, False]
    """
    P = V[triangles]
    cross = np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0])
    normal = np.add.reduceat(cross, np.flatnonzero(np.r_[True, polygon[1:] != polygon[:-1]]))  # twice the vector area
    along = np.einsum("td,td->t", cross, normal[polygon])
    bad = along <= FLAT * np.einsum("pd,pd->p", normal, normal)[polygon]
    folded = np.zeros(len(normal), dtype=bool)
    folded[polygon[bad]] = True
    return folded


def _ramps(counts):
    """Concatenated ``arange(c)`` for each ``c`` in ``counts``."""
    return np.arange(int(counts.sum())) - np.repeat(np.cumsum(counts) - counts, counts)
