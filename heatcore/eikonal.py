"""The eikonal pass of ``accuracy="high"`` without numba, and the corner geometry of both passes.

:mod:`heatcore.high_accuracy` chooses the pass: the compiled fast marching of
:mod:`heatcore.fast_marching` where numba is installed (same triangle update,
same corners as here, from :func:`corner_layout`), else this module's
vectorized pass, :func:`refine_distance`, described here.

The heat method gives a smooth distance ``phi`` whose error (1-2% on real
meshes) is low-frequency: the *order* in which it reaches the vertices is
nearly right even where its values are not. :func:`refine_distance` keeps
that order and recomputes the values with the fast-marching triangle update
of Kimmel and Sethian ("Computing geodesic paths on manifolds", PNAS 1998):

* every vertex starts at ``+inf`` except the pinned source vertices
  (:class:`~heatcore.domains.sources.SourcePins`: 0 at source vertices, the in-face
  straight-line distance around a surface point);
* vertices are swept in increasing ``phi``, in bands of heat distance
  ``band_width`` mean edge lengths wide. Each band is relaxed, fully
  vectorized, from the triangles around its vertices (every corner of every
  triangle of a band vertex is one array element): the first sweep evaluates
  all of the band's corners from the vertices known so far; later sweeps (at
  most ``max_sweeps`` per band) only the corners whose other two vertices
  just changed, which resolves the dependencies inside a band. Corners still
  pending move on with the next band;
* the ``lookback`` bands before the current one stay open: a change in the
  current band re-relaxes their corners too. A vertex at an obtuse corner can
  take its value from a vertex a little farther from the source (the
  characteristic crosses the opposite edge), and this lets that value arrive;
* values only decrease; a sweep counts a change when a value drops by more
  than ``tol`` relatively. Vertices the pass leaves unreached (``phi`` put
  them long before all their neighbours) get global relaxation sweeps.

Triangle update. For a corner ``C`` of a triangle ``ABC`` with known
distances ``d_A`` and ``d_B``, the triangle is laid out in the plane with
``A = (0, 0)``, ``B = (|AB|, 0)`` and ``C`` above the x axis, and the virtual
point source ``S`` with ``|SA| = d_A``, ``|SB| = d_B`` is placed below it (the
wavefront arriving at ``AB`` is then the one of a point source, exact on flat
pieces). If the segment ``SC`` crosses the edge ``AB`` between its ends, the
characteristic passes through the triangle and ``d_C = |SC|``. Otherwise (no
such ``S`` exists, or the characteristic falls outside the triangle, as it can
at an obtuse corner) only the edge updates ``d_A + |AC|`` and ``d_B + |BC|``
are used: lengths of actual paths, never an underestimate. No unfolding of
neighbouring triangles is needed: the obtuse corner gets its exact value from
the triangle the characteristic does cross, which the relaxation reaches.

The update set is the union of two triangulations of the same vertices: the
intrinsic Delaunay triangles the heat operators were built on, and the
(possibly midpoint-subdivided) extrinsic mesh with its Euclidean edge
lengths. Each vertex takes the minimum over all its corners in both.

Examples
--------
>>> import numpy as np, heatcore as hc
>>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
>>> solver = hc.HeatSolver(hc.TriangleMesh(V, [[0, 1, 2], [1, 3, 2]]), accuracy="high")
>>> round(float(solver.distance([0])[3]), 6)
1.414214
"""

import numpy as np

from .domains.intrinsic import NEXT, PREV

#: Width of a band of heat distance, in mean edge lengths.
BAND_WIDTH = 1.0
#: Settled bands that stay open to changes while the next band settles.
LOOKBACK = 2
#: Most relaxations per band before the rest carries over to the next band.
MAX_SWEEPS = 3
#: Most global relaxation sweeps after the ordered pass.
POLISH_SWEEPS = 0
#: A value counts as changed when it decreases by more than this, relatively.
TOL = 1e-6

_ZERO = np.zeros(1, dtype=np.int64)
_EMPTY = np.zeros(0, dtype=np.int64)


def corner_layout(faces, lengths):
    """Every corner of the given triangle sets, each triangle once, with its planar layout.

    Parameters
    ----------
    faces : list of (m, 3) int arrays
        Triangle sets on the same vertices; a triangle in several (the same
        vertices in the same turn) is kept once.
    lengths : list of (m, 3) float arrays
        Side lengths, the side opposite each corner.

    Returns
    -------
    C, A, B : int arrays
        Per corner: its vertex, the next and the previous corner's.
    layout : (5, k) float array
        ``c, x, y, ca, cb`` as in :class:`CornerTable`.

    Examples
    --------
    >>> import numpy as np
    >>> F, L = np.array([[0, 1, 2]]), np.ones((1, 3))
    >>> C, A, B, layout = corner_layout([F, F[:, [1, 2, 0]]], [L, L])  # the same triangle twice
    >>> C.tolist(), A.tolist(), layout[:3, 0].round(3).tolist()
    ([0, 1, 2], [1, 2, 0], [1.0, 0.5, 0.866])
    """
    faces = np.concatenate([np.asarray(f, dtype=np.int64) for f in faces])
    lengths = np.concatenate([np.asarray(l, dtype=float) for l in lengths])
    # Each triangle turned to start at its smallest vertex, then duplicates dropped.
    turn = np.argmin(faces, axis=1)[:, None] + np.arange(3)
    rows = np.arange(len(faces))[:, None]
    faces, lengths = faces[rows, turn % 3], lengths[rows, turn % 3]
    n = int(faces.max(initial=0)) + 1
    if n < 2**21:  # one int64 key per triangle
        _, first = np.unique((faces[:, 0] * n + faces[:, 1]) * n + faces[:, 2], return_index=True)
    else:
        order = np.lexsort(faces.T[::-1])
        first = order[np.r_[True, (np.diff(faces[order], axis=0) != 0).any(axis=1)]]
    faces, lengths = faces[first], lengths[first]
    C, A, B = faces.ravel(), faces[:, NEXT].ravel(), faces[:, PREV].ravel()
    # The five rows are computed in place in the returned array: at 1M vertices each temporary is 70 MB.
    layout = np.empty((5, C.size))
    c, x, y, ca, cb = layout
    c[:] = lengths.ravel()  # |AB|: opposite corner C
    np.take(lengths, NEXT, axis=1, out=cb.reshape(-1, 3))  # |CB|: opposite corner A
    np.take(lengths, PREV, axis=1, out=ca.reshape(-1, 3))  # |CA|: opposite corner B
    with np.errstate(divide="ignore", invalid="ignore"):
        np.multiply(ca, ca, out=x)  # x = (ca^2 - cb^2 + c^2) / 2c, in this order
        x -= cb * cb
        x += c * c
        x /= 2.0 * c
        np.multiply(ca, ca, out=y)  # y = sqrt(max(ca^2 - x^2, 0))
        y -= x * x
        np.maximum(y, 0.0, out=y)
        np.sqrt(y, out=y)
    bad = (A == C) | (B == C) | (A == B) | ~(y > 0) | ~(c > 0) | ~np.isfinite(x)
    c[bad] = np.nan
    ca[A == C] = np.inf
    cb[B == C] = np.inf
    return C, A, B, layout


class CornerTable:
    """Every triangle corner of the update set, grouped by the vertex at the corner.

    For the corner at vertex ``C`` of triangle ``(C, A, B)`` (``A``, ``B`` the
    next and previous corners) it stores ``A``, ``B`` and the planar layout
    ``A = (0, 0)``, ``B = (c, 0)``, ``C = (x, y)`` with ``y >= 0``, and the
    lengths ``|CA|`` and ``|CB|``.

    Attributes
    ----------
    start : (n + 1,) int array
        Corners of vertex ``v`` are rows ``start[v]:start[v + 1]``.
    a, b : (k,) int arrays
    geom : (5, k) float array
        Rows ``c, x, y, ca, cb``; ``c`` is ``nan`` where the triangle update is not allowed (a face
        repeating a vertex, or a degenerate face); ``ca``/``cb`` are ``inf``
        where the edge update is not allowed (the edge is a loop).

    Examples
    --------
    >>> import numpy as np
    >>> table = CornerTable(3, [np.array([[0, 1, 2]])], [np.array([[1.0, 1.0, 1.0]])])
    >>> table.start.tolist(), table.geom[:3, 0].round(3).tolist()  # an equilateral triangle
    ([0, 1, 2, 3], [1.0, 0.5, 0.866])
    """

    def __init__(self, n, faces, lengths):
        C, A, B, layout = corner_layout(faces, lengths)
        order = np.argsort(C, kind="stable")  # grouped by corner vertex
        self.n = n
        self.start = np.searchsorted(C[order], np.arange(n + 1))
        self.a, self.b = A[order], B[order]
        self.geom = layout[:, order]

    @classmethod
    def of_domain(cls, domain):
        """The corner table of a domain's :meth:`~heatcore.domains.base.Domain.eikonal_triangles` (built once,
        kept in the domain's cache)."""
        return domain.derived.get_or_build(
            ("eikonal corners", None), lambda: cls(domain.n_vertices, *domain.eikonal_triangles())
        )


def triangle_update(da, db, c, x, y, ca, cb):
    """Fast-marching update of corner ``C`` from the distances at ``A`` and ``B``.

    Parameters
    ----------
    da, db : float arrays
        Distances at ``A`` and ``B`` (``inf`` where unknown).
    c, x, y, ca, cb : float arrays
        Layout of the triangle (see :class:`CornerTable`).

    Returns
    -------
    float array
        ``|SC|`` for the virtual source ``S`` when the characteristic crosses
        ``AB`` inside the triangle, else ``min(d_A + |CA|, d_B + |CB|)``.

    Examples
    --------
    >>> import numpy as np
    >>> # unit right triangle A=(0,0), B=(1,0), C=(0,1); source at (0.5, -1)
    >>> da, db = np.hypot(0.5, 1.0), np.hypot(0.5, 1.0)
    >>> float(triangle_update(da, db, 1.0, 0.0, 1.0, 1.0, np.sqrt(2)))  # |(0,1)-(0.5,-1)|
    2.0615528128088303
    """
    with np.errstate(invalid="ignore", over="ignore", divide="ignore"):
        return _update(np.asarray(da, float), np.asarray(db, float), c, x, y, ca, cb)


def _update(da, db, c, x, y, ca, cb):
    """:func:`triangle_update` without the floating-point error state (set by the caller)."""
    edge = np.minimum(da + ca, db + cb)
    xs = 0.5 * ((da - db) * (da + db) / c + c)
    ys = np.sqrt((da - xs) * (da + xs))  # S = (xs, -ys); nan where no virtual source exists
    dx, dy = x - xs, y + ys
    # S->C meets the line AB at xs + dx * ys / dy; it must lie in [0, c] (dy > 0).
    t = xs * y + x * ys
    inside = (t >= 0.0) & (t <= c * dy)
    # where the update applies, |SC| <= d_A + |AC| and d_B + |BC| (triangle inequality)
    return np.where(inside, np.sqrt(dx * dx + dy * dy), edge)


class _Sweep:
    """The corners of the reached vertices laid out in sweep order, for one query."""

    def __init__(self, table, order, d, tol):
        counts = np.diff(table.start)[order]
        offsets = np.concatenate((_ZERO, np.cumsum(counts)))
        rows = np.repeat(table.start[order] - offsets[:-1], counts) + np.arange(offsets[-1])
        self.offsets = offsets
        self.cv = np.repeat(order, counts)
        self.a, self.b = table.a[rows], table.b[rows]
        self.geom = np.take(table.geom, rows, axis=1)
        self.mark = np.zeros(d.size, dtype=bool)
        self.d, self.tol = d, tol

    def settle(self, lo, mid, hi, max_sweeps, pending=None):
        """Relax corners ``lo:hi`` until no value drops by more than ``tol`` relative.

        The first sweep evaluates the corners ``mid:hi`` and the ``pending``
        ones; each later sweep only the corners in ``lo:hi`` whose ``A`` or
        ``B`` changed in the sweep before (the others cannot give a lower value
        than they already did). Returns the corners still pending after
        ``max_sweeps`` sweeps (sorted positions, possibly empty).
        """
        d, cv, a, b, geom, tol = self.d, self.cv, self.a, self.b, self.geom, self.tol
        mark = self.mark
        if pending is not None and pending.size:
            pending = pending[pending >= lo]  # corners leaving the window are final
            idx = np.concatenate((pending[pending < mid], np.arange(mid, hi)))
        else:
            idx = slice(mid, hi)
        for _ in range(max_sweeps):
            v = cv[idx]
            if v.size == 0:
                return _EMPTY
            val = _update(d[a[idx]], d[b[idx]], *geom[:, idx])
            starts = np.flatnonzero(v[1:] != v[:-1])
            starts += 1
            starts = np.concatenate((_ZERO, starts))
            new = np.minimum.reduceat(val, starts)
            vs = v[starts]
            old = d[vs]
            changed = vs[new < old * (1.0 - tol)]
            d[vs] = np.minimum(new, old)
            if changed.size == 0:
                return _EMPTY
            # the corners (in lo:hi) that have a changed vertex as A or B
            mark[changed] = True
            idx = np.flatnonzero(mark[a[lo:hi]] | mark[b[lo:hi]])
            idx += lo
            mark[changed] = False
        return idx


def refine_distance(
    domain,
    phi,
    pins,
    *,
    band_width=BAND_WIDTH,
    lookback=LOOKBACK,
    max_sweeps=MAX_SWEEPS,
    tol=TOL,
    polish=POLISH_SWEEPS,
):
    """Recompute distances by an eikonal pass ordered by the heat distance ``phi``.

    Parameters
    ----------
    domain : Domain with ``supports_high_accuracy``
        Provides the triangles to sweep (:meth:`~heatcore.domains.base.Domain.eikonal_triangles`;
        for a triangle mesh the intrinsic Delaunay triangles and the extrinsic
        mesh on the same vertices) and ``operators.mean_edge_length``.
    phi : (n,) float array
        Heat-method distance at the operator vertices, in the input's units
        (``inf`` where unreachable); only its order is used.
    pins : SourcePins
        Known distances, in the operators' units: ``pins.vertices`` keep
        ``pins.values``.
    band_width : float
        Band width in mean edge lengths.
    lookback : int
        Bands before the current one that stay open to changes.
    max_sweeps : int
        Most relaxations per band (it stops as soon as no value changes);
        what is left carries over to the next band.
    tol : float
        Relative decrease below which a value counts as unchanged.
    polish : int
        Most global relaxation sweeps after the pass (0: none; the pass alone
        is as accurate on the test meshes).

    Returns
    -------
    (n,) float array
        Refined distances in the input's units; ``inf`` where ``phi`` is ``inf``.

    Each connected part is swept in its own unit and its own edge lengths
    (bands start at distance 0, not at the nearest vertex of all parts), so
    its result does not depend on the other parts.

    Examples
    --------
    >>> import heatcore as hc
    >>> V, F = hc.io.load_demo_mesh()
    >>> smooth = hc.HeatSolver(hc.TriangleMesh(V, F))
    >>> pins = smooth.domain.source_pins([0])
    >>> high = refine_distance(smooth.domain, smooth.distance_from_pins(pins), pins)
    >>> bool(abs(high - smooth.distance_from_pins(pins)).max() < 0.05 * high.max())
    True
    """
    unit = domain.operators.unit_exponent
    h = np.broadcast_to(domain.operators.mean_edge_length, np.shape(phi))
    phi = np.ldexp(np.asarray(phi, dtype=float), np.negative(unit))  # in each part's unit
    n = phi.size
    d = np.full(n, np.inf)
    d[pins.vertices] = pins.values
    table = CornerTable.of_domain(domain)
    counts_all = np.diff(table.start)
    free = np.isfinite(phi) & (counts_all > 0)
    free[pins.vertices] = False
    order = np.flatnonzero(free)
    hops = phi[order] / h[order]  # heat distance in edge lengths of the vertex's own part
    rank = np.argsort(hops, kind="stable")
    order, hops = order[rank], hops[rank]
    if order.size == 0:
        return np.ldexp(np.where(np.isfinite(phi), d, np.inf), unit)

    sweep = _Sweep(table, order, d, tol)
    offsets = sweep.offsets

    # Band boundaries (corner positions): one band per band_width edge lengths of phi.
    edges = np.searchsorted(hops, band_width * np.arange(1, int(hops[-1] // band_width) + 2))
    bounds = offsets[np.unique(np.r_[0, edges, order.size])]

    with np.errstate(invalid="ignore", over="ignore", divide="ignore"):
        pending = _EMPTY
        for k in range(bounds.size - 1):
            pending = sweep.settle(bounds[max(k - lookback, 0)], bounds[k], bounds[k + 1], max_sweeps, pending)
        if pending.size:  # finish the last window
            last = bounds.size - 2
            sweep.settle(bounds[max(last - lookback, 0)], offsets[-1], offsets[-1], max(n, 1), pending)
        # Optional polish, and vertices the pass left unreached (phi put them
        # before all their neighbours): global sweeps.
        if polish:
            sweep.settle(0, 0, offsets[-1], polish)
        for _ in range(n):
            if not np.isinf(d[order]).any():
                break
            sweep.settle(0, 0, offsets[-1], 1)
    d[~np.isfinite(phi)] = np.inf
    return np.ldexp(d, unit)

