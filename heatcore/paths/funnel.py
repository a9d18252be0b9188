"""The shortest path inside a strip of faces: unfold the strip into the plane, then run the funnel.

A strip is a sequence of faces ``F_0 .. F_m`` in which consecutive faces share
an edge (the *portal* between them), with a start point in ``F_0`` and an end
point in ``F_m``. Laid out in the plane face after face across the portals
(each face keeps its edge lengths, so lengths and angles inside the strip are
those of the surface), the strip's shortest path is the shortest path through
the portals in order, which the funnel algorithm (Lee and Preparata 1984; the
"simple stupid funnel" form of Mononen 2010) finds in one sweep: a polyline
that bends only at portal end points, the strip's vertices, always around the
strip's inner side. A strip may visit a face twice or wrap around a vertex:
the layout is that of the strip, not of the surface, so overlaps do no harm.
The layout is vectorized: each face has a layout of its own and each pair of
neighbouring faces a plane isometry between theirs
(:meth:`~heatcore.paths.surface.PathMesh.layouts`), and a strip's layout is
their running composition (complex products and sums).

:func:`shortest_in_strip` returns the polyline as points *on the input mesh*:
each crossing of a portal is put on that edge of the mesh
(``P[a] + t (P[b] - P[a])``, ``t`` from the layout) and each bend is a mesh
vertex, so every segment lies in one face and the polyline's 3D length is
the length of a path on the surface (never less than the geodesic distance).

Examples
--------
>>> import numpy as np, heatcore as hc
>>> from heatcore.paths.surface import PathMesh
>>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
>>> mesh = PathMesh(hc.TriangleMesh(V, [[0, 1, 2], [1, 3, 2]], refine=0))
>>> piece = shortest_in_strip(mesh, [0, 1], mesh.vertex_point(0), mesh.vertex_point(3))
>>> piece.xyz.tolist()  # the diagonal crosses the shared edge in its middle
[[0.0, 0.0, 0.0], [0.5, 0.5, 0.0], [1.0, 1.0, 0.0]]
"""

import itertools
from dataclasses import dataclass

import numpy as np


@dataclass
class Piece:
    """The shortest path in a strip, as arrays of its points.

    Attributes
    ----------
    xyz : (k, 3) float array
        Start, portal crossings and bends, end.
    vertex : (k,) int array
        The (welded) vertex each point is, or -1.
    edge : (k, 2) int array
        ``(a, b)`` for a point ``P[a] + t (P[b] - P[a])`` inside an edge, else -1.
    t : (k,) float array
    faces : (k - 1,) int array
        The face of each segment.
    bends : list of tuple
        ``(i, first, last)`` for each bend ``xyz[i]`` (a vertex): the path
        arrives in strip face ``first`` and leaves from strip face ``last``
        (indices into ``strip``).
    strip : list of int
        The strip's faces after trimming (faces before the last one holding
        the start, and after the first one holding the end, dropped).
    start, end : SurfacePoint

    Examples
    --------
    >>> import numpy as np, heatcore as hc
    >>> from heatcore.paths.surface import PathMesh
    >>> mesh = PathMesh(hc.TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0))
    >>> piece = shortest_in_strip(mesh, [0], mesh.vertex_point(0), mesh.vertex_point(1))
    >>> piece.vertex.tolist(), piece.faces.tolist(), piece.bends
    ([0, 1], [0], [])
    """

    xyz: np.ndarray
    vertex: np.ndarray
    edge: np.ndarray
    t: np.ndarray
    faces: np.ndarray
    bends: list
    strip: list
    start: object
    end: object

    @classmethod
    def single(cls, point):
        """The path of one point (a :class:`~heatcore.paths.surface.SurfacePoint`): no segment."""
        vertex, edge, t = _endpoint_arrays(point)
        return cls(np.array([point.position], dtype=float), np.array([vertex]), np.array([edge]), np.array([t]),
                   np.zeros(0, dtype=np.int64), [], [], point, point)

    def split(self, mesh):
        """The pieces between the bends (each bend ends one piece and starts the next)."""
        if not self.bends:
            return [self]
        out, p0, s0, start = [], 0, 0, self.start
        for i, first, last in self.bends + [(len(self.xyz) - 1, len(self.strip) - 1, None)]:
            end = self.end if last is None else mesh.vertex_point(int(self.vertex[i]))
            out.append(Piece(self.xyz[p0:i + 1], self.vertex[p0:i + 1], self.edge[p0:i + 1], self.t[p0:i + 1],
                             self.faces[p0:i], [], self.strip[s0:first + 1], start, end))
            p0, s0, start = i, last, end
        return out


def trim(mesh, faces, start, end):
    """Drop the faces a path from ``start`` to ``end`` in the strip ``faces`` cannot use.

    A path leaving a vertex (or an edge point) leaves from the last face of
    the strip's first run of faces around it, and arrives at the end in the
    first face of the last run around the end.

    Examples
    --------
    >>> import numpy as np, heatcore as hc
    >>> from heatcore.paths.surface import PathMesh
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
    >>> mesh = PathMesh(hc.TriangleMesh(V, [[0, 1, 2], [1, 3, 2]], refine=0))
    >>> trim(mesh, [0, 1], mesh.vertex_point(1), mesh.vertex_point(3))
    [1]
    """
    i, j = 0, len(faces) - 1
    while i < j and mesh.contains(faces[i + 1], start):
        i += 1
    while j > i and mesh.contains(faces[j - 1], end):
        j -= 1
    return list(faces[i:j + 1])


def _cross(ax, ay, bx, by):
    return ax * by - ay * bx


def _endpoint_arrays(p):
    """``(vertex, edge, t)`` of a :class:`SurfacePoint`."""
    if p.vertex >= 0:
        return p.vertex, (-1, -1), 0.0
    if p.edge is not None:
        return -1, p.edge, p.t
    return -1, (-1, -1), 0.0


def shortest_in_strip(mesh, faces, start, end):
    """The shortest path from ``start`` to ``end`` inside the strip ``faces`` (a :class:`Piece`).

    Parameters
    ----------
    mesh : PathMesh
    faces : list of int
        Face rows; consecutive faces share a (manifold) edge. ``start`` lies
        in the first face, ``end`` in the last.
    start, end : SurfacePoint

    Returns
    -------
    Piece

    Examples
    --------
    >>> import numpy as np, heatcore as hc
    >>> from heatcore.paths.surface import PathMesh
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0.5, 0.4, 1]], float)
    >>> mesh = PathMesh(hc.TriangleMesh(V, [[0, 1, 4], [1, 2, 4], [2, 3, 4]], refine=0))
    >>> piece = shortest_in_strip(mesh, [0, 1, 2], mesh.vertex_point(0), mesh.vertex_point(3))
    >>> piece.vertex.tolist(), piece.bends  # around the tent over the apex 4: straight in the layout
    ([0, -1, -1, 3], [])
    """
    faces = trim(mesh, faces, start, end)
    m = len(faces) - 1
    if m == 0:
        ends = [_endpoint_arrays(start), _endpoint_arrays(end)]
        return Piece(np.array([start.position, end.position], dtype=float), np.array([e[0] for e in ends]),
                     np.array([e[1] for e in ends]), np.array([e[2] for e in ends]), np.array(faces[:1]), [], faces,
                     start, end)
    Z, a, b, right_is_a = _unfold(mesh, np.asarray(faces))
    s2 = complex(mesh.bary_in(faces[0], start) @ Z[0])
    e2 = complex(mesh.bary_in(faces[-1], end) @ Z[-1])
    za, zb = Z[np.arange(m), a], Z[np.arange(m), b]
    F = mesh.faces[faces[:-1]]
    ida, idb = F[np.arange(m), a], F[np.arange(m), b]
    zr, zl = np.where(right_is_a, za, zb), np.where(right_is_a, zb, za)
    idr, idl = np.where(right_is_a, ida, idb), np.where(right_is_a, idb, ida)
    left = [(s2.real, s2.imag, -1)] + list(zip(zl.real.tolist(), zl.imag.tolist(), idl.tolist())) + \
        [(e2.real, e2.imag, -2)]
    right = [(s2.real, s2.imag, -1)] + list(zip(zr.real.tolist(), zr.imag.tolist(), idr.tolist())) + \
        [(e2.real, e2.imag, -2)]
    return _assemble(mesh, faces, start, end, left, right, _funnel(left, right))


def _unfold(mesh, faces):
    """The strip's layout: its faces' corners in one plane (complex), and its portals.

    Returns
    -------
    Z : (m + 1, 3) complex array
        Corners of each face of the strip.
    a, b : (m,) int arrays
        The corners of face ``k`` on the portal to face ``k + 1``.
    right_is_a : (m,) bool array
        Whether corner ``a`` is on the right of the way through the portal.
    """
    local, rotation, shift, mirror = mesh.layouts()
    prev, nxt = faces[:-1], faces[1:]
    j = np.argmax(mesh.neighbor[prev] == nxt[:, None], axis=1)
    if not (mesh.neighbor[prev, j] == nxt).all():
        raise ValueError("consecutive faces of a strip share no manifold edge")  # pragma: no cover
    r, c, q = rotation[prev, j], shift[prev, j], mirror[prev, j]
    parity = np.r_[0, np.cumsum(q) % 2].astype(bool)  # face k's layout is mirrored
    r = np.where(parity[:-1], np.conj(r), r)
    c = np.where(parity[:-1], np.conj(c), c)
    A = np.r_[1.0 + 0j, np.cumprod(r)]
    B = np.r_[0j, np.cumsum(A[:-1] * c)]
    z = local[faces]
    Z = A[:, None] * np.where(parity[:, None], np.conj(z), z) + B[:, None]
    k = np.arange(prev.size)
    za, zb, zo = Z[k, j], Z[k, (j + 1) % 3], Z[k, (j + 2) % 3]
    right_is_a = (np.conj(za - zo) * (zb - zo)).imag > 0  # other corner, a, b counterclockwise
    return Z, j, (j + 1) % 3, right_is_a


def _funnel(left, right):
    """Indices of the portals whose end point is a bend: ``[(portal, side), ...]`` with side 'L' or 'R'."""
    n = len(left)
    ax, ay, aid = left[0]
    apex_i = left_i = right_i = 0
    lx, ly, lid = left[0]
    rx, ry, rid = right[0]
    left_is_apex = right_is_apex = True
    out = []
    i = 1
    while i < n:
        nlx, nly, nlid = left[i]
        nrx, nry, nrid = right[i]
        # The right side: tighten, or cross over the left side (the left point becomes a bend).
        if _cross(rx - ax, ry - ay, nrx - ax, nry - ay) >= 0.0:
            if right_is_apex or _cross(lx - ax, ly - ay, nrx - ax, nry - ay) < 0.0:
                rx, ry, rid, right_i = nrx, nry, nrid, i
                right_is_apex = _same(nrx, nry, nrid, ax, ay, aid)
            else:
                if lid == -2:  # the end is in sight
                    break
                if not left_is_apex:  # else the apex only moves on along its fan
                    out.append((left_i, "L"))
                ax, ay, aid, apex_i = lx, ly, lid, left_i
                rx, ry, rid, right_i = ax, ay, aid, apex_i
                left_is_apex = right_is_apex = True
                i = apex_i + 1
                continue
        # The left side, likewise.
        if _cross(lx - ax, ly - ay, nlx - ax, nly - ay) <= 0.0:
            if left_is_apex or _cross(rx - ax, ry - ay, nlx - ax, nly - ay) > 0.0:
                lx, ly, lid, left_i = nlx, nly, nlid, i
                left_is_apex = _same(nlx, nly, nlid, ax, ay, aid)
            else:
                if rid == -2:
                    break
                if not right_is_apex:
                    out.append((right_i, "R"))
                ax, ay, aid, apex_i = rx, ry, rid, right_i
                lx, ly, lid, left_i = ax, ay, aid, apex_i
                left_is_apex = right_is_apex = True
                i = apex_i + 1
                continue
        i += 1
    return out


def _same(x, y, vid, ax, ay, aid):
    """Whether a funnel point is the apex: the same vertex at the same place of the layout."""
    return vid == aid and vid >= 0 and abs(x - ax) + abs(y - ay) <= 1e-12 * (abs(ax) + abs(ay) + 1.0)


def _assemble(mesh, faces, start, end, left, right, apexes):
    """The :class:`Piece` through the bends ``apexes``, with every portal crossing in between.

    Each stop (start, bends, end) gets the strip face the path arrives in and
    the one it leaves from: a bend ``v`` is the same end of a run of portals
    (the fan around ``v``); the path arrives in the face before the run and
    leaves from the face after it. Two bends on the two ends of one portal
    (the path runs along that edge) arrive and leave in a face holding it.
    """
    m = len(faces) - 1
    stops = [[0, -1, 0, 0]]  # portal, vertex, arrival face, departure face
    for i, side in apexes:
        ends = left if side == "L" else right
        v = ends[i][2]
        r0, r1 = i, i
        while r0 > 1 and ends[r0 - 1][2] == v:
            r0 -= 1
        while r1 < m and ends[r1 + 1][2] == v:
            r1 += 1
        stops.append([i if side == "L" else -i, v, r0 - 1, r1])
    stops.append([m + 1, -2, m, m])
    for a, b in itertools.pairwise(stops):
        if a[3] > b[2]:  # along the edge of portal b[2] + 1
            a[3] = b[2] = b[2] + 1
    # Portal crossings between consecutive stops, all at once.
    cross_at, origin, toward = [], [], []
    for a, b in itertools.pairwise(stops):
        pa = left[a[0]] if a[0] >= 0 else right[-a[0]]
        pb = left[b[0]] if b[0] >= 0 else right[-b[0]]
        span = range(a[3] + 1, b[2] + 1)
        cross_at.extend(span)
        origin.extend([pa] * len(span))
        toward.extend([pb] * len(span))
    kinds = []  # per point: the stop's index, or -1 for a crossing
    for n, (a, b) in enumerate(itertools.pairwise(stops)):
        kinds.append(n)
        kinds.extend([-1] * (b[2] - a[3]))
    kinds.append(len(stops) - 1)
    k = len(kinds)
    xyz = np.empty((k, 3))
    vertex = np.full(k, -1, dtype=np.int64)
    edge = np.full((k, 2), -1, dtype=np.int64)
    tt = np.zeros(k)
    is_stop = np.array([x >= 0 for x in kinds])
    crossing = np.flatnonzero(~is_stop)
    if crossing.size:
        L = np.array([left[i] for i in cross_at], dtype=float)
        R = np.array([right[i] for i in cross_at], dtype=float)
        O, T = np.array(origin, dtype=float)[:, :2], np.array(toward, dtype=float)[:, :2]
        D = T - O
        denom = (R[:, 0] - L[:, 0]) * D[:, 1] - (R[:, 1] - L[:, 1]) * D[:, 0]
        num = (O[:, 0] - L[:, 0]) * D[:, 1] - (O[:, 1] - L[:, 1]) * D[:, 0]
        with np.errstate(invalid="ignore", divide="ignore"):
            t = np.clip(np.where(denom != 0, num / denom, 0.5), 0.0, 1.0)
        la, lb = L[:, 2].astype(np.int64), R[:, 2].astype(np.int64)
        P = mesh.positions
        xyz[crossing] = P[la] + t[:, None] * (P[lb] - P[la])
        edge[crossing] = np.stack([la, lb], axis=1)
        tt[crossing] = t
        at_end = (t <= 0.0) | (t >= 1.0)  # through a vertex
        vertex[crossing[at_end]] = np.where(t[at_end] <= 0.0, la[at_end], lb[at_end])
        edge[crossing[at_end]] = -1
    stop_rows = np.flatnonzero(is_stop)
    for n, row in enumerate(stop_rows):
        if 0 < n < len(stops) - 1:
            vertex[row] = stops[n][1]
            xyz[row] = mesh.positions[stops[n][1]]
        else:
            point = start if n == 0 else end
            vertex[row], edge[row], tt[row] = _endpoint_arrays(point)
            xyz[row] = point.position
    strip = np.asarray(faces)
    seg = np.concatenate([strip[a[3]:b[2] + 1] for a, b in itertools.pairwise(stops)])
    bends = [(int(row), stops[n][2], stops[n][3]) for n, row in enumerate(stop_rows) if 0 < n < len(stops) - 1]
    return Piece(xyz, vertex, edge, tt, seg, bends, list(faces), start, end)
