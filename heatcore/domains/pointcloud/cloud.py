"""The point-cloud domain: :class:`PointCloud` (the construction, and an example, in :mod:`heatcore.domains.pointcloud`)."""

import numpy as np
from scipy.spatial import cKDTree

from ...errors import InvalidMeshError, InvalidOptionError, InvalidSourceError
from ...progress import Progress
from ...settings import MeshSettings
from ..base import Domain
from ..cotan import intrinsic_operators
from ..refine import auto_refine_levels, midpoint_subdivide
from ..sources import index_list
from ..validate import vertex_array
from .local_delaunay import attach_left_out, local_delaunay_triangles
from .orientation import oriented_normals
from .neighborhoods import (
    MAX_ATTACH_RATIO,
    MAX_NEIGHBOR_RATIO,
    merge_duplicates,
    nearest_neighbors,
    pca_normals,
    within_ratio,
)
from .tufted import tufted_cover

#: Default neighborhood size.
DEFAULT_K = 30
#: Smallest and largest accepted neighborhood sizes.
MIN_K, MAX_K = 6, 256


class PointCloud(Domain):
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
    settings : MeshSettings or Settings, optional
        The mesh options, checked (:mod:`heatcore.settings`), as front ends
        hand them over; the keyword options below (checked here) change them.
        An option this domain does not take (:attr:`mesh_options`), given
        explicitly, is an :class:`~heatcore.InvalidOptionError`.
    refine : "auto" or int, default "auto"
        Midpoint subdivision levels of the proposed triangles, as for
        :class:`~heatcore.TriangleMesh` ("auto" refines clouds of fewer than
        ``AUTO_REFINE_MIN_VERTICES`` points).
    progress : callable, optional
        ``progress(fraction, message)`` at the start of each stage (duplicate
        points, neighbours, normals, local triangles, operators), as
        :class:`~heatcore.TriangleMesh` reports (:mod:`heatcore.progress`).

    Attributes
    ----------
    operators : Operators
    points : (n, 3) float array, the input points
    triangles : (m, 3) int array
        The union of the proposed local Delaunay triangles, indexing the
        distinct points (``distinct``), then one triangle per point that none
        of them uses but whose neighbors they do (heavy noise; see
        :func:`~heatcore.domains.pointcloud.local_delaunay.attach_left_out`).
    distinct : (n', 3) float array
        The points after merging duplicates; ``point_map`` sends each input
        point to its distinct point.
    normals : (n', 3) float array, unit normals of the distinct points
    votes : (m,) int array
        How many points proposed each triangle (1 to 3; 0 for an attached one).
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
    domain_name = "point cloud"

    #: The options of :class:`~heatcore.settings.MeshSettings` this domain takes.
    mesh_options = ("refine",)

    def __init__(self, P, normals=None, settings=None, *, k=None, progress=None, **options):
        settings = MeshSettings.of(settings, **options)
        settings.refuse_untaken(self.mesh_options, self.domain_name)
        progress = Progress(progress)
        progress(0.0, "merging duplicate points")
        self.points = vertex_array(P, name="P")
        n_in = self.points.shape[0]
        self.point_map, self.distinct = merge_duplicates(self.points)
        n = self.distinct.shape[0]
        self.n_duplicates = n_in - n
        if n < 3:
            raise InvalidMeshError(f"a point cloud needs at least 3 distinct points, got {n}")
        self.k = _neighborhood_size(k, n)
        refine = settings.refine

        progress(0.1, "finding each point's neighbours")
        near, dist = nearest_neighbors(self.distinct, self.k, ratio=MAX_ATTACH_RATIO)
        nbr = within_ratio(near, dist, MAX_NEIGHBOR_RATIO)  # the neighbors of the normals and local triangles
        progress(0.3, "estimating normals" if normals is None else "reading the normals")
        self.normals_given = normals is not None
        if normals is None:
            self.normals = pca_normals(self.distinct, nbr)
        else:
            self.normals = _normal_array(normals, n_in, self.point_map, n)
        progress(0.4, "local Delaunay triangles")
        tri, votes, self.boundary_points = local_delaunay_triangles(self.distinct, self.normals, nbr)
        if tri.shape[0]:
            tri = attach_left_out(self.distinct, tri, near)  # points heavy noise left out of every triangle
        self.votes = np.r_[votes, np.zeros(tri.shape[0] - votes.size, dtype=votes.dtype)]
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
        progress(0.7, f"midpoint subdivision ({self.levels} levels) and operators" if self.levels else "operators")
        self.operators = self._build_operators(self.distinct[used], self._operator_vertex[tri])
        progress(1.0, "point cloud ready")

    def _build_operators(self, V, F):
        sub = midpoint_subdivide(V, F, self.levels)
        n = sub.vertices.shape[0]
        # Boundary: sides of a single triangle between points on a scan border.
        on_rim = np.zeros(n, dtype=bool)
        used = np.flatnonzero(self._operator_vertex >= 0)
        on_rim[: used.size] = self.boundary_points[used]
        if self.levels:
            mid = np.arange(used.size, n)
            ends = sub.edges[sub.vertex_edge[mid]]
            on_rim[mid] = (sub.vertex_edge[mid] >= 0) & on_rim[ends[:, 0]] & on_rim[ends[:, 1]]
        self.operator_positions = sub.vertices
        cover = tufted_cover(sub.vertices, sub.faces)
        built = intrinsic_operators(sub.vertices, sub.faces, sub.mesh_edges, sub.side_edge, cover=cover, rim=on_rim)
        self.n_flips = built.n_flips
        self.cover = built.intrinsic
        return built.operators

    def oriented_normals(self):
        """Unit normals at the operator vertices with consistent signs (kept in the domain's cache).

        Normals given to the cloud keep their signs; PCA normals are oriented by
        :func:`~heatcore.domains.pointcloud.orientation.oriented_normals`. A
        refined vertex takes the normal of the nearest point.

        Examples
        --------
        >>> import numpy as np
        >>> theta = np.linspace(0, 2 * np.pi, 40, endpoint=False)
        >>> P = np.concatenate([np.column_stack([np.cos(theta), np.sin(theta), np.full(40, 0.15 * z)]) for z in range(8)])
        >>> N = PointCloud(P, k=12, refine=0).oriented_normals()
        >>> bool((np.einsum("ij,ij->i", N[:, :2], P[:, :2]) > 0.9).all())   # outwards
        True
        """
        return self.derived.get_or_build(("oriented normals", None), self._oriented_normals)

    def _oriented_normals(self):
        used = np.flatnonzero(self._operator_vertex >= 0)
        normals = self.normals if self.normals_given else oriented_normals(self.distinct, self.normals, self.k)
        X = self.operator_positions
        if X.shape[0] == used.size:
            return normals[used]
        return normals[used][cKDTree(X[:used.size]).query(X)[1]]

    @property
    def n_input_vertices(self):
        """Number of points as given."""
        return self.points.shape[0]

    @property
    def output_vertices(self):
        """Operator vertex of each input point (``-1`` for points in no triangle)."""
        return self._operator_vertex[self.point_map]

    @property
    def input_positions(self):
        """The points as given, ``(n, 3)``."""
        return self.points

    def _pin_vertices(self, vertices, pins):
        """Source points (indices into the input points); a typed error for an isolated point."""
        v = index_list(vertices, self.n_input_vertices, "point")
        op = self.output_vertices[v]
        if (op < 0).any():
            bad = int(v[op < 0][0])
            raise InvalidSourceError(
                f"point {bad} is isolated (no neighbor close enough to form a triangle), so it cannot be a source"
            )
        pins.add(op)


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
