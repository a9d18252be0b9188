"""What is known exactly near the sources, applied to the heat method's distances.

The heat method smooths: a source's direct neighbours come out 3-30% below
their edge length (the two-triangle unit square: 0.987 for 1; libigl issue
2442 reports the same), and a few percent of all vertex pairs below the
straight line between them, most of them next to the source. Two bounds hold
on every domain:

* **upper**: a side of a triangle, polygon or tet is a straight segment that
  lies in the domain, so a vertex joined to a source vertex by one is at most
  that segment's length away
  (:meth:`~heatcore.domains.base.Domain.straight_neighbours`);
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
>>> source_bounds(mesh, np.zeros(4, int), [0], {}).apply(d).round(4).tolist()
[0.0, 1.0, 1.0, 1.4142]
"""

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from ..domains.parts import row_norms
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
    ring : (r,) int array
        Input vertices with a lower bound: the rings of the point sources.
    ring_lower : (r,) float array
        Their straight-line distance to the nearest point source of their part.
    near : (j,) int array
        Input vertices joined to a source vertex by a straight segment.
    near_lengths : (j,) float array
        That segment's length (the upper bound).

    Examples
    --------
    >>> b = SourceBounds(np.array([1, 2]), np.array([1.0, 2.0]), np.array([1]), np.array([1.0]))
    >>> b.apply(np.array([0.0, 0.9, 1.5, 2.5])).tolist()
    [0.0, 1.0, 2.0, 2.5]
    """

    ring: np.ndarray
    ring_lower: np.ndarray
    near: np.ndarray
    near_lengths: np.ndarray

    def apply(self, d):
        """Raise ``d`` (per input vertex, modified in place and returned) to the lower bound, cap it at the upper."""
        d[self.ring] = np.maximum(d[self.ring], self.ring_lower)
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
        exponent = np.frexp(max(np.abs(points).max(), np.abs(positions).max(), np.finfo(float).tiny))[1]
        nearest = cKDTree(np.ldexp(points, -exponent)).query(np.ldexp(positions, -exponent))[1]
        return row_norms(positions - points[nearest])
    nearest = np.full(positions.shape[0], np.inf)
    for p in points:
        np.minimum(nearest, row_norms(positions - p), out=nearest)
    return nearest


def source_bounds(domain, component, vertices, kinds):
    """The :class:`SourceBounds` of a source given as :meth:`~heatcore.HeatSolver.distance` takes it.

    Parameters
    ----------
    domain : heatcore.domains.base.Domain
    component : (n_operator_vertices,) int array
        Connected part of each operator vertex: a part's bounds come from its own sources only.
    vertices : int, sequence of int or None
        Source vertices (input indices), already checked by the domain's pins.
    kinds : dict
        The other source keywords (``points``, ``edges``, ``region``). A part
        with an edge or region source gets no lower bound (their points are
        not listed); the upper bound holds everywhere.

    Examples
    --------
    >>> import heatcore as hc
    >>> mesh = hc.TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0)
    >>> b = source_bounds(mesh, np.zeros(3, int), None, {"points": ([0], [[1.0, 0.0, 0.0]])})
    >>> b.ring.tolist(), b.ring_lower.round(3).tolist(), b.near.tolist()
    ([0, 1, 2], [0.0, 1.414, 1.414], [])
    """
    kinds = {k: v for k, v in source_keywords(kinds, stacklevel=5).items() if v is not None}
    X, output = domain.input_positions, np.asarray(domain.output_vertices)
    given = np.zeros(0, dtype=np.int64) if vertices is None else index_list(vertices, X.shape[0], "vertex")
    # Without welded twins, _with_twins sorts the few vertices it is given: no pass over every vertex.
    op = output if domain.derived.get_or_build(("welded twins", None), lambda: has_twins(output)) else None
    sources = _with_twins(op, given)[0] if given.size else given  # a welded twin is the source too
    around, lengths = domain.straight_neighbours(sources)
    near, lengths = _with_twins(op, around, lengths)
    points, part, seeds = [X[given]], [component[output[given]]], [sources]
    if "points" in kinds:
        corners = domain.point_corners(kinds["points"])
        points.append(domain.point_positions(kinds["points"]))
        part.append(component[output[corners[:, 0]]])
        seeds.append(corners.ravel())
    points, part = np.concatenate(points), np.concatenate(part)
    ring = _with_twins(op, np.unique(np.concatenate(seeds)))[0]
    for level in range(RINGS):  # the first ring of vertex sources is the one found above
        reached = around if level == 0 and np.array_equal(ring, sources) else domain.straight_neighbours(ring)[0]
        ring = _with_twins(op, np.union1d(ring, reached))[0]
    other = {k: v for k, v in kinds.items() if k != "points"}
    if other:  # an edge or a region: its points are not listed, so its part gets no lower bound
        blocked = component[domain.source_pins(None, **other).vertices]
        ring = ring[~np.isin(component[output[ring]], blocked)]
    ring_part = component[output[ring]]
    lower = np.empty(ring.size)
    for p in np.unique(ring_part):
        here = ring_part == p
        lower[here] = straight_distance(X[ring[here]], points[part == p])
    return SourceBounds(ring, lower, near, lengths)


def has_twins(op):
    """Whether two input vertices share an operator vertex ``op`` (-1: a vertex no element uses, which is
    never a source nor a straight neighbour, so never a twin).

    Examples
    --------
    >>> has_twins(np.array([0, 1, 2])), has_twins(np.array([0, 1, 0])), has_twins(np.array([0, -1, -1]))
    (False, True, False)
    """
    return bool(np.bincount(op[op >= 0]).max(initial=0) > 1)


def _with_twins(op, vertices, values=None):
    """``vertices`` and every input vertex welded to one of them (the same operator vertex), with the
    smallest of their ``values``: welded copies (an OBJ seam, an STL soup) read one distance.

    ``op``: the operator vertex of each input vertex, or None where no two share one (:func:`has_twins`
    false): then only the given vertices are sorted, the same result without a pass over every vertex.
    """
    values = np.zeros(vertices.size) if values is None else values
    if op is None:
        order = np.lexsort((values, vertices))  # by vertex, its smallest value first
        vertices, values = vertices[order], values[order]
        first = values < np.inf
        first[1:] &= vertices[1:] != vertices[:-1]
        return vertices[first], values[first]
    best = np.full(op.size + 1, np.inf)  # by operator vertex; index -1 (unreferenced) stays inf
    np.minimum.at(best, op[vertices], values)
    reached = best[op]
    twins = np.flatnonzero(reached < np.inf)
    return twins, reached[twins]
