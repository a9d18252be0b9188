"""The tufted cover of a triangle set (Sharp and Crane, "A Laplacian for Nonmanifold Triangle Meshes", SGP 2020).

Each triangle becomes two oppositely oriented sheets, glued around every edge
in angular order, so that non-manifold and inconsistently oriented triangles
form one manifold (with the same metric) on which intrinsic Delaunay flips
and the cotan Laplacian are well defined.

Examples
--------
>>> import numpy as np
>>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [0, -1, 0]], float)
>>> F = np.array([[0, 1, 2], [0, 1, 3], [0, 1, 4]])  # three triangles on the edge 0-1
>>> faces, twin = tufted_cover(V, F)
>>> faces.shape, bool((twin[twin] == np.arange(18)).all())
((6, 3), True)
"""

import numpy as np

from ..intrinsic import NEXT, PREV


def tufted_cover(V, F):
    """Faces and half-edge twins of the tufted cover of a triangle set.

    Each triangle becomes two sheets with opposite orientations; around each
    edge the triangles are ordered by angle and each sheet is glued to the
    facing sheet of the next triangle, so that every interior edge joins two
    consistently oriented sheets whatever the input's orientation or
    manifoldness. An edge of a single triangle joins that triangle's two
    sheets (a fold).

    Parameters
    ----------
    V : (n, 3) float array
    F : (m, 3) int array (no duplicates)

    Returns
    -------
    faces : (2 m, 3) int array
        ``F`` and then ``F`` reversed (corners 0, 2, 1).
    twin : (6 m,) int array, half-edge ``3 f + c`` runs from corner ``c+1`` to ``c+2``.

    Examples
    --------
    >>> import numpy as np
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    >>> faces, twin = tufted_cover(V, np.array([[0, 1, 2]]))
    >>> faces.tolist(), twin.tolist()  # one triangle: each side folds onto the other sheet
    ([[0, 1, 2], [0, 2, 1]], [3, 5, 4, 0, 2, 1])
    """
    m = F.shape[0]
    faces = np.concatenate([F, F[:, [0, 2, 1]]])
    tail = faces[:, NEXT].ravel()
    head = faces[:, PREV].ravel()
    apex = faces.ravel()
    lo, hi = np.minimum(tail, head), np.maximum(tail, head)
    forward = tail < hi  # runs lo -> hi
    n = V.shape[0]
    key = lo * n + hi
    axis = V[hi] - V[lo]
    axis /= np.linalg.norm(axis, axis=1, keepdims=True)
    ref = np.where(np.abs(axis[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    u = np.cross(axis, ref)
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    w = np.cross(axis, u)
    r = V[apex] - V[lo]
    theta = np.arctan2(np.einsum("ij,ij->i", r, w), np.einsum("ij,ij->i", r, u))
    h = np.arange(3 * 2 * m)
    fw = h[forward]
    bw = h[~forward]
    # the same triangle's two sheets share (key, theta); order both lists alike
    fw = fw[np.lexsort((fw // 3 % m, theta[fw], key[fw]))]
    bw = bw[np.lexsort((bw // 3 % m, theta[bw], key[bw]))]
    kf = key[fw]
    start = np.r_[True, kf[1:] != kf[:-1]]
    group = np.cumsum(start) - 1
    first = np.flatnonzero(start)
    size = np.diff(np.r_[first, kf.size])
    pos = np.arange(kf.size) - first[group]
    nxt = first[group] + (pos + 1) % size[group]
    twin = np.full(6 * m, -1, dtype=np.int64)
    # forward sheet of the triangle at theta_i faces the backward sheet of the
    # next one (of its own other sheet on an edge of one triangle: a fold)
    twin[fw] = bw[nxt]
    twin[bw[nxt]] = fw
    return faces, twin
