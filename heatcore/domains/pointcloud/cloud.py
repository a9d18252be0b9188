"""Point clouds: heat-method operators from local tangent-plane Delaunay triangles.

A point cloud has no connectivity, so the operators are built on a triangle
set that the points propose themselves, following the point-cloud Laplacian
of Sharp and Crane ("A Laplacian for Nonmanifold Triangle Meshes", SGP 2020,
section 5):

1. neighborhoods: the ``k`` nearest neighbors of each point (a KD-tree),
   without neighbors much farther than the local spacing (so that separate
   clusters and stray points stay separate);
2. tangent planes: PCA of each neighborhood, or the given normals; neighbors
   far off the tangent plane (slope above ``MAX_SLOPE``: the other side of a
   thin part) are left out;
3. local triangulations: the neighbors are projected onto the tangent plane and
   the point's 1-ring in the planar Delaunay triangulation of its
   neighborhood is kept (computed for all points at once: a neighbor ``q`` of
   the point ``p`` at the origin is a Delaunay neighbor exactly when its
   inversion ``q / |q|^2`` is a vertex of the convex hull of the inverted
   neighbors and the origin);
4. the union of all proposed triangles (each kept once, edge lengths = 3D
   distances) is midpoint-subdivided on coarse clouds like a triangle mesh,
   doubled into its tufted cover (each triangle as two sheets, glued around
   every edge in angular order, so that non-manifold and inconsistently
   oriented triangles form one manifold), mollified and flipped to intrinsic
   Delaunay, and the cotan Laplacian, lumped mass, per-triangle gradients and
   divergence all come from the same intrinsic triangles
   (:func:`heatcore.domains.triangle.triangle_operators`).

Gradient and divergence are therefore consistent with the Laplacian
(``L = G^T diag(A) G``). This differs from the construction the reference
report describes (a Voronoi-area mass with a separate point-cloud Laplacian,
and weighted-least-squares gradients on moving-least-squares tangent planes),
where the three operators are built independently.

Examples
--------
>>> import numpy as np
>>> import heatcore as hc
>>> rng = np.random.default_rng(0)
>>> P = np.column_stack([rng.random((400, 2)), np.zeros(400)])
>>> cloud = PointCloud(P, k=16)
>>> d = hc.HeatSolver(cloud).distance([0])
>>> bool(np.all(np.isfinite(d)))
True
"""

import numpy as np
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from ..errors import InvalidMeshError, InvalidOptionError, InvalidSourceError
from .intrinsic import NEXT, PREV, IntrinsicTriangulation, face_edge_lengths, mollify
from .refine import auto_refine_levels, midpoint_subdivide
from .sources import SourcePins, index_list
from .triangle import triangle_operators
from .validate import vertex_array

#: Default neighborhood size.
DEFAULT_K = 30
#: Smallest and largest accepted neighborhood sizes.
MIN_K, MAX_K = 6, 256
#: Neighbors farther than this many times the local spacing are not neighbors.
MAX_NEIGHBOR_RATIO = 3.0
#: The local spacing of a point: distance to its ``SPACING_RANK``-th neighbor.
SPACING_RANK = 6
#: Neighbors whose offset along the normal exceeds this multiple of their
#: tangential distance (a slope) are left out: they lie across a thin gap.
MAX_SLOPE = 0.6
#: Triangles whose doubled area is below this fraction of their longest
#: squared side (all angles nearly 0 or pi) are left out.
MIN_SINE = 1e-6
#: Points closer than this fraction of the bounding-box diagonal are merged.
DUPLICATE_TOLERANCE = 1e-9


class PointCloud:
    """A point cloud as a heat-method domain.

    Parameters
    ----------
    P : (n, 3) array_like of float
        Point positions (``(n, 2)`` is read as points in the plane z = 0).
    normals : (n, 3) array_like of float, optional
        Normals defining the tangent planes; PCA normals of the
        neighborhoods when not given. Their sign does not matter.
    k : int, default 30
        Neighborhood size (``MIN_K`` to ``MAX_K``); clamped to the number of
        distinct points minus one on smaller clouds.
    refine : "auto" or int, default "auto"
        Midpoint subdivision levels of the proposed triangles, as for
        :class:`~heatcore.TriangleMesh` ("auto" refines clouds of fewer than
        ``AUTO_REFINE_MIN_VERTICES`` points).

    Attributes
    ----------
    operators : Operators
    points : (n, 3) float array, the input points
    triangles : (m, 3) int array
        The union of the proposed local Delaunay triangles, indexing the
        distinct points (``distinct``).
    distinct : (n', 3) float array
        The points after merging duplicates; ``point_map`` sends each input
        point to its distinct point.
    normals : (n', 3) float array, unit normals of the distinct points
    votes : (m,) int array
        How many points proposed each triangle (1 to 3).
    boundary_points : (n',) bool array
        Distinct points whose neighborhood leaves an angular gap of at least
        pi (scan borders and hole rims).
    n_duplicates : int
        Input points merged into another point.

    Raises
    ------
    InvalidMeshError
        Wrong shape, NaN or infinite coordinates, fewer than three distinct
        points, or unusable normals.
    InvalidOptionError
        ``k`` or ``refine`` out of range.

    Examples
    --------
    >>> import numpy as np
    >>> theta = np.linspace(0, 2 * np.pi, 60, endpoint=False)
    >>> P = np.concatenate([np.column_stack([np.cos(theta), np.sin(theta), np.full(60, z)])
    ...                     for z in np.linspace(0, 1, 12)])
    >>> cloud = PointCloud(P, k=12)
    >>> cloud.triangles.shape[1]
    3
    """

    element_name = "triangle"
    intrinsic = None  # the eikonal refinement (accuracy="high") needs a mesh

    def __init__(self, P, normals=None, *, k=None, refine="auto"):
        self.points = vertex_array(P, name="P")
        n_in = self.points.shape[0]
        self.point_map, self.distinct = _merge_duplicates(self.points)
        n = self.distinct.shape[0]
        self.n_duplicates = n_in - n
        if n < 3:
            raise InvalidMeshError(f"a point cloud needs at least 3 distinct points, got {n}")
        self.k = _neighborhood_size(k, n)
        if refine != "auto" and not (
            isinstance(refine, (int, np.integer)) and not isinstance(refine, bool) and 0 <= refine <= 4
        ):
            raise InvalidOptionError(f"refine must be 'auto' or an integer 0..4, got {refine!r}")

        nbr, dist = _neighborhoods(self.distinct, self.k)
        if normals is None:
            self.normals = pca_normals(self.distinct, nbr)
        else:
            self.normals = _normal_array(normals, n_in, self.point_map, n)
        tri, votes, self.boundary_points = local_delaunay_triangles(self.distinct, self.normals, nbr)
        self.votes = votes
        self.triangles = tri
        if tri.shape[0] == 0:
            raise InvalidMeshError(
                "no triangles could be formed: the points are too sparse for their neighborhoods "
                f"(k={self.k}) or all collinear"
            )
        used = np.unique(tri)
        self._operator_vertex = np.full(n, -1, dtype=np.int64)
        self._operator_vertex[used] = np.arange(used.size)
        self.levels = auto_refine_levels(used.size) if refine == "auto" else int(refine)
        self.operators = self._build_operators(self.distinct[used], self._operator_vertex[tri])

    def _build_operators(self, V, F):
        sub = midpoint_subdivide(V, F, self.levels)
        V, F = sub.vertices, sub.faces
        n = V.shape[0]
        edges, side_edge = sub.mesh_edges, sub.side_edge
        edge_faces = np.bincount(side_edge.ravel(), minlength=edges.shape[0])
        # Boundary: sides of a single triangle between points on a scan border.
        on_rim = np.zeros(n, dtype=bool)
        used = np.flatnonzero(self._operator_vertex >= 0)
        on_rim[: used.size] = self.boundary_points[used]
        if self.levels:
            mid = np.arange(used.size, n)
            ends = sub.edges[sub.vertex_edge[mid]]
            on_rim[mid] = (sub.vertex_edge[mid] >= 0) & on_rim[ends[:, 0]] & on_rim[ends[:, 1]]
        open_edges = edges[edge_faces == 1]
        open_edges = open_edges[on_rim[open_edges].all(axis=1)]
        boundary = np.zeros(n, dtype=bool)
        boundary[open_edges.ravel()] = True

        h = float(np.linalg.norm(V[edges[:, 0]] - V[edges[:, 1]], axis=1).mean())
        faces, twin = tufted_cover(V, F)
        lengths, _ = mollify(face_edge_lengths(V, faces) / h)
        tri = IntrinsicTriangulation(faces, lengths, twin)
        self.n_flips = tri.flip_to_delaunay()
        tri.lengths *= h
        self.cover = tri
        return triangle_operators(tri.lengths, tri.faces, n, boundary, h)

    @property
    def n_input_vertices(self):
        """Number of points as given."""
        return self.points.shape[0]

    @property
    def output_vertices(self):
        """Operator vertex of each input point (``-1`` for points in no triangle)."""
        return self._operator_vertex[self.point_map]

    def source_pins(self, vertices=None, **other):
        """Source points (indices into the input points) as :class:`SourcePins`.

        Raises
        ------
        InvalidSourceError
            No source, indices out of range, or an isolated point (one that
            lies in no triangle: too far from every other point).
        """
        if other:
            raise InvalidSourceError(
                f"point clouds take source points (vertex indices) only, not {', '.join(sorted(other))}"
            )
        if vertices is None:
            raise InvalidSourceError("no source given: pass point indices")
        v = index_list(vertices, self.n_input_vertices, "point")
        if v.size == 0:
            raise InvalidSourceError("no source given: the list of source points is empty")
        op = self.output_vertices[v]
        if (op < 0).any():
            bad = int(v[op < 0][0])
            raise InvalidSourceError(
                f"point {bad} is isolated (no neighbor close enough to form a triangle), so it cannot be a source"
            )
        ones = np.ones(op.size)
        return SourcePins.combine(self.operators.n_vertices, op, np.zeros(op.size), op, ones)


def _neighborhood_size(k, n):
    if k is None:
        return int(min(DEFAULT_K, n - 1))
    if not isinstance(k, (int, np.integer)) or isinstance(k, bool):
        raise InvalidOptionError(f"k must be an integer, got {k!r}")
    if not MIN_K <= k <= MAX_K:
        raise InvalidOptionError(f"k must be between {MIN_K} and {MAX_K} neighbors, got {k}")
    if k > n - 1:
        raise InvalidOptionError(f"k={k} neighbors asked for, but the cloud has only {n} distinct points")
    return int(k)


def _merge_duplicates(P):
    """Map each point to a representative of the points within a tiny distance of it."""
    diag = float(np.linalg.norm(P.max(axis=0) - P.min(axis=0)))
    pairs = cKDTree(P).query_pairs(DUPLICATE_TOLERANCE * diag, output_type="ndarray") if diag > 0 else None
    n = P.shape[0]
    if diag == 0:
        return np.zeros(n, dtype=np.int64), P[:1]
    if pairs.shape[0] == 0:
        return np.arange(n, dtype=np.int64), P
    import scipy.sparse as sp

    graph = sp.coo_matrix((np.ones(pairs.shape[0]), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    first = np.full(label.max() + 1, n, dtype=np.int64)
    np.minimum.at(first, label, np.arange(n))
    # distinct points in order of first appearance
    order = np.argsort(first)
    rank = np.empty_like(order)
    rank[order] = np.arange(order.size)
    return rank[label], P[first[order]]


def _normal_array(normals, n_in, point_map, n):
    try:
        N = np.array(normals, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InvalidMeshError(f"normals must be a numeric (n, 3) array: {exc}") from exc
    if N.shape != (n_in, 3):
        raise InvalidMeshError(f"normals must have shape ({n_in}, 3), one per point, got {N.shape}")
    norm = np.linalg.norm(N, axis=1)
    bad = ~np.isfinite(norm) | (norm == 0)
    if bad.any():
        raise InvalidMeshError(
            f"{int(bad.sum())} normals are zero, NaN or infinite (first: point {int(np.flatnonzero(bad)[0])})"
        )
    out = np.zeros((n, 3))
    out[point_map] = N / norm[:, None]  # a duplicate's normal: any of its copies
    return out


def _neighborhoods(P, k):
    """k nearest neighbors (self excluded), -1 where a neighbor is too far to count.

    A neighbor ``j`` of ``i`` is kept when ``|p_i - p_j| <= MAX_NEIGHBOR_RATIO
    * min(s_i, s_j)``, with ``s`` the distance to the ``SPACING_RANK``-th
    neighbor: clusters and isolated points stay apart (the far side's
    spacing is small), while density changes of a few times are kept.
    """
    dist, idx = cKDTree(P).query(P, k + 1)
    dist, idx = dist[:, 1:], idx[:, 1:]
    spacing = dist[:, min(SPACING_RANK, k) - 1]
    far = dist > MAX_NEIGHBOR_RATIO * np.minimum(spacing[:, None], spacing[idx])
    idx = np.where(far, -1, idx)
    return idx, dist


def pca_normals(P, nbr):
    """Unit normal of each point: least-variance direction of its neighborhood.

    Parameters
    ----------
    P : (n, 3) float array
    nbr : (n, k) int array, neighbor indices (-1 for none)

    Returns
    -------
    (n, 3) float array (sign arbitrary)
    """
    valid = nbr >= 0
    Q = np.where(valid[..., None], P[np.maximum(nbr, 0)], 0.0)
    count = valid.sum(axis=1) + 1
    mean = (Q.sum(axis=1) + P) / count[:, None]
    D = np.where(valid[..., None], Q - mean[:, None], 0.0)
    C = np.einsum("nki,nkj->nij", D, D) + np.einsum("ni,nj->nij", P - mean, P - mean)
    _, vec = np.linalg.eigh(C)
    return vec[:, :, 0]


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
    rows = np.arange(n)[:, None]
    col = np.arange(k)[None, :]
    tol = 1e-12
    while True:
        # compact the alive neighbors to the front, in angular order
        pos = np.argsort(~alive, axis=1, kind="stable")
        ux, uy, ang, nb, alive = (np.take_along_axis(A, pos, axis=1) for A in (ux, uy, ang, nb, alive))
        c = alive.sum(axis=1)[:, None]
        cc = np.maximum(c, 1)
        nxt = (col + 1) % cc
        prv = (col - 1) % cc
        wedge_next = np.mod(ang[rows, nxt] - ang, 2 * np.pi)
        wedge_prev = np.mod(ang - ang[rows, prv], 2 * np.pi)
        wedge_next = np.where(c == 1, 2 * np.pi, wedge_next)
        wedge_prev = np.where(c == 1, 2 * np.pi, wedge_prev)
        ax, ay = ux[rows, prv], uy[rows, prv]
        bx, by = ux[rows, nxt], uy[rows, nxt]
        cross = (bx - ax) * (uy - ay) - (by - ay) * (ux - ax)
        scale = (bx - ax) ** 2 + (by - ay) ** 2 + (ux - ax) ** 2 + (uy - ay) ** 2
        reflex = alive & (c >= 3) & (wedge_prev + wedge_next < np.pi) & (cross >= -tol * scale)
        if not reflex.any():
            break
        alive &= ~reflex
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
    if T.size:
        T, votes = np.unique(T, axis=0, return_counts=True)
    else:
        T, votes = T.reshape(0, 3), np.zeros(0, dtype=np.int64)
    return T.astype(np.int64), votes, boundary


def tufted_cover(V, F):
    """Faces and half-edge twins of the tufted cover of a triangle set.

    Each triangle becomes two sheets with opposite orientations; around each
    edge the triangles are ordered by angle and each sheet is glued to the
    facing sheet of the next triangle, so that every interior edge joins two
    consistently oriented sheets whatever the input's orientation or
    manifoldness. Edges of a single triangle stay boundary (twin ``-1``).

    Parameters
    ----------
    V : (n, 3) float array
    F : (m, 3) int array (no duplicates)

    Returns
    -------
    faces : (2 m, 3) int array
    twin : (6 m,) int array, half-edge ``3 f + c`` runs from corner ``c+1`` to ``c+2``.
    """
    m = F.shape[0]
    faces = np.concatenate([F, F[:, [0, 2, 1]]])
    tail = faces[:, NEXT].ravel()
    head = faces[:, PREV].ravel()
    apex = faces.ravel()
    lo, hi = np.minimum(tail, head), np.maximum(tail, head)
    forward = tail < hi  # runs lo -> hi
    n = V.shape[0]
    key = lo * n + hi
    axis = V[hi] - V[lo]
    axis /= np.linalg.norm(axis, axis=1, keepdims=True)
    ref = np.where(np.abs(axis[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    u = np.cross(axis, ref)
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    w = np.cross(axis, u)
    r = V[apex] - V[lo]
    theta = np.arctan2(np.einsum("ij,ij->i", r, w), np.einsum("ij,ij->i", r, u))
    h = np.arange(3 * 2 * m)
    fw = h[forward]
    bw = h[~forward]
    # the same triangle's two sheets share (key, theta); order both lists alike
    fw = fw[np.lexsort((fw // 3 % m, theta[fw], key[fw]))]
    bw = bw[np.lexsort((bw // 3 % m, theta[bw], key[bw]))]
    kf = key[fw]
    start = np.r_[True, kf[1:] != kf[:-1]]
    group = np.cumsum(start) - 1
    first = np.flatnonzero(start)
    size = np.diff(np.r_[first, kf.size])
    pos = np.arange(kf.size) - first[group]
    nxt = first[group] + (pos + 1) % size[group]
    twin = np.full(6 * m, -1, dtype=np.int64)
    # forward sheet of the triangle at theta_i faces the backward sheet of the
    # next one (of its own other sheet on an edge of one triangle: a fold)
    twin[fw] = bw[nxt]
    twin[bw[nxt]] = fw
    return faces, twin
