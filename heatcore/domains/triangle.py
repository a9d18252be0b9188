"""Triangle meshes: cotan Laplacian, lumped mass, per-face gradient and divergence.

All operators are built from edge lengths alone, on the intrinsic Delaunay
triangulation of the (mollified) mesh by default, so gradients and the
divergence live on the same intrinsic triangles as the Laplacian.

Examples
--------
>>> import numpy as np
>>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
>>> mesh = TriangleMesh(V, [[0, 1, 2], [1, 3, 2]], refine=0)
>>> mesh.operators.laplacian.shape
(4, 4)
"""

import dataclasses
import functools
import warnings

import numpy as np

from ..errors import (
    HeatcoreWarning,
    InvalidMeshError,
    InvalidSourceError,
)
from ..progress import Progress
from ..settings import MeshSettings
from .base import MeshDomain
from .cotan import intrinsic_triangulation
from .flat_parts import flat_parts
from .intrinsic import face_edge_lengths
from .parts import in_part_units, unit_exponents, vertex_components
from .refine import (
    AUTO_REFINE_BUDGET,
    AUTO_REFINE_MIN_VERTICES,
    auto_refine_levels,
    budgeted_levels,
    midpoint_subdivide,
)
from .sources import barycentric_array, edge_list, index_list
from .validate import clean_elements, mesh_arrays
from .weld import weld_map

#: Smallest triangle slack ``l_a + l_b - l_c`` (relative to the part's mean
#: edge length) the operators may keep. A part whose triangles are still
#: thinner after the intrinsic Delaunay flips (a strip 1e-8 wide, which no flip
#: can mend) gives cotangent weights of 1e5 and more, and the linear solves
#: lose every digit: it is mollified to this slack instead of 1e-6, which
#: lengthens its edges by at most 0.1% of the mean edge length. No shared test
#: mesh comes near it (their smallest slack after the flips: 4e-3 to 0.13).
THIN_TRIANGLE_SLACK = 1e-3


class TriangleMesh(MeshDomain):
    """A triangle mesh as a heat-method domain.

    Parameters
    ----------
    V : (n, 3) array_like of float
        Vertex positions.
    F : (m, 3) array_like of int
        Triangles (vertex indices). Faces with repeated vertices, duplicate
        faces and connected parts whose faces all have no area (collinear or
        coincident corners: :mod:`heatcore.domains.flat_parts`) are ignored
        with a warning; unreferenced vertices get ``inf``. A mesh with no area
        at all is an :class:`~heatcore.errors.InvalidMeshError`.
    settings : MeshSettings or Settings, optional
        The mesh options, checked (:mod:`heatcore.settings`), as front ends
        hand them over; the keywords below (checked here) change them.
    robust : bool, default True
        Build the operators on the intrinsic Delaunay triangulation of the
        mollified mesh (accurate on badly shaped triangles, tolerant of
        non-manifold edges). ``False`` gives the plain cotan operators.
    refine : "auto" or int, default "auto"
        Levels of midpoint subdivision before building the operators. "auto"
        subdivides each connected part with fewer than
        ``AUTO_REFINE_MIN_VERTICES`` vertices until it has that many (a
        coarse part cannot resolve the distance with one level of
        triangles); results are reported at the input vertices.
    weld : float or None, default 0.0
        Merge vertices closer than this tolerance (in the mesh's units; 0:
        only vertices at exactly the same position), as STL files (triangle
        soup) and OBJ files with texture seams need. ``None`` keeps every
        vertex apart. Distances are still reported at every input vertex.
    progress : callable, optional
        ``progress(fraction, message)`` at the start of each stage of the
        build (welding, connected parts, refinement, intrinsic Delaunay flips)
        and with 1.0 at the end; it may raise to abort the build
        (see :mod:`heatcore.progress`). Default: silent.
    only_parts_of : sequence of int, optional
        Input vertices: only the connected parts that hold one of them are
        built (refined, triangulated, factored later); the other parts'
        vertices are left out (``inf`` from any source, and refused as
        sources). A one-off query passes its sources' vertices
        (:func:`~heatcore.domains.sources.source_vertices`): every part is
        solved as if alone, so its distances are the same.

    Each connected part is solved as if it were alone: its own refinement
    level, time step, mollification and length unit (:mod:`heatcore.domains.parts`),
    so its distances do not depend on the other parts, and scaling the mesh
    by any finite factor scales the distances by the same factor.

    Attributes
    ----------
    operators : Operators
        Built on first use: the compiled ``accuracy="high"`` pass needs only
        :attr:`intrinsic`.
    n_welded : int
        Input vertices merged into another one by welding.
    n_parts : int
        Connected parts (after welding) built.
    parts_left_out : int
        Connected parts not built (``only_parts_of``).
    part_levels : (n_parts,) int array
        Midpoint subdivision levels of each part; ``levels`` is the largest.
    unit_exponent : (n_parts,) int array
        Each part's length unit, ``2**unit_exponent`` (0 for parts of
        ordinary size; see :func:`heatcore.domains.parts.unit_exponents`).
    n_flips : int
        Edge flips made by the intrinsic Delaunay step.
    mollification : (n_parts,) float array
        Length added to every edge of each part by mollification, in the
        input's units (0 for clean parts).
    thin_parts : int array
        Parts whose triangles were too thin to solve accurately as they are,
        mollified more strongly (see ``THIN_TRIANGLE_SLACK``; robust meshes
        only: ``robust=False`` keeps the plain cotan operators as they are).
    intrinsic : IntrinsicTriangulation
        The triangulation the operators are built on (faces index operator
        vertices; lengths in each part's unit).
    subdivision : Subdivision
        The (possibly midpoint-refined) mesh, in each part's unit; its first
        vertices are the input's referenced vertices, in ``vertex_map``
        order. Its ``mesh_edges``, ``side_edge`` and ``side_pairs`` are dropped (None) once
        the operators are built.

    Examples
    --------
    >>> import numpy as np
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    >>> TriangleMesh(V, [[0, 1, 2]]).operators.n_vertices > 3
    True
    >>> soup = np.vstack([V, [[1, 0, 0], [1, 1, 0], [0, 1, 0]]])  # two triangles, six vertices
    >>> mesh = TriangleMesh(soup, [[0, 1, 2], [3, 4, 5]], refine=0)
    >>> mesh.n_welded, mesh.operators.n_vertices, mesh.n_parts
    (2, 4, 1)
    """

    element_name = "face"
    domain_name = "triangle mesh"
    source_kinds = ("vertices", "edges", "region", "points")
    supports_high_accuracy = True

    #: The options of :class:`~heatcore.settings.MeshSettings` this domain takes.
    mesh_options = ("robust", "refine", "weld")

    def __init__(self, V, F, settings=None, *, progress=None, only_parts_of=None, **options):
        self.vertices, self.faces = mesh_arrays(V, F)
        settings = MeshSettings.of(settings, **options)
        settings.refuse_untaken(self.mesh_options, self.domain_name)
        refine, tolerance, self.robust = settings.refine, settings.weld, settings.robust
        progress = Progress(progress)
        progress(0.0, "welding coincident vertices" if tolerance is not None else "reading the triangles")
        representative, self.n_welded = weld_map(self.vertices, tolerance) if tolerance is not None else (None, 0)
        faces = representative[self.faces] if self.n_welded else self.faces  # no copy where nothing was welded
        kept = clean_elements(faces, stacklevel=3)
        if not kept.any():
            raise InvalidMeshError(
                f"every face has a repeated vertex{self._welded()}: all edges have zero length, the mesh has no area"
            )
        progress(0.1, "finding connected parts")
        V_used, F_used, part = self._surface(faces, kept, representative)
        if self._drop_flat_parts(faces, kept, V_used, F_used, part):
            V_used, F_used, part = self._surface(faces, kept, representative)
        self.parts_left_out = 0
        if only_parts_of is not None and self.n_parts > 1 and self._keep_parts_of(only_parts_of, faces, kept, part):
            V_used, F_used, part = self._surface(faces, kept, representative)
        if refine == "auto":
            sizes = np.bincount(part, minlength=self.n_parts)
            work = np.maximum(sizes, np.bincount(part[F_used[:, 0]], minlength=self.n_parts) // 2)  # soups: faces
            self.part_levels, cap = budgeted_levels(work, auto_refine_levels(sizes))
            if cap is not None:
                warnings.warn(
                    f"refine='auto': {self.n_parts:,} parts refined to at most {cap} levels each (not the "
                    f"{AUTO_REFINE_MIN_VERTICES:,} vertices a part gets alone), to stay under "
                    f"{AUTO_REFINE_BUDGET:,} vertices in all; pass refine=LEVELS to choose",
                    HeatcoreWarning,
                    stacklevel=2,
                )
        else:
            self.part_levels = np.full(self.n_parts, int(refine), dtype=np.int64)
        self.levels = int(self.part_levels.max())
        self.unit_exponent = unit_exponents(V_used, part, self.n_parts)
        self._input_part = part
        face_levels = self.part_levels[part[F_used[:, 0]]]
        levels = f"{self.levels} level{'s' * (self.levels > 1)}"
        progress(0.2, f"midpoint subdivision ({levels})" if self.levels else "listing the edges")
        self.subdivision = midpoint_subdivide(in_part_units(V_used, part, self.unit_exponent), F_used, face_levels)
        self._triangulate(self.subdivision.carry(part, F_used), progress.part(0.4, 1.0))
        progress(1.0, "triangle mesh ready")

    def _welded(self):
        """What an error about the faces adds when welding changed them."""
        return " once coincident vertices are welded" if self.n_welded else ""

    def _drop_flat_parts(self, faces, kept, V_used, F_used, part):
        """Drop from ``kept`` the faces of parts with no area (:mod:`.flat_parts`), with a warning; whether any went."""
        face_part = part[F_used[:, 0]]
        flat = flat_parts(V_used, F_used, face_part, self.n_parts)
        if not flat.any():
            return False
        if flat.all():
            raise InvalidMeshError(
                f"the mesh has no area{self._welded()}: the corners of every face are collinear or coincident, "
                "so there is no surface for heat to spread on"
            )
        kept_faces, on_flat_part = faces[kept], flat[face_part]
        on_flat = self._left_out(kept_faces[on_flat_part], kept_faces[~on_flat_part], "lies on a part with no "
                                 "area (the corners of all its faces are collinear or coincident), where heat cannot spread")
        warnings.warn(
            f"ignored {int(on_flat_part.sum()):,} faces on {int(on_flat.sum()):,} vertices: they form parts "
            "with no area (collinear or coincident corners); those vertices are unreachable (inf)",
            HeatcoreWarning,
            stacklevel=3,
        )
        kept[kept] = ~on_flat_part
        return True

    def _surface(self, faces, kept, representative):
        """Number the vertices the ``kept`` faces use; sets ``vertex_map``, ``face_map`` and ``n_parts``.

        Returns the used vertices, the kept faces on them and each used vertex's connected part.
        """
        n = self.vertices.shape[0]
        used = np.flatnonzero(np.bincount(faces[kept].ravel(), minlength=n))  # np.unique's result, no sort
        compact = np.full(n, -1, dtype=np.int64)
        compact[used] = np.arange(used.size)
        self.vertex_map = compact if representative is None else compact[representative]
        self.face_map = np.full(self.faces.shape[0], -1, dtype=np.int64)
        self.face_map[kept] = np.arange(int(kept.sum()))
        if used.size == n and kept.all():  # a clean mesh: no renumbered copy needed
            V_used, F_used = self.vertices, faces
        else:
            V_used, F_used = self.vertices[used], compact[faces[kept]]
        self.n_parts, part = vertex_components(F_used, used.size)
        return V_used, F_used, part

    def _keep_parts_of(self, vertices, faces, kept, part):
        """Drop from ``kept`` the faces of the parts that hold none of the input ``vertices``; whether any went.

        ``part``: the connected part of each vertex of :meth:`_surface`. Where
        no vertex is on a face, nothing goes (the source checks say so).
        """
        holding = self.vertex_map[index_list(vertices, self.vertices.shape[0], "vertex")]
        inside = np.zeros(self.n_parts, dtype=bool)
        inside[part[holding[holding >= 0]]] = True
        if not inside.any() or inside.all():
            return False
        kept_faces = faces[kept]
        face_inside = inside[part[self.vertex_map[kept_faces[:, 0]]]]
        self.parts_left_out = int((~inside).sum())
        self._left_out(kept_faces[~face_inside], kept_faces[face_inside],
                       "lies on a part this mesh was built without (only_parts_of)")
        kept[kept] = face_inside
        return True

    def _left_out(self, out, kept, why):
        """Record the vertices of faces ``out`` that no face of ``kept`` uses as left out, and why."""
        mask = np.zeros(self.vertices.shape[0], dtype=bool)
        mask[out.ravel()] = True
        mask[kept.ravel()] = False  # a vertex shared with a kept part stays
        self.left_out = (*self.left_out, (mask, why))
        return mask

    def _triangulate(self, part, progress=None):
        """The intrinsic Delaunay triangulation (:func:`~heatcore.domains.cotan.intrinsic_triangulation`) of the
        subdivision, whose vertices are in connected parts ``part``; the operators wait for their first use."""
        sub = self.subdivision
        robust = self.robust
        built = intrinsic_triangulation(
            sub.vertices,
            sub.faces,
            sub.mesh_edges,
            sub.side_edge,
            part=part,
            n_parts=self.n_parts,
            flip=robust,
            thin_slack=THIN_TRIANGLE_SLACK if robust else None,
            unit_exponent=self.unit_exponent,
            progress=progress,
            side_pairs=sub.side_pairs,
        )
        self.n_flips, self.thin_parts, self.intrinsic = built.n_flips, built.thin_parts, built.intrinsic
        self._built = built
        # The parts of the input faces, carried to the refined vertices: flips keep parts, and each part is still
        # numbered by its smallest vertex (an input vertex), so they are the parts of the operators' elements.
        self._vertex_parts = (self.n_parts, part)
        self.mollification = np.ldexp(built.eps * built.h, self.unit_exponent)
        # Only the build needs the refined mesh's edges (1M vertices: 48-96 MB).
        self.subdivision = dataclasses.replace(sub, mesh_edges=None, side_edge=None, side_pairs=None)

    @functools.cached_property
    def operators(self):
        """The cotan operators on :attr:`intrinsic`, built on first use (a one-off ``accuracy="high"`` query with
        numba needs none; on a 1M-vertex sphere they take 0.7-1.5 s and keep 0.27 GB, 0.48 GB at their peak).

        Examples
        --------
        >>> import numpy as np
        >>> mesh = TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0)
        >>> "operators" in vars(mesh), mesh.operators.n_vertices, "operators" in vars(mesh)
        (False, 3, True)
        """
        operators = self._built.operators()
        operators.parts = self._vertex_parts
        return operators

    @property
    def n_vertices(self):
        """Number of operator vertices (without building the operators)."""
        return self._vertex_parts[1].size

    @property
    def vertex_unit_exponent(self):
        """Each operator vertex's length unit (without building the operators)."""
        return self._built.unit_exponent

    @property
    def vertex_parts(self):
        """``(n_parts, part of each operator vertex)``, the operators' ``parts`` (without building them)."""
        return self._vertex_parts

    def eikonal_triangles(self):
        """The intrinsic Delaunay triangles, and the (refined) mesh's own where flips replaced them, with their lengths.

        The ``accuracy="high"`` pass may cross either (see :mod:`heatcore.eikonal`).
        A face no flip touched is the same row of both (the intrinsic
        triangulation starts as a copy of the mesh's faces), so only the rows
        that differ are listed again (on the 1M-vertex cube sphere of `scripts/bench_scale.py`, half of them).

        Examples
        --------
        >>> import numpy as np
        >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0.6, 0.6, 0]])
        >>> faces, lengths = TriangleMesh(V, [[0, 1, 2], [1, 3, 2]], refine=0).eikonal_triangles()
        >>> faces[0].tolist(), faces[1].tolist()  # the diagonal 1-2 flipped to 0-3; the mesh's own triangles too
        ([[3, 2, 0], [0, 1, 3]], [[0, 1, 2], [1, 3, 2]])
        >>> float(lengths[1][0].max().round(3))  # the mesh's diagonal, sqrt(2)
        1.414
        >>> [len(f) for f in TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0).eikonal_triangles()[0]]  # nothing flipped
        [1, 0]
        """
        tri, sub = self.intrinsic, self.subdivision
        replaced = sub.faces[(tri.faces != sub.faces).any(axis=1)]
        return [tri.faces, replaced], [tri.lengths, face_edge_lengths(sub.vertices, replaced)]

    def two_step_vertices(self):
        """The vertices of the refined parts (:meth:`Domain.two_step_vertices <heatcore.domains.base.Domain.two_step_vertices>`).

        Examples
        --------
        >>> import numpy as np
        >>> V, F = np.eye(3), [[0, 1, 2]]
        >>> TriangleMesh(V, F, refine=0).two_step_vertices() is None, TriangleMesh(V, F, refine=1).two_step_vertices()
        (True, True)
        """
        refined = self.part_levels > 0
        if not refined.any():
            return None
        return True if refined.all() else refined[self._vertex_parts[1]]

    def _element_corners(self):
        kept = np.flatnonzero(self.face_map >= 0)
        return np.repeat(kept, 3), self.faces[kept].ravel()

    def _element_sides(self, mark, elements=None):
        if elements is None:
            hit = mark[self.faces]
            elements = (hit[:, 0] | hit[:, 1] | hit[:, 2]) & (self.face_map >= 0)  # 3x faster than any(axis=1)
        faces = self.faces[elements]
        return faces.ravel(), np.roll(faces, -1, axis=1).ravel()

    def _point_elements(self):
        return self.faces

    def vertices_on_edges(self, edges):
        """Operator vertices on mesh edges (input vertex pairs): their end points and the refined vertices on them.

        Raises :class:`~heatcore.errors.InvalidSourceError` for a pair that is not an edge of the mesh.

        Examples
        --------
        >>> import numpy as np
        >>> mesh = TriangleMesh(np.eye(3), [[0, 1, 2]], refine=1)
        >>> mesh.vertices_on_edges([[0, 1]]).tolist()  # the ends and the midpoint
        [0, 1, 3]
        """
        e = edge_list(edges, self.n_input_vertices)
        ce = np.sort(self._referenced(e.ravel()).reshape(-1, 2), axis=1)
        edge_id = self._edge_ids(ce, e)
        inner = np.flatnonzero(np.isin(self.subdivision.vertex_edge, edge_id))
        return np.r_[np.unique(ce), inner]

    def _pin_edges(self, edges, pins):
        """Mesh edges (vertex pairs): their end points and the refined vertices on them, at distance 0."""
        pins.add(self.vertices_on_edges(edges))

    def _pin_region(self, faces, pins):
        """Faces (indices): their corners and the refined vertices inside them, at distance 0."""
        f = index_list(faces, self.faces.shape[0], "face")
        corners = np.unique(self.vertex_map[self.faces[f]])
        corners = corners[corners >= 0]  # an ignored face may have corners no kept face uses
        pins.add(np.r_[corners, self.vertices_inside(f)])

    def _pin_points(self, points, pins):
        """Points on faces ``(face_indices, barycentric)``: straight-line distances inside each face."""
        try:
            fi, bary = points
        except (TypeError, ValueError):
            raise InvalidSourceError("points must be a pair (face indices, barycentric coordinates)") from None
        fi = index_list(fi, self.faces.shape[0], "face")
        b = barycentric_array(bary, fi.size, 3)
        ignored = fi[self.face_map[fi] < 0]
        if ignored.size:
            raise InvalidSourceError(
                f"face {int(ignored[0])} was ignored (it has repeated vertices, after welding, duplicates "
                "another face, or lies in a part with no area), so a point on it cannot be a source; use a "
                "vertex or another face"
            )
        sub = self.subdivision
        for k in range(fi.size):  # a handful of points: one pin set per point
            tri = self.vertex_map[self.faces[fi[k]]]
            corners = sub.vertices[tri]  # in the part's unit, as every pinned distance
            inside = np.r_[tri, self.vertices_inside(fi[k : k + 1])]
            d = np.linalg.norm(sub.vertices[inside] - b[k] @ corners, axis=1)
            hv, hw = self._point_impulse(corners, self._part_levels_of(tri[0]), b[k], inside)
            pins.add(inside, d, hv, hw)

    def _part_levels_of(self, operator_vertex):
        """Subdivision levels of the part of an input vertex (given as its operator vertex)."""
        return int(self.part_levels[self._input_part[operator_vertex]])

    def _point_impulse(self, corners, levels, bary, inside):
        """Hat-function weights of a face point on the refined mesh (vertices, weights).

        After ``L`` levels of midpoint subdivision the vertices inside an input
        face (``corners``, in the part's unit) sit on the barycentric lattice of
        spacing ``1 / 2^L``; the point lies in one lattice triangle, whose
        corners get its barycentric weights.
        """
        N = 2**levels
        A = np.column_stack([corners[1] - corners[0], corners[2] - corners[0]])
        uv = np.linalg.lstsq(A, (self.subdivision.vertices[inside] - corners[0]).T, rcond=None)[0].T
        lattice = np.rint(np.column_stack([1 - uv.sum(1), uv]) * N).astype(np.int64)
        B = bary * N
        base = np.minimum(np.floor(B + 1e-12), N).astype(np.int64)
        frac = B - base
        excess = N - int(base.sum())
        if excess <= 0:  # the point is a lattice vertex
            cell, weights = [base], [1.0]
        elif excess == 1:  # upward lattice triangle
            cell = [base + np.eye(3, dtype=np.int64)[c] for c in range(3)]
            weights = list(frac)
        else:  # downward lattice triangle
            cell = [base + 1 - np.eye(3, dtype=np.int64)[c] for c in range(3)]
            weights = list(1.0 - frac)
        idx = [inside[np.flatnonzero((lattice == corner).all(axis=1))[0]] for corner in cell]
        return np.asarray(idx), np.clip(np.asarray(weights, dtype=float), 0.0, None)

    def _edge_ids(self, compact_pairs, user_pairs):
        edges = self.subdivision.edges
        n = self.n_vertices
        keys = edges[:, 0] * n + edges[:, 1]
        query = compact_pairs[:, 0] * n + compact_pairs[:, 1]
        pos = np.clip(np.searchsorted(keys, query), 0, keys.size - 1)
        missing = keys[pos] != query
        if missing.any():
            bad = user_pairs[np.flatnonzero(missing)[0]].tolist()
            raise InvalidSourceError(f"vertex pair {bad} is not an edge of the mesh")
        return pos

    def vertices_inside(self, user_faces):
        """Refined operator vertices lying on the sides of, or inside, the given input faces (none without refinement).

        Examples
        --------
        >>> import numpy as np
        >>> mesh = TriangleMesh(np.eye(3), [[0, 1, 2]], refine=1)
        >>> mesh.vertices_inside([0]).tolist()  # the three midpoints
        [3, 4, 5]
        """
        sub = self.subdivision
        if self.levels == 0:
            return np.zeros(0, dtype=np.int64)
        cf = self.face_map[user_faces]
        cf = cf[cf >= 0]
        tri = self.vertex_map[self.faces[user_faces]]
        sides = np.sort(np.stack([tri[:, [1, 2, 0]], tri[:, [2, 0, 1]]], axis=2).reshape(-1, 2), axis=1)
        n = self.n_vertices
        keys = sub.edges[:, 0] * n + sub.edges[:, 1]
        query = sides[:, 0] * n + sides[:, 1]
        pos = np.clip(np.searchsorted(keys, query), 0, keys.size - 1)
        side_ids = pos[keys[pos] == query]
        return np.flatnonzero(np.isin(sub.vertex_face, cf) | np.isin(sub.vertex_edge, side_ids))
