"""Point neighborhoods: duplicates merged, k nearest neighbors within the local spacing, PCA normals.

Examples
--------
>>> import numpy as np
>>> rng = np.random.default_rng(0)
>>> P = np.column_stack([rng.random((200, 2)), np.zeros(200)])
>>> point_map, distinct = merge_duplicates(P)
>>> nbr, dist = nearest_neighbors(distinct, 8)
>>> float(np.abs(pca_normals(distinct, nbr)[:, 2]).round(6).min())
1.0
"""

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

#: Neighbors farther than this many times the local spacing are not neighbors (of the local triangles,
#: the normals). Measured on the shared meshes' clouds: 2 against 3 before, clean clouds 0.00-0.30 points
#: closer to exact, holed ones too (homer 7.21% against 7.91%), nonuniform ones 0.1-0.4 points closer, mild
#: noise (0.1 h) 0.1-0.3 points further (docs/pointcloud.md).
MAX_NEIGHBOR_RATIO = 2.0
#: A point with no neighbor within this many times the spacing is isolated (``inf``); one with such a
#: neighbor but in no local triangle hangs on the surface by one (``local_delaunay.attach_left_out``).
MAX_ATTACH_RATIO = 3.0
#: The local spacing of a point: distance to its ``SPACING_RANK``-th neighbor.
SPACING_RANK = 6
#: Points closer than this fraction of the bounding-box diagonal are merged.
DUPLICATE_TOLERANCE = 1e-9


def merge_duplicates(P):
    """Map each point to a representative of the points within a tiny distance of it.

    Points closer than ``DUPLICATE_TOLERANCE`` times the bounding-box
    diagonal (and chains of such points) become one distinct point.

    Parameters
    ----------
    P : (n, 3) float array

    Returns
    -------
    point_map : (n,) int array
        Distinct point of each input point.
    distinct : (n', 3) float array
        The distinct points, in order of first appearance (each the first of its copies).

    Examples
    --------
    >>> import numpy as np
    >>> point_map, distinct = merge_duplicates(np.array([[0, 0, 0], [1, 0, 0], [0, 0, 0.0]]))
    >>> point_map.tolist(), distinct.shape
    ([0, 1, 0], (2, 3))
    """
    diag = float(np.linalg.norm(P.max(axis=0) - P.min(axis=0)))
    pairs = cKDTree(P).query_pairs(DUPLICATE_TOLERANCE * diag, output_type="ndarray") if diag > 0 else None
    n = P.shape[0]
    if diag == 0:
        return np.zeros(n, dtype=np.int64), P[:1]
    if pairs.shape[0] == 0:
        return np.arange(n, dtype=np.int64), P

    graph = sp.coo_matrix((np.ones(pairs.shape[0]), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    first = np.full(label.max() + 1, n, dtype=np.int64)
    np.minimum.at(first, label, np.arange(n))
    # distinct points in order of first appearance
    order = np.argsort(first)
    rank = np.empty_like(order)
    rank[order] = np.arange(order.size)
    return rank[label], P[first[order]]


def nearest_neighbors(P, k, ratio=None):
    """k nearest neighbors (self excluded), -1 where a neighbor is too far to count.

    A neighbor ``j`` of ``i`` is kept when ``|p_i - p_j| <= MAX_NEIGHBOR_RATIO
    * min(s_i, s_j)``, with ``s`` the distance to the ``SPACING_RANK``-th
    neighbor: clusters and isolated points stay apart (the far side's
    spacing is small), while density changes of a few times are kept.

    Parameters
    ----------
    P : (n, 3) float array, distinct points
    k : int, at most ``n - 1``
    ratio : float, optional
        ``MAX_NEIGHBOR_RATIO`` by default.

    Returns
    -------
    nbr : (n, k) int array
        Neighbor indices, nearest first; -1 for a neighbor too far away.
    dist : (n, k) float array
        Their distances (of the k nearest, kept or not).

    Examples
    --------
    >>> import numpy as np
    >>> line = np.column_stack([np.r_[np.arange(8.0), 100.0], np.zeros(9), np.zeros(9)])
    >>> nbr, dist = nearest_neighbors(line, 6)
    >>> nbr[0].tolist(), int((nbr[8] >= 0).sum())  # the far point has no neighbor
    ([1, 2, 3, 4, 5, 6], 0)
    """
    dist, idx = cKDTree(P).query(P, k + 1, workers=-1)  # every core: the same result
    dist, idx = dist[:, 1:], idx[:, 1:]
    return within_ratio(idx, dist, MAX_NEIGHBOR_RATIO if ratio is None else ratio), dist


def within_ratio(nbr, dist, ratio):
    """``nbr`` with ``-1`` for each neighbor farther than ``ratio`` times the smaller of the two spacings.

    Examples
    --------
    >>> line = np.column_stack([np.r_[np.arange(8.0), 100.0], np.zeros(9), np.zeros(9)])
    >>> nbr, dist = nearest_neighbors(line, 6, ratio=np.inf)
    >>> int((nbr[8] >= 0).sum()), int((within_ratio(nbr, dist, 3.0)[8] >= 0).sum())
    (6, 0)
    """
    spacing = dist[:, min(SPACING_RANK, nbr.shape[1]) - 1]
    far = (nbr < 0) | (dist > ratio * np.minimum(spacing[:, None], spacing[np.maximum(nbr, 0)]))
    return np.where(far, -1, nbr)


def pca_normals(P, nbr):
    """Unit normal of each point: least-variance direction of its neighborhood.

    Parameters
    ----------
    P : (n, 3) float array
    nbr : (n, k) int array, neighbor indices (-1 for none)

    Returns
    -------
    (n, 3) float array (sign arbitrary)

    Examples
    --------
    >>> import numpy as np
    >>> g = np.stack(np.meshgrid(np.arange(4.0), np.arange(4.0)), -1).reshape(-1, 2)
    >>> P = np.column_stack([g, g[:, 0] + g[:, 1]])  # the plane z = x + y
    >>> n = pca_normals(P, nearest_neighbors(P, 6)[0])
    >>> bool(np.allclose(np.abs(n @ [1, 1, -1]), np.sqrt(3)))
    True
    """
    valid = nbr >= 0
    Q = np.where(valid[..., None], P[np.maximum(nbr, 0)], 0.0)
    count = valid.sum(axis=1) + 1
    mean = (Q.sum(axis=1) + P) / count[:, None]
    D = np.where(valid[..., None], Q - mean[:, None], 0.0)
    C = np.einsum("nki,nkj->nij", D, D) + np.einsum("ni,nj->nij", P - mean, P - mean)
    _, vec = np.linalg.eigh(C)
    return vec[:, :, 0]
