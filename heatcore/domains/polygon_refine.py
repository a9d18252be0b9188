"""Polygon-aware refinement: each polygon split at its virtual vertex and edge midpoints.

A polygon with ``k >= 4`` corners is split into ``k`` quads
``(c_i, m_i, x_f, m_{i-1})``, where ``m_i`` is the midpoint of side ``i`` and
``x_f`` the polygon's virtual vertex (the area minimizer of
:func:`area_minimizer_weights`); a triangle is split
into four at its edge midpoints. That is the topology step of Catmull-Clark
without its smoothing: new points lie on the polygon's own virtual
refinement, so planar polygons keep exactly their surface, and the refined
mesh is again a polygon mesh (of quads) for virtual refinement. How many
levels each connected part gets is the triangle meshes' rule
(:func:`~heatcore.domains.refine.auto_refine_levels`, under the same budget),
and distances are read back at the input vertices, which come first.

Each new vertex remembers the input edge it lies on (or -1) and the input
polygon it lies inside (or -1), so that edge and region sources can be
carried to the refined mesh.

Examples
--------
>>> import numpy as np
>>> X = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)
>>> r = split_polygons(X, np.array([0, 4]), np.arange(4), np.array([1]))
>>> r.vertices.shape, np.diff(r.offsets).tolist()
((9, 3), [4, 4, 4, 4])
>>> r.vertices[-1].tolist(), r.vertex_edge.tolist(), r.vertex_polygon.tolist()
([0.5, 0.5, 0.0], [-1, -1, -1, -1, 0, 1, 2, 3, -1], [-1, -1, -1, -1, -1, -1, -1, -1, 0])
"""

from dataclasses import dataclass

import numpy as np


@dataclass
class PolygonRefinement:
    """Result of :func:`split_polygons`.

    Attributes
    ----------
    vertices : (n', 3) float array; the first ``n`` rows are the input's.
    offsets, corners : int arrays, the refined polygons.
    edges : (k, 2) int array, the unique (sorted) edges of the input polygons.
    vertex_edge : (n',) int array, input edge (into ``edges``) a vertex lies on, or -1.
    vertex_polygon : (n',) int array, input polygon a vertex lies strictly inside, or -1.

    Examples
    --------
    >>> X = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    >>> r = split_polygons(X, np.array([0, 3]), np.arange(3), np.array([1]))
    >>> r.edges.tolist(), r.vertex_edge.tolist()
    ([[0, 1], [0, 2], [1, 2]], [-1, -1, -1, 0, 1, 2])
    """

    vertices: np.ndarray
    offsets: np.ndarray
    corners: np.ndarray
    edges: np.ndarray
    vertex_edge: np.ndarray
    vertex_polygon: np.ndarray


def area_minimizer_weights(X):
    """Affine weights of the virtual vertex of polygons of one size (Bunge et al. 2020, eq. 3).

    The virtual vertex ``x = w @ X`` minimizes the sum of squared areas of the
    triangles ``(X_i, X_{i+1}, x)``; among the weights giving that point
    (unique for ``k > 4`` or planar polygons) the ones of least norm are chosen.

    Parameters
    ----------
    X : (m, k, 3) float array
        Corner positions of ``m`` polygons with ``k`` corners each.

    Returns
    -------
    (m, k) float array
        Weights summing to 1 per polygon; uniform for a polygon collapsed to a point.

    Examples
    --------
    >>> import numpy as np
    >>> square = np.array([[[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]], float)
    >>> area_minimizer_weights(square).round(3).tolist()
    [[0.25, 0.25, 0.25, 0.25]]
    """
    k = X.shape[1]
    c = X.mean(axis=1)
    Y = X - c[:, None, :]  # translation invariance: work around the centroid
    d = np.roll(Y, -1, axis=1) - Y
    # (Y_i - p) x d_i has squared norm (p - Y_i)^T C_i (p - Y_i), C_i = |d_i|^2 I - d_i d_i^T
    dd = np.einsum("mki,mki->mk", d, d)
    A = dd.sum(axis=1)[:, None, None] * np.eye(3) - np.einsum("mki,mkj->mij", d, d)
    b = dd[:, :, None] * Y - d * np.einsum("mki,mki->mk", d, Y)[:, :, None]
    p = _psd_solve(A, b.sum(axis=1))
    # least-norm weights: w = 1/k + Y (Y^T Y)^+ p  (sum(w) = 1 since sum_i Y_i = 0). A planar polygon's
    # Y^T Y is singular along its normal n, and p lies in its plane: (Y^T Y + tr n n^T)^-1 p is the same.
    YtY = np.einsum("mki,mkj->mij", Y, Y)
    normal = np.cross(Y, np.roll(Y, -1, axis=1)).sum(axis=1)
    normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), np.finfo(float).tiny)
    trace = np.trace(YtY, axis1=1, axis2=2)
    planar = (np.einsum("mki,mi->mk", Y, normal) ** 2).sum(axis=1) <= 1e-10 * trace  # within pinv's cut
    p[planar] -= np.einsum("mi,mi->m", p[planar], normal[planar])[:, None] * normal[planar]
    YtY[planar] += trace[planar, None, None] * normal[planar, :, None] * normal[planar, None, :]
    q = _psd_solve(YtY, p)
    w = 1.0 / k + np.einsum("mki,mi->mk", Y, q)
    return np.where(np.isfinite(w).all(axis=1, keepdims=True), w, 1.0 / k)


def _psd_solve(M, rhs):
    """``pinv(M) @ rhs`` for symmetric positive semidefinite 3 x 3 matrices ``M`` (m, 3, 3) and ``rhs`` (m, 3).

    By cofactors (vectorized) where ``M`` is well conditioned (its determinant
    above 1e-10 of its trace cubed: the smallest eigenvalue then above
    1e-10 of the largest, the cut of ``np.linalg.pinv``); the others by pinv,
    as a least-norm solve.
    """
    r0, r1, r2 = M[:, 0], M[:, 1], M[:, 2]
    c0, c1, c2 = np.cross(r1, r2), np.cross(r2, r0), np.cross(r0, r1)  # columns of the adjugate
    det = np.einsum("mi,mi->m", r0, c0)
    trace = np.trace(M, axis1=1, axis2=2)
    good = (det > 1e-10 * trace**3) & (det > 0)
    out = np.empty_like(rhs)
    out[good] = (c0[good] * rhs[good, :1] + c1[good] * rhs[good, 1:2] + c2[good] * rhs[good, 2:]) / det[good, None]
    bad = ~good
    if bad.any():
        scale = np.maximum(np.abs(M[bad]).max(axis=(1, 2)), np.finfo(float).tiny)
        inverse = np.linalg.pinv(M[bad] / scale[:, None, None], rcond=1e-10, hermitian=True)
        out[bad] = np.einsum("mij,mj->mi", inverse, rhs[bad] / scale[:, None])
    return out


def _extreme_eigenvalues(M):
    """Smallest and largest eigenvalues of symmetric 3 x 3 matrices ``M`` (m, 3, 3), in closed form.

    The trigonometric solution of the characteristic cubic, vectorized: eigenvalues
    within about 1e-15 of the largest of the exact ones (``np.linalg.eigvalsh``
    loops over the matrices, 20 times slower at 500k).
    """
    q = np.trace(M, axis1=1, axis2=2) / 3.0
    off = M[:, 0, 1] ** 2 + M[:, 0, 2] ** 2 + M[:, 1, 2] ** 2
    p = np.sqrt(((M[:, 0, 0] - q) ** 2 + (M[:, 1, 1] - q) ** 2 + (M[:, 2, 2] - q) ** 2 + 2.0 * off) / 6.0)
    B = (M - q[:, None, None] * np.eye(3)) / np.maximum(p, np.finfo(float).tiny)[:, None, None]
    r = np.clip(np.linalg.det(B) / 2.0, -1.0, 1.0)
    phi = np.arccos(r) / 3.0
    return q + 2.0 * p * np.cos(phi + 2.0 * np.pi / 3.0), q + 2.0 * p * np.cos(phi)


def polygon_sides(offsets, corners, n):
    """Unique edges of polygons and the edge id of each side (side ``s`` runs from corner ``s`` to the next).

    Returns
    -------
    edges : (k, 2) int array of sorted vertex pairs
    side : (offsets[-1],) int array
    nxt : (offsets[-1],) int array, the position of the next corner of each corner's polygon

    Examples
    --------
    >>> edges, side, nxt = polygon_sides(np.array([0, 4]), np.array([0, 1, 2, 3]), 4)
    >>> edges.tolist(), side.tolist(), nxt.tolist()
    ([[0, 1], [0, 3], [1, 2], [2, 3]], [0, 2, 3, 1], [1, 2, 3, 0])
    """
    nxt = np.arange(corners.size) + 1
    nxt[offsets[1:] - 1] = offsets[:-1]
    a, b = corners, corners[nxt]
    keys, side = np.unique(np.minimum(a, b) * n + np.maximum(a, b), return_inverse=True)
    return np.stack([keys // n, keys % n], axis=1), side.reshape(-1), nxt


def split_polygons(X, offsets, corners, levels, weights=None):
    """Split polygons ``levels`` times: k-gons into k quads at their virtual vertex, triangles into four.

    Parameters
    ----------
    X : (n, 3) float array
    offsets, corners : int arrays
        Polygon ``p`` is ``corners[offsets[p]:offsets[p + 1]]``.
    levels : (m,) int array
        Levels per polygon; polygons sharing an edge must get the same (give
        it per connected part), so that no edge is split on one side only.
    weights : callable, optional
        ``weights(P)`` for corner positions ``P`` of shape ``(p, k, 3)`` gives
        the ``(p, k)`` affine weights of the split point; default
        :func:`area_minimizer_weights`.

    Returns
    -------
    PolygonRefinement

    Examples
    --------
    >>> X = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0]], float)
    >>> r = split_polygons(X, np.array([0, 4, 7]), np.array([0, 1, 2, 3, 1, 4, 2]), np.array([2, 2]))
    >>> np.bincount(np.diff(r.offsets)).tolist(), r.vertices.shape[0]
    ([0, 0, 0, 16, 16], 35)
    """
    if weights is None:
        weights = area_minimizer_weights
    n0 = X.shape[0]
    edges, side_origin, _ = polygon_sides(offsets, corners, n0)
    poly_levels = np.asarray(levels, dtype=np.int64)
    poly_origin = np.arange(offsets.size - 1)
    vertex_edge = np.full(n0, -1, dtype=np.int64)
    vertex_polygon = np.full(n0, -1, dtype=np.int64)
    for level in range(int(poly_levels.max(initial=0))):
        n = X.shape[0]
        sizes = np.diff(offsets)
        owner = np.repeat(np.arange(sizes.size), sizes)
        cur_edges, side, nxt = polygon_sides(offsets, corners, n)
        prv = np.empty_like(nxt)
        prv[nxt] = np.arange(nxt.size)
        split = poly_levels > level
        corner_split = split[owner]
        cut = np.zeros(cur_edges.shape[0], dtype=bool)
        cut[side[corner_split]] = True
        mid = np.full(cur_edges.shape[0], -1, dtype=np.int64)
        mid[cut] = n + np.arange(int(cut.sum()))
        new_edge = np.full(cur_edges.shape[0], -1, dtype=np.int64)
        new_poly = np.full(cur_edges.shape[0], -1, dtype=np.int64)
        new_edge[side[corner_split]] = side_origin[corner_split]
        inner = corner_split & (side_origin == -1)
        new_poly[side[inner]] = poly_origin[owner[inner]]
        # virtual vertices of the split polygons with k >= 4 corners
        big = split & (sizes > 3)
        center = np.full(sizes.size, -1, dtype=np.int64)
        center[big] = n + int(cut.sum()) + np.arange(int(big.sum()))
        centers = np.zeros((int(big.sum()), 3))
        order = np.flatnonzero(big)
        for k in np.unique(sizes[big]):
            polys = np.flatnonzero(big & (sizes == k))
            P = X[corners[offsets[polys][:, None] + np.arange(k)]]
            centers[np.searchsorted(order, polys)] = np.einsum("pk,pkd->pd", weights(P), P)
        X = np.vstack([X, 0.5 * (X[cur_edges[cut, 0]] + X[cur_edges[cut, 1]]), centers])
        vertex_edge = np.r_[vertex_edge, new_edge[cut], np.full(order.size, -1)]
        vertex_polygon = np.r_[vertex_polygon, new_poly[cut], poly_origin[order]]

        # quads (c_i, m_i, x_f, m_{i-1}) of big polygons, one per corner
        q = np.flatnonzero(big[owner])
        m_i, m_p = mid[side[q]], mid[side[prv[q]]]
        none = np.full(q.size, -1)
        quads = np.stack([corners[q], m_i, center[owner[q]], m_p], axis=1)
        quad_sides = np.stack([side_origin[q], none, none, side_origin[prv[q]]], axis=1)
        # triangles: three corner triangles (c_i, m_i, m_{i-1}) and the middle one
        t = np.flatnonzero((split & (sizes == 3))[owner])
        tri = np.stack([corners[t], mid[side[t]], mid[side[prv[t]]]], axis=1)
        tri_sides = np.stack([side_origin[t], np.full(t.size, -1), side_origin[prv[t]]], axis=1)
        first = t[::3]  # the corners of a triangle are consecutive
        middle = mid[side[np.stack([first, first + 1, first + 2], axis=1)]]
        keep = ~corner_split
        offsets = np.r_[
            0,
            np.cumsum(np.r_[sizes[~split], np.full(q.size, 4), np.full(t.size + first.size, 3)]),
        ]
        corners = np.r_[corners[keep], quads.ravel(), tri.ravel(), middle.ravel()]
        side_origin = np.r_[side_origin[keep], quad_sides.ravel(), tri_sides.ravel(), np.full(3 * first.size, -1)]
        poly_origin = np.r_[poly_origin[~split], poly_origin[owner[q]], poly_origin[owner[t]], poly_origin[owner[first]]]
        poly_levels = np.r_[poly_levels[~split], poly_levels[owner[q]], poly_levels[owner[t]], poly_levels[owner[first]]]
    return PolygonRefinement(X, offsets.astype(np.int64), corners.astype(np.int64), edges, vertex_edge, vertex_polygon)


#: Time factor of refined parts: their heat flows for ``t = REFINED_TIME_FACTOR * m * h**2``
#: (``h``: the refined polygons' mean edge length). Measured over m = 1 .. 2.5 on
#: every refined mesh of docs/polygon.md (planar and jittered quad and hex grids,
#: the Catmull-Clark sphere and cube, suzanne; central, corner and boundary
#: sources), the error falls to 2 and flattens; a refined triangle mesh's mean
#: edge includes the fan diagonals, so its step is already 1.3-2 times ``m h**2``
#: of the same polygons. Unrefined parts keep ``m h**2``.
REFINED_TIME_FACTOR = 2.0


def refine_levels(n, offsets, corners, refine):
    """Split levels of each polygon: the triangle meshes' rule, per connected part.

    Parameters
    ----------
    n : int
        Vertices (``corners`` index ``0 .. n - 1``).
    offsets, corners : int arrays
    refine : "auto" or int
        "auto": :func:`~heatcore.domains.refine.auto_refine_levels` of each
        part's vertex count, under :data:`~heatcore.domains.refine.AUTO_REFINE_BUDGET`
        in all; an int: that many levels everywhere. A part with a polygon
        that visits a corner twice (a sliver ``[a, b, c, b]``) is not split:
        its pieces would fold onto each other.

    Returns
    -------
    part_levels : (n_parts,) int array
    levels : (m,) int array, per polygon
    part : (n,) int array, the connected part of each vertex

    Examples
    --------
    >>> refine_levels(4, np.array([0, 4]), np.arange(4), "auto")[0].tolist()
    [7]
    """
    from .parts import vertex_components
    from .refine import auto_refine_levels, budgeted_levels

    edges = polygon_sides(offsets, corners, n)[0]
    count, part = vertex_components(edges, n)
    if refine == "auto":
        sizes = np.bincount(part, minlength=count)
        part_levels = budgeted_levels(sizes, auto_refine_levels(sizes))[0]
    else:
        part_levels = np.full(count, int(refine), dtype=np.int64)
    owner = np.repeat(np.arange(offsets.size - 1), np.diff(offsets))
    key = np.sort(owner * n + corners)
    repeated = key[1:][key[1:] == key[:-1]] % n
    part_levels[part[repeated]] = 0
    return part_levels, part_levels[part[corners[offsets[:-1]]]], part


def unfold(refined):
    """Fan triangles for refined quads that cross themselves (a split strongly non-convex polygon).

    Examples
    --------
    >>> X = np.array([[0, 0, 0], [1, 1, 0], [1, 0, 0], [0, 1, 0]], float)
    >>> r = PolygonRefinement(X, np.array([0, 4]), np.arange(4), None, None, None)
    >>> unfold(r).corners.tolist()
    [0, 1, 2, 0, 2, 3]
    """
    from .polygon_shape import crossing_polygons, fan_triangulate

    bad = np.array([p for p, _ in crossing_polygons(refined.vertices, refined.offsets, refined.corners)], dtype=np.int64)
    if not bad.size:
        return refined
    sizes = np.diff(refined.offsets)
    keep = np.ones(sizes.size, dtype=bool)
    keep[bad] = False
    triangles, polygon = fan_triangulate(refined.offsets, refined.corners)
    fans = triangles[np.isin(polygon, bad)]
    offsets = np.r_[0, np.cumsum(np.r_[sizes[keep], np.full(len(fans), 3)])]
    corners = np.r_[refined.corners[np.repeat(keep, sizes)], fans.ravel()]
    return PolygonRefinement(
        refined.vertices, offsets, corners, refined.edges, refined.vertex_edge, refined.vertex_polygon
    )


def vertices_inside(refined, offsets, corners, polygons):
    """Refined vertices on the sides of, or inside, the given input polygons.

    Parameters
    ----------
    refined : PolygonRefinement
    offsets, corners : int arrays
        The polygons that were split.
    polygons : int array
        Indices into them.

    Examples
    --------
    >>> X = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0]], float)
    >>> o, c = np.array([0, 4, 7]), np.array([0, 1, 2, 3, 1, 4, 2])
    >>> vertices_inside(split_polygons(X, o, c, np.array([1, 1])), o, c, np.array([1])).tolist()
    [7, 8, 10]
    """
    _, side, _ = polygon_sides(offsets, corners, int(max(corners.max(), refined.edges.max())) + 1)
    chosen = np.zeros(offsets.size - 1, dtype=bool)
    chosen[polygons] = True
    sides = side[np.repeat(chosen, np.diff(offsets))]
    on_side = np.isin(refined.vertex_edge, sides)
    inside = (refined.vertex_polygon >= 0) & chosen[np.maximum(refined.vertex_polygon, 0)]
    return np.flatnonzero(on_side | inside)


#: Non-planarity (smallest over largest singular value of a polygon's centred
#: corners) from which the operators' virtual vertex is the corners' centroid
#: (:func:`operator_weights`); below it the weights blend linearly towards the
#: area minimizer, which planar polygons keep exactly.
NONPLANAR_RAMP = 0.003


def operator_weights(X):
    """Virtual-vertex weights of the operators: the area minimizer on planar polygons, the centroid on non-planar ones.

    Measured (docs/polygon.md): on beast's non-planar quads the centroid (the
    centre of a quad's bilinear patch) gives 2.67% against 2.85% for the area
    minimizer, suzanne 2.04% against 2.10%; on planar polygons (kites of a
    split hex grid) the area minimizer is better (0.60% against 0.72%). The
    blend is linear in the non-planarity up to :data:`NONPLANAR_RAMP`.

    Parameters
    ----------
    X : (m, k, 3) float array

    Returns
    -------
    (m, k) float array, affine weights

    Examples
    --------
    >>> flat = np.array([[[0, 0, 0], [2, 0, 0], [1, 1, 0], [0, 1, 0]]], float)
    >>> bool(np.allclose(operator_weights(flat), area_minimizer_weights(flat)))
    True
    >>> twisted = np.array([[[0, 0, 0], [1, 0, 1], [1, 1, 0], [0, 1, 1]]], float)
    >>> operator_weights(twisted).tolist()
    [[0.25, 0.25, 0.25, 0.25]]
    """
    w = area_minimizer_weights(X)
    Y = X - X.mean(axis=1, keepdims=True)
    smallest, largest = _extreme_eigenvalues(np.einsum("mki,mkj->mij", Y, Y))  # squared singular values of Y
    ratio = np.sqrt(np.maximum(smallest, 0.0) / np.maximum(largest, np.finfo(float).tiny))
    s = np.clip(ratio / NONPLANAR_RAMP, 0.0, 1.0)[:, None]
    return (1.0 - s) * w + s / X.shape[1]
