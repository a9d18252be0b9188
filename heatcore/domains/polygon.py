"""Polygon meshes: heatcore's triangulation of the polygons, or virtual refinement (Bunge et al. 2020).

By default (``virtual=False``) every polygon is replaced by heatcore's
triangulation of it (:func:`triangulate_polygons`), and each part is built
as :class:`~heatcore.TriangleMesh` builds those triangles: the polygons keep
their role as sources (``region=``) and their edges as edges. That is never
less accurate than the triangles, which virtual refinement cannot promise:
measured on 20 polygon meshes (docs/polygon.md), once refined it is 0.3 to
0.9 times the triangulation's error on dissolved, regular and jittered grids
and Catmull-Clark surfaces, but 1.1 to 1.8 times on a plate with holes,
stretched hexagons, suzanne, a cylinder and a smoothly subdivided cube, and
up to 3.2 times unrefined.

With ``virtual=True``, "Polygon Laplacian Made Simple" (Bunge, Herholz,
Kazhdan, Botsch 2020) refines every polygon with ``k >= 4`` corners
by a virtual vertex ``x_f = sum_i w_i x_i`` (an affine combination of its
corners) and splits it into the ``k`` fan triangles ``(x_i, x_{i+1}, x_f)``.
Triangles stay as they are. The weights minimize the sum of the squared fan
triangle areas (among all such minimizers, the weights of least norm), which
works for non-planar and non-convex polygons alike. With the prolongation
``P`` (input vertices to input plus virtual vertices: identity on the corners,
the weights on the virtual vertices), the polygon operators are the
Galerkin projections of the triangle operators of the refinement:

* Laplacian ``L = P^T L_fan P``;
* lumped mass: the row sums of ``P^T M_fan P``, i.e. ``P^T m_fan``;
* gradient ``G = G_fan P`` on the fan triangles, with the fan triangles'
  areas as element volumes, so that the divergence ``-G^T diag(A)`` is
  consistent with the Laplacian (``L = G^T diag(A) G``).

The heat solver (:mod:`heatcore.heat`) sees only these operators and the
input vertices; the virtual vertices are eliminated.

Degenerate fan triangles (zero-area polygons, repeated corners) are
mollified (Sharp and Crane 2020) as in :class:`~heatcore.TriangleMesh`, so
results stay finite; on clean meshes this changes nothing. The mesh's own
triangles (those given, and those of the polygons
:mod:`~heatcore.domains.polygon_triangulate` triangulates: concave,
straight-cornered and thin ones) are flipped to intrinsic Delaunay among
themselves, as :class:`~heatcore.TriangleMesh` flips them. ``delaunay=True``
flips the whole refinement, virtual fans included (an M-matrix Laplacian).
That is not the paper's operator and is less accurate on the measured meshes
(docs/polygon.md), hence off by default.

Examples
--------
>>> import numpy as np, heatcore as hc
>>> V = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0], [1, 1, 0], [2, 1, 0]], float)
>>> mesh = PolygonMesh(V, [[0, 1, 4, 3], [1, 2, 5, 4]], virtual=True)
>>> mesh.n_virtual, PolygonMesh(V, [[0, 1, 4, 3], [1, 2, 5, 4]]).n_triangulated
(2, 2)
>>> d = hc.HeatSolver(mesh).distance([0])
>>> bool(abs(d[2] - 2.0) < 0.2)
True
"""

import warnings

import numpy as np
import scipy.sparse as sp

from ..errors import HeatcoreWarning, InvalidMeshError, InvalidSourceError
from ..progress import Progress
from ..settings import MeshSettings
from .base import MeshDomain
from .cotan import MOLLIFY_SLACK, triangle_operators
from .intrinsic import (
    IntrinsicTriangulation,
    face_edge_lengths,
    mollify,
    triangle_slack,
)
from .operators import Operators
from .parts import elements_in_parts_of, part_extremes, part_means, vertex_components
from .polygon_refine import (
    REFINED_TIME_FACTOR,
    area_minimizer_weights,
    operator_weights,
    refine_levels,
    split_polygons,
    unfold,
    vertices_inside,
)
from .polygon_shape import fan_triangulate, simple_polygons  # noqa: F401 (fan_triangulate: public here too)
from .polygon_triangulate import (  # noqa: F401
    straight_chords,
    triangulate_polygons,
    triangulate_where_needed,
)
from .refine import unique_edges
from .sources import edge_list, index_list
from .triangle import THIN_TRIANGLE_SLACK, TriangleMesh
from .validate import one_based_hint, vertex_array


def polygon_arrays(polygons, n_vertices):
    """Polygons as flat ``(offsets, indices)`` arrays, validated.

    Parameters
    ----------
    polygons : sequence of sequences of int, (m, k) int array, or (offsets, indices) tuple
        Polygon ``p`` is ``indices[offsets[p]:offsets[p + 1]]`` in the last
        form: ``offsets`` has ``m + 1`` non-decreasing entries from 0 to
        ``len(indices)`` (a tuple of two 1-D numpy arrays).
    n_vertices : int

    Returns
    -------
    offsets : (m + 1,) int64 array
    indices : (offsets[-1],) int64 array

    Raises
    ------
    InvalidMeshError
        Malformed input, non-integer or out-of-range indices, no polygons.

    Examples
    --------
    >>> offsets, indices = polygon_arrays([[0, 1, 2, 3], [1, 4, 2]], 5)
    >>> offsets.tolist(), indices.tolist()
    ([0, 4, 7], [0, 1, 2, 3, 1, 4, 2])
    """
    if (
        isinstance(polygons, tuple)
        and len(polygons) == 2
        and all(isinstance(a, np.ndarray) and a.ndim == 1 for a in polygons)
    ):
        offsets, indices = _integers(polygons[0], "polygon offsets"), _integers(polygons[1], "polygon indices")
        if offsets.size == 0 or offsets[0] != 0 or offsets[-1] != indices.size or np.any(offsets[1:] < offsets[:-1]):
            raise InvalidMeshError(
                "polygon offsets must start at 0, never decrease and end at len(indices) "
                f"(got {offsets.size} offsets, first {offsets[:1].tolist()}, last {offsets[-1:].tolist()}, "
                f"{indices.size} indices)"
            )
        offsets = offsets.astype(np.int64)  # now known to lie in 0..len(indices)
    elif isinstance(polygons, np.ndarray) and polygons.dtype != object:
        if polygons.ndim != 2:
            raise InvalidMeshError(f"a polygon array must have shape (m, k), got {polygons.shape}")
        indices = _integers(polygons.reshape(-1), "polygon indices")
        offsets = np.arange(polygons.shape[0] + 1, dtype=np.int64) * polygons.shape[1]
    else:
        try:
            rows = [np.asarray(p).reshape(-1) for p in polygons]
        except (TypeError, ValueError) as exc:
            raise InvalidMeshError(f"polygons must be a list of index lists: {exc}") from exc
        sizes = np.fromiter((r.size for r in rows), dtype=np.int64, count=len(rows))
        offsets = np.r_[0, np.cumsum(sizes)].astype(np.int64)
        indices = _integers(np.concatenate(rows) if rows else np.zeros(0, np.int64), "polygon indices")
    if offsets.size < 2:
        raise InvalidMeshError("polygons is empty: the mesh has no polygons")
    bad = (indices < 0) | (indices >= n_vertices)
    if bad.any():
        pos = int(np.flatnonzero(bad)[0])
        poly = int(np.searchsorted(offsets, pos, side="right") - 1)
        raise InvalidMeshError(
            f"polygon {poly} references vertex {int(indices[pos])} but the mesh has {n_vertices} vertices "
            f"(valid indices are 0..{n_vertices - 1}){one_based_hint(indices, n_vertices)}"
        )
    return offsets, indices.astype(np.int64)


def _integers(a, name):
    a = np.asarray(a)
    if a.dtype == object:
        raise InvalidMeshError(f"{name} must be integers")
    if a.size and not np.issubdtype(a.dtype, np.integer):
        if not np.issubdtype(a.dtype, np.floating) or not np.all(np.isfinite(a)) or np.any(a != np.round(a)):
            raise InvalidMeshError(f"{name} must be integers, got dtype {a.dtype}")
    return a.reshape(-1)  # not cast yet: a uint64 2**64 - 1 would read as -1 in messages


def clean_polygons(offsets, indices):
    """Collapse repeated consecutive corners, drop polygons left with < 3 corners and duplicates.

    A :class:`~heatcore.HeatcoreWarning` says how many polygons went.

    Returns
    -------
    offsets, indices : the kept polygons
    kept : (m,) bool array over the input polygons

    Examples
    --------
    The second polygon collapses to an edge, the third repeats the first:

    >>> import numpy as np, warnings
    >>> with warnings.catch_warnings():
    ...     warnings.simplefilter("ignore")
    ...     o, i, kept = clean_polygons(np.array([0, 4, 7, 10]), np.array([0, 1, 1, 2, 2, 3, 2, 0, 1, 2]))
    >>> o.tolist(), i.tolist(), kept.tolist()
    ([0, 3], [0, 1, 2], [True, False, False])
    """
    m = offsets.size - 1
    sizes = np.diff(offsets)
    owner = np.repeat(np.arange(m), sizes)
    nxt = np.arange(indices.size) + 1
    nxt[offsets[1:][sizes > 0] - 1] = offsets[:-1][sizes > 0]  # wrap around
    keep_corner = indices != indices[nxt] if indices.size else np.zeros(0, bool)
    # a polygon whose corners are all one vertex keeps none: fine, it goes below
    new_sizes = np.bincount(owner[keep_corner], minlength=m)
    indices = indices[keep_corner]
    owner = owner[keep_corner]
    short = new_sizes < 3
    # duplicates: same corner set and size (in any order or orientation)
    offs = np.r_[0, np.cumsum(new_sizes)]
    duplicate = np.zeros(m, dtype=bool)
    for k in np.unique(new_sizes[~short]):
        polys = np.flatnonzero(new_sizes == k)
        S = np.sort(indices[offs[polys][:, None] + np.arange(k)], axis=1)
        order = np.lexsort(S.T[::-1])
        same = np.r_[False, (S[order[1:]] == S[order[:-1]]).all(axis=1)]
        duplicate[polys[order[same]]] = True
    kept = ~short & ~duplicate
    n_short, n_dup = int(short.sum()), int(duplicate.sum())
    if n_short or n_dup:
        warnings.warn(
            f"ignored {n_short} polygons with fewer than 3 distinct corners and {n_dup} duplicate polygons",
            HeatcoreWarning,
            stacklevel=3,
        )
    keep_entry = kept[owner]
    return np.r_[0, np.cumsum(new_sizes[kept])].astype(np.int64), indices[keep_entry], kept


class PolygonMesh(MeshDomain):
    """A polygon mesh as a heat-method domain: heatcore's triangulation of its polygons, or virtual refinement.

    Parameters
    ----------
    V : (n, 3) array_like of float
        Vertex positions.
    polygons : list of index lists, (m, k) int array, or (offsets, indices) tuple
        Polygons of any size >= 3, mixed; see :func:`polygon_arrays`. Repeated
        consecutive corners are merged; polygons left with fewer than three
        corners, and duplicates, are ignored with a warning. Non-planar
        polygons, non-manifold edges and several connected components are
        fine; unreferenced vertices get ``inf``. By default every polygon is
        measured on heatcore's triangulation of it (``virtual=False``).
    settings : MeshSettings or Settings, optional
        The mesh options, checked (:mod:`heatcore.settings`), as front ends
        hand them over; the keyword options below (checked here) change them.
        An option this domain does not take (:attr:`mesh_options`), given
        explicitly, is an :class:`~heatcore.InvalidOptionError`.
    refine : "auto" or int, default "auto"
        Levels of polygon-aware refinement before building the operators
        (:mod:`~heatcore.domains.polygon_refine`: each k-gon into k quads at
        its virtual vertex and edge midpoints, each triangle into four).
        "auto" is :class:`~heatcore.TriangleMesh`'s rule: each connected part
        with fewer than ``AUTO_REFINE_MIN_VERTICES`` vertices is split until
        it has about that many. Results are reported at the input vertices.
    virtual : bool, default False
        Keep convex polygons whole, each with a virtual vertex (Bunge et al.
        2020, the module docstring); concave polygons, those with a nearly
        straight corner (what Blender's Dissolve Edges leaves) and thin ones
        are triangulated still (``n_triangulated``). More accurate than the
        triangulation on many meshes once refined (0.3 to 0.9 times its
        error), less accurate on others (up to 1.8 times refined, 3.2
        unrefined; docs/polygon.md), hence off. The default, ``False``, triangulates
        every polygon (:func:`triangulate_polygons`): each part is then built
        as :class:`~heatcore.TriangleMesh` builds that triangulation.
    delaunay : bool, default False
        With ``virtual=True``, build the refined triangle operators on the intrinsic Delaunay
        triangulation of the whole refinement (see the module docstring). The
        default gives the paper's operators on the virtual fans (and flips
        only the mesh's own triangles).
    split_crossing : bool, default False
        A polygon whose sides cross (a bowtie, a pentagram) has no surface
        for virtual refinement to span: by default it is an
        :class:`~heatcore.InvalidMeshError` naming it; ``True`` uses its fan
        triangles instead, with a warning (beast.obj has 24 such quads).
    only_parts_of : sequence of int, optional
        Input vertices: only the connected parts that hold one of them are
        built, as :class:`~heatcore.TriangleMesh` does (``parts_left_out``
        counts the others).
    progress : callable, optional
        ``progress(fraction, message)`` at the start of each build stage
        (polygons, their shapes, refinement, operators), as
        :class:`~heatcore.TriangleMesh` reports (:mod:`heatcore.progress`).

    Attributes
    ----------
    operators : Operators
        On the referenced input vertices (``vertex_map`` order), then the
        vertices refinement added.
    offsets, indices : int arrays
        The kept polygons, on input vertex indices.
    polygon_map : (m,) int array
        Kept polygon index of each input polygon, ``-1`` if ignored.
    triangles : TriangleMesh or None
        Where every polygon is spanned by triangles (the default triangulates
        them all): the :class:`~heatcore.TriangleMesh` of those triangles,
        whose operators these are (the same numbers as the polygon build, to
        rounding, at a triangle mesh's cost); None where virtual vertices remain.
        ``weights``, ``prolongation``, ``refined_vertices``, ``refined_faces`` and
        ``refinement`` belong to the polygon build and are set by it only
        (``refinement`` is None otherwise).
    weights : float array
        Virtual-vertex weight of each corner of the refined polygons (1/3 on triangles, unused).
    prolongation : (n_ops + n_refined_virtual, n_ops) sparse matrix
        ``P``: operator vertices to refined vertices.
    refined_vertices : (n_ops + n_refined_virtual, 3) float array
    refined_faces : (f, 3) int array
        The (extrinsic) fan triangulation on refined vertices.
    n_virtual : int
        Input polygons with more than three corners that keep a virtual vertex.
    n_triangulated : int
        Input polygons triangulated instead (heatcore's triangulation,
        :mod:`~heatcore.domains.polygon_triangulate`): concave ones, whose
        virtual fan would fold, those with a nearly straight corner, and thin ones.
    part_levels : (n_parts,) int array
        Refinement levels of each connected part; ``levels`` is the largest.
    refinement : PolygonRefinement
        The refined polygon mesh the operators are built on (input vertices
        first), each part translated to put its first vertex at the origin.
    n_flips : int
        Intrinsic Delaunay flips on the refinement: among its triangles (those
        given, and those of triangulated polygons), as :class:`~heatcore.TriangleMesh`
        flips; with ``delaunay=True`` among the virtual fans' triangles too.
    thin_parts : int array
        Connected parts of triangles only (no virtual vertex) whose triangles
        were still thinner than ``THIN_TRIANGLE_SLACK`` after the flips, and
        were mollified to that slack, as :class:`~heatcore.TriangleMesh` does.
    mollification : (n_parts,) float array
        Length added to every refined edge of each connected part (0 for a
        clean part). Each part also gets its own mean edge length ``h``
        (the time step's), as in :class:`~heatcore.TriangleMesh`.

    Examples
    --------
    >>> import numpy as np, heatcore as hc
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0.2], [0, 1, 0], [2, 0.5, 0]], float)
    >>> mesh = PolygonMesh(V, [[0, 1, 2, 3], [1, 4, 2]], refine=0, virtual=True)
    >>> mesh.operators.laplacian.shape, mesh.n_virtual
    ((5, 5), 1)
    >>> PolygonMesh(V, [[0, 1, 2, 3], [1, 4, 2]], virtual=True).levels  # a small mesh is split first
    6
    """

    element_name = "polygon"
    domain_name = "polygon mesh"
    source_kinds = ("vertices", "edges", "region")
    unit_heat_once = True

    #: The options of :class:`~heatcore.settings.MeshSettings` this domain takes.
    mesh_options = ("refine",)

    def __init__(self, V, polygons, settings=None, *, virtual=False, delaunay=False, split_crossing=False,
                 only_parts_of=None, progress=None, **options):
        settings = MeshSettings.of(settings, **options)
        settings.refuse_untaken(self.mesh_options, self.domain_name)
        self.mesh_settings = settings
        progress = Progress(progress)
        progress(0.0, "reading the polygons")
        self.vertices = vertex_array(V)
        n = self.vertices.shape[0]
        offsets, indices = polygon_arrays(polygons, n)
        self.n_input_polygons = offsets.size - 1
        self.offsets, self.indices, kept = clean_polygons(offsets, indices)
        if self.offsets.size < 2:
            raise InvalidMeshError("no polygon has three distinct corners: the mesh has no area")
        self.parts_left_out = 0
        if only_parts_of is not None:
            kept[np.flatnonzero(kept)] = self._keep_parts_of(index_list(only_parts_of, n, "vertex"))
        self.polygon_map = np.full(kept.size, -1, dtype=np.int64)
        self.polygon_map[kept] = np.arange(int(kept.sum()))
        refine = settings.refine
        progress(0.05, "checking the polygons' shapes (crossing sides, concave corners)")
        planes = {}  # each size's plane coordinates: the crossing check's, reused by the triangulation
        offsets, indices, origin = simple_polygons(
            self.vertices, self.offsets, self.indices, np.flatnonzero(kept), split_crossing, planes
        )
        used = np.flatnonzero(np.bincount(self.indices, minlength=n))  # np.unique's result, no sort
        self.vertex_map = np.full(n, -1, dtype=np.int64)
        self.vertex_map[used] = np.arange(used.size)
        offsets, indices, self._origin, self.n_triangulated = triangulate_where_needed(
            self.vertices, offsets, indices, origin, everywhere=not virtual, planes=planes
        )
        self._spanned = (offsets, indices)
        self.delaunay = bool(delaunay)
        corners = self.vertex_map[indices]
        self._split = (offsets, corners)
        self.n_virtual = int((np.diff(offsets) > 3).sum())
        self.triangles = self.refinement = None
        if self._plain_triangles(offsets, indices, used.size):
            self._build_triangles(indices.reshape(-1, 3), refine, progress.part(0.45, 0.99))
            progress(1.0, "polygon mesh ready")
            return
        self.part_levels, levels, part = refine_levels(used.size, offsets, corners, refine)
        self.levels = int(self.part_levels.max())
        progress(0.45, f"polygon refinement ({self.levels} level{'s' * (self.levels != 1)})" if self.levels
                 else "virtual vertices")
        # each part split around its own first vertex: new points far from the origin keep their digits
        X = self.vertices[used]
        X = X - X[np.unique(part, return_index=True)[1]][part]
        self.refinement = unfold(split_polygons(X, offsets, corners, levels, area_minimizer_weights))
        r = self.refinement
        progress(0.6, "Laplacian, mass and gradient of the polygons")
        self.operators = self._build_operators(r.vertices, r.offsets, r.corners, used.size)
        progress(1.0, "polygon mesh ready")

    def _plain_triangles(self, offsets, indices, n_used):
        """Whether the polygons, as spanned, are triangles that :class:`~heatcore.TriangleMesh` builds as they are.

        Every polygon a triangle with three distinct corners (a polygon that visits
        a corner twice keeps its part unsplit: :func:`refine_levels`), on every used vertex.
        """
        if (np.diff(offsets) != 3).any():
            return False
        T = indices.reshape(-1, 3)
        if ((T[:, 0] == T[:, 1]) | (T[:, 1] == T[:, 2]) | (T[:, 0] == T[:, 2])).any():
            return False
        return np.count_nonzero(np.bincount(indices, minlength=self.vertices.shape[0])) == n_used

    def _build_triangles(self, triangles, refine, progress):
        """The operators of :class:`~heatcore.TriangleMesh` on the polygons' triangles: its numbers, at its cost."""
        mesh = TriangleMesh(self.vertices, triangles, refine=refine, weld=None, progress=progress)
        self.triangles, self.operators = mesh, mesh.operators
        self.left_out = (*self.left_out, *mesh.left_out)
        self.part_levels, self.levels = mesh.part_levels, mesh.levels
        self.n_flips, self.thin_parts, self.mollification = mesh.n_flips, mesh.thin_parts, mesh.mollification

    def two_step_vertices(self):
        """The vertices of the refined parts: :class:`~heatcore.TriangleMesh`'s where the polygons became its
        triangles, else every vertex once any part is refined (``virtual=True``).

        Examples
        --------
        >>> import numpy as np
        >>> V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)
        >>> PolygonMesh(V, [[0, 1, 2, 3]], refine=0).two_step_vertices() is None
        True
        """
        if self.triangles is not None:
            return self.triangles.two_step_vertices()
        return True if self.levels > 0 else None

    def _keep_parts_of(self, vertices):
        """Keep the polygons of the connected parts that hold one of ``vertices`` (all where none does)."""
        sizes = np.diff(self.offsets)
        owner = np.repeat(np.arange(sizes.size), sizes)
        inside, left_out = elements_in_parts_of(self.vertices.shape[0], owner, self.indices, vertices)
        if inside.any():  # else no source is on a polygon: the source checks say so
            self.parts_left_out = left_out
            left = np.zeros(self.vertices.shape[0], dtype=bool)
            left[self.indices[~inside[owner]]] = True
            left[self.indices[inside[owner]]] = False
            self.left_out = ((left, "lies on a part this mesh was built without (only_parts_of)"),)
            self.indices = self.indices[inside[owner]]
            self.offsets = np.r_[0, np.cumsum(sizes[inside])].astype(np.int64)
            return inside
        return np.ones_like(inside)

    @property
    def n_polygons(self):
        """Number of polygons kept."""
        return self.offsets.size - 1

    def _build_operators(self, X, offsets, corners, n_input):
        n = X.shape[0]
        sizes = np.diff(offsets)
        m = sizes.size
        # polygon edges: boundary flags and the time step's mean edge length
        nxt = np.arange(corners.size) + 1
        nxt[offsets[1:] - 1] = offsets[:-1]
        a, b = corners, corners[nxt]
        keys, counts = np.unique(np.minimum(a, b) * n + np.maximum(a, b), return_counts=True)
        edges = np.stack([keys // n, keys % n], axis=1)
        boundary = np.zeros(n, dtype=bool)
        boundary[edges[counts == 1].ravel()] = True
        count, part = vertex_components(edges, n)  # each connected part its own h
        h = part_means(np.linalg.norm(X[edges[:, 0]] - X[edges[:, 1]], axis=1), part[edges[:, 0]], count)
        if not (h > 0.0).all():
            raise InvalidMeshError("all edges have zero length: the mesh (or one of its parts) collapses to a point")
        self.polygon_edges = edges

        # virtual vertices, grouped by polygon size
        big = sizes > 3
        virtual = np.full(m, -1, dtype=np.int64)
        virtual[big] = n + np.arange(int(big.sum()))
        weights = np.full(corners.size, 1.0 / 3.0)
        for k in np.unique(sizes[big]):
            polys = np.flatnonzero(sizes == k)
            pos = offsets[polys][:, None] + np.arange(k)
            weights[pos] = operator_weights(X[corners[pos]] / h[part[corners[pos[:, 0]]]][:, None, None])
        self.weights = weights
        owner = np.repeat(np.arange(m), sizes)
        is_virtual = big[owner]
        rows = np.r_[np.arange(n), virtual[owner[is_virtual]]]
        cols = np.r_[np.arange(n), corners[is_virtual]]
        vals = np.r_[np.ones(n), weights[is_virtual]]
        N = n + int(big.sum())
        P = sp.csr_matrix((vals, (rows, cols)), shape=(N, n))
        self.prolongation = P
        self.refined_vertices = P @ X

        # refined faces: the fan (c_i, c_{i+1}, virtual) of each polygon, triangles as they are
        fan = np.stack([corners[is_virtual], corners[nxt][is_virtual], virtual[owner[is_virtual]]], axis=1)
        tri = corners[offsets[:-1][~big][:, None] + np.arange(3)]
        F = np.concatenate([tri, fan])
        self.refined_faces = F

        face_part = part[F[:, 0]]  # the first corner of a fan triangle is a polygon corner
        face_h = h[face_part][:, None]
        polygonal = np.bincount(part[corners[offsets[:-1][big]]], minlength=count) > 0  # parts with a virtual vertex
        unit_lengths, side_edge = face_edge_lengths(self.refined_vertices, F) / face_h, unique_edges(F)[1]
        flippable = None if self.delaunay else np.arange(len(F)) < len(tri)

        def triangulate(relative_delta):
            lengths, eps = mollify(unit_lengths, relative_delta, part=face_part, n_parts=count)
            intrinsic = IntrinsicTriangulation.from_mesh(None, F, lengths=lengths, side_edge=side_edge)
            # the triangles (given, or of the polygons triangulated) flip among themselves, as TriangleMesh's do
            return intrinsic, eps, intrinsic.flip_to_delaunay(flippable=flippable)

        intrinsic, eps, self.n_flips = triangulate(MOLLIFY_SLACK)
        # a part of triangles only is built as TriangleMesh builds it: if its triangles are still thinner than
        # THIN_TRIANGLE_SLACK after the flips, it is mollified to that slack (a part with virtual fans keeps 1e-6:
        # beast, whose split bowties are thin, measured 2.76% -> 2.80% with it)
        least = part_extremes(triangle_slack(intrinsic.lengths).min(axis=1), face_part, count)
        least[polygonal] = np.inf
        self.thin_parts = np.flatnonzero(least < THIN_TRIANGLE_SLACK)
        if self.thin_parts.size:
            intrinsic, eps, self.n_flips = triangulate(np.where(least < THIN_TRIANGLE_SLACK, THIN_TRIANGLE_SLACK,
                                                                MOLLIFY_SLACK))
        self.mollification = eps * h
        fan_ops = triangle_operators(intrinsic.lengths * face_h, intrinsic.faces, N, np.zeros(N, bool), 1.0)

        L = (P.T @ fan_ops.laplacian @ P).tocsr()
        L = 0.5 * (L + L.T)
        mass = P.T @ fan_ops.mass
        # Negative weights (strongly non-convex polygons) could in principle leave a
        # vertex without mass; give it the mass of its own fan triangles then.
        own = fan_ops.mass[:n]
        largest = part_extremes(own, part, count, largest=True)
        mass = np.where(mass > 1e-12 * largest[part], mass, own)
        G = (fan_ops.gradient @ P).tocsr()
        # elements for connectivity: virtual vertices stand in for their polygon's first corner
        stand_in = np.r_[np.arange(n), corners[offsets[:-1][big]]]
        elements = stand_in[intrinsic.faces]
        # refined parts (those with new vertices) diffuse longer: REFINED_TIME_FACTOR
        # (parts of triangles only keep TriangleMesh's step, whose mean edge is that of the same triangles)
        refined = np.zeros(count, dtype=bool)
        refined[part[n_input:]] = True
        refined &= polygonal
        time_h = h * np.where(refined, np.sqrt(REFINED_TIME_FACTOR), 1.0)
        return Operators(L, mass, G, fan_ops.volumes, 2, boundary, elements, time_h[part])

    def _element_corners(self):
        offsets, corners = self._spanned
        return np.repeat(np.arange(offsets.size - 1), np.diff(offsets)), corners

    def _element_sides(self, mark, elements=None):
        """The sides of the polygons at ``mark``ed corners, and the diagonals of the flat ones, which lie in them."""
        offsets, corners = self._spanned
        if elements is None:
            sizes = np.diff(offsets)
            elements = np.flatnonzero(np.bincount(np.repeat(np.arange(sizes.size), sizes), weights=mark[corners],
                                                  minlength=sizes.size))
        sizes = offsets[elements + 1] - offsets[elements]
        first = np.repeat(offsets[elements] - np.r_[0, np.cumsum(sizes)[:-1]], sizes) + np.arange(sizes.sum())
        return straight_chords(self.vertices, np.r_[0, np.cumsum(sizes)], corners[first])

    def _pin_edges(self, edges, pins):
        """Polygon edges (vertex pairs): their end points and the refined vertices on them, at distance 0."""
        e = edge_list(edges, self.n_input_vertices)
        ce = np.sort(self._referenced(e.ravel()).reshape(-1, 2), axis=1)
        sides = self._side_keys()
        not_side = ~np.isin(np.sort(e, axis=1) @ [self.n_input_vertices, 1], sides)
        if not_side.any():  # a diagonal of a triangulated polygon is an edge of its triangles, not of the mesh
            raise InvalidSourceError(f"vertex pair {e[np.flatnonzero(not_side)[0]].tolist()} is not an edge of the "
                                     "polygon mesh")
        if self.triangles is not None:
            pins.add(self.triangles.vertices_on_edges(e))
            return
        edges, r = self.refinement.edges, self.refinement
        n = int(max(edges.max(), ce.max())) + 1
        keys = edges[:, 0] * n + edges[:, 1]
        query = ce[:, 0] * n + ce[:, 1]
        pos = np.clip(np.searchsorted(keys, query), 0, max(keys.size - 1, 0))
        missing = keys[pos] != query
        if missing.any():
            bad = e[np.flatnonzero(missing)[0]].tolist()
            raise InvalidSourceError(f"vertex pair {bad} is not an edge of the polygon mesh")
        pins.add(np.r_[np.unique(ce), np.flatnonzero(np.isin(r.vertex_edge, pos))])

    def _side_keys(self):
        """The kept polygons' sides, each as ``n * min + max`` of its input vertices (``n``: input vertex count)."""
        nxt = np.arange(self.indices.size) + 1
        nxt[self.offsets[1:] - 1] = self.offsets[:-1]
        a, b = self.indices, self.indices[nxt]
        return np.minimum(a, b) * self.n_input_vertices + np.maximum(a, b)

    def _pin_region(self, polygons, pins):
        """Input polygons (indices): their corners, at distance 0."""
        f = index_list(polygons, self.n_input_polygons, "polygon")
        kept = self.polygon_map[f]
        if (kept < 0).any():
            bad = int(f[kept < 0][0])
            raise InvalidSourceError(f"polygon {bad} was ignored (fewer than 3 distinct corners or a duplicate)")
        starts, stops = self.offsets[kept], self.offsets[kept + 1]
        sizes = stops - starts
        pos = np.repeat(starts - np.r_[0, np.cumsum(sizes)[:-1]], sizes) + np.arange(sizes.sum())
        corners = np.unique(self.vertex_map[self.indices[pos]])
        split = np.flatnonzero(np.isin(self._origin, kept))  # the polygons split (crossing ones: triangles)
        inside = (self.triangles.vertices_inside(split) if self.triangles is not None
                  else vertices_inside(self.refinement, *self._split, split))
        pins.add(np.r_[corners, inside])

