"""Midpoint (1-to-4) subdivision that keeps the surface and remembers where new vertices lie.

Splitting every triangle at its edge midpoints leaves the surface and the
original vertices unchanged, so distances computed on the refined mesh are
read back at the original vertices. Each new vertex records the original edge
it lies on (or ``-1``) and the original face it lies in (or ``-1``), so that
region and surface-point sources can be carried to the refined mesh.

Examples
--------
>>> import numpy as np
>>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
>>> sub = midpoint_subdivide(V, np.array([[0, 1, 2]]), levels=1)
>>> sub.vertices.shape, sub.faces.shape
((6, 3), (4, 3))
"""

from dataclasses import dataclass

import numpy as np

from ..compiled import use_build_kernels

#: ``refine="auto"`` subdivides meshes with fewer vertices than this. On
#: coarser meshes one level of midpoint subdivision is cheap and lowers the
#: heat method's error markedly (measured: spot 2.1% -> 1.2%, homer 2.2% ->
#: 1.5%, see docs/accuracy.md); finer meshes are accurate without it.
AUTO_REFINE_MIN_VERTICES = 11000

#: ``refine="auto"`` refines each part on its own, but all parts together to at
#: most this many vertices: a soup of thousands of loose triangles (or
#: thousands of small parts) would otherwise grow to tens of millions. Past it
#: every part is refined to at most the same, smaller, number of levels.
AUTO_REFINE_BUDGET = 1_000_000


def refined_size(n_vertices, levels):
    """Vertex count of a closed part of ``n_vertices`` vertices after ``levels`` midpoint subdivisions (about).

    Examples
    --------
    >>> refined_size(np.array([2930, 3]), np.array([1, 2])).tolist()
    [11714, 18]
    """
    n = np.array(n_vertices, dtype=np.int64)
    for level in range(int(np.max(levels, initial=0))):
        n = np.where(level < levels, np.where(n > 3, 4 * n - 6, 2 * n), n)
    return n


def budgeted_levels(n_vertices, levels, budget=AUTO_REFINE_BUDGET):
    """``levels`` per part, capped alike where all parts together would pass ``budget`` vertices.

    Returns
    -------
    levels : (k,) int array
    cap : int or None
        The cap applied (None when the budget holds).

    Examples
    --------
    >>> budgeted_levels(np.full(1000, 3), np.full(1000, 7))
    (array([4, 4, 4, ..., 4, 4, 4]), 4)
    """
    cap = int(np.max(levels, initial=0))
    if refined_size(n_vertices, levels).sum() <= budget:
        return levels, None
    while cap > 0 and refined_size(n_vertices, np.minimum(levels, cap)).sum() > budget:
        cap -= 1
    return np.minimum(levels, cap), cap


def auto_refine_levels(n_vertices, min_vertices=AUTO_REFINE_MIN_VERTICES):
    """Midpoint subdivision levels that bring a mesh (or each part) to at least ``min_vertices`` vertices.

    Each level multiplies the vertex count by about four.

    Parameters
    ----------
    n_vertices : int or (k,) int array

    Returns
    -------
    int, or (k,) int array

    Examples
    --------
    >>> auto_refine_levels(2930), auto_refine_levels(np.array([3, 50_000])).tolist()
    (1, [7, 0])
    """
    n = np.array(n_vertices, dtype=np.int64)
    levels = np.zeros_like(n)
    while (refined_size(n, levels) < min_vertices).any():
        levels += refined_size(n, levels) < min_vertices
    return int(levels) if levels.ndim == 0 else levels


def work_ahead(faces, n_vertices, refine="auto", only_parts_of=None):
    """The work a triangle mesh's build has ahead: about how many vertices its solver gets, and its parts.

    Each connected part of ``faces`` is refined as ``TriangleMesh(refine=...)``
    refines it (``"auto"``: :func:`auto_refine_levels` under
    :data:`AUTO_REFINE_BUDGET`), so a mesh of many small parts counts the
    vertices it will have, not the ones it has. Parts are those of the faces
    as given: before welding, so a triangle soup (an STL file) counts more
    parts, and vertices, than its welded build (an upper bound).

    Parameters
    ----------
    faces : (m, 3) int array
    n_vertices : int
    refine : "auto" or int, default "auto"
    only_parts_of : sequence of int, optional
        Only the parts holding these vertices count (a one-off query's build).

    Returns
    -------
    (int, int)
        Solver vertices (about) and parts.

    Examples
    --------
    >>> F = np.array([[0, 1, 2], [3, 4, 5]])
    >>> work_ahead(F, 6, refine=0), work_ahead(F, 6, refine=1), work_ahead(F, 6, only_parts_of=[0])
    ((6, 2), (12, 2), (16386, 1))
    >>> work_ahead([[0, 1, 99]], 6)  # faces that do not fit: the file's count (the build refuses them)
    (6, 1)
    """
    from .parts import vertex_components

    faces = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    n_vertices = int(n_vertices)
    if faces.size and (faces.min() < 0 or faces.max() >= n_vertices):  # the build will say what is wrong
        return n_vertices, 1
    count, part = vertex_components(faces, n_vertices)
    used = np.zeros(int(n_vertices), dtype=bool)
    used[faces.ravel()] = True
    sizes = np.bincount(part[used], minlength=count)
    keep = sizes > 0
    if only_parts_of is not None:
        holding = np.zeros(count, dtype=bool)
        given = np.asarray(only_parts_of, dtype=np.int64).ravel()
        holding[part[given[(given >= 0) & (given < n_vertices)]]] = True
        keep &= holding
    sizes = sizes[keep]
    if refine == "auto":
        levels = budgeted_levels(sizes, auto_refine_levels(sizes))[0]
    else:
        levels = np.full(sizes.size, int(refine), dtype=np.int64)
    return int(refined_size(sizes, levels).sum()), int(sizes.size)


@dataclass
class Subdivision:
    """Result of :func:`midpoint_subdivide`.

    Attributes
    ----------
    vertices : (n', 3) float array; the first ``n`` rows are the input vertices.
    faces : (m', 3) int array
    edges : (k, 2) int array, the unique edges of the input mesh (sorted pairs).
    vertex_edge : (n',) int array, input edge a vertex lies on, or -1.
    vertex_face : (n',) int array, input face a vertex lies strictly inside, or -1.
    mesh_edges : (k', 2) int array, the unique edges of the subdivided mesh.
    side_edge : (m', 3) int array, edge id (into ``mesh_edges``) of each face side.
    side_pairs : (p, 2) int array or None, the two sides (half-edges ``3 f + c``) of each subdivided edge
        that has exactly two, as :func:`unique_edges` gives them (None where it did not).

    Examples
    --------
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    >>> sub = midpoint_subdivide(V, np.array([[0, 1, 2]]), 1)
    >>> sub.vertices.shape, sub.faces.shape, sub.vertex_edge.tolist()
    ((6, 3), (4, 3), [-1, -1, -1, 0, 1, 2])
    """

    vertices: np.ndarray
    faces: np.ndarray
    edges: np.ndarray
    vertex_edge: np.ndarray
    vertex_face: np.ndarray
    mesh_edges: np.ndarray
    side_edge: np.ndarray
    side_pairs: np.ndarray = None

    def carry(self, labels, faces):
        """Extend per-vertex ``labels`` of the input mesh ``faces`` to every refined vertex.

        A new vertex takes the label of the first corner of the input edge or
        face it lies on (labels constant on connected parts carry exactly).

        Examples
        --------
        >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
        >>> F = np.array([[0, 1, 2]])
        >>> midpoint_subdivide(V, F, 1).carry(np.array([7, 7, 7]), F).tolist()
        [7, 7, 7, 7, 7, 7]
        """
        n = labels.shape[0]
        on_edge, in_face = self.vertex_edge[n:], self.vertex_face[n:]
        corner = np.where(on_edge >= 0, self.edges[np.maximum(on_edge, 0), 0], faces[np.maximum(in_face, 0), 0])
        return np.r_[labels, labels[corner]]


def unique_edges(F, with_pairs=False):
    """Unique undirected edges of a face array, and each face side's edge id.

    Parameters
    ----------
    F : (m, 3) int array
    with_pairs : bool, default False
        Also return the sides of each edge that has exactly two, found by the
        same sort (:func:`heatcore.domains.intrinsic.halfedge_twins` pairs them).

    Returns
    -------
    edges : (k, 2) int array of sorted vertex pairs
    side_edge : (m, 3) int array, edge id of the side opposite each corner
    pairs : (p, 2) int array or None, only ``with_pairs``
        Half-edges ``3 f + c`` (face ``f``'s side opposite corner ``c``), the
        two of each edge with exactly two, the smaller first, by edge; None
        on meshes too large for the one sort (the pairs are then left to find).

    Examples
    --------
    >>> edges, side_edge = unique_edges(np.array([[0, 1, 2], [0, 2, 3]]))
    >>> edges.tolist(), side_edge.tolist()
    ([[0, 1], [0, 2], [0, 3], [1, 2], [2, 3]], [[3, 1, 0], [4, 2, 1]])
    >>> unique_edges(np.array([[0, 1, 2], [0, 2, 3]]), with_pairs=True)[2].tolist()   # edge 0-2
    [[1, 5]]
    """
    if use_build_kernels(F.shape[0]):  # a large mesh: the same arrays from compiled passes
        from .build_kernels import edge_table

        edges, side_edge, pairs = edge_table(F)
        return (edges, side_edge, pairs) if with_pairs else (edges, side_edge)
    a = F[:, [1, 2, 0]].ravel()
    b = F[:, [2, 0, 1]].ravel()
    n = int(F.max()) + 1 if F.size else 1
    key = np.minimum(a, b) * n + np.maximum(a, b)
    shift = int(key.size).bit_length()
    pairs = None
    if key.size == 0 or (n * n) << shift >= 2**63:  # the key and its position do not fit one int64
        keys, inverse = np.unique(key, return_inverse=True)
    else:  # np.unique's result from one sort of key-and-position (800k vertices: 0.49 s against 0.70 s)
        packed = np.sort((key << shift) | np.arange(key.size))
        sorted_keys = packed >> shift
        first = np.empty(key.size, dtype=bool)
        first[0] = True
        np.not_equal(sorted_keys[1:], sorted_keys[:-1], out=first[1:])
        keys = sorted_keys[first]
        del sorted_keys
        side = packed & ((1 << shift) - 1)  # the sides, edge by edge, each edge's in ascending order
        inverse = np.empty(key.size, dtype=np.int64)
        inverse[side] = np.cumsum(first) - 1
        if with_pairs:
            pairs = _side_pairs(side, first)
    edges = np.stack([keys // n, keys % n], axis=1)
    return (edges, inverse.reshape(F.shape), pairs) if with_pairs else (edges, inverse.reshape(F.shape))


def _side_pairs(side, first):
    """The two sides of each edge with exactly two, from the sides listed edge by edge (``first``: an edge's first)."""
    starts = np.flatnonzero(first)
    two = np.diff(np.r_[starts, side.size]) == 2
    starts = starts[two]
    return np.stack([side[starts], side[starts + 1]], axis=1)


def midpoint_subdivide(V, F, levels):
    """Subdivide ``levels`` times, each triangle into four at its edge midpoints.

    Parameters
    ----------
    V : (n, 3) float array
    F : (m, 3) int array
    levels : int or (m,) int array
        Levels for every face, or per face. Faces that share an edge must get
        the same number of levels (give it per connected part), so that no
        edge is split on one side only.

    Returns
    -------
    Subdivision

    Examples
    --------
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [5, 0, 0], [6, 0, 0], [5, 1, 0]], float)
    >>> sub = midpoint_subdivide(V, np.array([[0, 1, 2], [3, 4, 5]]), levels=np.array([2, 0]))
    >>> sub.faces.shape[0], sub.vertices.shape[0]
    (17, 18)
    """
    face_levels = np.broadcast_to(np.asarray(levels, dtype=np.int64), (F.shape[0],))
    most = int(face_levels.max()) if face_levels.size else 0
    if most:
        edges, side_edge = unique_edges(F)
    else:  # these are the final faces: their sides' pairs too
        edges, side_edge, pairs = unique_edges(F, with_pairs=True)
    cur_edges, cur_side = edges, side_edge
    n = V.shape[0]
    vertex_edge = np.full(n, -1, dtype=np.int64)
    vertex_face = np.full(n, -1, dtype=np.int64)
    face_origin = np.arange(F.shape[0])
    side_origin = side_edge.copy()  # input edge id of each face side, -1 if interior
    for level in range(most):
        if level:
            cur_edges, cur_side = unique_edges(F)
        split = face_levels > level  # faces of parts that are done stay as they are
        cut = np.zeros(cur_edges.shape[0], dtype=bool)
        cut[cur_side[split].ravel()] = True
        mid = np.full(cur_edges.shape[0], -1, dtype=np.int64)
        mid[cut] = V.shape[0] + np.arange(int(cut.sum()))
        V = np.vstack([V, 0.5 * (V[cur_edges[cut, 0]] + V[cur_edges[cut, 1]])])
        # origin of each new vertex: the input edge its side lies on, else the input face
        sides, origin = cur_side[split].ravel(), side_origin[split].ravel()
        new_edge = np.full(cur_edges.shape[0], -1, dtype=np.int64)
        new_face = np.full(cur_edges.shape[0], -1, dtype=np.int64)
        new_edge[sides] = origin
        inner = origin == -1
        new_face[sides[inner]] = np.repeat(face_origin[split], 3)[inner]
        vertex_edge = np.r_[vertex_edge, new_edge[cut]]
        vertex_face = np.r_[vertex_face, new_face[cut]]

        v0, v1, v2 = F[split].T
        m0, m1, m2 = mid[cur_side[split]].T
        s0, s1, s2 = side_origin[split].T
        none = np.full_like(s0, -1)
        F = np.concatenate(
            [
                F[~split],
                np.stack([v0, m2, m1], 1),
                np.stack([m2, v1, m0], 1),
                np.stack([m1, m0, v2], 1),
                np.stack([m0, m1, m2], 1),
            ]
        )
        side_origin = np.concatenate(
            [
                side_origin[~split],
                np.stack([none, s1, s2], 1),
                np.stack([s0, none, s2], 1),
                np.stack([s0, s1, none], 1),
                np.stack([none, none, none], 1),
            ]
        )
        face_origin = np.r_[face_origin[~split], np.tile(face_origin[split], 4)]
        face_levels = np.r_[face_levels[~split], np.tile(face_levels[split], 4)]
    if most:
        cur_edges, cur_side, pairs = unique_edges(F, with_pairs=True)
    return Subdivision(V, F, edges, vertex_edge, vertex_face, cur_edges, cur_side, pairs)
