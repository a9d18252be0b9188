"""Local Delaunay triangles: each point's 1-ring in the Delaunay triangulation of its projected neighborhood.

Computed for all points at once: with the point ``p`` at the origin of its
tangent plane, a neighbor ``q`` is a Delaunay neighbor exactly when its
inversion ``q / |q|^2`` is a vertex of the convex hull of the inverted
neighbors and the origin. The hull is found by sorting the neighbors by angle
and removing reflex vertices in vectorized rounds.

Examples
--------
>>> import numpy as np
>>> from heatcore.domains.pointcloud.neighborhoods import nearest_neighbors
>>> t = np.arange(6) * np.pi / 3  # a regular hexagon around point 0
>>> P = np.vstack([[0, 0, 0], np.column_stack([np.cos(t), np.sin(t), np.zeros(6)])])
>>> T, votes, rim = local_delaunay_triangles(P, np.tile([0, 0, 1.0], (7, 1)), nearest_neighbors(P, 6)[0])
>>> len(T), votes.tolist(), np.flatnonzero(rim).tolist()  # six triangles, each proposed by its 3 corners
(6, [3, 3, 3, 3, 3, 3], [1, 2, 3, 4, 5, 6])
"""

import numpy as np

#: Neighbors whose offset along the normal exceeds this multiple of their
#: tangential distance (a slope) are left out: they lie across a thin gap.
MAX_SLOPE = 0.6
#: Triangles whose doubled area is below this fraction of their longest
#: squared side (all angles nearly 0 or pi) are left out.
MIN_SINE = 1e-6
#: A neighbor is reflex (dropped from the hull) up to this relative rounding of its turn.
REFLEX_TOLERANCE = 1e-12


def local_delaunay_triangles(P, normals, nbr):
    """Union of each point's 1-ring in the Delaunay triangulation of its projected neighborhood.

    Parameters
    ----------
    P : (n, 3) float array
    normals : (n, 3) float array, unit
    nbr : (n, k) int array, neighbor indices (-1 for none)

    Returns
    -------
    triangles : (m, 3) int array, each proposed triangle once (sorted indices)
    votes : (m,) int array, how many points proposed each triangle
    boundary : (n,) bool array, points whose 1-ring leaves a gap of at least pi

    Examples
    --------
    >>> import numpy as np
    >>> P = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1.1, 0]])
    >>> nbr = np.array([[1, 2, 3], [0, 2, 3], [0, 1, 3], [0, 1, 2]])
    >>> T, votes, boundary = local_delaunay_triangles(P, np.tile([0, 0, 1.0], (4, 1)), nbr)
    >>> T.tolist(), votes.tolist(), boundary.tolist()
    ([[0, 1, 2], [1, 2, 3]], [3, 3], [True, True, True, True])
    """
    n, k = nbr.shape
    # tangent frame
    a = np.where(np.abs(normals[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    e1 = np.cross(normals, a)
    e1 /= np.linalg.norm(e1, axis=1, keepdims=True)
    e2 = np.cross(normals, e1)
    valid = nbr >= 0
    R = P[np.maximum(nbr, 0)] - P[:, None]
    x = np.einsum("nkd,nd->nk", R, e1)
    y = np.einsum("nkd,nd->nk", R, e2)
    z = np.einsum("nkd,nd->nk", R, normals)
    r2 = x * x + y * y
    valid &= (r2 > 0) & (z * z <= MAX_SLOPE**2 * r2)
    with np.errstate(divide="ignore", invalid="ignore"):
        ux, uy = np.where(valid, x / r2, 0.0), np.where(valid, y / r2, 0.0)  # inversion
    ang = np.where(valid, np.arctan2(y, x), 10.0)  # invalid entries sort last
    order = np.argsort(ang, axis=1)
    take = lambda A: np.take_along_axis(A, order, axis=1)
    ux, uy, ang, nb, alive = take(ux), take(uy), take(ang), take(nbr), take(valid)
    col = np.arange(k)[None, :]
    active = np.arange(n)  # rows that may still have reflex neighbors: later rounds touch only these
    while active.size:
        A = _without_reflex_round(ux[active], uy[active], ang[active], nb[active], alive[active], col)
        ux[active], uy[active], ang[active], nb[active], alive[active], changed = A
        active = active[changed]
    rows = np.arange(n)[:, None]
    c = alive.sum(axis=1)[:, None]
    nxt = (col + 1) % np.maximum(c, 1)
    wedge = np.mod(ang[rows, nxt] - ang, 2 * np.pi)
    closed = alive & (c >= 2) & (wedge < np.pi) & (col != nxt)
    gap = np.where(alive, np.where(c >= 2, wedge, 2 * np.pi), 0.0).max(axis=1)
    boundary = gap >= np.pi
    i, j = np.nonzero(closed)
    T = np.stack([i, nb[i, j], nb[i, nxt[i, j]]], axis=1)
    T = np.sort(T, axis=1)
    T = T[(T[:, 0] != T[:, 1]) & (T[:, 1] != T[:, 2])]
    # drop triangles that are flat in 3D (collinear points): no area, no direction
    l2 = np.stack([((P[T[:, a]] - P[T[:, b]]) ** 2).sum(axis=1) for a, b in ((0, 1), (1, 2), (2, 0))], axis=1)
    doubled_area = np.linalg.norm(np.cross(P[T[:, 1]] - P[T[:, 0]], P[T[:, 2]] - P[T[:, 0]]), axis=1)
    T = T[doubled_area > MIN_SINE * l2.max(axis=1)]
    if n > 2_000_000:  # one integer per triple would overflow
        T, votes = np.unique(T.reshape(-1, 3), axis=0, return_counts=True)
        return T.astype(np.int64), votes, boundary
    key = (T[:, 0] * n + T[:, 1]) * n + T[:, 2]  # sorted triples as one integer, in the same order
    _, first, votes = np.unique(key, return_index=True, return_counts=True)
    return T[first].astype(np.int64), votes, boundary


def _without_reflex_round(ux, uy, ang, nb, alive, col):
    """One round of removing reflex vertices from the rows' angular fans (the alive ones compacted first).

    Returns the rows' compacted arrays and which rows lost a vertex this round.
    """
    pos = np.argsort(~alive, axis=1, kind="stable")  # the alive neighbors to the front, in angular order
    ux, uy, ang, nb, alive = (np.take_along_axis(A, pos, axis=1) for A in (ux, uy, ang, nb, alive))
    rows = np.arange(ux.shape[0])[:, None]
    c = alive.sum(axis=1)[:, None]
    cc = np.maximum(c, 1)
    nxt = (col + 1) % cc
    prv = (col - 1) % cc
    wedge_next = np.where(c == 1, 2 * np.pi, np.mod(ang[rows, nxt] - ang, 2 * np.pi))
    wedge_prev = np.where(c == 1, 2 * np.pi, np.mod(ang - ang[rows, prv], 2 * np.pi))
    ax, ay = ux[rows, prv], uy[rows, prv]
    bx, by = ux[rows, nxt], uy[rows, nxt]
    cross = (bx - ax) * (uy - ay) - (by - ay) * (ux - ax)
    scale = (bx - ax) ** 2 + (by - ay) ** 2 + (ux - ax) ** 2 + (uy - ay) ** 2
    reflex = alive & (c >= 3) & (wedge_prev + wedge_next < np.pi) & (cross >= -REFLEX_TOLERANCE * scale)
    return ux, uy, ang, nb, alive & ~reflex, reflex.any(axis=1)


def attach_left_out(P, triangles, nbr):
    """Triangles joining each point that no local triangle uses to two of its neighbors that one does.

    Heavy noise leaves a few points with no triangle (their neighbors all lie
    at steep slopes, ``MAX_SLOPE``). Each such point ``o`` with a neighbor on
    the surface gets one triangle ``(o, a, b)``: ``a`` its nearest neighbor
    that a triangle uses, ``b`` the nearest other such neighbor that shares
    an edge with ``a`` (else the nearest other), so that ``o`` hangs on the
    surface beside ``a`` and gets a distance. Two passes: a point next to
    one attached in the first pass gets attached in the second. Points with
    no such neighbor (isolated points) stay out.

    Parameters
    ----------
    P : (n, 3) float array
    triangles : (m, 3) int array, sorted rows
    nbr : (n, k) int array, neighbors nearest first (-1 for none)

    Returns
    -------
    (m', 3) int array, sorted rows: ``triangles`` and the added ones

    Examples
    --------
    >>> import numpy as np
    >>> P = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0.2, 0.2, 1.0]])
    >>> nbr = np.array([[1, 2, 3], [0, 2, 3], [0, 1, 3], [0, 1, 2]])
    >>> attach_left_out(P, np.array([[0, 1, 2]]), nbr).tolist()  # point 3 hangs on edge (0, 1)
    [[0, 1, 2], [0, 1, 3]]
    """
    n = P.shape[0]
    for _ in range(2):
        used = np.zeros(n, dtype=bool)
        used[triangles] = True
        left = np.flatnonzero(~used & (nbr >= 0).any(axis=1))
        if not left.size:
            break
        cand = nbr[left]
        ok = cand >= 0
        ok[ok] = used[cand[ok]]
        has_two = ok.sum(axis=1) >= 2
        left, cand, ok = left[has_two], cand[has_two], ok[has_two]
        if not left.size:
            break
        rows = np.arange(left.size)
        a = cand[rows, ok.argmax(axis=1)]
        other = ok & (cand != a[:, None])
        edges = np.sort(triangles[:, [0, 1, 1, 2, 0, 2]].reshape(-1, 2), axis=1)
        edge_keys = np.unique(edges[:, 0] * n + edges[:, 1])
        lo, hi = np.minimum(a[:, None], cand), np.maximum(a[:, None], cand)
        shares = other & np.isin(lo * n + hi, edge_keys)
        pick = np.where(shares.any(axis=1), shares.argmax(axis=1), other.argmax(axis=1))
        added = np.sort(np.column_stack([left, a, cand[rows, pick]]), axis=1)
        triangles = np.concatenate([triangles, added])
    return triangles
