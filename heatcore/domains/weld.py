"""Welding: vertices at the same position become one.

STL files are triangle soup (every triangle has its own three vertices), and
OBJ files split vertices along texture seams. Read as they are, such a mesh
falls apart into thousands of one-triangle parts and the distance is ``inf``
almost everywhere. Welding finds the vertices that sit at the same position
(exactly, or within a tolerance) and lets each group stand for one vertex; the
distances are still reported at every vertex of the file.

Examples
--------
>>> import numpy as np
>>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)
>>> representative, n_welded = weld_map(V)
>>> representative.tolist(), n_welded
([0, 1, 2, 1, 4, 2], 2)
"""

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components


def weld_map(V, tolerance=0.0):
    """The vertex that stands for each vertex once coincident vertices are merged.

    Parameters
    ----------
    V : (n, 3) float array
    tolerance : float, default 0.0
        Vertices closer than this (Euclidean distance, in the mesh's units)
        are merged, and so are chains of such vertices; 0 merges only
        vertices at exactly the same position.

    Returns
    -------
    representative : (n,) int array
        The smallest index of each vertex's group (itself if it has no twin).
    n_welded : int
        Vertices merged into another one.

    Examples
    --------
    >>> V = np.array([[0, 0, 0], [1e-9, 0, 0], [1, 0, 0]])
    >>> weld_map(V, 1e-6)[0].tolist()
    [0, 0, 2]
    """
    n = V.shape[0]
    if tolerance > 0:
        from scipy.spatial import cKDTree

        pairs = cKDTree(V).query_pairs(tolerance, output_type="ndarray")
        graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
        _, group = connected_components(graph, directed=False)
        first = np.unique(group, return_index=True)[1]
    else:
        rows = np.ascontiguousarray(V + 0.0, dtype=np.float64)  # + 0.0 turns -0.0 into 0.0
        if not _may_repeat(rows):  # most meshes: no sort of the rows (800k vertices: 0.05 s against 0.27 s)
            return np.arange(n), 0
        keys = rows.view(np.dtype((np.void, rows.itemsize * rows.shape[1]))).ravel()
        _, first, group = np.unique(keys, return_index=True, return_inverse=True)
    representative = first[group.ravel()]  # the smallest index of each group
    return representative, int(n - first.size)


def _may_repeat(rows):
    """False where no two rows of a float64 array are equal; True where two may be.

    Equal rows have equal hashes of their bits, so sorted hashes with no
    repeat prove the rows distinct; a repeated hash (equal rows, or rarely
    two rows that collide) sends the caller to the exact comparison.

    Examples
    --------
    >>> _may_repeat(np.array([[0.0, 1.0], [1.0, 0.0]])), _may_repeat(np.array([[1.0, 2.0], [1.0, 2.0]]))
    (False, True)
    """
    bits = rows.view(np.uint64)
    hashes = np.zeros(len(bits), dtype=np.uint64)
    for column in bits.T:  # a multiply-xorshift chain over the columns (unsigned: wraps, no warning)
        hashes = (hashes ^ column) * np.uint64(0x9E3779B97F4A7C15)
        hashes ^= hashes >> np.uint64(29)
    hashes.sort()
    return bool((hashes[1:] == hashes[:-1]).any())
