"""Parts with no area: every face's corners collinear or coincident.

A connected part whose faces all have zero area is not a surface: heat has
nowhere to spread, the cotangent weights are undefined, and mollification
(which mends a few slivers in a real surface) only invents a surface of its
own. On a million zero-area faces over 3,000 collinear vertices the heat
method gave 31.9 where the answer is 1. Such a part is left out of the
domain: its vertices are unreachable (``inf``) from sources elsewhere, and a
source on it is refused with a typed error that says why.

Flatness is decided per face, in the face's own scale (its edge vectors
divided by their largest coordinate), so a part of ordinary triangles at
1e-200 or 1e200 is never mistaken for a flat one by underflow or overflow.

Examples
--------
>>> import numpy as np
>>> V = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [5, 0, 0], [6, 0, 0], [5, 1, 0]], float)
>>> F = np.array([[0, 1, 2], [3, 4, 5]])
>>> flat_faces(V, F).tolist()
[True, False]
>>> flat_parts(V, F, np.array([0, 1]), 2).tolist()
[True, False]
"""

import numpy as np


#: A face is flat when twice its area is at most this fraction of its longest
#: edge squared (a triangle 1e12 times longer than high). Collinear corners
#: in floating point give about 1e-16.
FLAT_FACE_RATIO = 1e-12


def flat_faces(V, F, ratio=FLAT_FACE_RATIO):
    """Which faces have (numerically) zero area: collinear or coincident corners.

    Parameters
    ----------
    V : (n, 3) float array
    F : (m, 3) int array
    ratio : float
        Largest ``2 * area / longest_edge**2`` of a flat face.

    Returns
    -------
    (m,) bool array

    Examples
    --------
    >>> V = np.array([[0, 0, 0], [1e-200, 0, 0], [0, 1e-200, 0], [3, 0, 0]], float)
    >>> flat_faces(V, np.array([[0, 1, 2], [0, 1, 3]])).tolist()
    [False, True]
    """
    flat = ~_has_area(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]], ratio)
    if flat.any():  # again in each face's own scale: raw squares may have underflowed or overflowed
        e1, e2 = (V[F[flat, k]] - V[F[flat, 0]] for k in (1, 2))
        scale = np.maximum(np.abs(e1).max(axis=1), np.abs(e2).max(axis=1))
        scale[scale == 0] = 1.0  # every corner at one point: flat
        flat[flat] = ~_has_area(e1 / scale[:, None], e2 / scale[:, None], ratio)
    return flat


def _has_area(e1, e2, ratio):
    """``2 * area > ratio * longest_edge**2`` for the triangles spanned by edge vectors ``e1``, ``e2``.

    Squares that overflow (inf) or underflow (0) give False: "not certainly
    with area", for :func:`flat_faces` to check again in the face's scale.
    Computed column by column (twice as fast as over rows of three).
    """
    (ux, uy, uz), (wx, wy, wz) = np.asarray(e1).T, np.asarray(e2).T
    with np.errstate(over="ignore", under="ignore", invalid="ignore"):
        cx, cy, cz = uy * wz - uz * wy, uz * wx - ux * wz, ux * wy - uy * wx
        dx, dy, dz = wx - ux, wy - uy, wz - uz
        longest = np.maximum(np.maximum(ux * ux + uy * uy + uz * uz, wx * wx + wy * wy + wz * wz),
                             dx * dx + dy * dy + dz * dz)
        return cx * cx + cy * cy + cz * cz > ratio * ratio * longest * longest


def flat_parts(V, F, face_part, n_parts):
    """Which connected parts have only flat faces (:func:`flat_faces`): parts with no area.

    Each part's first face is tested first; only the faces of parts whose
    first face is flat are tested all (a clean mesh costs one test per part).

    Parameters
    ----------
    V : (n, 3) float array
    F : (m, 3) int array
        Faces without repeated vertices.
    face_part : (m,) int array
        The connected part of each face.
    n_parts : int

    Returns
    -------
    (n_parts,) bool array

    Examples
    --------
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [1, 1, 0], [5, 0, 0], [6, 0, 0], [7, 0, 0]], float)
    >>> F = np.array([[0, 1, 2], [0, 1, 3], [4, 5, 6]])   # a sliver in a part with area; a flat part
    >>> flat_parts(V, F, np.array([0, 0, 1]), 2).tolist()
    [False, True]
    """
    first = np.full(n_parts, -1, dtype=np.int64)
    first[face_part[::-1]] = np.arange(len(F))[::-1]  # the last write wins: each part's first face
    doubtful = np.zeros(n_parts, dtype=bool)
    doubtful[first >= 0] = flat_faces(V, F[first[first >= 0]])
    if not doubtful.any():
        return doubtful
    look = np.flatnonzero(doubtful[face_part])
    with_area = np.bincount(face_part[look[~flat_faces(V, F[look])]], minlength=n_parts) > 0
    return doubtful & ~with_area
