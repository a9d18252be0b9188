"""Cotan operators of triangles given by their edge lengths, built on the intrinsic Delaunay triangulation.

Two steps that every triangle-based domain shares:

* :func:`triangle_operators`: cotan Laplacian, lumped mass, per-triangle
  gradient (in a 2D layout of each triangle) and element areas from the
  edge lengths alone;
* :func:`intrinsic_triangulation`: from a mesh with its edge table,
  boundary vertices, mean edge length (per connected part), mollification
  and intrinsic Delaunay flips at unit mean edge length; its
  :meth:`~IntrinsicBuild.operators` are :func:`triangle_operators` on the
  flipped triangles, and :func:`intrinsic_operators` both at once.

:class:`~heatcore.domains.triangle.TriangleMesh` runs
:func:`intrinsic_triangulation` on its (refined) faces, one connected part at a
time, and builds the operators on first use; :class:`~heatcore.domains.pointcloud.PointCloud` on the tufted cover of
its proposed triangles (:func:`~heatcore.domains.pointcloud.tufted_cover`);
:class:`~heatcore.domains.polygon.PolygonMesh` calls :func:`triangle_operators`
on its fan triangles.

Examples
--------
>>> import numpy as np
>>> from heatcore.domains.refine import unique_edges
>>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
>>> F = np.array([[0, 1, 2], [1, 3, 2]])
>>> built = intrinsic_operators(V, F, *unique_edges(F))
>>> L, A = built.operators.laplacian, built.operators.volumes
>>> G = built.operators.gradient
>>> bool(np.allclose(L.toarray(), (G.T @ np.diag(np.repeat(A, 2)) @ G)))
True
"""

from typing import NamedTuple

import numpy as np
import scipy.sparse as sp

from ..errors import InvalidMeshError
from ..progress import Progress
from .intrinsic import (
    NEXT,
    PREV,
    IntrinsicTriangulation,
    corner_cotangents,
    face_areas,
    face_edge_lengths,
    mollify,
    triangle_slack,
)
from .operators import Operators, laplacian_from_weights
from .parts import part_extremes, part_means, row_reduce

#: Smallest slack ``l_a + l_b - l_c`` (relative to the mean edge length) that
#: :func:`intrinsic_operators` asks of every triangle by default (mollification).
MOLLIFY_SLACK = 1e-6


def triangle_operators(lengths, faces, n_vertices, boundary, mean_edge_length, unit_exponent=0):
    """Operator bundle of a triangulation given by its edge lengths.

    Parameters
    ----------
    lengths : (m, 3) float array, column ``c`` opposite corner ``c``
    faces : (m, 3) int array
    n_vertices : int
    boundary : (n,) bool array
    mean_edge_length : float or (n,) float array
    unit_exponent : int or (n,) int array
        See :class:`~heatcore.domains.operators.Operators`.

    Returns
    -------
    Operators
        Gradients are expressed in a 2D frame laid out on each triangle.

    Examples
    --------
    >>> import numpy as np
    >>> ops = triangle_operators(np.array([[1.0, 1.0, 1.0]]), np.array([[0, 1, 2]]), 3, np.ones(3, bool), 1.0)
    >>> ops.laplacian.toarray().round(3).tolist()[0], round(float(ops.volumes[0]), 4)
    ([0.577, -0.289, -0.289], 0.433)
    """
    areas = face_areas(lengths)
    cot = corner_cotangents(lengths, areas)
    a = faces[:, NEXT].ravel()
    b = faces[:, PREV].ravel()
    L = laplacian_from_weights(a, b, 0.5 * cot.ravel(), n_vertices)  # half the cotangent opposite each side
    mass = np.bincount(faces.ravel(), weights=np.repeat(areas / 3.0, 3), minlength=n_vertices)

    # Planar layout of each triangle: corner 0 at (0, 0), corner 1 at (l2, 0), corner 2 at (x, y).
    # The gradient of corner c's hat function is the edge opposite c (counter-clockwise)
    # turned by 90 degrees, over twice the area.
    l0, l1, l2 = lengths.T
    x = (l1**2 + l2**2 - l0**2) / (2.0 * l2)
    y = 2.0 * areas / l2
    m = faces.shape[0]
    grad_hat = np.empty((m, 2, 3))  # row 2 f + k of G: component k on face f, one column per corner
    grad_hat[:, 0, 0], grad_hat[:, 0, 1], grad_hat[:, 0, 2] = -y, y, 0.0
    grad_hat[:, 1, 0], grad_hat[:, 1, 1], grad_hat[:, 1, 2] = x - l2, -x, l2
    grad_hat /= (2.0 * areas)[:, None, None]
    index = np.int32 if max(n_vertices, 6 * m + 1) < np.iinfo(np.int32).max else np.int64
    columns = np.repeat(faces[:, None, :].astype(index), 2, axis=1).ravel()
    G = sp.csr_matrix((grad_hat.ravel(), columns, np.arange(0, 6 * m + 1, 3, dtype=index)), shape=(2 * m, n_vertices))
    return Operators(L, mass, G, areas, 2, boundary, faces, mean_edge_length, unit_exponent)


def segment_lengths(V, pairs):
    """Lengths of the segments ``V[pairs[:, 0]]`` to ``V[pairs[:, 1]]``: ``np.linalg.norm(..., axis=1)``'s numbers
    (the same sum of squares, in the same order), without its general-purpose passes.

    Examples
    --------
    >>> segment_lengths(np.array([[0, 0, 0], [3, 4, 0]], float), np.array([[0, 1]])).tolist()
    [5.0]
    """
    D = V[pairs[:, 0]] - V[pairs[:, 1]]
    squares = D[:, 0] * D[:, 0]
    for axis in range(1, D.shape[1]):
        squares += D[:, axis] * D[:, axis]
    return np.sqrt(squares, out=squares)


class IntrinsicBuild(NamedTuple):
    """What :func:`intrinsic_triangulation` builds: the triangulation, and what its operators take besides.

    Attributes
    ----------
    intrinsic : IntrinsicTriangulation
        The (flipped) triangulation the operators are built on, lengths in the input's units.
    n_flips : int
        Edge flips made (of the last mollification, when thin parts were mollified again).
    eps : float or (n_parts,) float array
        Length added to every edge by mollification, in units of the (part's) mean edge length.
    h : float or (n_parts,) float array
        Mean edge length (of each part), in the input's units.
    thin_parts : int array
        Parts mollified again because their triangles were thinner than ``thin_slack``.
    boundary : (n,) bool array
        Boundary vertices.
    mean_edge_length : float or (n,) float array
        ``h`` of each vertex's part (one float without parts).
    unit_exponent : int or (n,) int array
        Each vertex's length unit (see :class:`~heatcore.domains.operators.Operators`).

    Examples
    --------
    >>> import numpy as np
    >>> from heatcore.domains.refine import unique_edges
    >>> F = np.array([[0, 1, 2]])
    >>> built = intrinsic_triangulation(np.eye(3), F, *unique_edges(F))
    >>> built.n_flips, built.eps, round(built.h, 3), built.intrinsic.faces.tolist()
    (0, 0.0, 1.414, [[0, 1, 2]])
    >>> built.operators().laplacian.shape
    (3, 3)
    """

    intrinsic: IntrinsicTriangulation
    n_flips: int
    eps: object
    h: object
    thin_parts: np.ndarray
    boundary: np.ndarray
    mean_edge_length: object
    unit_exponent: object

    def operators(self):
        """The cotan operators on the triangulation (:func:`triangle_operators`)."""
        tri = self.intrinsic
        return triangle_operators(tri.lengths, tri.faces, self.boundary.size, self.boundary, self.mean_edge_length,
                                  self.unit_exponent)


class IntrinsicOperators(NamedTuple):
    """What :func:`intrinsic_operators` builds: :class:`IntrinsicBuild`'s fields and the operators on them.

    Attributes
    ----------
    operators : Operators
    intrinsic, n_flips, eps, h, thin_parts
        As in :class:`IntrinsicBuild`.

    Examples
    --------
    >>> import numpy as np
    >>> from heatcore.domains.refine import unique_edges
    >>> F = np.array([[0, 1, 2]])
    >>> built = intrinsic_operators(np.eye(3), F, *unique_edges(F))
    >>> built.operators.laplacian.shape, built.operators.mass.round(3).tolist()
    ((3, 3), [0.289, 0.289, 0.289])
    """

    operators: Operators
    intrinsic: IntrinsicTriangulation
    n_flips: int
    eps: object
    h: object
    thin_parts: np.ndarray


def intrinsic_operators(V, F, edges, side_edge, *, progress=None, **options):
    """Cotan operators of a triangle mesh, on its mollified intrinsic Delaunay triangulation.

    :func:`intrinsic_triangulation` (same parameters), then
    :func:`triangle_operators` on the flipped triangles.

    Returns
    -------
    IntrinsicOperators
        The operators and what the build measured on the way.

    Examples
    --------
    >>> import numpy as np
    >>> from heatcore.domains.refine import unique_edges
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
    >>> F = np.array([[0, 1, 2], [1, 3, 2]])
    >>> built = intrinsic_operators(V, F, *unique_edges(F))
    >>> built.operators.boundary.tolist(), built.n_flips, round(built.h, 4)
    ([True, True, True, True], 0, 1.0828)
    >>> V[3] = [0.6, 0.6, 0]  # the angles opposite the diagonal sum to over pi: it is flipped
    >>> intrinsic_operators(V, F, *unique_edges(F)).n_flips
    1
    """
    progress = Progress(progress)
    built = intrinsic_triangulation(V, F, edges, side_edge, progress=progress.part(0.0, 0.6), **options)
    progress(0.6, "cotan Laplacian, mass and gradient")
    return IntrinsicOperators(built.operators(), *built[:5])


def intrinsic_triangulation(
    V, F, edges, side_edge, *, part=None, n_parts=1, cover=None, rim=None, flip=True, thin_slack=None, unit_exponent=0,
    progress=None, side_pairs=None,
):
    """The mollified intrinsic Delaunay triangulation of a triangle mesh, ready for its cotan operators.

    The edges are measured in ``V``; each connected part is scaled to unit
    mean edge length, mollified (every triangle gets a slack ``l_a + l_b -
    l_c`` of at least ``MOLLIFY_SLACK``), flipped to intrinsic Delaunay and
    scaled back; :meth:`IntrinsicBuild.operators` builds the bundle on the
    flipped triangles (:func:`triangle_operators`), when they are needed.
    Working at unit mean edge length makes the result scale exactly with
    the mesh.

    Parameters
    ----------
    V : (n, 3) float array
        Vertex positions.
    F : (m, 3) int array
        Faces.
    edges : (k, 2) int array
        The mesh's unique edges (sorted vertex pairs, as from
        :func:`heatcore.domains.refine.unique_edges`).
    side_edge : (m, 3) int array
        Edge id (into ``edges``) of the side of each face opposite each corner.
    part : (n,) int array, optional
        Connected part of each vertex: each part gets its own mean edge
        length, mollification, thin-triangle treatment and ``unit_exponent``.
        None: the mesh is one part (mean edge length a float).
    n_parts : int, default 1
        Number of parts (with ``part``).
    cover : (faces, twin) pair, optional
        Build the triangulation on these faces over the same vertices (with
        these half-edge twins) instead of on ``F``, e.g. the tufted cover of
        ``F`` (:func:`heatcore.domains.pointcloud.tufted_cover`). Boundary and
        mean edge length still come from ``F``'s edges.
    rim : (n,) bool array, optional
        Only open edges (sides of a single face) with both ends on the rim
        make boundary vertices. None: every open edge does.
    flip : bool, default True
        Flip to intrinsic Delaunay; False keeps the (mollified) faces as they are.
    thin_slack : float, optional
        Parts whose least triangle slack after the flips is below this
        (relative to their mean edge length) are mollified again to this
        slack (a strip far thinner than its length, which no flip mends).
    unit_exponent : int or (n_parts,) int array, default 0
        Each part's length unit (see :class:`~heatcore.domains.operators.Operators`).
    progress : callable, optional
        ``progress(fraction, message)`` at each stage (see :mod:`heatcore.progress`).
    side_pairs : (p, 2) int array, optional
        The two sides of each edge of ``F`` with exactly two, where already found
        (:func:`heatcore.domains.refine.unique_edges` with ``with_pairs``).

    Returns
    -------
    IntrinsicBuild
        The triangulation and what the build measured on the way.

    Raises
    ------
    InvalidMeshError
        A part whose edges all have zero length.

    Examples
    --------
    >>> import numpy as np
    >>> from heatcore.domains.refine import unique_edges
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
    >>> F = np.array([[0, 1, 2], [1, 3, 2]])
    >>> built = intrinsic_triangulation(V, F, *unique_edges(F))
    >>> built.boundary.tolist(), built.n_flips, round(built.h, 4)
    ([True, True, True, True], 0, 1.0828)
    """
    progress = Progress(progress)
    progress(0.0, "intrinsic Delaunay flips" if flip else "mollifying the triangles")
    n = V.shape[0]
    edge_faces = np.bincount(side_edge.ravel(), minlength=edges.shape[0])
    open_edges = edges[edge_faces == 1]
    if rim is not None:
        open_edges = open_edges[rim[open_edges].all(axis=1)]
    boundary = np.zeros(n, dtype=bool)
    boundary[open_edges.ravel()] = True
    edge_lengths = segment_lengths(V, edges)
    if part is None:
        h = float(edge_lengths.mean())
        face_part, face_h, vertex_h = None, h, h
        if not h > 0:
            raise InvalidMeshError("all edges have zero length: the mesh collapses to a point")
    else:
        h = part_means(edge_lengths, part[edges[:, 0]], n_parts)  # in each part's unit
        if not (h > 0).all():
            bad = int(np.flatnonzero(~(h > 0))[0])
            raise InvalidMeshError(
                f"all edges of connected part {bad} (of {n_parts}) have zero length: it collapses to a point"
            )
        faces = F if cover is None else cover[0]
        face_part = part[faces[:, 0]]
        face_h = h[face_part][:, None]
        vertex_h = h[part]
        if np.ndim(unit_exponent):
            unit_exponent = np.asarray(unit_exponent)[part]
    if cover is None:
        unit_lengths = edge_lengths[side_edge] / face_h
    else:
        unit_lengths = face_edge_lengths(V, cover[0]) / face_h

    def triangulate(relative_delta):
        if face_part is None:
            lengths, eps = mollify(unit_lengths, relative_delta)
        else:
            lengths, eps = mollify(unit_lengths, relative_delta, part=face_part, n_parts=n_parts)
        if cover is None:
            tri = IntrinsicTriangulation.from_mesh(None, F, lengths=lengths, side_edge=side_edge, side_pairs=side_pairs)
        else:
            tri = IntrinsicTriangulation(cover[0].copy(), lengths, cover[1].copy())
        return tri, eps, tri.flip_to_delaunay() if flip else 0

    tri, eps, n_flips = triangulate(MOLLIFY_SLACK)
    thin_parts = np.zeros(0, np.int64)
    if thin_slack is not None:
        slack = row_reduce(np.minimum, triangle_slack(tri.lengths))
        least = part_extremes(slack, face_part, n_parts) if face_part is not None else np.array([slack.min()])
        thin_parts = np.flatnonzero(least < thin_slack)  # flips keep parts
        if thin_parts.size:
            delta = np.where(least < thin_slack, thin_slack, MOLLIFY_SLACK)
            tri, eps, n_flips = triangulate(delta if face_part is not None else float(delta[0]))
    tri.lengths *= face_h
    return IntrinsicBuild(tri, n_flips, eps, h, thin_parts, boundary, vertex_h, unit_exponent)
