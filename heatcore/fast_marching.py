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

from .compiled import available, compiled  # noqa: F401 (available: the callers ask fast_marching.available())
from .domains.build_kernels import sort_by_key


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
    _march_loop(readers.start, readers.rows, readers.corners, readers.layout, d, is_pinned,
                np.asarray(pinned, dtype=np.int64), float(tol))


class Readers:
    """The corners of triangle sets by the vertices they read, laid out for :func:`march`.

    A corner at ``C`` of triangle ``(C, A, B)`` is read by ``A`` and by ``B``:
    its layout is stored once, and listed twice in ``rows``, once per reader;
    the loop turns it to its reader (mirrored about the middle of ``AB`` for
    ``B``: ``x`` becomes ``c - x`` and the two sides swap; the update does not
    change). One vertex's rows are consecutive; storing each layout once
    keeps the table at 60 bytes per corner instead of 96 (1M-vertex sphere:
    0.54 GB instead of 0.86 GB).

    Parameters
    ----------
    n : int
        Number of vertices.
    C, A, B, layout : arrays
        The corners, as :func:`heatcore.eikonal.corner_layout` returns them.

    Attributes
    ----------
    start : (n + 1,) int array
        The corners read by vertex ``u`` are ``rows[start[u]:start[u + 1]]``.
    rows : int32 (int64 past 2**30 corners) array
        ``2 j`` where the reader is corner ``j``'s ``A``, ``2 j + 1`` where it is its ``B``.
    corners : (k, 3) int32 array
        ``C, A, B`` of each corner.
    layout : (k, 5) float array
        ``c, x, y, |CA|, |CB|`` of each corner, as in :class:`~heatcore.eikonal.CornerTable`.

    Examples
    --------
    >>> import numpy as np
    >>> from heatcore.eikonal import corner_layout
    >>> readers = Readers(3, *corner_layout([np.array([[0, 1, 2]])], [np.array([[1.0, 1.0, 1.0]])]))
    >>> C, other, layout = readers.turned(0)  # the corners that read vertex 0
    >>> C.tolist(), other.tolist()
    ([1, 2], [2, 1])
    """

    def __init__(self, n, C, A, B, layout):
        self.corners = np.stack([C, A, B], axis=1).astype(np.int32)
        self.layout = np.ascontiguousarray(layout.T)
        self.start, self.rows = _by_reader(n, self.corners, _row_codes(C.size))

    def turned(self, u):
        """The corners vertex ``u`` reads, turned to it as :func:`march` sees them: ``C``, the other vertex of the
        side (``B``, ``u`` being ``A``) and the ``(r, 5)`` layouts ``c, x, y, |CA|, |CB|``."""
        code = self.rows[self.start[u] : self.start[u + 1]]
        j, mirrored = code >> 1, (code & 1).astype(bool)
        other = np.where(mirrored, self.corners[j, 1], self.corners[j, 2])
        layout = self.layout[j]
        layout[mirrored, 1] = layout[mirrored, 0] - layout[mirrored, 1]
        layout[mirrored, 3:5] = layout[mirrored][:, [4, 3]]
        return self.corners[j, 0], other, layout

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
        ...               for k in ("start", "rows", "corners", "layout")))
        ... else:
        ...     print(True)
        True
        """
        # The first set (the intrinsic triangles) is read where it is: stacking it with the rest made the corner
        # table's peak (1M-vertex sphere: 144 MB more, the one-off's peak).
        faces, lengths = _head_and_tail(faces, np.int64), _head_and_tail(lengths, float)
        readers = cls.__new__(cls)
        kept = _kept_in_order(*faces, max(int(f.max(initial=0)) for f in faces) + 1)
        readers.corners, readers.layout = _turned_corners(*faces, *lengths, kept)
        del faces, lengths
        readers.start, readers.rows = _by_reader(n, readers.corners, _row_codes(readers.corners.shape[0]))
        return readers


def _head_and_tail(arrays, dtype):
    """The first of the ``(k_i, 3)`` arrays, and the others stacked (``(0, 3)`` where there are none), C-ordered."""
    head = np.ascontiguousarray(arrays[0], dtype=dtype)
    tail = [np.asarray(a, dtype=dtype) for a in arrays[1:]]
    return head, np.ascontiguousarray(np.concatenate(tail) if tail else np.zeros((0, 3), dtype=dtype))


@compiled
def _march_loop(start, rows, corners, layout, d, is_pinned, pinned, tol):  # pragma: no cover - compiled
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
            j = rows[k] >> 1
            w = corners[j, 0]
            if is_pinned[w]:
                continue
            c = layout[j, 0]
            if rows[k] & 1:  # u is the corner's B: the triangle mirrored about the middle of AB
                o, x, first, second = corners[j, 1], c - layout[j, 1], layout[j, 4], layout[j, 3]
            else:
                o, x, first, second = corners[j, 2], layout[j, 1], layout[j, 3], layout[j, 4]
            if accepted[o]:
                value = _triangle(du, d[o], c, x, layout[j, 2], first, second)
            else:
                value = du + first
            if value < d[w] * (1.0 - tol) or (value < d[w] and not accepted[w]):
                d[w] = value
                size = _sift_up(heap, where, d, size, w)


def _row_codes(k):
    """An empty array for the ``rows`` of ``k`` corners: int32 where ``2 k`` fits."""
    return np.empty(2 * k, dtype=np.int32 if 2 * k < 2**31 else np.int64)


@compiled
def _by_reader(n, corners, rows):  # pragma: no cover - compiled
    """:class:`Readers`' ``start``, and its ``rows`` filled in: a counting sort of the corners by reading vertex
    (the ``A`` of each corner, then its ``B``, corner by corner)."""
    start = np.zeros(n + 1, dtype=np.int64)
    for j in range(corners.shape[0]):
        start[corners[j, 1] + 1] += 1
        start[corners[j, 2] + 1] += 1
    start = np.cumsum(start)
    place = start[:-1].copy()
    for j in range(corners.shape[0]):
        for side in range(2):
            reader = corners[j, 1 + side]
            rows[place[reader]] = 2 * j + side
            place[reader] += 1
    return start, rows


@compiled
def _row(head, tail, t):  # pragma: no cover - compiled
    """Row ``t`` of ``head`` stacked over ``tail``, without stacking them."""
    return head[t] if t < head.shape[0] else tail[t - head.shape[0]]


@compiled
def _first_corner(face):  # pragma: no cover - compiled
    """The corner of a triangle at its smallest vertex (the first of them, as ``np.argmin``)."""
    k = 0
    if face[1] < face[0]:
        k = 1
    if face[2] < face[k]:
        k = 2
    return k


@compiled
def _kept_in_order(head, tail, n):  # pragma: no cover - compiled
    """The triangles :func:`~heatcore.eikonal.corner_layout` keeps (of ``head`` stacked over ``tail``), in its
    order: turned to start at their smallest vertex, sorted (a counting sort by it, then a stable sort by the
    other two), the first of equal ones."""
    m = head.shape[0] + tail.shape[0]
    start = np.zeros(n + 1, dtype=np.int64)
    for t in range(m):
        face = _row(head, tail, t)
        start[face[_first_corner(face)] + 1] += 1
    start = np.cumsum(start)
    place = start[:-1].copy()
    order = np.empty(m, dtype=np.int64)
    key = np.empty(m, dtype=np.int64)  # the turned triangle's other two vertices, as one number
    for t in range(m):
        face = _row(head, tail, t)
        k = _first_corner(face)
        j = place[face[k]]
        place[face[k]] += 1
        order[j], key[j] = t, face[(k + 1) % 3] * n + face[(k + 2) % 3]
    kept = np.ones(m, dtype=np.bool_)
    for v in range(n):
        lo, hi = start[v], start[v + 1]
        sort_by_key(order, key, lo, hi)  # stable
        for j in range(lo + 1, hi):
            kept[j] = key[j] != key[j - 1]
    return order[kept]


@compiled
def _turned_corners(faces_head, faces_tail, lengths_head, lengths_tail, kept):  # pragma: no cover - compiled
    """:class:`Readers`' ``corners`` and ``layout`` of :func:`~heatcore.eikonal.corner_layout`'s corners of the
    ``kept`` triangles (of the heads stacked over the tails), each computed as there (the same floating-point
    operations, in the same order)."""
    corners = np.empty((3 * kept.size, 3), dtype=np.int32)
    layout = np.empty((3 * kept.size, 5))
    j = 0
    for t in kept:
        face, side = _row(faces_head, faces_tail, t), _row(lengths_head, lengths_tail, t)
        first = _first_corner(face)
        for k in range(3):
            corner, nxt, prv = (first + k) % 3, (first + k + 1) % 3, (first + k + 2) % 3
            C, A, B = face[corner], face[nxt], face[prv]
            c, cb, ca = side[corner], side[nxt], side[prv]
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
            corners[j, 0], corners[j, 1], corners[j, 2] = C, A, B
            layout[j, 0], layout[j, 1], layout[j, 2], layout[j, 3], layout[j, 4] = c, x, y, ca, cb
            j += 1
    return corners, layout


@compiled
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


@compiled
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


@compiled
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
