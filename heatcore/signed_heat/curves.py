"""Curves of the signed heat method: surface points in order, and the tangent vectors they start the flow with.

A curve is an ordered sequence of surface points in heatcore's source
vocabulary: a vertex index, or a point on a face ``(face, (b0, b1, b2))``. A
closed curve repeats its first point at the end. Consecutive points need not
share a face: each segment is the straight chord between them, which on a mesh
fine enough for the curve is the curve.

A *signed* curve starts the vector heat flow with its normals: at each end of
each segment, half the segment's length times the unit normal pointing to its
*left* (``normal x tangent``, looking along the surface normal), spread on the
operator vertices that carry the point with their hat weights. An *unsigned*
curve, and an isolated point, start it with vectors pointing *away* from them
on the vertices around them (on the curve itself, normals of both sides would
cancel): a distance with no sign, positive on both sides.

Examples
--------
>>> parse_curve([0, 5, (3, (0.2, 0.3, 0.5)), 0]).n_nodes
4
"""

from typing import NamedTuple

import numpy as np

from ..errors import InvalidSourceError


class ParsedCurve(NamedTuple):
    """One curve's points, split by kind but kept in order.

    Attributes
    ----------
    kinds : (k,) bool array
        True where the point is a vertex.
    vertices : (k,) int array
        The vertex of each vertex point (-1 elsewhere).
    faces : (k,) int array
        The face of each face point (-1 elsewhere).
    barycentric : (k, 3) float array
        The coordinates of each face point (zeros elsewhere).

    Examples
    --------
    >>> parse_curve([2, (0, (1.0, 0.0, 0.0))]).faces.tolist()
    [-1, 0]
    """

    kinds: np.ndarray
    vertices: np.ndarray
    faces: np.ndarray
    barycentric: np.ndarray

    @property
    def n_nodes(self):
        return self.kinds.size

    @property
    def closed(self):
        """Whether the first and the last point are the same (a loop)."""
        same_kind = self.kinds[0] == self.kinds[-1]
        if self.kinds[0]:
            return bool(same_kind and self.vertices[0] == self.vertices[-1])
        return bool(same_kind and self.faces[0] == self.faces[-1] and np.allclose(self.barycentric[0], self.barycentric[-1]))


def parse_curve(curve, label="curve"):
    """A :class:`ParsedCurve` from a sequence of vertex indices and ``(face, barycentric)`` pairs.

    Raises
    ------
    InvalidSourceError
        An item that is neither, or fewer than two points.

    Examples
    --------
    >>> c = parse_curve(np.array([4, 2]))
    >>> c.kinds.tolist(), c.vertices.tolist()
    ([True, True], [4, 2])
    """
    arr = np.asarray(curve, dtype=object) if not isinstance(curve, np.ndarray) else curve
    if isinstance(curve, np.ndarray) and curve.ndim == 1 and np.issubdtype(curve.dtype, np.integer):
        items = curve.tolist()
    else:
        items = list(curve) if arr.ndim >= 1 else None
    if items is None or len(items) < 2:
        raise InvalidSourceError(f"a {label} needs at least two points (vertex indices or (face, barycentric) pairs)")
    k = len(items)
    kinds = np.zeros(k, dtype=bool)
    vertices, faces, bary = np.full(k, -1, dtype=np.int64), np.full(k, -1, dtype=np.int64), np.zeros((k, 3))
    for j, item in enumerate(items):
        if isinstance(item, (int, np.integer)) and not isinstance(item, bool):
            kinds[j], vertices[j] = True, int(item)
            continue
        try:
            face, coordinates = item
            b = np.asarray(coordinates, dtype=float).reshape(3)
        except (TypeError, ValueError):
            raise InvalidSourceError(
                f"point {j} of the {label} must be a vertex index or a pair (face, (b0, b1, b2)), got {item!r}"
            ) from None
        if not isinstance(face, (int, np.integer)) or isinstance(face, bool):
            raise InvalidSourceError(f"point {j} of the {label}: the face must be an integer index, got {face!r}")
        faces[j], bary[j] = int(face), b
    return ParsedCurve(kinds, vertices, faces, bary)


class CurveNodes(NamedTuple):
    """The surface points of all curves, as the operators see them.

    Attributes
    ----------
    carriers : list of (vertices, weights)
        Per point: the operator vertices that carry it and their hat weights (sum 1).
    positions, normals : (k, 3) float arrays
        Each point's position (operators' length unit) and unit surface normal.
    curve : (k,) int array
        The curve each point belongs to.

    Examples
    --------
    >>> I = np.eye(3)
    >>> nodes = CurveNodes([(np.array([0]), np.ones(1))], np.zeros((1, 3)), I[[2]], np.zeros(1, int))
    >>> len(nodes.carriers), nodes.normals.tolist()
    (1, [[0.0, 0.0, 1.0]])
    """

    carriers: list
    positions: np.ndarray
    normals: np.ndarray
    curve: np.ndarray


def curve_nodes(parsed, sources_of):
    """:class:`CurveNodes` of the parsed curves; ``sources_of(vertices, points)`` gives their TangentSources in order.

    ``sources_of`` is :meth:`heatcore.vector_heat.VectorHeatSolver.sources`: vertices first, then points.

    Examples
    --------
    >>> import heatcore as hc
    >>> solver = hc.VectorHeatSolver(hc.TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0))
    >>> nodes = curve_nodes([parse_curve([0, (0, (0.0, 0.5, 0.5))])], lambda v, p: solver.sources(v, points=p))
    >>> nodes.positions.round(3).tolist(), nodes.curve.tolist()
    ([[1.0, 0.0, 0.0], [0.0, 0.5, 0.5]], [0, 0])
    """
    carriers, positions, normals, owner = [], [], [], []
    for c, curve in enumerate(parsed):
        vertex_sources = sources_of(curve.vertices[curve.kinds], None) if curve.kinds.any() else []
        point_sources = []
        if not curve.kinds.all():
            points = (curve.faces[~curve.kinds], curve.barycentric[~curve.kinds])
            point_sources = sources_of(None, points)
        by_vertex, by_point = iter(vertex_sources), iter(point_sources)
        for is_vertex in curve.kinds.tolist():
            s = next(by_vertex) if is_vertex else next(by_point)
            carriers.append((s.vertices, s.weights))
            positions.append(s.position)
            normals.append(s.normal)
            owner.append(c)
    return CurveNodes(carriers, np.array(positions), np.array(normals), np.array(owner, dtype=np.int64))


def spread(rhs, carriers, vectors, basis):
    """Add each 3D ``vectors[j]`` to ``rhs`` on the vertices carrying point ``j``, in their frames, by hat weight.

    Examples
    --------
    >>> I = np.eye(3)
    >>> basis = (np.tile(I[2], (2, 1)), np.tile(I[0], (2, 1)), np.tile(I[1], (2, 1)))
    >>> rhs = np.zeros(2, dtype=complex)
    >>> spread(rhs, [(np.array([0, 1]), np.array([0.25, 0.75]))], [np.array([0.0, 4.0, 0.0])], basis)
    >>> rhs.tolist()
    [1j, 3j]
    """
    _, e1, e2 = basis
    for (vertices, weights), v in zip(carriers, vectors):
        rhs[vertices] += weights * (e1[vertices] @ v + 1j * (e2[vertices] @ v))


def signed_source(nodes, rhs, curve, basis):
    """The normals of one signed curve's segments, half of each at each end (the left side positive).

    Examples
    --------
    >>> I = np.eye(3)
    >>> basis = (np.tile(I[2], (2, 1)), np.tile(I[0], (2, 1)), np.tile(I[1], (2, 1)))
    >>> carriers = [(np.array([0]), np.ones(1)), (np.array([1]), np.ones(1))]
    >>> nodes = CurveNodes(carriers, np.array([[0.0, 0, 0], [2, 0, 0]]), np.tile(I[2], (2, 1)), np.zeros(2, int))
    >>> rhs = np.zeros(2, dtype=complex)
    >>> signed_source(nodes, rhs, 0, basis)   # along +x, seen from +z: +y is on the left
    >>> rhs.tolist()
    [1j, 1j]
    """
    j = np.flatnonzero(nodes.curve == curve)
    a, b = j[:-1], j[1:]
    chord = nodes.positions[b] - nodes.positions[a]
    for ends in (a, b):
        normal = np.cross(nodes.normals[ends], chord)  # |chord| long where the chord is tangent
        spread(rhs, [nodes.carriers[e] for e in ends], 0.5 * normal, basis)


def away_source(nodes, rhs, curve, basis, positions, neighbours, h):
    """Vectors pointing away from one unsigned curve (or one point), on the vertices around its points.

    Each point's carrying vertices hand their weight to their neighbours
    (``neighbours``: CSR adjacency of the operator vertices), each getting a
    vector of length ``h`` (times that weight, shared among the ring) along
    the direction away from the nearest of the curve's segments.

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> I = np.eye(3)
    >>> X = np.array([[0.0, 0, 0], [1, 0, 0], [-1, 0, 0]])
    >>> basis = (np.tile(I[2], (3, 1)), np.tile(I[0], (3, 1)), np.tile(I[1], (3, 1)))
    >>> ring = sp.csr_matrix(np.array([[0, 1, 1], [1, 0, 0], [1, 0, 0]]))
    >>> nodes = CurveNodes([(np.array([0]), np.ones(1))], X[:1], I[[2]], np.zeros(1, int))
    >>> rhs = np.zeros(3, dtype=complex)
    >>> away_source(nodes, rhs, 0, basis, X, ring, 2.0)   # a point at vertex 0: its neighbours point away
    >>> rhs.tolist()
    [0j, (1+0j), (-1+0j)]
    """
    _, e1, e2 = basis
    j = np.flatnonzero(nodes.curve == curve)
    carried = np.unique(np.concatenate([nodes.carriers[i][0] for i in j]))
    ends = (j[:-1], j[1:]) if j.size > 1 else (j, j)
    a, b = nodes.positions[ends[0]], nodes.positions[ends[1]]
    for i in j:
        vertices, weights = nodes.carriers[i]
        for v, w in zip(vertices.tolist(), weights.tolist()):
            ring = neighbours.indices[neighbours.indptr[v]:neighbours.indptr[v + 1]]
            ring = ring[~np.isin(ring, carried)]
            if ring.size == 0:
                continue
            away = positions[ring] - _nearest_on_segments(positions[ring], a, b)
            away -= (away @ nodes.normals[i])[:, None] * nodes.normals[i]  # in the point's tangent plane
            size = np.linalg.norm(away, axis=1)
            keep = size > 0
            unit = away[keep] / size[keep, None]
            r = ring[keep]
            rhs[r] += (w * h / max(keep.sum(), 1)) * (np.einsum("ij,ij->i", unit, e1[r]) + 1j * np.einsum("ij,ij->i", unit, e2[r]))


def _nearest_on_segments(X, a, b):
    """The nearest point to each row of ``X`` on the segments ``a[i] -> b[i]``."""
    d = b - a
    length2 = np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)
    t = np.clip(((X[:, None, :] - a[None]) * d[None]).sum(axis=2) / length2, 0.0, 1.0)
    near = a[None] + t[..., None] * d[None]
    best = np.argmin(((X[:, None, :] - near) ** 2).sum(axis=2), axis=1)
    return near[np.arange(X.shape[0]), best]

