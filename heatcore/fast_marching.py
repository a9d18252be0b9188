"""Compiled fast marching for ``accuracy="high"`` (numba, the ``fast`` extra).

The same triangle update and the same corners as the vectorized pass of
:mod:`heatcore.eikonal`, in a different order: a fast-marching loop (Kimmel
and Sethian's method with a binary heap) compiled by numba, which numpy cannot
express without a Python step per vertex. Vertices are accepted in increasing
distance; an accepted vertex re-evaluates the corners of its neighbours, where
a triangle update uses two accepted vertices and an edge update one. A vertex
that an update lowers by more than ``tol`` relative goes back on the heap,
accepted or not: at an obtuse corner the characteristic can cross the
opposite edge between a closer and a farther vertex, and the farther one is
accepted later (the vectorized pass keeps bands of heat distance open for the
same reason). Values only decrease; every value is the length of a path or a
triangle update of accepted values.

The heat distance is not needed for the order (the heap gives it); it only
marks the reachable vertices. On the shared meshes the result is within 1e-6
of the vectorized pass's on most vertices and as close to the exact
geodesics (see docs/accuracy-high.md), in a tenth of its time.

numba compiles the loop on first use (seconds, cached on disk next to this
module where it is writable). Without numba, :func:`available` is False and
:func:`heatcore.eikonal.refine_distance` takes the vectorized pass.

Examples
--------
>>> import numpy as np
>>> from heatcore.eikonal import corner_layout
>>> equilateral = Readers(3, *corner_layout([np.array([[0, 1, 2]])], [np.array([[1.0, 1.0, 1.0]])]))
>>> d = np.array([0.0, np.inf, np.inf])
>>> if available():
...     march(equilateral, d, np.array([0]), 1e-6)
>>> np.round(d, 12).tolist() if available() else [0.0, 1.0, 1.0]
[0.0, 1.0, 1.0]
"""

import numpy as np

from .linalg.libraries import optional

_numba = optional("numba")


def _compiled(function):
    """``function`` compiled by numba on its first call (cached on disk), or as it is without numba."""
    return function if _numba is None else _numba.njit(cache=True, nogil=True, error_model="numpy")(function)


def available():
    """Whether numba is installed, so that :func:`march` can run.

    Examples
    --------
    >>> isinstance(available(), bool)
    True
    """
    return _numba is not None


def march(readers, d, pinned, tol):
    """Fast marching from the pinned vertices, in place on ``d``.

    Parameters
    ----------
    readers : Readers
        The corners to update from.
    d : (n,) float array
        Known distances at ``pinned`` (kept), ``inf`` elsewhere; on return,
        the distance at every vertex reached from the pins.
    pinned : (k,) int array
    tol : float
        A value is lowered (and its vertex re-opened) only by more than this, relatively.

    Examples
    --------
    >>> import numpy as np
    >>> from heatcore.eikonal import corner_layout
    >>> V = np.array([[0, 0], [1, 0], [0, 1], [1, 1]], float)
    >>> F = np.array([[0, 1, 2], [1, 3, 2]])
    >>> L = np.linalg.norm(V[F[:, [1, 2, 0]]] - V[F[:, [2, 0, 1]]], axis=2)  # side opposite each corner
    >>> d = np.array([0.0, np.inf, np.inf, np.inf])
    >>> if available():
    ...     march(Readers(4, *corner_layout([F], [L])), d, np.array([0]), 1e-6)
    ...     print(np.round(d, 6).tolist())
    ... else:
    ...     print([0.0, 1.0, 1.0, 1.414214])
    [0.0, 1.0, 1.0, 1.414214]
    """
    is_pinned = np.zeros(d.size, dtype=np.bool_)
    is_pinned[pinned] = True
    _march_loop(readers.start, readers.corner_vertex, readers.other, readers.layout, d, is_pinned,
                np.asarray(pinned, dtype=np.int64), float(tol))


class Readers:
    """The corners of triangle sets by the vertices they read, laid out for :func:`march`.

    A corner at ``C`` of triangle ``(C, A, B)`` is read by ``A`` and by ``B``:
    it appears twice, each time turned so that the reading vertex is ``A``
    (mirrored about the middle of ``AB`` where it was ``B``; the update does
    not change). The loop then reads one vertex's corners from consecutive
    memory.

    Parameters
    ----------
    n : int
        Number of vertices.
    C, A, B, layout : arrays
        The corners, as :func:`heatcore.eikonal.corner_layout` returns them.

    Attributes
    ----------
    start : (n + 1,) int array
        The corners read by vertex ``u`` are rows ``start[u]:start[u + 1]``.
    corner_vertex, other : int32 arrays
        ``C`` and ``B`` of each row (``A`` is the reading vertex).
    layout : (rows, 5) float array
        ``c, x, y, |CA|, |CB|`` as in :class:`~heatcore.eikonal.CornerTable`.

    Examples
    --------
    >>> import numpy as np
    >>> from heatcore.eikonal import corner_layout
    >>> readers = Readers(3, *corner_layout([np.array([[0, 1, 2]])], [np.array([[1.0, 1.0, 1.0]])]))
    >>> rows = slice(readers.start[0], readers.start[1])  # the corners that read vertex 0
    >>> readers.corner_vertex[rows].tolist(), readers.other[rows].tolist()
    ([1, 2], [2, 1])
    """

    def __init__(self, n, C, A, B, layout):
        self.start, self.corner_vertex, self.other, self.layout = _by_reader(n, C, A, B, layout)

    @classmethod
    def of_triangles(cls, n, faces, lengths):
        """``Readers(n, *corner_layout(faces, lengths))``, the same arrays, in one compiled pass (needs numba).

        :func:`~heatcore.eikonal.corner_layout`'s order (each triangle turned
        to start at its smallest vertex, kept once, in lexicographic order)
        comes from a counting sort by that vertex, without its 1M-vertex
        temporaries (1.5-2 s there, 0.3 s here).

        Examples
        --------
        >>> import numpy as np
        >>> from heatcore.eikonal import corner_layout
        >>> F, L = [np.array([[2, 0, 1], [0, 1, 3]])], [np.array([[1.0, 1.2, 1.1], [1.0, 1.0, 1.4]])]
        >>> if available():
        ...     readers, layout = Readers.of_triangles(4, F, L), Readers(4, *corner_layout(F, L))
        ...     print(all(np.array_equal(getattr(readers, k), getattr(layout, k), equal_nan=True)
        ...               for k in ("start", "corner_vertex", "other", "layout")))
        ... else:
        ...     print(True)
        True
        """
        faces = np.concatenate([np.asarray(f, dtype=np.int64) for f in faces])
        lengths = np.concatenate([np.asarray(l, dtype=float) for l in lengths])
        readers = cls.__new__(cls)
        kept = _kept_in_order(faces, int(faces.max(initial=0)) + 1)
        readers.start, readers.corner_vertex, readers.other, readers.layout = _turned_by_reader(n, faces, lengths, kept)
        return readers


@_compiled
def _march_loop(start, corner_vertex, other, layout, d, is_pinned, pinned, tol):  # pragma: no cover - compiled
    """The heap loop of :func:`march` (plain Python, compiled by numba)."""
    n = d.size
    accepted = np.zeros(n, dtype=np.bool_)
    heap = np.empty(n, dtype=np.int64)  # vertices, a binary heap on d
    where = np.full(n, -1, dtype=np.int64)  # each vertex's place in the heap, -1 if not there
    size = 0
    for v in pinned:
        size = _sift_up(heap, where, d, size, v)
    while size > 0:
        u = heap[0]
        size = _pop(heap, where, d, size)
        accepted[u] = True
        du = d[u]
        for k in range(start[u], start[u + 1]):
            w = corner_vertex[k]
            if is_pinned[w]:
                continue
            o = other[k]
            if accepted[o]:
                value = _triangle(du, d[o], layout[k, 0], layout[k, 1], layout[k, 2], layout[k, 3], layout[k, 4])
            else:
                value = du + layout[k, 3]
            if value < d[w] * (1.0 - tol) or (value < d[w] and not accepted[w]):
                d[w] = value
                size = _sift_up(heap, where, d, size, w)


@_compiled
def _by_reader(n, C, A, B, layout):  # pragma: no cover - compiled
    """:class:`Readers`' arrays from the corners (a counting sort by reading vertex)."""
    start = np.zeros(n + 1, dtype=np.int64)
    for j in range(C.size):
        start[A[j] + 1] += 1
        start[B[j] + 1] += 1
    start = np.cumsum(start)
    place = start[:-1].copy()
    corner_vertex = np.empty(2 * C.size, dtype=np.int32)
    other = np.empty(2 * C.size, dtype=np.int32)
    rows = np.empty((2 * C.size, 5))
    for j in range(C.size):
        c, x, y, ca, cb = layout[0, j], layout[1, j], layout[2, j], layout[3, j], layout[4, j]
        for reader, second, xr, first_side, second_side in ((A[j], B[j], x, ca, cb), (B[j], A[j], c - x, cb, ca)):
            k = place[reader]
            place[reader] += 1
            corner_vertex[k], other[k] = C[j], second
            rows[k, 0], rows[k, 1], rows[k, 2], rows[k, 3], rows[k, 4] = c, xr, y, first_side, second_side
    return start, corner_vertex, other, rows


@_compiled
def _first_corner(f, t):  # pragma: no cover - compiled
    """The corner of triangle ``t`` at its smallest vertex (the first of them, as ``np.argmin``)."""
    k = 0
    if f[t, 1] < f[t, 0]:
        k = 1
    if f[t, 2] < f[t, k]:
        k = 2
    return k


@_compiled
def _kept_in_order(f, n):  # pragma: no cover - compiled
    """The triangles :func:`~heatcore.eikonal.corner_layout` keeps, in its order: turned to start at their smallest
    vertex, sorted (a counting sort by it, then insertion by the other two), the first of equal ones."""
    start = np.zeros(n + 1, dtype=np.int64)
    for t in range(f.shape[0]):
        start[f[t, _first_corner(f, t)] + 1] += 1
    start = np.cumsum(start)
    place = start[:-1].copy()
    order = np.empty(f.shape[0], dtype=np.int64)
    second = np.empty(f.shape[0], dtype=np.int64)  # the turned triangle's other two vertices
    third = np.empty(f.shape[0], dtype=np.int64)
    for t in range(f.shape[0]):
        k = _first_corner(f, t)
        v = f[t, k]
        j = place[v]
        place[v] += 1
        b, c = f[t, (k + 1) % 3], f[t, (k + 2) % 3]
        while j > start[v] and (second[j - 1] > b or (second[j - 1] == b and third[j - 1] > c)):  # stable
            order[j], second[j], third[j] = order[j - 1], second[j - 1], third[j - 1]
            j -= 1
        order[j], second[j], third[j] = t, b, c
    kept = np.ones(f.shape[0], dtype=np.bool_)
    for v in range(n):
        for j in range(start[v] + 1, start[v + 1]):
            kept[j] = second[j] != second[j - 1] or third[j] != third[j - 1]
    return order[kept]


@_compiled
def _turned_by_reader(n, f, lengths, kept):  # pragma: no cover - compiled
    """:func:`_by_reader` of :func:`~heatcore.eikonal.corner_layout`'s corners of the ``kept`` triangles, each
    row computed as there (the same floating-point operations, in the same order)."""
    start = np.zeros(n + 1, dtype=np.int64)
    for t in kept:
        for k in range(3):
            start[f[t, k] + 1] += 2  # each vertex reads the two corners beside it in each of its triangles
    start = np.cumsum(start)
    place = start[:-1].copy()
    size = 6 * kept.size
    corner_vertex = np.empty(size, dtype=np.int32)
    other = np.empty(size, dtype=np.int32)
    rows = np.empty((size, 5))
    for t in kept:
        first = _first_corner(f, t)
        for k in range(3):
            corner, nxt, prv = (first + k) % 3, (first + k + 1) % 3, (first + k + 2) % 3
            C, A, B = f[t, corner], f[t, nxt], f[t, prv]
            c, cb, ca = lengths[t, corner], lengths[t, nxt], lengths[t, prv]
            x = (ca * ca - cb * cb + c * c) / (2.0 * c)
            y = ca * ca - x * x
            if y < 0.0:
                y = 0.0
            y = np.sqrt(y)
            if A == C or B == C or A == B or not y > 0.0 or not c > 0.0 or not np.isfinite(x):
                c = np.nan
            if A == C:
                ca = np.inf
            if B == C:
                cb = np.inf
            for reader, second, xr, first_side, second_side in ((A, B, x, ca, cb), (B, A, c - x, cb, ca)):
                j = place[reader]
                place[reader] += 1
                corner_vertex[j], other[j] = C, second
                rows[j, 0], rows[j, 1], rows[j, 2], rows[j, 3], rows[j, 4] = c, xr, y, first_side, second_side
    return start, corner_vertex, other, rows


@_compiled
def _triangle(da, db, c, x, y, ca, cb):  # pragma: no cover - compiled
    """:func:`heatcore.eikonal.triangle_update` for one corner."""
    edge = min(da + ca, db + cb)
    xs = 0.5 * ((da - db) * (da + db) / c + c)
    square = (da - xs) * (da + xs)
    if not square >= 0.0:  # no virtual source (or a nan layout)
        return edge
    ys = np.sqrt(square)
    dx, dy = x - xs, y + ys
    t = xs * y + x * ys
    if t >= 0.0 and t <= c * dy:
        return np.sqrt(dx * dx + dy * dy)
    return edge


@_compiled
def _sift_up(heap, where, d, size, v):  # pragma: no cover - compiled
    """Put ``v`` on the heap of ``size`` vertices, or move it up after its ``d`` decreased; the new size."""
    k = where[v]
    if k < 0:
        k = size
        size += 1
    value = d[v]
    while k > 0:
        parent = (k - 1) >> 1
        if d[heap[parent]] <= value:
            break
        heap[k] = heap[parent]
        where[heap[k]] = k
        k = parent
    heap[k] = v
    where[v] = k
    return size


@_compiled
def _pop(heap, where, d, size):  # pragma: no cover - compiled
    """Remove the first vertex of the heap of ``size`` vertices; the new size."""
    where[heap[0]] = -1
    size -= 1
    if size == 0:
        return 0
    v = heap[size]
    value = d[v]
    k = 0
    while True:
        child = 2 * k + 1
        if child >= size:
            break
        if child + 1 < size and d[heap[child + 1]] < d[heap[child]]:
            child += 1
        if d[heap[child]] >= value:
            break
        heap[k] = heap[child]
        where[heap[k]] = k
        k = child
    heap[k] = v
    where[v] = k
    return size
