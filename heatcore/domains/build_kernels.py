"""Compiled kernels of a large mesh's build: its edge table, connected parts, twins, Delaunay tests and flips (numba).

On a 1M-vertex mesh the numpy build sorts 6M face sides and computes every
corner's cotangent in 48 MB temporaries; these loops make the same arrays
without them. Each kernel gives bit for bit the numpy path's result (the
same floating-point operations in the same order; tested), so whether it
runs changes the time only.

Importing this module imports numba (the ``fast`` extra): a build asks
:func:`heatcore.compiled.build_kernels`, which says from which size they run.

Examples
--------
>>> import numpy as np
>>> from heatcore.domains.refine import unique_edges
>>> F = np.array([[0, 1, 2], [0, 2, 3]])
>>> edges, side_edge, pairs = edge_table(F)
>>> expected = unique_edges(F, with_pairs=True)
>>> all(np.array_equal(a, b) for a, b in zip((edges, side_edge, pairs), expected))
True
"""

import numpy as np

from ..compiled import compiled


def edge_table(F):
    """:func:`heatcore.domains.refine.unique_edges` with ``with_pairs``: the same three arrays, in compiled passes.

    A counting sort of the sides by their smaller vertex, then an insertion
    sort by the larger one within each vertex's sides, lists the sides edge
    by edge, each edge's in ascending order: the order of numpy's one sort.

    Parameters
    ----------
    F : (m, 3) int array

    Returns
    -------
    edges : (k, 2) int64 array
    side_edge : (m, 3) int64 array
    pairs : (p, 2) int64 array

    Examples
    --------
    >>> edges, side_edge, pairs = edge_table(np.array([[0, 1, 2], [0, 2, 3]]))
    >>> edges.tolist(), side_edge.tolist(), pairs.tolist()
    ([[0, 1], [0, 2], [0, 3], [1, 2], [2, 3]], [[3, 1, 0], [4, 2, 1]], [[1, 5]])
    """
    F = np.ascontiguousarray(F, dtype=np.int64)
    n = int(F.max()) + 1 if F.size else 1
    edges, side_edge, pairs = _edge_table(F, n)
    return edges, side_edge.reshape(F.shape), pairs


def vertex_components(elements, n):
    """:func:`heatcore.domains.parts.vertex_components` without a graph: the same count and parts, from a
    union-find over the elements' corners (each part keeps its smallest vertex as its root, so the parts are
    numbered by their smallest vertex, as there).

    Parameters
    ----------
    elements : (m, k) int array
    n : int

    Returns
    -------
    count : int
    part : (n,) int64 array

    Examples
    --------
    >>> count, part = vertex_components(np.array([[3, 1, 2]]), 5)
    >>> count, part.tolist()
    (3, [0, 1, 1, 1, 2])
    """
    count, part = _components(np.ascontiguousarray(elements, dtype=np.int64), n)
    return int(count), part


def twins_of_pairs(F, pairs, oriented=True):
    """:func:`heatcore.domains.intrinsic.halfedge_twins` from the pairs of sides: the same twins, in one pass.

    Examples
    --------
    >>> twins_of_pairs(np.array([[0, 1, 2], [0, 2, 3]]), np.array([[1, 5]])).tolist()
    [-1, 5, -1, -1, -1, 1]
    """
    F = np.ascontiguousarray(F, dtype=np.int64)
    return _twins_of_pairs(F, np.ascontiguousarray(pairs, dtype=np.int64), oriented)


def cotangent_sums(lengths, h, t):
    """``cot`` of the corner opposite half-edge ``h`` plus that opposite ``t``, each as
    :func:`heatcore.domains.intrinsic.corner_cotangents` computes it.

    Parameters
    ----------
    lengths : (m, 3) float array, C-ordered
    h, t : (k,) int arrays
        Half-edges ``3 f + c``.

    Returns
    -------
    (k,) float array

    Examples
    --------
    >>> from heatcore.domains.intrinsic import corner_cotangents
    >>> L = np.array([[5.0, 4.0, 3.0], [1.0, 1.0, 1.0]])
    >>> bool(cotangent_sums(L, np.array([1]), np.array([5]))[0] == corner_cotangents(L).ravel()[[1, 5]].sum())
    True
    """
    return _cotangent_sums(lengths, np.asarray(h, dtype=np.int64), np.asarray(t, dtype=np.int64))


def flip_pairs(faces, lengths, twin, h0, h1):
    """Flip the edges of half-edge pairs ``(h0, h1)`` (no two sharing a face) in place, one after the other:
    the faces, lengths and twins :meth:`IntrinsicTriangulation._flip` makes at once.

    Parameters
    ----------
    faces : (m, 3) int64 array, C-ordered
    lengths : (m, 3) float array, C-ordered
    twin : (3 m,) int64 array
    h0, h1 : (k,) int arrays

    Examples
    --------
    Two flat triangles on a long shared edge 0-1 (half-edges 2 and 5), whose opposite angles are obtuse:

    >>> faces, twin = np.array([[0, 1, 2], [1, 0, 3]]), np.array([-1, -1, 5, -1, -1, 2])
    >>> lengths = np.full((2, 3), np.hypot(1.0, 0.2))
    >>> lengths[:, 2] = 2.0
    >>> flip_pairs(faces, lengths, twin, [2], [5])
    >>> faces.tolist(), lengths[0].round(3).tolist()  # the new edge 2-3 is 0.4 long
    ([[3, 1, 2], [2, 0, 3]], [1.02, 0.4, 1.02])
    """
    _flip_pairs(faces, lengths, twin, np.asarray(h0, dtype=np.int64), np.asarray(h1, dtype=np.int64))


def fits(faces, lengths, twin):
    """Whether the arrays are as the kernels read them (int64 and float64, C-ordered).

    Examples
    --------
    >>> lengths, twin = np.ones((1, 3)), np.full(3, -1)
    >>> fits(np.zeros((1, 3), np.int64), lengths, twin), fits(np.zeros((1, 3), np.int32), lengths, twin)
    (True, False)
    """
    return (faces.dtype == np.int64 and twin.dtype == np.int64 and lengths.dtype == np.float64
            and faces.flags.c_contiguous and lengths.flags.c_contiguous)


@compiled
def _edge_table(F, n):  # pragma: no cover - compiled
    """The sides sorted by edge (counting sort by the smaller vertex, insertion sort by the larger), then the
    edges, each side's edge and the pairs, as :func:`edge_table` returns them."""
    k = 3 * F.shape[0]
    start = np.zeros(n + 1, dtype=np.int64)
    for s in range(k):
        a, b = F[s // 3, (s + 1) % 3], F[s // 3, (s + 2) % 3]
        start[min(a, b) + 1] += 1
    for v in range(n):
        start[v + 1] += start[v]
    place = start[:-1].copy()
    side = np.empty(k, dtype=np.int64)
    high = np.empty(k, dtype=np.int64)
    for s in range(k):
        a, b = F[s // 3, (s + 1) % 3], F[s // 3, (s + 2) % 3]
        low = min(a, b)
        side[place[low]], high[place[low]] = s, max(a, b)
        place[low] += 1
    n_edges = 0
    for v in range(n):
        sort_by_key(side, high, start[v], start[v + 1])
        for j in range(start[v], start[v + 1]):
            n_edges += j == start[v] or high[j] != high[j - 1]
    edges = np.empty((n_edges, 2), dtype=np.int64)
    side_edge = np.empty(k, dtype=np.int64)
    size = np.zeros(n_edges, dtype=np.int64)
    e = -1
    for v in range(n):
        for j in range(start[v], start[v + 1]):
            if j == start[v] or high[j] != high[j - 1]:
                e += 1
                edges[e, 0], edges[e, 1] = v, high[j]
            side_edge[side[j]] = e
            size[e] += 1
    pairs = np.empty((np.sum(size == 2), 2), dtype=np.int64)
    p, j = 0, 0
    for e in range(n_edges):  # the sides are listed edge by edge
        if size[e] == 2:
            pairs[p, 0], pairs[p, 1] = side[j], side[j + 1]
            p += 1
        j += size[e]
    return edges, side_edge, pairs


@compiled
def sort_by_key(items, keys, lo, hi):  # pragma: no cover - compiled
    """Sort ``items[lo:hi]`` and ``keys[lo:hi]`` by ``keys``, stably, in place: an insertion sort, a merge sort
    past 16 (a vertex's sides or triangles, in compiled loops).

    Examples
    --------
    >>> items, keys = np.array([0, 1, 2, 3]), np.array([9, 7, 8, 7])
    >>> sort_by_key(items, keys, 0, 4)
    >>> items.tolist(), keys.tolist()
    ([1, 3, 2, 0], [7, 7, 8, 9])
    """
    if hi - lo > 16:
        by = np.argsort(keys[lo:hi], kind="mergesort")
        items[lo:hi], keys[lo:hi] = items[lo:hi][by], keys[lo:hi][by]
        return
    for j in range(lo + 1, hi):
        item, value, i = items[j], keys[j], j
        while i > lo and keys[i - 1] > value:
            items[i], keys[i] = items[i - 1], keys[i - 1]
            i -= 1
        items[i], keys[i] = item, value


@compiled
def _root(parent, v):  # pragma: no cover - compiled
    """The root of ``v``'s tree, halving the path on the way."""
    while parent[v] != v:
        parent[v] = parent[parent[v]]
        v = parent[v]
    return v


@compiled
def _components(E, n):  # pragma: no cover - compiled
    """:func:`vertex_components`: union by the smaller root, then parts numbered in the order of their roots."""
    parent = np.arange(n)
    for e in range(E.shape[0]):
        a = _root(parent, E[e, 0])
        for c in range(1, E.shape[1]):
            b = _root(parent, E[e, c])
            if b < a:
                a, b = b, a
            parent[b] = a
    part = np.empty(n, dtype=np.int64)
    count = 0
    for v in range(n):
        root = _root(parent, v)
        if root == v:
            part[v] = count
            count += 1
        else:
            part[v] = part[root]  # a root is its part's smallest vertex: numbered already
    return count, part


@compiled
def _twins_of_pairs(F, pairs, oriented):  # pragma: no cover - compiled
    """:func:`twins_of_pairs`: a pair are twins if they run in opposite directions (``oriented``) or join two
    vertices (not a loop)."""
    twin = np.full(F.size, -1, dtype=np.int64)
    for p in range(pairs.shape[0]):
        a, b = pairs[p, 0], pairs[p, 1]
        tail_a, head_a = F[a // 3, (a + 1) % 3], F[a // 3, (a + 2) % 3]
        tail_b, head_b = F[b // 3, (b + 1) % 3], F[b // 3, (b + 2) % 3]
        if oriented:
            paired = (tail_a < head_a) != (tail_b < head_b)
        else:
            paired = tail_a != head_a
        if paired:
            twin[a], twin[b] = b, a
    return twin


@compiled
def _area(x, y, z):  # pragma: no cover - compiled
    """:func:`heatcore.domains.intrinsic.face_areas` of one triangle."""
    lo_xy, hi_xy = min(x, y), max(x, y)
    a = max(hi_xy, z)
    c = min(lo_xy, z)
    b = max(lo_xy, min(hi_xy, z))
    q = (a + (b + c)) * (c - (a - b)) * (c + (a - b)) * (a + (b - c))
    return 0.25 * np.sqrt(max(q, 0.0))


@compiled
def _cotangent(L, h):  # pragma: no cover - compiled
    """The cotangent of the corner opposite half-edge ``h``, as :func:`~heatcore.domains.intrinsic.corner_cotangents`."""
    f, c = h // 3, h % 3
    a, b, o = L[f, (c + 1) % 3], L[f, (c + 2) % 3], L[f, c]
    return (a * a + b * b - o * o) / (4.0 * _area(L[f, 0], L[f, 1], L[f, 2]))


@compiled
def _cotangent_sums(L, h, t):  # pragma: no cover - compiled
    """:func:`cotangent_sums`."""
    out = np.empty(h.size)
    for e in range(h.size):
        out[e] = _cotangent(L, h[e]) + _cotangent(L, t[e])
    return out


@compiled
def _flipped_diagonal(l_ij, l_jk, l_ki, l_il, l_lj):  # pragma: no cover - compiled
    """The intrinsic module's ``_flipped_diagonal`` for one quad: diagonal k-l of (i, l, j, k) laid out flat."""
    area_k = _area(l_ij, l_jk, l_ki)
    area_l = _area(l_ij, l_lj, l_il)
    x_k = (l_ij * l_ij + l_ki * l_ki - l_jk * l_jk) / (2.0 * l_ij)
    x_l = (l_ij * l_ij + l_il * l_il - l_lj * l_lj) / (2.0 * l_ij)
    y_k = 2.0 * area_k / l_ij
    y_l = -2.0 * area_l / l_ij
    return np.hypot(x_k - x_l, y_k - y_l)


@compiled
def _flip_pairs(F, L, twin, h0, h1):  # pragma: no cover - compiled
    """:func:`flip_pairs`: each flip reads the twins the flips before it left (a batch's flips share no face)."""
    old = np.empty(4, dtype=np.int64)
    new = np.empty(4, dtype=np.int64)
    outside = np.empty(4, dtype=np.int64)
    for e in range(h0.size):
        f0, c0, f1, c1 = h0[e] // 3, h0[e] % 3, h1[e] // 3, h1[e] % 3
        n0, p0, n1, p1 = (c0 + 1) % 3, (c0 + 2) % 3, (c1 + 1) % 3, (c1 + 2) % 3
        k, i, j, l = F[f0, c0], F[f0, n0], F[f0, p0], F[f1, c1]
        l_ij, l_jk, l_ki, l_il, l_lj = L[f0, c0], L[f0, n0], L[f0, p0], L[f1, n1], L[f1, p1]
        l_kl = _flipped_diagonal(l_ij, l_jk, l_ki, l_il, l_lj)
        # The outer edges jk, ki, il, lj: their old half-edges, and the ones they become in (l, j, k), (k, i, l).
        old[0], old[1], old[2], old[3] = 3 * f0 + n0, 3 * f0 + p0, 3 * f1 + n1, 3 * f1 + p1
        new[0], new[1], new[2], new[3] = 3 * f0, 3 * f1 + 2, 3 * f1, 3 * f0 + 2
        for q in range(4):
            outside[q] = twin[old[q]]
            for r in range(4):  # twinned with another outer edge of the same two faces: that one moves too
                if outside[q] == old[r]:
                    outside[q] = new[r]
                    break
        for q in range(4):
            twin[new[q]] = outside[q]
        for q in range(4):
            if outside[q] >= 0:
                twin[outside[q]] = new[q]
        twin[3 * f0 + 1], twin[3 * f1 + 1] = 3 * f1 + 1, 3 * f0 + 1
        F[f0, 0], F[f0, 1], F[f0, 2] = l, j, k
        F[f1, 0], F[f1, 1], F[f1, 2] = k, i, l
        L[f0, 0], L[f0, 1], L[f0, 2] = l_jk, l_kl, l_lj
        L[f1, 0], L[f1, 1], L[f1, 2] = l_il, l_kl, l_ki
