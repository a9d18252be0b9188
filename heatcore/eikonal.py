"""Accuracy mode: an ordered eikonal pass that uses the heat distance as its order.

The heat method gives a smooth distance ``phi`` whose error (1-2% on real
meshes) is low-frequency: the *order* in which it reaches the vertices is
nearly right even where its values are not. :func:`refine_distance` keeps
that order and recomputes the values with the fast-marching triangle update
of Kimmel and Sethian ("Computing geodesic paths on manifolds", PNAS 1998):

* every vertex starts at ``+inf`` except the pinned source vertices
  (:class:`~heatcore.sources.SourcePins`: 0 at source vertices, the in-face
  straight-line distance around a surface point);
* vertices are swept in increasing ``phi``, in narrow bands of heat distance
  (``band_width`` times the mean edge length). A window of ``1 + lookahead``
  bands is relaxed at once, fully vectorized (every corner of every triangle
  around every window vertex is evaluated with array operations); then the
  first band of the window is final and the window slides by one band. A
  vertex is therefore relaxed ``1 + lookahead`` times, each time from
  neighbours that are final or were themselves just relaxed, which resolves
  the dependencies inside a band and the small ordering errors of ``phi``;
* a few global relaxation sweeps at the end (``polish``) let late vertices
  improve early ones where ``phi`` ordered them wrongly; they stop as soon as
  no value changes by more than a relative ``1e-12``.

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

import weakref

import numpy as np

from .intrinsic import NEXT, PREV, face_edge_lengths

#: Width of a band of heat distance, in mean edge lengths.
BAND_WIDTH = 1.0
#: Most relaxations of one band.
MAX_SWEEPS = 32
#: Most global relaxation sweeps after the ordered pass.
POLISH_SWEEPS = 0
#: A band is settled when no value decreases by more than this, relatively.
TOL = 1e-9

_CORNERS = weakref.WeakKeyDictionary()


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
    """

    def __init__(self, n, faces, lengths):
        faces = np.concatenate([np.asarray(f, dtype=np.int64) for f in faces])
        lengths = np.concatenate([np.asarray(l, dtype=float) for l in lengths])
        C = faces.ravel()
        A = faces[:, NEXT].ravel()
        B = faces[:, PREV].ravel()
        c = lengths.ravel()  # |AB|: opposite corner C
        cb = lengths[:, NEXT].ravel()  # |CB|: opposite corner A
        ca = lengths[:, PREV].ravel()  # |CA|: opposite corner B
        # Group by corner vertex; a triangle present in both sets (one the
        # intrinsic Delaunay step did not flip) is kept once.
        order = np.lexsort((B, A, C))
        C, A, B = C[order], A[order], B[order]
        keep = np.r_[True, (C[1:] != C[:-1]) | (A[1:] != A[:-1]) | (B[1:] != B[:-1])]
        order = order[keep]
        C, A, B, c, ca, cb = C[keep], A[keep], B[keep], c[order], ca[order], cb[order]
        with np.errstate(divide="ignore", invalid="ignore"):
            x = (ca * ca - cb * cb + c * c) / (2.0 * c)
            y = np.sqrt(np.maximum(ca * ca - x * x, 0.0))
        bad = (A == C) | (B == C) | (A == B) | ~(y > 0) | ~(c > 0) | ~np.isfinite(x)
        c = np.where(bad, np.nan, c)
        ca = np.where(A == C, np.inf, ca)
        cb = np.where(B == C, np.inf, cb)
        self.n = n
        self.start = np.searchsorted(C, np.arange(n + 1))
        self.a, self.b = A, B
        self.geom = np.stack([c, x, y, ca, cb])

    @classmethod
    def of_domain(cls, domain):
        """The corner table of a :class:`~heatcore.triangle.TriangleMesh` (built once, cached)."""
        try:
            return _CORNERS[domain]
        except (KeyError, TypeError):
            pass
        tri, sub = domain.intrinsic, domain.subdivision
        n = domain.operators.n_vertices
        table = cls(
            n,
            [tri.faces, sub.faces],
            [tri.lengths, face_edge_lengths(sub.vertices, sub.faces)],
        )
        try:
            _CORNERS[domain] = table
        except TypeError:  # pragma: no cover - a domain that cannot be weakly referenced
            pass
        return table


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
        edge = np.minimum(da + ca, db + cb)
        xs = 0.5 * ((da - db) * (da + db) / c + c)
        h2 = (da - xs) * (da + xs)
        ys = -np.sqrt(h2)  # nan where no virtual source exists
        dx, dy = x - xs, y - ys
        cross = xs + dx * (-ys / dy)  # where S->C meets the line AB
        inside = (cross >= 0.0) & (cross <= c)
        return np.where(inside, np.minimum(np.hypot(dx, dy), edge), edge)


def _relax(d, a, b, geom, vertices, first, tol):
    """One Jacobi relaxation of ``vertices`` from their corners (``a``, ``b``, ``geom`` rows); in place.

    Returns whether any value decreased by more than ``tol`` relative.
    """
    c, x, y, ca, cb = geom
    new = np.minimum.reduceat(triangle_update(d[a], d[b], c, x, y, ca, cb), first)
    old = d[vertices]
    if (new < old * (1.0 - tol)).any():
        d[vertices] = np.minimum(new, old)
        return True
    d[vertices] = np.minimum(new, old)
    return False


def refine_distance(domain, phi, pins, *, band_width=BAND_WIDTH, max_sweeps=MAX_SWEEPS, tol=TOL, polish=POLISH_SWEEPS):
    """Recompute distances by an eikonal pass ordered by the heat distance ``phi``.

    Parameters
    ----------
    domain : TriangleMesh
        Provides ``intrinsic`` (intrinsic Delaunay triangles with lengths),
        ``subdivision`` (the extrinsic mesh on the same vertices) and
        ``operators.mean_edge_length``.
    phi : (n,) float array
        Heat-method distance at the operator vertices (``inf`` where
        unreachable); only its order is used.
    pins : SourcePins
        Known distances: ``pins.vertices`` keep ``pins.values``.
    band_width : float
        Band width in mean edge lengths.
    max_sweeps : int
        Most relaxations of one band (it stops as soon as no value changes).
    polish : int
        Most global relaxation sweeps after the pass.

    Returns
    -------
    (n,) float array
        Refined distances; ``inf`` where ``phi`` is ``inf``.
    """
    phi = np.asarray(phi, dtype=float)
    n = phi.size
    table = CornerTable.of_domain(domain)
    d = np.full(n, np.inf)
    d[pins.vertices] = pins.values
    counts_all = np.diff(table.start)
    free = np.isfinite(phi) & (counts_all > 0)
    free[pins.vertices] = False
    order = np.flatnonzero(free)
    order = order[np.argsort(phi[order], kind="stable")]
    if order.size == 0:
        return np.where(np.isfinite(phi), d, np.inf)

    # The corners of the vertices in sweep order, laid out contiguously.
    counts = counts_all[order]
    offsets = np.r_[0, np.cumsum(counts)]
    rows = np.repeat(table.start[order] - offsets[:-1], counts) + np.arange(offsets[-1])
    a, b = table.a[rows], table.b[rows]
    geom = np.take(table.geom, rows, axis=1)

    # Band boundaries (positions in ``order``): one band per band_width * h of phi.
    h = domain.operators.mean_edge_length
    ps = phi[order]
    nb = int(np.ceil((ps[-1] - ps[0]) / (band_width * h))) + 1
    edges = np.searchsorted(ps, ps[0] + band_width * h * np.arange(1, nb + 1))
    bounds = np.unique(np.r_[0, edges, order.size])

    with np.errstate(invalid="ignore", over="ignore", divide="ignore"):
        for lo, hi in zip(bounds[:-1], bounds[1:]):
            r0, r1 = offsets[lo], offsets[hi]
            args = (a[r0:r1], b[r0:r1], geom[:, r0:r1], order[lo:hi], offsets[lo:hi] - r0, tol)
            for _ in range(max_sweeps):
                if not _relax(d, *args):
                    break
        args = (a, b, geom, order, offsets[:-1], tol)
        sweeps = 0
        # Vertices the pass left unreached (phi ordered them before all their
        # neighbours) and the optional polish: global relaxation sweeps.
        while (sweeps < polish or np.isinf(d[order]).any()) and sweeps < n:
            sweeps += 1
            if not _relax(d, *args):
                break
    d[~np.isfinite(phi)] = np.inf
    return d
