"""Self-crossing polygons: a bowtie or a pentagram is no surface patch.

Virtual refinement (:mod:`heatcore.domains.polygon`) spans a polygon by fan
triangles around a virtual vertex. On a polygon whose sides cross each other
(a bowtie quad, a pentagram) the fan folds over itself and the distances come
out shorter than the straight line, so such polygons are refused with an
error that names them. Each polygon is projected along its vector area
(Newell's normal, which sees a twisted quad as the square it spans), or, where
that vanishes as on a bowtie, onto its plane of least variance, and its
non-adjacent sides are tested for a proper crossing there.

Examples
--------
>>> import numpy as np
>>> X = np.array([[0, 0, 0], [1, 1, 0], [1, 0, 0], [0, 1, 0], [2, 0, 0], [3, 0, 0], [3, 1, 0]], float)
>>> offsets, corners = np.array([0, 4, 7]), np.array([0, 1, 2, 3, 4, 5, 6])
>>> [(p, sides) for p, sides in crossing_polygons(X, offsets, corners)]
[(0, (0, 2))]
"""

import warnings

import numpy as np

from ..errors import HeatcoreWarning, InvalidMeshError


def simple_polygons(X, offsets, corners, given, split=False, planes=None):
    """The polygons as virtual refinement may span them: a self-crossing one is an error, or its fan triangles.

    Parameters
    ----------
    X : (n, 3) float array
    offsets, corners : int arrays
        Polygons, as in :func:`crossing_polygons`.
    given : (m,) int array
        The index the user gave each polygon (for messages).
    split : bool, default False
        Replace self-crossing polygons by their fan triangles from the first
        corner (real triangles), with a :class:`~heatcore.HeatcoreWarning`,
        instead of raising.
    planes : dict, optional
        Filled as :func:`crossing_polygons` fills it, and emptied where
        polygons were split (those returned are then not those given).

    Returns
    -------
    offsets, corners : int arrays
    origin : int array
        The index (into the ``offsets`` given) of the polygon each returned
        polygon comes from.

    Raises
    ------
    InvalidMeshError
        A polygon crosses itself (and ``split`` is False); the message names it.

    Examples
    --------
    >>> X = np.array([[0, 0, 0], [1, 1, 0], [1, 0, 0], [0, 1, 0]], float)
    >>> simple_polygons(X, np.array([0, 4]), np.arange(4), np.array([7]))
    Traceback (most recent call last):
    heatcore.errors.InvalidMeshError: 1 polygon(s) cross themselves, as a bowtie does: 7 (sides 0 and 2); polygon 7 has vertices [0, 1, 2, 3]. Fix them, pass split_crossing=True to use their fan triangles, or read the mesh as triangles
    """
    crossing = crossing_polygons(X, offsets, corners, planes)
    if not crossing:
        return offsets, corners, np.arange(offsets.size - 1)
    bad = np.array([k for k, _ in crossing])
    named = ", ".join(f"{int(given[k])} (sides {a} and {b})" for k, (a, b) in crossing[:5])
    named += ", ..." if bad.size > 5 else ""
    if not split:
        k = crossing[0][0]
        raise InvalidMeshError(
            f"{bad.size} polygon(s) cross themselves, as a bowtie does: {named}; polygon {int(given[k])} has "
            f"vertices {corners[offsets[k] : offsets[k + 1]].tolist()}. Fix them, pass split_crossing=True to "
            "use their fan triangles, or read the mesh as triangles"
        )
    warnings.warn(f"{bad.size} polygon(s) cross themselves and are split into triangles: {named}", HeatcoreWarning, stacklevel=3)
    if planes is not None:
        planes.clear()
    sizes = np.diff(offsets)
    keep = np.ones(sizes.size, dtype=bool)
    keep[bad] = False
    triangles, polygon = fan_triangulate(offsets, corners)
    fans = triangles[np.isin(polygon, bad)]
    kept_corners = corners[np.repeat(keep, sizes)]
    new_sizes = np.r_[sizes[keep], np.full(len(fans), 3)]
    origin = np.r_[np.flatnonzero(keep), polygon[np.isin(polygon, bad)]]
    return np.r_[0, np.cumsum(new_sizes)], np.r_[kept_corners, fans.ravel()], origin


def fan_triangulate(offsets, indices):
    """Split each polygon into the triangles ``(c_0, c_i, c_{i+1})`` fanned from its first corner.

    Parameters
    ----------
    offsets : (m + 1,) int array
    indices : (offsets[-1],) int array

    Returns
    -------
    triangles : (sum(k - 2), 3) int array
    polygon : (sum(k - 2),) int array, the polygon each triangle comes from

    Examples
    --------
    >>> import numpy as np
    >>> fan_triangulate(np.array([0, 4, 7]), np.array([0, 1, 2, 3, 1, 4, 2]))[0].tolist()
    [[0, 1, 2], [0, 2, 3], [1, 4, 2]]
    """
    sizes = np.diff(offsets)
    n_tri = np.maximum(sizes - 2, 0)
    polygon = np.repeat(np.arange(sizes.size), n_tri)
    first = offsets[:-1][polygon]
    step = np.arange(polygon.size) - np.repeat(np.r_[0, np.cumsum(n_tri)[:-1]], n_tri)
    tri = np.stack([indices[first], indices[first + step + 1], indices[first + step + 2]], axis=1)
    return tri, polygon


def crossing_polygons(X, offsets, corners, planes=None):
    """Polygons whose sides cross, each with the first pair of crossing sides.

    Parameters
    ----------
    X : (n, 3) float array
        Vertex positions.
    offsets : (m + 1,) int array
        Polygon ``p`` has corners ``corners[offsets[p]:offsets[p + 1]]``.
    corners : (offsets[-1],) int array
    planes : dict, optional
        Filled with what is computed on the way: ``planes[k]`` the
        :func:`plane_coordinates` of the polygons of ``k > 3`` corners, in
        their order (the triangulation reuses them:
        :func:`~heatcore.domains.polygon_triangulate.triangulate_polygons`).

    Returns
    -------
    list of ``(polygon, (side_a, side_b))``
        Side ``i`` runs from corner ``i`` to corner ``i + 1``; empty when every
        polygon is simple. Triangles never cross.

    Examples
    --------
    >>> X = np.array([[0, 0, 0], [1, 1, 0], [1, 0, 0], [0, 1, 0]], float)   # a bowtie
    >>> crossing_polygons(X, np.array([0, 4]), np.array([0, 1, 2, 3]))
    [(0, (0, 2))]
    """
    sizes = np.diff(offsets)
    found = []
    for k in np.unique(sizes[sizes > 3]):
        polygons = np.flatnonzero(sizes == k)
        flat = plane_coordinates(X, corners[offsets[polygons][:, None] + np.arange(k)])
        if planes is not None:
            planes[k] = flat
        a, b = np.triu_indices(k, 2)
        keep = (b - a) % k != k - 1  # sides k-1 and 0 share corner 0
        a, b = a[keep], b[keep]
        crossing = _segments_cross(flat, a, b)  # (p, pairs)
        rows = np.flatnonzero(crossing.any(axis=1))
        first = crossing[rows].argmax(axis=1)
        found += [(int(polygons[r]), (int(a[f]), int(b[f]))) for r, f in zip(rows, first)]
    return sorted(found)


def plane_coordinates(X, idx):
    """Corners ``X[idx]`` of ``(p, k)`` polygons projected along each polygon's normal, ``(p, k, 2)``.

    The normal is the vector area (Newell's), or where that vanishes (a
    bowtie) the direction of least variance; the 2D axes ``(u, v)`` make a
    right-handed frame with it, so a polygon turning counterclockwise about
    its vector area is counterclockwise in the plane. Computed coordinate by
    coordinate on rows of ``p`` (a corner's ``x`` of every polygon): passes
    over rows of 3 were several times slower (1 s for 500k quads).

    Examples
    --------
    >>> X = np.array([[0, 0, 5], [1, 0, 5], [1, 1, 5], [0, 1, 5]], float)
    >>> Q = plane_coordinates(X, np.array([[0, 1, 2, 3]]))[0]
    >>> (u, v), (s, t) = Q[1] - Q[0], Q[2] - Q[0]
    >>> round(float(u * t - v * s), 12)   # counterclockwise in the plane
    1.0
    """
    k = idx.shape[1]
    P = np.ascontiguousarray(X.T)[:, idx.T]  # (3, k, p): coordinate, corner, polygon
    total = P[:, 0] + P[:, 1]  # the corners' mean: summed in order, over k
    for corner in range(2, k):
        total += P[:, corner]
    centered = P - (total / k)[:, None, :]
    normal = 0.5 * _vector_area_rows(centered)  # (3, p)
    spread = (centered * centered).sum(axis=(0, 1))
    weak = np.sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]) <= 1e-3 * spread
    if weak.any():  # a bowtie's areas cancel: the least-spread direction
        normal[:, weak] = np.linalg.svd(centered[:, :, weak].transpose(2, 1, 0), full_matrices=False)[2][:, 2].T
    normal /= np.sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2])
    helper = np.zeros_like(normal)
    along_x = np.abs(normal[0]) < 0.9
    helper[0, along_x] = 1.0
    helper[1, ~along_x] = 1.0
    u = _cross_rows(normal, helper)
    u /= np.sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2])
    v = _cross_rows(normal, u)
    Q = np.empty((idx.shape[0], k, 2))
    for axis, (x, y, z) in enumerate((u, v)):  # summed as np.einsum summed these products: the numbers of before
        Q[:, :, axis] = ((centered[0] * x + centered[2] * z) + centered[1] * y).T
    return Q


def vector_area_sum(centered):
    """``np.cross(c, np.roll(c, -1, axis=1)).sum(axis=1)`` over the corners ``c`` of ``(p, k, 3)`` polygons: the same
    sums in the same order, on component rows (a strided sum over few corners is several times slower).

    Twice the vector area of polygons centred on their mean corner.

    Examples
    --------
    >>> square = np.array([[[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]]], float)
    >>> vector_area_sum(square).tolist()
    [[0.0, 0.0, 8.0]]
    """
    return _vector_area_rows(np.ascontiguousarray(centered.transpose(2, 1, 0))).T


def _vector_area_rows(X):
    """:func:`vector_area_sum` of polygons laid out ``(3, k, p)`` (coordinate, corner, polygon): ``(3, p)``."""
    Y = np.concatenate([X[:, 1:], X[:, :1]], axis=1)  # each corner's next
    return np.stack([(X[1] * Y[2] - X[2] * Y[1]).sum(axis=0), (X[2] * Y[0] - X[0] * Y[2]).sum(axis=0),
                     (X[0] * Y[1] - X[1] * Y[0]).sum(axis=0)])


def area_vectors(X, F):
    """Twice the vector area of each triangle ``F`` (m, 3) of ``X`` (n, 3), as its three coordinates ``(x, y, z)``.

    Coordinate by coordinate: contiguous passes, several times faster than over rows of 3.

    Examples
    --------
    >>> X = np.array([[0, 0, 0], [2, 0, 0], [0, 1, 0]], float)
    >>> [c.tolist() for c in area_vectors(X, np.array([[0, 1, 2]]))]
    [[0.0], [0.0], [2.0]]
    """
    a, b, c = (np.ascontiguousarray(F[:, k]) for k in range(3))
    x, y, z = (np.ascontiguousarray(X[:, k]) for k in range(3))
    ux, uy, uz, vx, vy, vz = x[b] - x[a], y[b] - y[a], z[b] - z[a], x[c] - x[a], y[c] - y[a], z[c] - z[a]
    return uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx


def _cross_rows(a, b):
    """The cross product of 3-vectors laid out as rows ``(3, p)``."""
    return np.stack([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


def _segments_cross(flat, a, b):
    """Whether side ``a[j]`` crosses side ``b[j]`` of each polygon (a proper crossing, not a touch): ``(p, pairs)``.

    On corner rows of ``p`` polygons (each coordinate of a corner contiguous), each difference made once.
    """
    x, y = (np.ascontiguousarray(flat[..., axis].T) for axis in (0, 1))  # (k, p)
    nx, ny = np.concatenate([x[1:], x[:1]]), np.concatenate([y[1:], y[:1]])  # each corner's next
    px, py, qx, qy = x[a], y[a], nx[a], ny[a]  # side a from p to q, side b from r to s
    rx, ry, sx, sy = x[b], y[b], nx[b], ny[b]
    ux, uy, vx, vy = qx - px, qy - py, sx - rx, sy - ry
    d1, d2 = ux * (ry - py) - uy * (rx - px), ux * (sy - py) - uy * (sx - px)  # orientation(p, q, r), (p, q, s)
    d3, d4 = vx * (py - ry) - vy * (px - rx), vx * (qy - ry) - vy * (qx - rx)  # orientation(r, s, p), (r, s, q)
    extent = np.maximum(np.abs(x).max(axis=0), np.abs(y).max(axis=0))
    scale = extent**2 * 1e-12 + np.finfo(float).tiny
    crossing = (d1 * d2 < 0) & (d3 * d4 < 0) & (np.minimum(np.abs(d1), np.abs(d2)) > scale) & (
        np.minimum(np.abs(d3), np.abs(d4)) > scale
    )
    return crossing.T
