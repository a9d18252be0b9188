"""Triangulating polygons that virtual refinement spans badly: concave, straight-cornered, thin, non-planar n-gons.

Virtual refinement (:mod:`heatcore.domains.polygon`) spans a polygon by the
fan of triangles around one virtual vertex. On a concave polygon (an L, a U, a
letter of text, what Blender's Dissolve Edges and Limited Dissolve leave) no
point sees every side: the fan folds over itself, and its split into quads
(:func:`~heatcore.domains.polygon_refine.split_polygons`) folds again at every
level (a dissolved 24 x 24 grid: 9-13% mean error, against 1.2% for the same
polygons triangulated). A convex polygon with a (nearly) straight corner, a
side cut in two by a vertex as dissolving leaves them, is spanned without
folding, but each split turns that corner into a quad with a 180-degree angle,
and the error grows with every level (the same grid: 0.64, 0.75, 1.20, 2.00%
at 1-4 levels, against 0.59, 0.52, 0.50, 0.49% with those polygons
triangulated). A thin polygon's fan has obtuse triangles that refinement
multiplies (a UV sphere's rows next to a pole: 3-5.7 times the triangles'
error from the pole, :data:`THIN_SIDE_RATIO`). An n-gon far from a plane spans
no definite surface (:data:`NONPLANAR_NGON`). These kinds are triangulated
here, and so are whole the parts left mostly triangles (:data:`MOSTLY_TRIANGLES`),
and every polygon where the caller asks (``PolygonMesh`` by default, without
``virtual=True``); the other polygons keep virtual refinement,
which is the more accurate operator on them (docs/polygon.md: hexagons 0.60%
against 1.35% for their triangles).

The triangulation is heatcore's own for any polygon: ear clipping in the
polygon's plane (along its vector area), then Lawson flips of the diagonals
to the polygon's constrained Delaunay triangulation, so that no sliver ear and
no zero-area triangle at a 180-degree corner is left where a better diagonal
exists.

Examples
--------
>>> import numpy as np
>>> L = np.array([[0, 0, 0], [2, 0, 0], [2, 1, 0], [1, 1, 0], [1, 2, 0], [0, 2, 0]], float)
>>> concave_polygons(L, np.array([0, 6]), np.arange(6)).tolist()
[True]
>>> triangles, polygon = triangulate_polygons(L, np.array([0, 6]), np.arange(6))
>>> len(triangles), polygon.tolist()
(4, [0, 0, 0, 0])
"""

import numpy as np

from .ear_clipping import delaunay_triangles
from .parts import vertex_components
from .polygon_shape import (
    area_vectors,
    fan_triangulate,
    plane_coordinates,
    vector_area_sum,
)

#: Relative size (of a polygon's squared extent) below which a corner's turn counts as none (rounding).
STRAIGHT_TOLERANCE = 1e-9

#: A quad whose opposite angles sum to pi within this (radians) has its corners on a circle: both
#: diagonals are Delaunay, and :func:`_either_diagonal` picks one.
COCIRCULAR_RADIANS = 1e-6
#: A fan triangle whose area along its polygon's normal is at most this fraction of the polygon's area
#: (zero at a straight corner, negative where the fan folds) sends the polygon to the triangulation
#: (:func:`covering_triangles`).
FLAT = 1e-9

#: A corner turning less than this (degrees) is nearly straight: its polygon is triangulated. A
#: regular 36-gon turns 10 degrees at each corner; hexagons (60) and octagons (45) keep their
#: virtual vertex. Triangulating is the safe side (measured: never worse than the triangles).
STRAIGHT_TURN_DEGREES = 10.0

#: A polygon whose shortest side is below this share of its longest is thin: its virtual fan has
#: obtuse triangles, refined into more of the same, and it is triangulated (and flipped to
#: Delaunay). Measured: a 32 x 16 UV sphere's rows next to the poles (sides 0.19 of each other) gave
#: 3-5.7 times the triangles' error from the pole once refined; triangulated, 0.96-1.00 times and half
#: the mean error (0.42% -> 0.22% by default); jittered quad and hex grids within 0.03 either way.
THIN_SIDE_RATIO = 0.5

#: A polygon of five or more corners further from a plane than this (smallest over largest singular
#: value of its centred corners) spans no definite surface: its virtual fan tents over it, and it is
#: triangulated (the surface Blender and a triangle file show). Measured on a UV sphere after Limited
#: Dissolve (10 degrees; its n-gons 0.03-0.05): 1.07 -> 1.00 times the triangles' error at refine=0,
#: 0.78 -> 0.74 at 1 and 0.67 -> 0.63 by default. Quads are left as they are: a Catmull-Clark
#: sphere's reach 0.01 and their virtual vertex serves them (0.58 times the triangles' error).
NONPLANAR_NGON = 0.02

#: A connected part at least this share triangles by area (given, or polygons triangulated for the
#: reasons above) is triangulated whole: its few polygons left gain little from their virtual
#: vertex and are where it lost to the triangles. Measured: a cube with extruded bumps after
#: Limited Dissolve (0.86 triangles; its 38 quads squares) 1.05-1.19 times the triangles' error at
#: refine 0-2 and 1.07 by default, now equal; a UV sphere after Limited Dissolve 20 degrees (0.93)
#: 1.02 -> 1.00 at refine=0. The parts of the dissolved grids (0.41-0.55) and of a plate with
#: holes (0.31) keep their quads.
MOSTLY_TRIANGLES = 0.85


def concave_polygons(X, offsets, corners):
    """Which polygons have a reflex corner (turning clockwise) in their own plane.

    Straight (180-degree) corners are not reflex. Triangles never are.

    Parameters
    ----------
    X : (n, 3) float array
    offsets, corners : int arrays
        Polygon ``p`` is ``corners[offsets[p]:offsets[p + 1]]``.

    Returns
    -------
    (m,) bool array

    Examples
    --------
    >>> X = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [2, 1, 0], [0, 1, 0]], float)
    >>> concave_polygons(X, np.array([0, 5]), np.arange(5)).tolist()   # a straight corner: convex
    [False]
    >>> X[1, 1] = 0.5
    >>> concave_polygons(X, np.array([0, 5]), np.arange(5)).tolist()   # pushed in: reflex
    [True]
    """
    sizes = np.diff(offsets)
    concave = np.zeros(sizes.size, dtype=bool)
    for k in np.unique(sizes[sizes > 3]):
        polygons = np.flatnonzero(sizes == k)
        Q = _counterclockwise(plane_coordinates(X, corners[offsets[polygons][:, None] + np.arange(k)]))
        turn = _cross(np.roll(Q, 1, axis=1), Q, np.roll(Q, -1, axis=1))
        extent = np.ptp(Q, axis=1).max(axis=1) ** 2
        concave[polygons] = (turn < -STRAIGHT_TOLERANCE * extent[:, None]).any(axis=1)
    return concave


def polygons_to_triangulate(X, offsets, corners):
    """Polygons virtual refinement spans badly: concave, with a nearly straight corner, thin, or non-planar n-gons.

    Concave in their plane (:func:`concave_polygons`), with a corner turning
    less than ``STRAIGHT_TURN_DEGREES``, with a side shorter than
    ``THIN_SIDE_RATIO`` of their longest, or of five corners or more and
    further from a plane than ``NONPLANAR_NGON``.

    Returns
    -------
    (m,) bool array

    Examples
    --------
    >>> X = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [2, 1, 0], [0, 1, 0], [3, 0, 0], [3, 1, 0], [9, 0, 0]], float)
    >>> o, c = np.array([0, 5, 9, 13]), np.array([0, 1, 2, 3, 4, 2, 5, 6, 3, 2, 7, 6, 3])
    >>> polygons_to_triangulate(X, o, c).tolist()   # a straight corner; a unit square; a thin quad
    [True, False, True]
    """
    sizes = np.diff(offsets)
    chosen = concave_polygons(X, offsets, corners)
    limit = np.sin(np.radians(STRAIGHT_TURN_DEGREES))
    for k in np.unique(sizes[sizes > 3]):
        polygons = np.flatnonzero(sizes == k)
        Q = plane_coordinates(X, corners[offsets[polygons][:, None] + np.arange(k)])
        before, after = Q - np.roll(Q, 1, axis=1), np.roll(Q, -1, axis=1) - Q
        lengths = np.linalg.norm(before, axis=2) * np.linalg.norm(after, axis=2)
        turn_sin = np.abs(_cross(np.zeros(2), before, after)) / np.maximum(lengths, np.finfo(float).tiny)
        turning_back = np.einsum("pkd,pkd->pk", before, after) < 0  # a spike: turns by nearly 180 degrees
        sides = np.linalg.norm(after, axis=2)
        thin = sides.min(axis=1) < THIN_SIDE_RATIO * sides.max(axis=1)
        chosen[polygons] |= ((turn_sin < limit) & ~turning_back).any(axis=1) | thin
        if k > 4:
            P = X[corners[offsets[polygons][:, None] + np.arange(k)]]
            spread = np.linalg.svd(P - P.mean(axis=1, keepdims=True), compute_uv=False)
            chosen[polygons] |= spread[:, 2] > NONPLANAR_NGON * spread[:, 0]
    return chosen


def triangulate_polygons(X, offsets, corners, planes=None):
    """Triangles covering each polygon: its constrained Delaunay triangulation in its plane.

    Triangles are kept; quads get the diagonal of the Delaunay split (the
    concave corner's diagonal on a dart); larger polygons are ear-clipped and
    flipped one by one. Triangles are oriented as their polygon.

    Parameters
    ----------
    X : (n, 3) float array
    offsets, corners : int arrays
        Polygon ``p`` is ``corners[offsets[p]:offsets[p + 1]]``; simple
        (non-self-crossing) polygons, as :class:`~heatcore.PolygonMesh` keeps.
    planes : dict, optional
        ``planes[k]``: the :func:`~heatcore.domains.polygon_shape.plane_coordinates`
        of these polygons of ``k`` corners, in order, where computed already
        (:func:`~heatcore.domains.polygon_shape.crossing_polygons` fills it).

    Returns
    -------
    triangles : (sum(k - 2), 3) int array, vertex indices
    polygon : (sum(k - 2),) int array, the polygon each triangle comes from

    Examples
    --------
    A rectangle with a straight corner on each long side gets no zero-area triangle:

    >>> X = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [2, 1, 0], [1, 1, 0], [0, 1, 0]], float)
    >>> t, _ = triangulate_polygons(X, np.array([0, 6]), np.arange(6))
    >>> a = np.cross(X[t[:, 1]] - X[t[:, 0]], X[t[:, 2]] - X[t[:, 0]])[:, 2] / 2
    >>> a.round(3).tolist()
    [0.5, 0.5, 0.5, 0.5]
    """
    sizes = np.diff(offsets)
    parts, owners = [], []
    for k in np.unique(sizes):
        polygons = np.flatnonzero(sizes == k)
        idx = corners[offsets[polygons][:, None] + np.arange(k)]
        if k == 3:
            local = np.zeros((polygons.size, 1, 3), dtype=np.int64) + np.arange(3)
        else:
            Q = planes[k] if planes and k in planes else plane_coordinates(X, idx)
            local = _quad_splits(Q, idx) if k == 4 else delaunay_triangles(_counterclockwise(Q), STRAIGHT_TOLERANCE)
        parts.append(np.take_along_axis(idx[:, None, :], local.reshape(polygons.size, -1)[:, None, :], 2)
                     .reshape(-1, 3))
        owners.append(np.repeat(polygons, k - 2))
    order = np.argsort(np.concatenate(owners), kind="stable")
    return np.concatenate(parts)[order], np.concatenate(owners)[order]


def covering_triangles(X, offsets, corners):
    """Triangles covering each polygon exactly: its fan where that covers it, else :func:`triangulate_polygons`.

    A fan (the triangles around the first corner, :func:`~heatcore.domains.polygon_shape.fan_triangulate`)
    covers its polygon where every fan triangle faces the way the polygon does
    (along its vector area) by more than ``FLAT`` of its area
    (:func:`folded_fans`). The others (a concave polygon whose first corner
    does not see all of it, a fan triangle of zero area at a straight corner,
    a fold out of a non-planar polygon) are triangulated in their plane. The
    test is a few products per triangle; the triangulation costs about 0.6 ms
    a polygon (a Python loop), paid only where the fan is wrong.

    Parameters
    ----------
    X : (n, 3) float array
    offsets, corners : int arrays
        Polygon ``p`` is ``corners[offsets[p]:offsets[p + 1]]`` (one of fewer than 3 corners gets no triangle).

    Returns
    -------
    (sum(k - 2), 3) int64 array
        Polygon ``p``'s ``k - 2`` triangles follow polygon ``p - 1``'s, each oriented as its polygon.

    Examples
    --------
    An L from its corner 2, whose fan would cover the notch at corner 3 (triangle 2, 4, 5):

    >>> L = np.array([[0, 0, 0], [2, 0, 0], [2, 1, 0], [1, 1, 0], [1, 2, 0], [0, 2, 0]], float)
    >>> F = covering_triangles(L, np.array([0, 6]), np.array([2, 3, 4, 5, 0, 1]))
    >>> (np.cross(L[F[:, 1]] - L[F[:, 0]], L[F[:, 2]] - L[F[:, 0]])[:, 2] / 2).tolist()   # the L, area 3
    [0.5, 0.5, 1.0, 1.0]
    """
    sizes = np.diff(offsets)
    triangles, polygon = fan_triangulate(offsets, corners)
    chosen = np.flatnonzero(folded_fans(X, triangles, polygon, sizes.size))
    if chosen.size:
        pos = np.repeat(offsets[chosen], sizes[chosen]) + _ramps(sizes[chosen])
        own, _ = triangulate_polygons(X, np.r_[0, np.cumsum(sizes[chosen])], corners[pos])
        first = np.r_[0, np.cumsum(np.maximum(sizes - 2, 0))[:-1]]  # each polygon's first triangle
        triangles[np.repeat(first[chosen], sizes[chosen] - 2) + _ramps(sizes[chosen] - 2)] = own
    return triangles


def folded_fans(X, triangles, polygon, n_polygons=None):
    """Which polygons' fans do not cover them exactly: a fan triangle against the polygon's vector area, or flat.

    Coordinate by coordinate (:func:`~heatcore.domains.polygon_shape.area_vectors`).

    Parameters
    ----------
    X : (n, 3) float array
    triangles : (t, 3) int array
        The fans (:func:`~heatcore.domains.polygon_shape.fan_triangulate`).
    polygon : (t,) int array
        The polygon of each triangle.
    n_polygons : int, optional
        How many polygons (default ``polygon.max() + 1``); one without a triangle is not folded.

    Returns
    -------
    (n_polygons,) bool array

    Examples
    --------
    >>> V = np.array([[0, 0, 0], [2, 1, 0], [0, 2, 0], [0.5, 1, 0]], float)   # a dart, reflex at 3
    >>> offsets = np.array([0, 4, 8])
    >>> folded_fans(V, *fan_triangulate(offsets, np.array([0, 1, 2, 3, 3, 0, 1, 2]))).tolist()
    [True, False]
    """
    cross = area_vectors(X, triangles)
    m = int(polygon.max()) + 1 if n_polygons is None else n_polygons
    normal = [np.bincount(polygon, weights=component, minlength=m) for component in cross]  # twice the vector area
    along = cross[0] * normal[0][polygon] + cross[1] * normal[1][polygon] + cross[2] * normal[2][polygon]
    bad = along <= FLAT * (normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2])[polygon]
    folded = np.zeros(m, dtype=bool)
    folded[polygon[bad]] = True
    return folded


def _ramps(counts):
    """Concatenated ``arange(c)`` for each ``c`` in ``counts``."""
    return np.arange(int(counts.sum())) - np.repeat(np.cumsum(counts) - counts, counts)


def _cross(a, b, c):
    """Twice the signed area of triangles ``(a, b, c)`` of 2D points (any leading shape)."""
    return (b[..., 0] - a[..., 0]) * (c[..., 1] - a[..., 1]) - (b[..., 1] - a[..., 1]) * (c[..., 0] - a[..., 0])


def _counterclockwise(Q):
    """Polygons ``(p, k, 2)`` mirrored where their signed area is negative (the corner order kept): a new array."""
    x, y = Q[..., 0], Q[..., 1]  # _cross(0, Q, next)'s numbers (x - 0 is x), one coordinate at a time
    area = (x * np.roll(y, -1, axis=1) - y * np.roll(x, -1, axis=1)).sum(axis=1)
    Q = Q.copy()
    Q[area < 0, :, 1] *= -1.0
    return Q


def _quad_splits(Q, idx):
    """Local triangles ``(p, 2, 3)`` of quads: the diagonal whose opposite angles sum to at most pi.

    Where both diagonals are Delaunay (the corners on a circle: rectangles,
    a regular grid), :func:`_either_diagonal` chooses: the same diagonal in
    every square of a grid biases the distance along it (a corner source on a
    31 x 31 grid: -1.5% to -2% far from it at any refinement, mean error 1.62%
    to 1.94%, rising with refinement; chosen apart, 1.91% falling to 1.29%).
    """
    x, y = (np.array(Q[..., axis].T, order="C") for axis in (0, 1))  # corner rows (4, p), copies: contiguous passes
    y[:, (x * np.roll(y, -1, axis=0) - y * np.roll(x, -1, axis=0)).sum(axis=0) < 0] *= -1.0  # counterclockwise
    excess = _row_angle(x, y, 1, 0, 2) + _row_angle(x, y, 3, 2, 0) - np.pi  # angles at corners 1 and 3
    straight_02 = np.where(np.abs(excess) <= COCIRCULAR_RADIANS, _either_diagonal(idx), excess <= 0)
    # a dart's reflex corner must end the diagonal: 0-2 is outside when corner 1 or 3 is reflex
    px, py = np.roll(x, 1, axis=0), np.roll(y, 1, axis=0)  # _cross(previous, Q, next)
    turn = (x - px) * (np.roll(y, -1, axis=0) - py) - (y - py) * (np.roll(x, -1, axis=0) - px)
    span = np.maximum(x.max(axis=0) - x.min(axis=0), y.max(axis=0) - y.min(axis=0))
    reflex = turn < -STRAIGHT_TOLERANCE * span**2
    use_02 = np.where(reflex[[1, 3]].any(axis=0), False, np.where(reflex[[0, 2]].any(axis=0), True, straight_02))
    a = np.array([[0, 1, 2], [0, 2, 3]])
    b = np.array([[0, 1, 3], [1, 2, 3]])
    return np.where(use_02[:, None, None], a, b)


def _row_angle(x, y, at, i, j):
    """Angle at corner ``at`` between the directions to corners ``i`` and ``j``, polygons as corner rows ``(k, p)``."""
    ux, uy, vx, vy = x[i] - x[at], y[i] - y[at], x[j] - x[at], y[j] - y[at]
    return np.arctan2(np.abs(ux * vy - uy * vx), ux * vx + uy * vy + 0.0)  # + 0.0: a zero side's -0.0 is 0.0


def _either_diagonal(idx):
    """A fair coin per quad, from its corners' vertex indices (the same for any order of the quads or corners).

    Examples
    --------
    >>> grid = np.array([[a, a + 1, a + 32, a + 31] for a in range(30 * 31) if a % 31 < 30])
    >>> bool(0.45 < _either_diagonal(grid).mean() < 0.55)
    True
    >>> bool((_either_diagonal(grid) == _either_diagonal(np.roll(grid, 1, axis=1)[::-1])[::-1]).all())
    True
    """
    corners = np.sort(idx, axis=1).astype(np.uint64)
    mixed = (corners * np.array([0x9E3779B97F4A7C15, 0xC2B2AE3D27D4EB4F, 0x165667B19E3779F9, 0xD6E8FEB86659FD93],
                                dtype=np.uint64)).sum(axis=1, dtype=np.uint64)
    return ((mixed >> np.uint64(29)) & np.uint64(1)).astype(bool)


def mostly_triangles(X, offsets, corners, chosen):
    """The polygons of connected parts whose area is mostly triangles (given, or ``chosen`` to be triangulated).

    In a part at least ``MOSTLY_TRIANGLES`` triangles by area, the few
    polygons left are triangulated too, and the part is built as its
    triangulated twin (:class:`~heatcore.TriangleMesh`) is.

    Returns
    -------
    (m,) bool array, over polygons of four corners or more

    Examples
    --------
    >>> X = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0], [2, 1, 0], [8, 0, 0], [8, 1, 0]], float)
    >>> o, c = np.array([0, 4, 7, 10, 14]), np.array([0, 1, 2, 3, 1, 4, 5, 1, 5, 2, 4, 6, 7, 5])
    >>> mostly_triangles(X, o, c, np.zeros(4, bool)).tolist()  # a unit square, two triangles, a 6 x 1 quad
    [False, False, False, False]
    >>> mostly_triangles(X, o, c, np.array([False, False, False, True])).tolist()  # the long quad to be triangulated: 7/8 triangles
    [True, False, False, True]
    """
    sizes = np.diff(offsets)
    owner = np.repeat(np.arange(sizes.size), sizes)
    nxt = np.arange(corners.size) + 1
    nxt[offsets[1:] - 1] = offsets[:-1]
    first = X[corners[offsets[:-1]]][owner]
    area = 0.5 * np.linalg.norm(np.add.reduceat(np.cross(X[corners] - first, X[corners[nxt]] - first), offsets[:-1]),
                                axis=1)
    count, part = vertex_components(np.c_[corners, corners[nxt]], X.shape[0])
    part = part[corners[offsets[:-1]]]
    triangles = np.bincount(part, weights=area * ((sizes == 3) | chosen), minlength=count)
    return (triangles >= MOSTLY_TRIANGLES * np.bincount(part, weights=area, minlength=count))[part] & (sizes > 3)


def triangulate_where_needed(X, offsets, corners, origin, everywhere=False, planes=None):
    """Polygons virtual refinement spans badly (:func:`polygons_to_triangulate`), or all, replaced by their triangles.

    Parameters
    ----------
    X : (n, 3) float array
    offsets, corners : int arrays
    origin : (m,) int array
        What each polygon comes from (carried to its triangles).
    everywhere : bool, default False
        Triangulate every polygon (what ``PolygonMesh`` does by default), whatever its shape.
    planes : dict, optional
        The polygons' plane coordinates by size (:func:`~heatcore.domains.polygon_shape.crossing_polygons`),
        which triangulating ``everywhere`` reuses.

    Returns
    -------
    offsets, corners, origin : the polygons after the change
    n_triangulated : int, the polygons triangulated

    Examples
    --------
    >>> L = np.array([[0, 0, 0], [2, 0, 0], [2, 1, 0], [1, 1, 0], [1, 2, 0], [0, 2, 0], [3, 0, 0]], float)
    >>> o, c, origin, n = triangulate_where_needed(L, np.array([0, 6, 9]), np.r_[np.arange(6), 1, 6, 2], np.array([4, 5]))
    >>> np.diff(o).tolist(), origin.tolist(), n
    ([3, 3, 3, 3, 3], [5, 4, 4, 4, 4], 1)
    """
    if everywhere:
        concave = np.diff(offsets) > 3  # no shape to check
    else:
        concave = polygons_to_triangulate(X, offsets, corners)
        concave |= mostly_triangles(X, offsets, corners, concave)
    if not concave.any():
        return offsets, corners, origin, 0
    sizes = np.diff(offsets)
    chosen = np.flatnonzero(concave)
    pos = np.repeat(offsets[chosen] - np.r_[0, np.cumsum(sizes[chosen])[:-1]], sizes[chosen])
    sub_offsets = np.r_[0, np.cumsum(sizes[chosen])]
    triangles, polygon = triangulate_polygons(X, sub_offsets, corners[pos + np.arange(pos.size)],
                                              planes if everywhere else None)  # everywhere: the same polygons
    keep = ~concave
    new_sizes = np.r_[sizes[keep], np.full(len(triangles), 3)]
    new_corners = np.r_[corners[np.repeat(keep, sizes)], triangles.ravel()]
    new_origin = np.r_[origin[keep], origin[chosen[polygon]]]
    return np.r_[0, np.cumsum(new_sizes)], new_corners, new_origin, int(chosen.size)


def straight_chords(X, offsets, corners):
    """Pairs of corners joined by a straight segment inside their polygon: sides, and every diagonal of a flat polygon.

    The polygons are those virtual refinement spans (convex, or triangles):
    a flat convex polygon holds the segment between any two of its corners; a
    polygon out of its plane (more than ``STRAIGHT_TOLERANCE`` of its extent)
    holds only its sides.

    Returns
    -------
    start, end : int arrays of vertex indices

    Examples
    --------
    >>> X = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0, 1], [2, 1, 0]], float)
    >>> a, b = straight_chords(X, np.array([0, 4, 8]), np.array([0, 1, 2, 3, 1, 4, 5, 2]))
    >>> sorted(zip(a.tolist(), b.tolist()))   # the flat square's two diagonals, the bent quad's sides
    [(0, 1), (0, 2), (0, 3), (1, 2), (1, 2), (1, 3), (1, 4), (2, 3), (4, 5), (5, 2)]
    """
    sizes = np.diff(offsets)
    starts, ends = [np.zeros(0, dtype=np.int64)], [np.zeros(0, dtype=np.int64)]
    for k in np.unique(sizes):
        polygons = np.flatnonzero(sizes == k)
        idx = corners[offsets[polygons][:, None] + np.arange(k)]
        P = X[idx]
        P -= P.mean(axis=1, keepdims=True)
        normal = vector_area_sum(P)
        normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), np.finfo(float).tiny)
        extent = np.abs(P).max(axis=(1, 2))
        flat = np.abs(np.einsum("pkd,pd->pk", P, normal)).max(axis=1) <= STRAIGHT_TOLERANCE * extent
        a, b = np.triu_indices(k, 1)
        side = (b - a == 1) | ((a == 0) & (b == k - 1))
        starts += [idx[flat][:, a].ravel(), idx[~flat][:, a[side]].ravel()]
        ends += [idx[flat][:, b].ravel(), idx[~flat][:, b[side]].ravel()]
    return np.concatenate(starts), np.concatenate(ends)
