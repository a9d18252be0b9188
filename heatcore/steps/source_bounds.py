"""What is known exactly near the sources, applied to the heat method's distances.

The heat method smooths: a source's direct neighbours come out 3-30% below
their edge length (the two-triangle unit square: 0.987 for 1; libigl issue
2442 reports the same), and a few percent of all vertex pairs below the
straight line between them, most of them next to the source. Two bounds hold
on every domain:

* **upper**: a side of a triangle, polygon or tet is a straight segment that
  lies in the domain, so a vertex joined to a source vertex by one is at most
  that segment's length away
  (:attr:`~heatcore.domains.base.Domain.straight_neighbours`);
* **lower**: no path on a surface or through a volume is shorter than the
  straight line, so the distance to a set of source points is at least the
  Euclidean distance to the nearest of them.

For a neighbour whose nearest source is the one it is joined to, the two
bounds meet: its distance is exactly the edge length. Each bound moves a
distance towards the truth, never away. They are applied on the sources'
two rings of straight neighbours (:data:`RINGS`), where the heat method's
smoothing is strongest; farther out the field is the heat method's own, so
that what it computes stays smooth and measurable (on a plane the lower bound
is the exact answer everywhere). The lower bound needs every source to be a
point (vertices, ``points`` inside elements); with edge or region sources only
the upper bound applies.

Examples
--------
>>> import numpy as np, heatcore as hc
>>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
>>> mesh = hc.TriangleMesh(V, [[0, 1, 2], [1, 3, 2]])
>>> d = np.array([0.0, 0.98, 0.98, 1.40])          # as the heat method gives them
>>> source_bounds(mesh, [0], {}).apply(d, mesh.input_positions).round(4).tolist()
[0.0, 1.0, 1.0, 1.4142]
"""

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from ..domains.sources import index_list, source_keywords

#: Above this many source points, the nearest one per vertex is found with a k-d tree.
TREE_FROM_POINTS = 16


#: Rings of straight neighbours around the sources where the lower bound is applied.
RINGS = 2


@dataclass(frozen=True)
class SourceBounds:
    """Exact bounds on the distance to one source set, at input vertices.

    Attributes
    ----------
    points : (k, 3) float array or None
        The source points, where every source is a point (the lower bound).
    ring : (r,) int array
        Input vertices the lower bound is applied to: the sources' rings.
    near : (j,) int array
        Input vertices joined to a source vertex by a straight segment.
    near_lengths : (j,) float array
        That segment's length (the upper bound).

    Examples
    --------
    >>> b = SourceBounds(np.zeros((1, 3)), np.array([1, 2]), np.array([1]), np.array([1.0]))
    >>> b.apply(np.array([0.0, 0.9, 1.5, 2.5]), np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0]], float)).tolist()
    [0.0, 1.0, 2.0, 2.5]
    """

    points: np.ndarray
    ring: np.ndarray
    near: np.ndarray
    near_lengths: np.ndarray

    def apply(self, d, positions):
        """Raise ``d`` (per input vertex, modified in place and returned) to the lower bound, cap it at the upper."""
        if self.points is not None and self.ring.size:
            d[self.ring] = np.maximum(d[self.ring], straight_distance(positions[self.ring], self.points))
        np.minimum.at(d, self.near, self.near_lengths)
        return d


def straight_distance(positions, points):
    """Euclidean distance from each of ``positions`` (n, 3) to the nearest of ``points`` (k, 3).

    Examples
    --------
    >>> straight_distance(np.array([[0, 0, 0], [3, 4, 0]], float), np.array([[0, 0, 1], [3, 4, 2]], float)).tolist()
    [1.0, 2.0]
    """
    if points.shape[0] > TREE_FROM_POINTS:
        return cKDTree(points).query(positions)[0]
    nearest = np.full(positions.shape[0], np.inf)
    for p in points:
        np.minimum(nearest, np.linalg.norm(positions - p, axis=1), out=nearest)
    return nearest


def source_bounds(domain, vertices, kinds):
    """The :class:`SourceBounds` of a source given as :meth:`~heatcore.HeatSolver.distance` takes it.

    Parameters
    ----------
    domain : heatcore.domains.base.Domain
    vertices : int, sequence of int or None
        Source vertices (input indices), already checked by the domain's pins.
    kinds : dict
        The other source keywords (``points``, ``edges``, ``region``).

    Examples
    --------
    >>> import heatcore as hc
    >>> mesh = hc.TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0)
    >>> b = source_bounds(mesh, None, {"points": ([0], [[1.0, 0.0, 0.0]])})
    >>> b.points.tolist(), b.ring.tolist(), b.near.tolist()
    ([[1.0, 0.0, 0.0]], [0, 1, 2], [])
    """
    kinds = {k: v for k, v in source_keywords(kinds, stacklevel=5).items() if v is not None}
    X, op = domain.input_positions, np.asarray(domain.output_vertices)
    given = np.zeros(0, dtype=np.int64) if vertices is None else index_list(vertices, X.shape[0], "vertex")
    is_source = np.zeros(op.size + 1, dtype=bool)  # by operator vertex: a welded twin is the source too
    is_source[op[given]] = True
    sources = np.flatnonzero(is_source[op]) if given.size else given
    A = domain.straight_neighbours
    near, lengths = _with_twins(op, *_neighbours(A, sources))
    if set(kinds) - {"points"}:  # an edge or a region: its points are not listed, no lower bound
        return SourceBounds(None, np.zeros(0, dtype=np.int64), near, lengths)
    points, seeds = [X[given]], [sources]
    if "points" in kinds:
        points.append(domain.point_positions(kinds["points"]))
        seeds.append(domain.point_corners(kinds["points"]).ravel())
    ring = np.unique(np.concatenate(seeds))
    for _ in range(RINGS):
        ring = _with_twins(op, np.union1d(ring, _neighbours(A, ring)[0]))[0]
    return SourceBounds(np.concatenate(points), ring, near, lengths)


def _with_twins(op, vertices, values=None):
    """``vertices`` and every input vertex welded to one of them (the same operator vertex), with the
    smallest of their ``values``: welded copies (an OBJ seam, an STL soup) read one distance."""
    values = np.zeros(vertices.size) if values is None else values
    best = np.full(op.size + 1, np.inf)  # by operator vertex; index -1 (unreferenced) stays inf
    np.minimum.at(best, op[vertices], values)
    reached = best[op]
    twins = np.flatnonzero(reached < np.inf)
    return twins, reached[twins]


def _neighbours(A, vertices):
    """Straight neighbours of ``vertices`` (repeated where shared) and the segment lengths to them."""
    starts, stops = A.indptr[vertices], A.indptr[vertices + 1]
    counts = stops - starts
    pos = np.repeat(starts - np.r_[0, np.cumsum(counts)[:-1]], counts) + np.arange(counts.sum())
    return A.indices[pos], A.data[pos]
