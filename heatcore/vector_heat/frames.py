"""Vertex tangent spaces of an intrinsic triangulation: angular coordinates around each vertex.

A tangent vector at a vertex is a complex number in the vertex's own frame.
The frame is intrinsic (edge lengths only): walking counter-clockwise around
the vertex through its triangle corners, each corner's first side gets the
sum of the corner angles before it, scaled so that a closed ring of corners
(an interior vertex, cone angle ``Θ``) spans exactly ``2π``: the *angle-scaled*
directions of the vector heat method (Sharp, Soliman and Crane 2019). Angle 0
is the first side of the ring's first corner. A boundary vertex (an open fan
of corners) keeps its angles unscaled, so the frames of a flat mesh agree
everywhere, at its boundary too (geometry-central scales a boundary fan to
``π`` instead; on a flat square that rotates vectors at the corners).

Half-edge ``h = 3 f + c`` runs from corner ``c + 1`` to corner ``c + 2`` of face
``f`` (see :mod:`heatcore.domains.intrinsic`); corner ``k = 3 f + c`` is corner
``c`` of face ``f``. Corners around a vertex are chained through the half-edge
twins; rings are ranked by pointer jumping (a few vectorized rounds, no loop
over vertices). Non-manifold vertices (several fans) get their fans one
after the other, unscaled.

Examples
--------
>>> import numpy as np
>>> from heatcore.domains.intrinsic import IntrinsicTriangulation
>>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0]], float)
>>> F = np.array([[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 1]])
>>> frames = vertex_frames(IntrinsicTriangulation.from_mesh(V, F), 5)
>>> (frames.start[[0, 3, 6, 9]] / np.pi).round(3).tolist()   # the four corners at the centre vertex
[0.0, 0.5, 1.0, 1.5]
"""

from dataclasses import dataclass

import numpy as np

from ..domains.intrinsic import NEXT, PREV, face_areas


def corner_angles(lengths):
    """Interior angle at each corner of triangles given by their edge lengths (column ``c`` opposite corner ``c``).

    Examples
    --------
    >>> (corner_angles(np.array([[5.0, 4.0, 3.0]])) / np.pi * 180).round(2).tolist()
    [[90.0, 53.13, 36.87]]
    """
    sq = lengths**2
    return np.arctan2(4.0 * face_areas(lengths)[:, None], sq[:, NEXT] + sq[:, PREV] - sq)


@dataclass
class VertexFrames:
    """Angular coordinates of every corner of a triangulation in its vertex's frame.

    Attributes
    ----------
    vertex : (3 m,) int array
        The vertex at each corner ``k = 3 f + c``.
    angle : (3 m,) float array
        Each corner's interior angle (unscaled).
    start : (3 m,) float array
        Direction of each corner's first side (towards corner ``c + 1``) in its
        vertex's frame, scaled angle in ``[0, 2π)``.
    scale : (n,) float array
        Each vertex's angle scaling: ``2π / Θ`` on a closed ring, 1 elsewhere.
    closed : (n,) bool array
        Vertices whose corners form one closed ring (interior manifold vertices).

    Examples
    --------
    >>> from heatcore.domains.intrinsic import IntrinsicTriangulation
    >>> tri = IntrinsicTriangulation.from_mesh(np.eye(3), np.array([[0, 1, 2]]))
    >>> vertex_frames(tri, 3).closed.tolist()
    [False, False, False]
    """

    vertex: np.ndarray
    angle: np.ndarray
    start: np.ndarray
    scale: np.ndarray
    closed: np.ndarray

    def tail_direction(self, h):
        """Direction of half-edge ``h`` at its tail vertex (towards its head), in the tail's frame."""
        return self.start[3 * (h // 3) + NEXT[h % 3]]

    def head_direction(self, h):
        """Direction from the head of half-edge ``h`` back towards its tail, in the head's frame."""
        k = 3 * (h // 3) + PREV[h % 3]
        return self.start[k] + self.scale[self.vertex[k]] * self.angle[k]

    def transport(self, h):
        """Rotation angle carrying a vector at the tail of ``h`` to its head along the edge (Levi-Civita)."""
        return self.head_direction(h) - self.tail_direction(h) + np.pi


def vertex_frames(tri, n_vertices):
    """The :class:`VertexFrames` of an intrinsic triangulation.

    Parameters
    ----------
    tri : IntrinsicTriangulation
        Faces, edge lengths and half-edge twins.
    n_vertices : int

    Returns
    -------
    VertexFrames

    Examples
    --------
    >>> from heatcore.domains.intrinsic import IntrinsicTriangulation
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
    >>> frames = vertex_frames(IntrinsicTriangulation.from_mesh(V, np.array([[0, 1, 2], [1, 3, 2]])), 4)
    >>> (frames.start / np.pi).round(3).tolist()   # vertex 1: corner 3 (towards 3) first, then corner 1
    [0.0, 0.25, 0.0, 0.0, 0.0, 0.25]
    """
    faces, twin = tri.faces, tri.twin
    angle = corner_angles(tri.lengths).ravel()
    vertex = faces.ravel()
    k = np.arange(vertex.size)
    # The next corner counter-clockwise: across the corner's second side (its incoming half-edge).
    across = twin[3 * (k // 3) + NEXT[k % 3]]
    nxt = np.where(across >= 0, 3 * (across // 3) + NEXT[np.maximum(across, 0) % 3], -1)
    pred = np.full(k.size, -1, dtype=np.int64)
    pred[nxt[nxt >= 0]] = k[nxt >= 0]
    open_start = pred < 0  # the first corner of an open fan
    degree = np.bincount(vertex, minlength=n_vertices)
    rounds = int(np.ceil(np.log2(max(int(degree.max(initial=1)), 1) + 1))) + 1
    while True:
        prefix, root, left = _ranked(pred, angle, rounds)
        cycling = left >= 0
        if not cycling.any():
            break
        # Cut each closed ring (one per vertex and pass) before its smallest corner.
        first = np.full(n_vertices, k.size, dtype=np.int64)
        np.minimum.at(first, vertex[cycling], k[cycling])
        pred[first[first < k.size]] = -1
    before = prefix - angle  # angle of the fan's corners before this one
    roots = np.flatnonzero(pred < 0)
    fan_vertex = vertex[roots]
    fan_total = np.bincount(root, weights=angle, minlength=k.size)[roots]
    order = np.argsort(fan_vertex, kind="stable")  # fans of a vertex by their first corner
    sorted_total = fan_total[order]
    running = np.cumsum(sorted_total) - sorted_total
    group_first = np.r_[True, fan_vertex[order][1:] != fan_vertex[order][:-1]]
    running -= np.maximum.accumulate(np.where(group_first, running, 0.0))
    fan_offset = np.zeros(k.size)
    fan_offset[roots[order]] = running
    fans = np.bincount(fan_vertex, minlength=n_vertices)
    ring_closed = np.zeros(n_vertices, dtype=bool)
    ring_closed[fan_vertex[~open_start[roots]]] = True
    closed = ring_closed & (fans == 1)
    total = np.bincount(vertex, weights=angle, minlength=n_vertices)
    scale = np.ones(n_vertices)
    good = closed & (total > 0)
    scale[good] = 2.0 * np.pi / total[good]
    start = scale[vertex] * (fan_offset[root] + before)
    return VertexFrames(vertex, angle, start, scale, closed)


def _ranked(pred, values, rounds):
    """Inclusive prefix sums of ``values`` along chains given by ``pred`` (pointer jumping).

    Returns the prefix sums, each element's chain start, and what is left of
    each pointer after ``rounds`` rounds (``>= 0`` only on cycles, when
    ``2**rounds`` exceeds the longest chain).
    """
    prefix = values.copy()
    root = np.arange(values.size)
    left = pred.copy()
    for _ in range(rounds):
        active = np.flatnonzero(left >= 0)
        if active.size == 0:
            break
        target = left[active]
        new_prefix, new_root, new_left = prefix[target], root[target], left[target]  # all read before writing
        prefix[active] += new_prefix
        root[active] = new_root
        left[active] = new_left
    return prefix, root, left
