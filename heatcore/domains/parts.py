"""Connected parts of a domain, and the length unit each part is solved in.

Every connected part of a mesh is solved as if it were alone: it gets its own
time step, refinement level, mollification and underflow guard, and its own
length unit. A part whose coordinates are of ordinary size (largest absolute
coordinate between ``2**-UNIT_RANGE`` and ``2**UNIT_RANGE``) keeps the input's
unit. A part beyond that (scaled by 1e-60 or 1e100, say) is measured in the
power of two that brings its largest coordinate into ``[0.5, 1)``: its squared
lengths, areas and heat would underflow or overflow otherwise. Multiplying by
a power of two changes no digit of a floating-point number, so the distances
are exactly those of the same part at an ordinary size, times the scale.

Examples
--------
>>> import numpy as np
>>> F = np.array([[0, 1, 2], [3, 4, 5]])
>>> count, part = vertex_components(F, 6)
>>> count, part.tolist()
(2, [0, 0, 0, 1, 1, 1])
>>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]] + [[0, 0, 0], [3e-80, 0, 0], [0, 3e-80, 0]], float)
>>> unit_exponents(V, part, count).tolist()
[0, -264]
"""

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import breadth_first_order, connected_components, dijkstra

from ..compiled import use_build_kernels

#: Parts whose largest absolute coordinate lies within ``2**-UNIT_RANGE`` ..
#: ``2**UNIT_RANGE`` keep the input's unit: their squared lengths, areas and
#: heat are far from underflow and overflow.
UNIT_RANGE = 64


def vertex_graph(elements, n):
    """Symmetric sparse adjacency of the vertex graph induced by the elements (a star per element).

    Parameters
    ----------
    elements : (m, k) int array
    n : int

    Returns
    -------
    (n, n) scipy.sparse.csr_matrix

    Examples
    --------
    >>> vertex_graph(np.array([[0, 1, 2]]), 4).nnz
    4
    """
    k = elements.shape[1]
    rows = np.repeat(elements[:, 0], k - 1)
    cols = elements[:, 1:].ravel()
    graph = sp.coo_matrix((np.ones(rows.size), (rows, cols)), shape=(n, n)).tocsr()
    return (graph + graph.T).tocsr()


def edge_graph(elements, n):
    """Symmetric sparse adjacency joining every two corners of each element (a triangle's three sides).

    Unlike :func:`vertex_graph` (a star from each element's first corner), it
    does not depend on which corner an element lists first, so two meshes of
    the same triangles, their corners in another order, get the same graph.

    Parameters
    ----------
    elements : (m, k) int array
    n : int

    Returns
    -------
    (n, n) scipy.sparse.csr_matrix

    Examples
    --------
    >>> edge_graph(np.array([[0, 1, 2]]), 4).nnz
    6
    """
    k = elements.shape[1]
    a, b = np.triu_indices(k, 1)
    graph = sp.coo_matrix((np.ones(a.size * elements.shape[0]), (elements[:, a].ravel(), elements[:, b].ravel())),
                          shape=(n, n)).tocsr()
    return (graph + graph.T).tocsr()


def vertex_components(elements, n, graph=None):
    """Connected components of the vertex graph of ``elements``.

    Parameters
    ----------
    elements : (m, k) int array
    n : int
        Number of vertices.
    graph : sparse matrix, optional
        A graph of the elements' vertices with these components (:func:`vertex_graph`, :func:`edge_graph`),
        if already built.

    Returns
    -------
    count : int
    part : (n,) int array, the component of each vertex (a vertex in no element is a part of its own)

    Examples
    --------
    >>> vertex_components(np.array([[0, 1, 2]]), 4)[0]
    2
    """
    if graph is None and use_build_kernels(elements.shape[0]):  # a large mesh: compiled, the same parts
        from .build_kernels import vertex_components as compiled_components

        return compiled_components(elements, n)
    if graph is None:  # vertices, then one node per element joined to its corners: a CSR graph with no sorting
        m, k = elements.shape
        indptr = np.concatenate([np.zeros(n + 1, dtype=np.int64), np.arange(k, k * m + 1, k)])
        graph = sp.csr_matrix((np.ones(k * m), elements.ravel(), indptr), shape=(n + m, n + m))
    # Each part is numbered by its smallest vertex, whatever graph joins them (an element node is never alone).
    count, part = connected_components(graph, directed=True, connection="weak")
    return int(count), part[:n].copy()


def elements_in_parts_of(n, owner, corners, vertices):
    """Which elements lie in a connected part that holds one of ``vertices``.

    Parts are those of the vertex graph of the elements (an element joins
    all its corners). Used to build only the parts a one-off query's sources
    are on.

    Parameters
    ----------
    n : int
        Number of vertices.
    owner, corners : (c,) int arrays
        The element and the vertex of each corner (triangles:
        ``np.repeat(np.arange(m), 3)`` and ``F.ravel()``).
    vertices : (j,) int array
        Vertex indices (below ``n``).

    Returns
    -------
    inside : (m,) bool array, ``m = owner.max() + 1``
    left_out : int
        The parts of the other elements.

    Examples
    --------
    >>> F = np.array([[0, 1, 2], [3, 4, 5], [2, 6, 7]])
    >>> inside, left_out = elements_in_parts_of(8, np.repeat(np.arange(3), 3), F.ravel(), np.array([7]))
    >>> inside.tolist(), left_out
    ([True, False, True], 1)
    """
    m = int(owner.max(initial=-1)) + 1
    # a graph of vertices (0 .. n-1) and elements (n .. n+m-1): each corner joins its vertex to its element
    graph = sp.coo_matrix((np.ones(corners.size), (corners, n + owner)), shape=(n + m, n + m))
    _, part = connected_components(graph, directed=True, connection="weak")
    holding = np.zeros(part.max(initial=0) + 1, dtype=bool)
    holding[part[vertices]] = True
    inside = holding[part[n:]]
    return inside, int(np.unique(part[n:][~inside]).size)


def unit_exponents(V, part, count, unit_range=UNIT_RANGE):
    """Per part, the power of two of its length unit (0: the input's unit).

    A part whose largest absolute coordinate is beyond ``2**unit_range`` (or
    below ``2**-unit_range``) gets the power of two that brings it into
    ``[0.5, 1)``; the others keep the input's unit. A part's coordinates in
    its own unit are ``np.ldexp(V, -exponent)``; lengths measured there are
    converted back with ``np.ldexp(length, exponent)``.

    Parameters
    ----------
    V : (n, d) float array
    part : (n,) int array, part of each vertex
    count : int, number of parts

    Returns
    -------
    (count,) int array; 0 for a part whose coordinates are all zero

    Examples
    --------
    >>> unit_exponents(np.array([[3.0, 0, 0], [1e-30, 0, 0]]), np.array([0, 1]), 2).tolist()
    [0, -99]
    """
    largest = np.maximum(part_extremes(row_reduce(np.maximum, np.abs(V)), part, count, largest=True), 0.0)
    exponent = np.frexp(largest)[1].astype(np.int64)
    exponent[np.abs(exponent) <= unit_range] = 0
    return exponent


def in_part_units(V, part, exponents):
    """Coordinates of each vertex in its part's unit (exact: a power-of-two scaling).

    Examples
    --------
    >>> in_part_units(np.array([[3.0, 1.0, 0.0]]), np.array([0]), np.array([2])).tolist()
    [[0.75, 0.25, 0.0]]
    """
    if not exponents.any():
        return V
    return np.ldexp(V, -exponents[part][:, None])


def part_extremes(values, part, count, largest=False):
    """Smallest (or largest) of ``values`` over each part; ``inf`` (``-inf``) for a part without values.

    Faster than ``np.minimum.at`` (one sort; no sort at all for one part).

    Examples
    --------
    >>> part_extremes(np.array([4.0, 3.0, 5.0]), np.array([0, 0, 1]), 3).tolist()
    [3.0, 5.0, inf]
    >>> part_extremes(np.array([4.0, 3.0, 5.0]), np.array([0, 0, 1]), 2, largest=True).tolist()
    [4.0, 5.0]
    """
    reduce, empty = (np.maximum, -np.inf) if largest else (np.minimum, np.inf)
    out = np.full(count, empty)
    if values.size == 0:
        return out
    if count == 1:
        out[0] = values.max() if largest else values.min()
        return out
    order = np.argsort(part, kind="stable")
    starts = np.searchsorted(part[order], np.arange(count))
    present = np.bincount(part, minlength=count) > 0
    out[present] = reduce.reduceat(values[order], starts[present])
    return out


def first_of_each(part, count):
    """The smallest index of each part (every part must occur).

    Examples
    --------
    >>> first_of_each(np.array([1, 0, 1, 2]), 3).tolist()
    [1, 0, 3]
    """
    return np.unique(part, return_index=True)[1][:count].astype(np.int64)


def part_means(values, part, count):
    """Mean of ``values`` over each part (``nan`` for a part without values).

    Examples
    --------
    >>> part_means(np.array([1.0, 3.0, 5.0]), np.array([0, 0, 1]), 2).tolist()
    [2.0, 5.0]
    """
    if count == 1:  # numpy's pairwise summation: the rounding of a plain mean
        return np.array([values.mean()])
    total = np.bincount(part, weights=values, minlength=count)
    with np.errstate(invalid="ignore", divide="ignore"):
        return total / np.bincount(part, minlength=count)


def hop_diameters(graph, part, count, bounds=False, first_sweep=None):
    """Edge hops across each part (double-sweep breadth-first estimate, exact on trees and paths).

    Both sweeps start from one vertex per part at once, so the cost does not
    grow with the number of parts.

    Parameters
    ----------
    graph : (n, n) symmetric sparse matrix
    part : (n,) int array
    count : int
    bounds : bool, default False
        Return upper bounds from the first sweep alone (twice each part's
        depth from its first vertex, at least the diameter), for half the work.
    first_sweep : (n,) float array, optional
        The first sweep (:func:`hop_sweep`), where it was made already (for
        the bounds): the estimate then makes only the second.

    Returns
    -------
    (count,) int array

    Examples
    --------
    >>> path = vertex_graph(np.array([[0, 1], [1, 2], [3, 4]]), 5)
    >>> hop_diameters(path, np.array([0, 0, 0, 1, 1]), 2).tolist()
    [2, 1]
    >>> hop_diameters(path, np.array([0, 0, 0, 1, 1]), 2, bounds=True).tolist()
    [4, 2]
    """
    hops = hop_sweep(graph, part, count) if first_sweep is None else first_sweep
    depth = part_extremes(hops, part, count, largest=True)
    if bounds:
        return 2 * depth.astype(np.int64)
    far = np.flatnonzero(hops == depth[part])
    far = far[np.unique(part[far], return_index=True)[1]]  # one farthest vertex per part
    return part_extremes(_hops_from(graph, far), part, count, largest=True).astype(np.int64)


#: Up to this many roots, :func:`_hops_from` searches from each in turn; more, from all at once.
FEW_ROOTS = 16


def hop_sweep(graph, part, count):
    """Edge hops from each part's first vertex to every vertex of the part: :func:`hop_diameters`' first sweep.

    Examples
    --------
    >>> path = vertex_graph(np.array([[0, 1], [1, 2], [3, 4]]), 5)
    >>> hop_sweep(path, np.array([0, 0, 0, 1, 1]), 2).tolist()
    [0.0, 1.0, 2.0, 0.0, 1.0]
    """
    return _hops_from(graph, first_of_each(part, count))


def _hops_from(graph, roots):
    """Edge hops from the nearest root to every vertex (``inf`` where none reaches).

    A few roots (one per part of a model of a few parts): a breadth-first
    search from each, its depths by pointer jumping up the search tree (800k
    vertices: 0.06 s against 0.14 s for Dijkstra's unweighted search; 504k
    vertices in 3 parts: 0.04 s against 0.10 s). Many roots: one Dijkstra
    search from all at once (each search costs a pass over every vertex).

    Examples
    --------
    >>> path = vertex_graph(np.array([[0, 1], [1, 2], [3, 4]]), 5)
    >>> _hops_from(path, np.array([0])).tolist(), _hops_from(path, np.array([0, 4])).tolist()
    ([0.0, 1.0, 2.0, inf, inf], [0.0, 1.0, 2.0, 1.0, 0.0])
    >>> _hops_from(path, np.array([0, 2])).tolist()  # two roots in one part: the nearest
    [0.0, 1.0, 0.0, inf, inf]
    """
    if roots.size > FEW_ROOTS:
        return dijkstra(graph, directed=True, indices=roots, unweighted=True, min_only=True)
    hops = np.full(graph.shape[0], np.inf)
    for root in roots:
        order, depth = _search_depths(graph, int(root))
        np.minimum(hops[order], depth, out=depth)
        hops[order] = depth
    return hops


def _search_depths(graph, root):
    """The vertices a breadth-first search from ``root`` reaches, in its order, and their hops from it."""
    order, up = breadth_first_order(graph, root, directed=True, return_predecessors=True)
    up[order[0]] = order[0]  # the root is its own parent; unreached vertices are not in ``order``
    depth = np.ones(order.size, dtype=np.int64)
    depth[0] = 0
    up = up[order]  # parents, of the reached vertices in search order
    rank = np.empty(graph.shape[0], dtype=np.int64)
    rank[order] = np.arange(order.size)
    up = rank[up]  # ... as positions in ``order``
    while (up != 0).any():  # pointer jumping: ``depth`` counts the hops to ``up``; each step doubles the span
        depth += depth[up]  # the root's depth is 0: nothing is added past it
        up = up[up]
    return order, depth.astype(float)


def row_reduce(ufunc, a):
    """``ufunc.reduce(a, axis=1)`` for an ``(m, k)`` array of a few columns, column by column: the same
    numbers (for ``np.minimum``, ``np.maximum``, ``np.logical_and``...), over 10x faster on rows of 3.

    Examples
    --------
    >>> row_reduce(np.minimum, np.array([[3.0, 1.0, 2.0], [0.0, 5.0, 4.0]])).tolist()
    [1.0, 0.0]
    """
    if a.shape[1] == 1:
        return a[:, 0].copy()
    out = ufunc(a[:, 0], a[:, 1])
    for j in range(2, a.shape[1]):
        ufunc(out, a[:, j], out=out)
    return out


def row_norms(D):
    """Euclidean norms of the rows of ``D`` at any finite scale (no overflow at 1e300, no underflow at 1e-300).

    Rows whose largest entry lies outside 1e-150 .. 1e150 are divided by a power of two near it
    before squaring; the others are squared as they are.

    Examples
    --------
    >>> norms = row_norms(np.array([[3e-300, 4e-300, 0.0], [3e300, 4e300, 0.0], [0.0, 0.0, 0.0]]))
    >>> bool(np.allclose(norms, [5e-300, 5e300, 0.0], rtol=1e-15, atol=0))
    True
    """
    D = np.asarray(D, dtype=float).reshape(-1, np.shape(D)[-1])
    norms = np.sqrt(np.einsum("ij,ij->i", D, D))
    largest = row_reduce(np.maximum, np.abs(D))
    odd = np.flatnonzero(~((largest > 1e-150) & (largest < 1e150)))  # squares that would under- or overflow
    if odd.size:
        exponent = np.frexp(np.where(largest[odd] > 0, largest[odd], 1.0))[1]
        norms[odd] = np.ldexp(np.linalg.norm(np.ldexp(D[odd], -exponent[:, None]), axis=1), exponent)
    return norms
