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
>>> [p.position.tolist() for p in piece.points]  # the diagonal crosses the shared edge in its middle
[[0.0, 0.0, 0.0], [0.5, 0.5, 0.0], [1.0, 1.0, 0.0]]
"""

import math
from dataclasses import dataclass

import numpy as np


@dataclass
class Piece:
    """The shortest path in a strip.

    Attributes
    ----------
    points : list of SurfacePoint
        Start, portal crossings and bends, end.
    faces : list of int
        The face of each segment (``len(points) - 1``).
    bends : list of tuple
        ``(i, first, last)`` for each bend ``points[i]`` (a vertex): the path
        arrives in strip face ``first`` and leaves from strip face ``last``
        (indices into the strip's faces, after trimming).
    strip : list of int
        The strip's faces after trimming (faces before the last one holding
        the start, and after the first one holding the end, dropped).

    Examples
    --------
    >>> Piece([], [], [], [4]).bends
    []
    """

    points: list
    faces: list
    bends: list
    strip: list


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


def shortest_in_strip(mesh, faces, start, end):
    """The shortest path from ``start`` to ``end`` inside the strip ``faces`` (a :class:`Piece`).

    Parameters
    ----------
    mesh : PathMesh
    faces : list of int
        Face rows; consecutive faces share an edge. ``start`` lies in the
        first face, ``end`` in the last.
    start, end : SurfacePoint
    """
    faces = trim(mesh, faces, start, end)
    F, P = mesh.faces, mesh.positions
    m = len(faces) - 1
    if m == 0:
        return Piece([start, end], [faces[0]], [], faces)
    # Lay the first face out, then each next face across its portal.
    c0 = F[faces[0]].tolist()
    xy = {c0[0]: (0.0, 0.0)}
    l01 = _length(P, c0[0], c0[1])
    xy[c0[1]] = (l01, 0.0)
    xy[c0[2]] = _apex(xy[c0[0]], xy[c0[1]], _length(P, c0[0], c0[2]), _length(P, c0[1], c0[2]), 1.0)
    sx, sy = _at(xy, c0, mesh.bary_in(faces[0], start))
    # Portals: index 0 is the start, 1..m the shared edges, m + 1 the end.
    left, right = [(sx, sy, -1)], [(sx, sy, -1)]
    corners = c0
    for k in range(1, m + 1):
        nxt = F[faces[k]].tolist()
        shared = [v for v in corners if v in nxt]
        if len(shared) != 2:
            raise ValueError(f"faces {faces[k - 1]} and {faces[k]} of a strip share no edge")  # pragma: no cover
        a, b = shared
        old = [v for v in corners if v not in shared][0]
        new = [v for v in nxt if v not in shared][0]
        (ax, ay), (bx, by), (ox, oy) = xy[a], xy[b], xy[old]
        if _cross(ax - ox, ay - oy, bx - ox, by - oy) > 0:  # old, a, b counterclockwise: a is on the right
            right.append((ax, ay, a))
            left.append((bx, by, b))
        else:
            right.append((bx, by, b))
            left.append((ax, ay, a))
        side = _cross(bx - ax, by - ay, ox - ax, oy - ay)
        xy = {a: xy[a], b: xy[b]}
        xy[new] = _apex(xy[a], xy[b], _length(P, a, new), _length(P, b, new), -1.0 if side > 0 else 1.0)
        corners = nxt
    ex, ey = _at(xy, corners, mesh.bary_in(faces[m], end))
    left.append((ex, ey, -2))
    right.append((ex, ey, -2))
    apexes = _funnel(left, right)
    return _assemble(mesh, faces, start, end, left, right, apexes)


def _length(P, a, b):
    d = P[a] - P[b]
    return math.sqrt(float(d @ d))


def _apex(pa, pb, la, lb, sign):
    """The point at distances ``la`` from ``pa`` and ``lb`` from ``pb``, left of ``pa -> pb`` for sign 1."""
    dx, dy = pb[0] - pa[0], pb[1] - pa[1]
    d = math.hypot(dx, dy)
    if d == 0.0:
        return pa
    x = (d * d + la * la - lb * lb) / (2.0 * d)
    y = sign * math.sqrt(max(la * la - x * x, 0.0))
    ux, uy = dx / d, dy / d
    return (pa[0] + x * ux - y * uy, pa[1] + x * uy + y * ux)


def _at(xy, corners, bary):
    x = sum(float(w) * xy[c][0] for c, w in zip(corners, bary))
    y = sum(float(w) * xy[c][1] for c, w in zip(corners, bary))
    return x, y


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
    stops = [[left[0][0], left[0][1], start, 0, 0]]  # x, y, point, arrival face, departure face
    for i, side in apexes:
        ends = left if side == "L" else right
        v = ends[i][2]
        r0, r1 = i, i
        while r0 > 1 and ends[r0 - 1][2] == v:
            r0 -= 1
        while r1 < m and ends[r1 + 1][2] == v:
            r1 += 1
        stops.append([ends[i][0], ends[i][1], mesh.vertex_point(v), r0 - 1, r1])
    stops.append([left[m + 1][0], left[m + 1][1], end, m, m])
    for a, b in zip(stops[:-1], stops[1:]):
        if a[4] > b[3]:  # along the edge of portal b[3] + 1
            a[4] = b[3] = b[3] + 1
    points, seg_faces, bends = [start], [], []
    for a, b in zip(stops[:-1], stops[1:]):
        ax, ay, bx, by = a[0], a[1], b[0], b[1]
        dx, dy = bx - ax, by - ay
        for j in range(a[4] + 1, b[3] + 1):
            lx, ly, lid = left[j]
            rx, ry, rid = right[j]
            denom = _cross(rx - lx, ry - ly, dx, dy)
            t = _cross(ax - lx, ay - ly, dx, dy) / denom if denom != 0.0 else 0.5
            points.append(mesh.edge_point(lid, rid, min(max(t, 0.0), 1.0)))
        seg_faces.extend(faces[a[4]:b[3] + 1])
        points.append(b[2])
        if b is not stops[-1]:
            bends.append((len(points) - 1, b[3], b[4]))
    return Piece(points, seg_faces, bends, faces)
