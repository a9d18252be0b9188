"""Triangles of a mesh file's faces: heatcore's triangulation of its polygons, not the readers' fans.

The libraries split a polygon into the fan of triangles around its first
corner (trimesh for OBJ and OFF, meshio's polygon cells as heatcore used to
read them). On a concave polygon, as Blender's Dissolve Edges, Limited
Dissolve and text leave them, that fan folds outside the polygon: an L of area
3 came back as 4 triangles of total area 4, one of them flipped, a different
surface with exit status 0. :func:`triangulate_faces` checks the file's
indices and keeps a polygon's fan only where it covers the polygon exactly
(:func:`~heatcore.domains.polygon_triangulate.covering_triangles`: the other
polygons are triangulated in their plane). The test is a few products per
triangle (1M convex quads: a binary PLY reads in 0.8 s instead of 0.45 s,
before the test went column by column); the ear clipping costs about 0.6 ms a
polygon (a Python loop), paid only by polygons whose fan is wrong (250k folded
L-octagons: 140 s).

Examples
--------
>>> V = np.array([[0, 0, 0], [2, 0, 0], [2, 1, 0], [1, 1, 0], [1, 2, 0], [0, 2, 0]], float)
>>> F = triangulate_faces(V, np.array([0, 6]), np.array([2, 3, 4, 5, 0, 1]))
>>> (np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])[:, 2] / 2).tolist()   # the L, area 3
[0.5, 0.5, 1.0, 1.0]
"""

import numpy as np

from ..domains.polygon_triangulate import covering_triangles
from ..domains.validate import one_based_hint
from ..errors import InvalidMeshError


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
    return covering_triangles(np.asarray(V, dtype=float), offsets, corners)
