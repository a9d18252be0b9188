"""Consistently oriented normals of a point cloud: one side of the surface is "out" everywhere.

PCA normals have no sign. Signed quantities (the signed heat method's left of
a curve) need one: the signs are propagated along a minimum spanning tree of
the neighbour graph weighted by ``1 - |n_i . n_j|`` (Hoppe et al. 1992: flat
neighbourhoods first, so that a sign crosses sharp folds last), and each
connected part is then turned so that its normals point away from its
centroid on the whole (outwards on a closed surface); a flat part, whose
normals have no such preference, points towards the positive side of the
axis its normals follow most.

Examples
--------
>>> import numpy as np
>>> P = np.column_stack([np.random.default_rng(0).random((50, 2)), np.zeros(50)])
>>> N = np.tile([0.0, 0.0, 1.0], (50, 1)) * np.where(np.arange(50) % 2, 1.0, -1.0)[:, None]
>>> np.unique(oriented_normals(P, N, 8)[:, 2]).tolist()   # a flat part: along +z
[1.0]
"""

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import (
    breadth_first_order,
    connected_components,
    minimum_spanning_tree,
)
from scipy.spatial import cKDTree

#: A part whose normals' mean outward component is below this (times its extent) counts as flat.
FLAT_TOLERANCE = 1e-6


def oriented_normals(P, N, k):
    """``N`` (unit normals of the points ``P``) with signs flipped so that neighbours agree, outwards per part.

    Parameters
    ----------
    P : (n, 3) float array
    N : (n, 3) float array
        Unit normals, any signs.
    k : int
        Neighbours per point in the graph the signs travel along.

    Returns
    -------
    (n, 3) float array

    Examples
    --------
    >>> rng = np.random.default_rng(1)
    >>> P = rng.normal(size=(400, 3))
    >>> P /= np.linalg.norm(P, axis=1)[:, None]
    >>> N = P * rng.choice([-1.0, 1.0], size=(400, 1))   # a sphere's normals, random signs
    >>> bool(np.allclose(oriented_normals(P, N, 8), P))   # outwards
    True
    """
    n = P.shape[0]
    k = int(min(k, n - 1))
    _, near = cKDTree(P).query(P, k + 1)
    rows, cols = np.repeat(np.arange(n), k), near[:, 1:].ravel()
    keep = cols < n
    rows, cols = rows[keep], cols[keep]
    weight = 1.0 - np.abs(np.einsum("ij,ij->i", N[rows], N[cols])) + 1e-9  # no zero weight: an edge stays an edge
    graph = sp.csr_matrix((weight, (rows, cols)), shape=(n, n))
    tree = minimum_spanning_tree(graph.maximum(graph.T))
    tree = tree + tree.T
    out = N.copy()
    n_parts, part = connected_components(tree, directed=False)
    for p in range(n_parts):
        root = int(np.flatnonzero(part == p)[0])
        order, parent = breadth_first_order(tree, root, directed=False)
        sign = np.ones(n)
        for v in order[1:].tolist():  # parents come first in breadth-first order
            sign[v] = sign[parent[v]] * (1.0 if N[v] @ N[parent[v]] >= 0 else -1.0)
        out[order] = N[order] * sign[order, None]
        out[order] *= _outwards(P[order], out[order])
    return out


def _outwards(P, N):
    """+1 or -1: the sign that turns a part's normals away from its centroid (or along its main axis, if flat)."""
    lean = np.einsum("ij,ij->", N, P - P.mean(axis=0))
    extent = float(np.ptp(P, axis=0).max()) * len(P)
    if abs(lean) > FLAT_TOLERANCE * max(extent, 1e-300):
        return 1.0 if lean > 0 else -1.0
    axis = int(np.argmax(np.abs(N).sum(axis=0)))
    return 1.0 if N[:, axis].sum() >= 0 else -1.0
