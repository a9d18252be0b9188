"""Isoline curves of a piecewise-linear function on a triangle mesh (marching triangles).

A level ``c`` crosses each edge whose values straddle it; every face with a
crossing holds one segment between its two crossed edges, and the segments
are joined through the edges they share into polylines, closed where they
come back to their start, open where they end on the mesh's boundary (or at
the edge of the faces whose values are all finite).

**Degenerate values.** A vertex whose value is exactly ``c`` counts as above
the level (simulation of simplicity): the curves are the boundary of the
region where the values are at least ``c``, the limit of the curves at
``c - eps``. Where they meet a vertex at the level the points of the
adjoining edges coincide with that vertex and are merged into one point, so a
curve never holds two equal consecutive points. It follows that a curve through
a vertex at the level passes through that vertex once per passage, that an
edge at the level between lower values is drawn once (an open curve, not a
loop of zero width), that a flat region at the level is outlined where it meets
lower values, and that a vertex or an edge that touches the level from above,
or a single vertex at the level among lower values, gives no curve. Faces
with a non-finite value (``inf`` where no source reaches, NaN) get no
segment.

Each point lies on a mesh edge, ``(1 - t) V[a] + t V[b]`` with ``t`` interpolating the level
linearly between the values at ``a`` and ``b``, or on a vertex; each segment lies in one face.
Curves have the higher values on their left, seen from where the faces turn counterclockwise.

Examples
--------
>>> import numpy as np
>>> V = np.array([[0, 0, 0], [2, 0, 0], [0, 2, 0], [2, 2, 0]], float)
>>> F = np.array([[0, 1, 2], [1, 3, 2]])
>>> [curve] = isolines(V, F, V[:, 0] + V[:, 1], [1.0])
>>> curve.points.tolist(), curve.closed      # higher values on the left
([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0]], False)
"""

from dataclasses import dataclass

import numpy as np

from .domains.validate import index_array, vertex_array
from .errors import InvalidOptionError

#: A point this many units in the last place (of the coordinates) from a vertex is put on the vertex.
SNAP_ULPS = 8
#: The corners of each face edge: edge ``k`` runs from corner ``k`` to corner ``k + 1``.
_NEXT = np.array([1, 2, 0])


@dataclass(frozen=True, eq=False)
class Isoline:
    """One polyline at one level.

    Attributes
    ----------
    points : (k, 3) float array
        The curve's points, no two consecutive ones equal; a closed curve does
        not repeat its first point at the end.
    level : float
    closed : bool
        Whether the curve comes back to its first point (then it has at least 3 points).
    edges : (k, 2) int array
        The mesh edge ``(a, b)`` each point lies on, with ``points = (1 - t) V[a] + t V[b]``
        and the value at ``a`` below the level, at ``b`` above it; ``(v, v)`` for a point on
        vertex ``v`` (whose value is the level).
    t : (k,) float array
        Where on its edge each point lies, in ``[0, 1)`` (0 on a vertex).
    faces : (k - 1,) or (k,) int array
        The face each segment lies in: segment ``i`` joins points ``i`` and ``i + 1``; a closed
        curve has one more, from its last point back to the first.

    Examples
    --------
    >>> import numpy as np
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    >>> [curve] = isolines(V, [[0, 1, 2]], [0.0, 1.0, 1.0], [0.25])
    >>> curve.edges.tolist(), curve.t.tolist(), curve.faces.tolist(), round(curve.length, 4)
    ([[0, 2], [0, 1]], [0.25, 0.25], [0], 0.3536)
    """

    points: np.ndarray
    level: float
    closed: bool
    edges: np.ndarray
    t: np.ndarray
    faces: np.ndarray

    @property
    def length(self):
        """Length of the polyline (the closing segment of a closed curve included)."""
        p = np.concatenate([self.points, self.points[:1]]) if self.closed else self.points
        return float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum())

    def __repr__(self):
        kind = "closed" if self.closed else "open"
        return f"Isoline(level={self.level!r}, {kind}, {len(self.points)} points)"


def isoline_levels(values, count):
    """``count`` evenly spaced levels: ``lo + (hi - lo) * j / (count + 1)`` for ``j = 1..count``.

    ``hi`` is the largest finite value and ``lo`` the smaller of 0 and the
    smallest finite value: for a distance field (no negative values) the
    levels are ``max * j / (count + 1)``, the lines of the PNG picture, the
    vertex-color stripes of :func:`heatcore.viz.colormap.colorize` and the
    Blender add-on's isoline material.
    None at all where no value is finite or all values are equal.

    Parameters
    ----------
    values : (n,) array_like of float
    count : int, at least 0

    Returns
    -------
    (count,) or (0,) float array

    Examples
    --------
    >>> isoline_levels([0.0, 2.0, np.inf], 3).tolist()
    [0.5, 1.0, 1.5]
    >>> isoline_levels([-1.0, 3.0], 1).tolist()
    [1.0]
    """
    _check_count(count)
    v = np.asarray(values, dtype=float).ravel()
    v = v[np.isfinite(v)]
    if count == 0 or v.size == 0:
        return np.zeros(0)
    lo, hi = min(0.0, float(v.min())), float(v.max())
    if not hi > lo:
        return np.zeros(0)
    return lo + (hi - lo) * np.arange(1, count + 1) / (count + 1)


def signed_levels(values, count):
    """Levels of a signed field: 0, and ``count`` on each side at ``vmax * j / (count + 1)`` (``vmax``: largest ``|value|``).

    Parameters
    ----------
    values : (n,) array_like of float
    count : int, at least 0

    Returns
    -------
    (2 count + 1,) float array, increasing; ``[0.0]`` where no value is finite and nonzero.

    Examples
    --------
    >>> signed_levels([-1.0, 0.5, 3.0], 2).tolist()
    [-2.0, -1.0, 0.0, 1.0, 2.0]
    """
    _check_count(count)
    v = np.abs(np.asarray(values, dtype=float).ravel())
    v = v[np.isfinite(v)]
    vmax = float(v.max()) if v.size else 0.0
    if not vmax > 0:
        return np.zeros(1)
    return vmax * np.arange(-count, count + 1) / (count + 1)


def _check_count(count):
    if isinstance(count, bool) or not isinstance(count, (int, np.integer)) or count < 0:
        raise InvalidOptionError(f"the number of isolines must be a non-negative integer, got {count!r}")


def isolines(V, F, values, levels):
    """Isoline curves of the linear interpolation of vertex ``values`` over the triangles.

    Parameters
    ----------
    V : (n, 3) array_like of float
        Vertex positions (``(n, 2)`` is read with z = 0).
    F : (m, 3) array_like of int
        Triangles.
    values : (n,) array_like of float
        A value per vertex; faces with a non-finite value (``inf``: unreachable) get no curve.
    levels : int or sequence of float
        An int ``N``: ``N`` evenly spaced levels (:func:`isoline_levels`; ``max * j / (N + 1)``,
        ``j = 1..N``, for distances); or the levels themselves (finite; duplicates count once).

    Returns
    -------
    list of Isoline
        By increasing level; see the module's notes on values exactly at a level.

    Raises
    ------
    InvalidMeshError
        Malformed ``V`` or ``F``.
    InvalidOptionError
        ``values`` not one per vertex, or a non-finite level.

    Examples
    --------
    >>> import heatcore as hc
    >>> V, F = hc.io.load_demo_mesh()
    >>> d = hc.geodesic_distance(V, F, [0])
    >>> curves = hc.isolines(V, F, d, 4)
    >>> [round(c.level, 3) for c in curves[:2]], all(c.closed for c in curves)
    ([0.312, 0.624], True)
    """
    V = vertex_array(V)
    F = index_array(F, V.shape[0], 3)
    values = np.asarray(values, dtype=float)
    if values.shape != (V.shape[0],):
        raise InvalidOptionError(f"values must hold one value per vertex, shape ({V.shape[0]},); got {values.shape}")
    if isinstance(levels, (int, np.integer)) and not isinstance(levels, bool):
        levels = isoline_levels(values, levels)
    try:
        levels = np.unique(np.asarray(levels, dtype=float).ravel())
    except (TypeError, ValueError) as exc:
        raise InvalidOptionError(f"levels must be an int or a sequence of numbers: {exc}") from exc
    if not np.isfinite(levels).all():
        raise InvalidOptionError(f"levels must be finite, got {levels[~np.isfinite(levels)][:3].tolist()}")
    segments = _face_segments(F, values, levels)
    if segments is None:
        return []
    return _polylines(V, values, levels, *segments)


def _face_segments(F, values, levels):
    """The segments of every (face, level) pair that the level crosses, oriented, on nodes (crossed edges).

    Returns ``(node_level, node_below, node_above, seg_start, seg_end, seg_face)`` or None: a node is
    a crossed edge at one level, from its vertex below the level to its vertex at or above it.
    """
    finite_vertex = np.isfinite(values)
    if finite_vertex.all():
        finite = np.arange(len(F))
    else:
        finite = np.flatnonzero(finite_vertex[F[:, 0]] & finite_vertex[F[:, 1]] & finite_vertex[F[:, 2]])
        F = F[finite]
    D0, D1, D2 = values[F[:, 0]], values[F[:, 1]], values[F[:, 2]]
    # (face, level) pairs with min < level <= max: the faces whose corners are not all on one side
    first = np.searchsorted(levels, np.minimum(np.minimum(D0, D1), D2), side="right")
    count = np.searchsorted(levels, np.maximum(np.maximum(D0, D1), D2), side="right") - first
    del D0, D1, D2
    crossed = np.flatnonzero(count > 0)
    if crossed.size == 0:
        return None
    count = count[crossed]
    pair_face = np.repeat(crossed, count)
    starts = np.cumsum(count) - count
    pair_level = np.repeat(first[crossed] - starts, count) + np.arange(int(count.sum()))
    corners = F[pair_face]
    above = values[corners] >= levels[pair_level][:, None]
    above_next = above[:, _NEXT]
    k_start = np.argmax(above & ~above_next, axis=1)  # edge leaving the region above: the segment starts there
    k_end = np.argmax(~above & above_next, axis=1)  # edge entering it: the segment ends there (higher values left)
    rows = np.arange(len(corners))
    start_below, start_above = corners[rows, _NEXT[k_start]], corners[rows, k_start]
    end_below, end_above = corners[rows, k_end], corners[rows, _NEXT[k_end]]
    keep = (start_below != end_below) | (start_above != end_above)  # a face with a repeated vertex
    n_pairs = int(keep.sum())
    columns = (np.tile(pair_level[keep], 2), np.concatenate([start_below[keep], end_below[keep]]),
               np.concatenate([start_above[keep], end_above[keep]]))
    first_row, inverse = _group(columns, (len(levels), len(values), len(values)))
    level, below, above = (column[first_row] for column in columns)
    return level, below, above, inverse[:n_pairs], inverse[n_pairs:], finite[pair_face[keep]]


def _group(columns, sizes):
    """Rows of equal integer ``columns`` (each in ``[0, size)``): a row of each group, and each row's group."""
    if float(np.prod([float(s) for s in sizes])) < 2.0**62:  # one int64 key per row
        key = np.zeros(len(columns[0]), dtype=np.int64)
        for column, size in zip(columns, sizes):
            key = key * size + column
        _, first, inverse = np.unique(key, return_index=True, return_inverse=True)
    else:  # pragma: no cover - over about 2e9 vertices with many levels
        _, first, inverse = np.unique(np.stack(columns, axis=1), axis=0, return_index=True, return_inverse=True)
    return first, inverse.ravel()


def _polylines(V, values, levels, node_level, node_below, node_above, seg_start, seg_end, seg_face):
    """Join the segments through their shared nodes into :class:`Isoline` curves."""
    va, vb, c = values[node_below], values[node_above], levels[node_level]
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        t = (c - va) / (vb - va)
    on_vertex = (vb == c) | ~(t < 1.0)  # the upper vertex is at the level (or t rounds to 1)
    t[on_vertex] = 0.0
    edge_a, edge_b = np.where(on_vertex, node_above, node_below), node_above.copy()
    node_points = V[edge_a] + t[:, None] * (V[edge_b] - V[edge_a]) + 0.0  # + 0.0: no -0.0
    # A point within rounding of a vertex is that vertex: the points of two edges of a vertex never
    # coincide otherwise (a level 1e-16 above a vertex's value), and every face around it holds it.
    tol = SNAP_ULPS * np.finfo(float).eps * np.maximum(np.abs(V[node_below]).max(axis=1),
                                                       np.abs(V[node_above]).max(axis=1))
    for end in (node_below, node_above):
        snap = np.abs(node_points - V[end]).max(axis=1) <= tol
        edge_a[snap], edge_b[snap], t[snap], node_points[snap] = end[snap], end[snap], 0.0, V[end[snap]]
    # nodes whose points coincide (the edges around a vertex at the level) share a point id
    rows = np.ascontiguousarray(node_points).view(np.dtype((np.void, node_points.dtype.itemsize * 3))).ravel()
    _, position = np.unique(rows, return_inverse=True)
    _, point_id = _group((node_level, position.ravel()), (len(levels), len(rows)))

    nxt, head = _links(seg_start, seg_end, len(node_level))
    tail = head[np.arange(len(head)) ^ 1]
    h_seq, chain, closed = _chains(nxt, point_id[tail] == point_id[head])
    if h_seq.size == 0:
        return []

    # Points: the tail of each half-segment, and the head of the last one of an open chain;
    # with each point, the half-segment arriving at it (-1: none).
    starts = np.flatnonzero(np.r_[True, chain[1:] != chain[:-1]])
    lengths = np.diff(np.r_[starts, len(chain)])
    is_closed = closed[chain[starts]]
    n_points = lengths + ~is_closed
    out = np.cumsum(n_points) - n_points
    pos = np.arange(len(h_seq)) + np.repeat(out - starts, lengths)
    last = h_seq[starts + lengths - 1]
    p_node = np.empty(int(n_points.sum()), dtype=np.int64)
    p_arrive = np.empty_like(p_node)
    p_node[pos] = tail[h_seq]
    p_arrive[pos[1:]] = h_seq[:-1]
    ends = (out + n_points - 1)[~is_closed]
    p_node[ends] = head[last[~is_closed]]
    p_arrive[ends] = last[~is_closed]
    p_arrive[out] = -1
    p_chain = np.repeat(np.arange(len(starts)), n_points)

    # One point per run of coincident points (a curve passing through a vertex at the level).
    pid = point_id[p_node]
    keep = np.r_[True, (pid[1:] != pid[:-1]) | (p_chain[1:] != p_chain[:-1])]
    p_node, p_arrive, p_chain, pid = p_node[keep], p_arrive[keep], p_chain[keep], pid[keep]
    edges, tt, points = np.stack([edge_a[p_node], edge_b[p_node]], axis=1), t[p_node], node_points[p_node]

    counts = np.bincount(p_chain, minlength=len(starts))
    first = np.cumsum(counts) - counts
    last_point = first + counts - 1
    # the face of the segment from each point to the next (a closed curve's last: back to its first)
    faces = np.empty_like(p_arrive)
    faces[:-1] = seg_face[p_arrive[1:] // 2]  # the face of the segment arriving at the next point
    faces[last_point] = seg_face[last // 2]
    # a spike: the curve runs out along an edge at the level and straight back
    nxt_pid, prv_pid = np.empty_like(pid), np.empty_like(pid)
    nxt_pid[:-1], prv_pid[1:] = pid[1:], pid[:-1]
    nxt_pid[last_point], prv_pid[first] = pid[first], pid[last_point]
    spike = nxt_pid == prv_pid
    spike[first[~is_closed]] = spike[last_point[~is_closed]] = False
    spiky = np.bincount(p_chain[spike], minlength=len(starts)) > 0

    level = levels[node_level[p_node[first]]]
    kept = np.flatnonzero(counts >= 2)  # one merged point only (a touching vertex): no curve
    kept = kept[np.argsort(level[kept], kind="stable")]
    curves = []
    columns = (first[kept].tolist(), counts[kept].tolist(), is_closed[kept].tolist(), level[kept].tolist(),
               spiky[kept].tolist())
    for s, k, closed, c, spiky_ in zip(*columns):  # a few microseconds per curve
        e = s + k if closed else s + k - 1
        if not spiky_:
            curves.append(Isoline(points[s : s + k], c, closed, edges[s : s + k], tt[s : s + k], faces[s:e]))
            continue
        for rows, segment_faces, closed_ in _without_spurs(pid[s : s + k], np.arange(s, s + k), faces[s:e], closed):
            curves.append(Isoline(points[rows], c, closed_, edges[rows], tt[rows], segment_faces))
    return curves


def _links(seg_start, seg_end, n_nodes):
    """Successor of each half-segment, and the node each arrives at.

    Half-segment ``h = 2 s`` runs segment ``s`` from its start node to its end
    node, ``h = 2 s + 1`` back. At a node of two segments, arriving by one
    leaves by the other; a node of one segment (the mesh boundary) or of more
    than two (a non-manifold edge) ends the chains that reach it.
    """
    n_seg = len(seg_start)
    inc_node = np.concatenate([seg_start, seg_end])  # incidence i = (s, e): e = 0 at the start, 1 at the end
    inc_seg = np.tile(np.arange(n_seg), 2)
    inc_end = np.repeat([0, 1], n_seg)
    arrive, leave = 2 * inc_seg + 1 - inc_end, 2 * inc_seg + inc_end
    head = np.empty(2 * n_seg, dtype=np.int64)
    head[arrive] = inc_node
    degree = np.bincount(inc_node, minlength=n_nodes)
    order = np.argsort(inc_node, kind="stable")
    node = inc_node[order]
    pair = np.flatnonzero((node[1:] == node[:-1]) & (degree[node[1:]] == 2))
    i1, i2 = order[pair], order[pair + 1]
    nxt = np.full(2 * n_seg, -1, dtype=np.int64)
    nxt[arrive[i1]] = leave[i2]
    nxt[arrive[i2]] = leave[i1]
    return nxt, head


def _chains(nxt, zero):
    """Order the half-segments into chains, one direction per chain.

    Each chain of segments appears twice in ``nxt`` (once per direction); the
    direction that runs more segments from start to end is kept (all of them
    on a consistently oriented mesh). A closed chain is cut before its
    smallest half-segment that follows one of nonzero length (``zero``: both
    ends at one merged point), so that no run of merged points straddles the
    cut; a closed chain of zero-length segments only is dropped.

    Returns
    -------
    h_seq : (k,) int array
        The kept half-segments, chain by chain, each chain in order.
    chain : (k,) int array
        The chain of each (sorted).
    closed : (n_chains,) bool array
        Whether each chain (by its id in ``chain``) is closed.
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    H = len(nxt)
    h = np.arange(H)
    linked = nxt >= 0
    graph = coo_matrix((np.ones(int(linked.sum()), dtype=np.int8), (h[linked], nxt[linked])), shape=(H, H))
    n_comp, comp = connected_components(graph, directed=True, connection="weak")
    forward = np.bincount(comp, weights=(h % 2 == 0), minlength=n_comp)
    partner = np.empty(n_comp, dtype=np.int64)
    partner[comp] = comp[h ^ 1]
    chosen = (forward > forward[partner]) | ((forward == forward[partner]) & (np.arange(n_comp) < partner))
    pred = np.full(H, -1, dtype=np.int64)
    pred[nxt[linked]] = h[linked]
    has_start = np.zeros(n_comp, bool)
    has_start[comp[pred < 0]] = True
    closed = chosen & ~has_start
    candidate = closed[comp].copy()
    candidate[candidate] = ~zero[pred[candidate]]
    cut_comp, first = np.unique(comp[candidate], return_index=True)  # h ascending: the smallest of each
    cut = np.flatnonzero(candidate)[first]
    chosen[closed] = False
    chosen[cut_comp] = True  # a closed chain of zero-length segments only (a touching vertex): dropped
    nxt = nxt.copy()
    nxt[pred[cut]] = -1

    live = np.flatnonzero(chosen[comp])
    index = np.full(H, -1, dtype=np.int64)
    index[live] = np.arange(live.size)
    jump = np.where(nxt[live] >= 0, index[nxt[live]], -1)
    rank = (jump >= 0).astype(np.int64)  # list ranking by pointer jumping: steps to the chain's end
    active = np.flatnonzero(jump >= 0)
    while active.size:
        rank[active] += rank[jump[active]]
        jump[active] = jump[jump[active]]
        active = active[jump[active] >= 0]
    order = np.lexsort((-rank, comp[live]))
    return live[order], comp[live][order], closed


def _without_spurs(pid, rows, faces, closed):
    """Split off the parts of a curve that it runs out and back along (an edge at the level with
    lower values on both sides): each becomes an open curve of its own, drawn once.

    ``pid`` are the point ids (no two consecutive equal), ``rows`` the points' rows, ``faces`` the
    segments' faces. Yields ``(rows, faces, closed)`` per curve of at least two points.
    """
    pid, rows, faces = list(pid), list(rows), list(faces)
    while True:  # rare: a spur of a curve at the level
        k = len(pid)
        if closed:
            tips = [i for i in range(k) if pid[i - 1] == pid[(i + 1) % k]]
        else:
            tips = [i for i in range(1, k - 1) if pid[i - 1] == pid[i + 1]]
        if not tips:
            break
        i = tips[0]
        if closed:  # rotate the tip to the front: pid[-j] == pid[j] along the spur
            pid, rows, faces = pid[i:] + pid[:i], rows[i:] + rows[:i], faces[i:] + faces[:i]
            j = 1
            while 2 * j < k and pid[-(j + 1)] == pid[(j + 1) % k]:
                j += 1
            if 2 * j >= k:  # the whole curve runs out and back: one open curve, tip to tip
                yield np.array(rows[: k // 2 + 1]), np.array(faces[: k // 2]), False
                return
            yield np.array(rows[k - j :] + rows[:1]), np.array(faces[k - j :]), False
            pid, rows, faces = pid[j : k - j], rows[j : k - j], faces[j : k - j]
        else:
            j = 1
            while i - j - 1 >= 0 and i + j + 1 < k and pid[i - j - 1] == pid[i + j + 1]:
                j += 1
            yield np.array(rows[i - j : i + 1]), np.array(faces[i - j : i]), False
            pid, rows, faces = pid[: i - j + 1] + pid[i + j + 1 :], rows[: i - j + 1] + rows[i + j + 1 :], \
                faces[: i - j] + faces[i + j :]
        if len(pid) < 2:
            return
    yield np.array(rows), np.array(faces), closed  # a closed one has 3 points or more (2 make a spike)
