"""Mesh edges along a geodesic path: the shortest chain of edges among the faces the path crosses.

A geodesic path runs across faces; a front end that selects mesh edges (a
seam, a cut) wants a chain of the mesh's own edges that follows it.
:func:`edge_chain` gives the shortest chain (by edge length) from the source
vertex to the target vertex that uses only the vertices of the faces the path
crosses (the caller passes them: the polygons' vertices when the faces are a
polygon mesh's triangles, so that a chain never takes a diagonal that is not
an edge). Those faces form a connected strip holding both ends, so the chain
stays within one face of the path; where the path runs along edges (through
vertices) the chain is those edges.

Examples
--------
>>> import numpy as np
>>> V = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0], [1, 1, 0], [2, 1, 0]], float)
>>> E = [[0, 1], [1, 2], [3, 4], [4, 5], [0, 3], [1, 4], [2, 5], [0, 4]]
>>> vertices, edges = edge_chain(V, E, [0, 1, 2, 3, 4, 5], 0, 5)
>>> vertices.tolist(), edges.tolist()
([0, 4, 5], [7, 3])
"""

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra


def edge_chain(positions, edges, allowed, source, target):
    """The shortest chain of ``edges`` from vertex ``source`` to vertex ``target`` through ``allowed`` vertices only.

    Parameters
    ----------
    positions : (n, 3) array_like
        Vertex positions (the edge lengths are the weights).
    edges : (m, 2) array_like of int
        The mesh's edges (each once, either direction).
    allowed : array_like of int
        The vertices the chain may use (``source`` and ``target`` always may),
        e.g. the vertices of the faces a :class:`~heatcore.GeodesicPath` crosses.
    source, target : int

    Returns
    -------
    vertices : (k,) int array
        The chain's vertices from ``source`` to ``target`` (``[source]`` when
        they are the same; empty when no chain through ``allowed`` joins them).
    edge_ids : (k - 1,) int array
        The row of ``edges`` of each step.

    Examples
    --------
    >>> import numpy as np
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [1, 1, 0]], float)
    >>> E = [[0, 1], [1, 2], [0, 3], [3, 2]]
    >>> [a.tolist() for a in edge_chain(V, E, [1], 0, 2)]  # not through 3
    [[0, 1, 2], [0, 1]]
    >>> [a.tolist() for a in edge_chain(V, E, [], 0, 2)]  # no chain through the allowed vertices
    [[], []]
    """
    V = np.asarray(positions, dtype=np.float64).reshape(-1, 3)
    E = np.asarray(edges, dtype=np.int64).reshape(-1, 2)
    n = len(V)
    if source == target:
        return np.array([source], dtype=np.int64), np.zeros(0, dtype=np.int64)
    keep = np.zeros(n, dtype=bool)
    keep[np.asarray(allowed, dtype=np.int64).ravel()] = True
    keep[[source, target]] = True
    rows = np.flatnonzero(keep[E].all(axis=1) & (E[:, 0] != E[:, 1]))
    a, b = E[rows].T
    # Zero-length edges still join: a tiny weight, never an explicit zero (no edge to the graph routines).
    weight = np.linalg.norm(V[a] - V[b], axis=1) + 1e-300
    graph = coo_matrix((weight, (a, b)), shape=(n, n)).tocsr()
    dist, pred = dijkstra(graph, directed=False, indices=int(source), return_predecessors=True)
    if not np.isfinite(dist[target]):
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    chain = [int(target)]
    while chain[-1] != source:  # the chain's length, not the mesh's size
        chain.append(int(pred[chain[-1]]))
    chain = np.array(chain[::-1], dtype=np.int64)
    # The edge row of each step: sorted pairs looked up among the kept edges' sorted pairs.
    keys = np.sort(E[rows], axis=1) @ np.array([n, 1])
    order = np.argsort(keys)
    steps = np.sort(np.column_stack([chain[:-1], chain[1:]]), axis=1) @ np.array([n, 1])
    return chain, rows[order[np.searchsorted(keys, steps, sorter=order)]]
