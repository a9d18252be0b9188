"""From a route of faces to a geodesic: funnels in strips, and bends moved to the side that shortens them.

The path is kept as *pieces* joined at mesh vertices: each piece is the
shortest path inside its strip (:func:`~heatcore.paths.funnel.shortest_in_strip`),
straight in the strip's layout, and may bend only at the vertices where two
pieces meet. At such a vertex ``v`` the path makes two angles, one on each
side, that add up to the total angle around ``v`` (``2 pi`` minus ``v``'s
curvature). If one of them is less than ``pi``, the path is not locally
shortest: it can cut the corner on that side. The two pieces are then merged
into one strip through the fan of faces around ``v`` on that side, and the
funnel of the merged strip is shorter (it holds the old path). Rounds of this
(every such vertex of a round at once) end when every bend has at least
``pi`` on both sides (a saddle vertex, whose angles add up to more than
``2 pi``, or a boundary vertex, which the path may only go around on the
surface side): the path is then a geodesic, straight in every strip and
bending only where no shorter path passes nearby. Each round makes the path
strictly shorter. This is the strip form of the "wedge flip" of FlipOut
(Sharp and Crane, "You can find geodesic paths in triangle meshes by just
flipping edges", 2020), without changing the mesh. A route's legs are first
joined through the shorter fan of faces around each vertex between them (where
the vertex has one fan), so that most routes start as one strip; a side chosen
wrongly there is a bend with less than ``pi`` on the other side, cut as above.

Examples
--------
>>> import numpy as np, heatcore as hc
>>> from heatcore.paths.surface import PathMesh
>>> from heatcore.paths.trace import Route
>>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
>>> mesh = PathMesh(hc.TriangleMesh(V, [[0, 1, 2], [1, 3, 2]], refine=0))
>>> route = Route([[0], [1]], [1])  # 0 -> 1 -> 3 along two edges
>>> straighten(mesh, route, mesh.vertex_point(0), mesh.vertex_point(3)).xyz.tolist()  # the bend at 1 is cut
[[0.0, 0.0, 0.0], [0.5, 0.5, 0.0], [1.0, 1.0, 0.0]]
"""

import itertools
import math

import numpy as np

from .funnel import Piece, shortest_in_strip

#: A bend is kept when both its angles are at least ``pi - ANGLE_TOL`` (radians).
ANGLE_TOL = 1e-9


def straighten(mesh, route, start, end, max_rounds=None):
    """The geodesic from ``start`` to ``end`` that ``route`` leads to: ``(points, faces)``.

    Parameters
    ----------
    mesh : PathMesh
    route : Route
        From ``start`` to ``end``.
    start, end : SurfacePoint
    max_rounds : int, optional
        Rounds of corner cutting at most (default: the number of faces of the route, plus 100).

    Returns
    -------
    Piece
        The whole path (its ``bends`` and ``strip`` empty).

    Examples
    --------
    >>> import numpy as np, heatcore as hc
    >>> from heatcore.paths.surface import PathMesh
    >>> from heatcore.paths.trace import Route
    >>> V = np.array([[0, 0, 0], [2, 0, 0], [2, 1, 0], [0, 1, 0], [1, 0.5, 0]], float)
    >>> mesh = PathMesh(hc.TriangleMesh(V, [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]], refine=0))
    >>> route = Route([[0], [2]], [4])  # from 0 to the centre 4, then on to 2: straight already
    >>> straighten(mesh, route, mesh.vertex_point(0), mesh.vertex_point(2)).vertex.tolist()
    [0, 4, 2]
    """
    ends = [start] + [mesh.vertex_point(v) for v in route.joints] + [end]
    pieces, strip, first = [], list(route.legs[0]), 0
    for k, v in enumerate(route.joints):  # the legs joined through a fan at each vertex, where there is one
        fan = _bridge(mesh, v, strip[-1], route.legs[k + 1][0])
        if fan is None:
            pieces.extend(shortest_in_strip(mesh, clean(strip), ends[first], ends[k + 1]).split(mesh))
            strip, first = list(route.legs[k + 1]), k + 1
        else:
            strip += fan[1:-1] + list(route.legs[k + 1])
    pieces.extend(shortest_in_strip(mesh, clean(strip), ends[first], ends[-1]).split(mesh))
    limit = max_rounds if max_rounds is not None else sum(len(leg) for leg in route.legs) + 100
    checked = {}  # (id(a), id(b)) -> the shortcut of the bend between pieces a and b (pieces never change)
    for _ in range(limit):
        fans = []
        for a, b in itertools.pairwise(pieces):
            key = (id(a), id(b))
            if key not in checked:
                checked[key] = (_shortcut(mesh, a, b), a, b)  # the pieces kept alive: their ids stay theirs
            fans.append(checked[key][0])
        if not any(fan is not None for fan in fans):
            break
        merged, group = [], [pieces[0]]
        strip = list(pieces[0].strip)
        for fan, piece in zip(fans, pieces[1:]):
            if fan is None:
                merged.append((strip, group))
                group, strip = [piece], list(piece.strip)
            else:
                group.append(piece)
                strip += fan[1:-1] + list(piece.strip)
        merged.append((strip, group))
        pieces = []
        for strip, group in merged:
            if len(group) == 1:
                pieces.append(group[0])
            else:
                piece = shortest_in_strip(mesh, clean(strip), group[0].start, group[-1].end)
                pieces.extend(piece.split(mesh))
    return _join(pieces)


def clean(faces):
    """A strip without repeated faces in a row and without detours into a face and straight back.

    Examples
    --------
    >>> clean([1, 1, 2, 3, 2, 4])
    [1, 2, 4]
    """
    out = []
    for f in faces:
        if out and out[-1] == f:
            continue
        if len(out) >= 2 and out[-2] == f:
            out.pop()
            continue
        out.append(f)
    return out


def _join(pieces):
    """One :class:`Piece` of the pieces end to end."""
    cut = [slice(None)] + [slice(1, None)] * (len(pieces) - 1)
    return Piece(np.concatenate([p.xyz[c] for p, c in zip(pieces, cut)]),
                 np.concatenate([p.vertex[c] for p, c in zip(pieces, cut)]),
                 np.concatenate([p.edge[c] for p, c in zip(pieces, cut)]),
                 np.concatenate([p.t[c] for p, c in zip(pieces, cut)]),
                 np.concatenate([p.faces for p in pieces]), [], [], pieces[0].start, pieces[-1].end)


def _shortcut(mesh, a, b):
    """The fan of faces (from ``a``'s last face to ``b``'s first) cutting the bend between ``a`` and ``b``, or None.

    None when the bend has at least ``pi`` on both sides, or when the side
    below ``pi`` cannot be crossed (a boundary, a non-manifold vertex).
    """
    v = int(a.vertex[-1])
    fan = mesh.fan(v)
    if fan is None:
        return None
    faces, first, _, angles, closed = fan
    try:
        k_in, k_out = faces.index(int(a.faces[-1])), faces.index(int(b.faces[0]))
    except ValueError:
        return None
    origin = mesh.positions[v].tolist()
    offset = [0.0]
    for angle in angles:
        offset.append(offset[-1] + angle)
    total = offset[-1]
    alpha = _coordinate(mesh, origin, first[k_in], angles[k_in], offset[k_in], a.xyz[-2])
    beta = _coordinate(mesh, origin, first[k_out], angles[k_out], offset[k_out], b.xyz[1])
    if closed:
        ccw = (beta - alpha) % total
        sides = [(ccw, 1), (total - ccw, -1)]
    else:
        sides = [(beta - alpha, 1) if beta >= alpha else (alpha - beta, -1)]
    wedge, step = min(sides)
    if wedge >= math.pi - ANGLE_TOL:
        return None
    d = len(faces)
    k, out = k_in, [faces[k_in]]
    if k_in == k_out and ((beta >= alpha) == (step == 1)):
        return out + [faces[k_out]]
    for _ in range(d):
        k = (k + step) % d
        out.append(faces[k])
        if k == k_out:
            return out
    return None  # pragma: no cover - the fan holds both faces


def _bridge(mesh, v, fa, fb):
    """The shorter run of faces around ``v`` from face ``fa`` to face ``fb`` (both included), or None."""
    fan = mesh.fan(v)
    if fan is None or fa not in fan[0] or fb not in fan[0]:
        return None
    faces, closed = fan[0], fan[4]
    i, j = faces.index(fa), faces.index(fb)
    if i <= j:
        ahead = faces[i:j + 1]
        back = (faces[i::-1] + faces[:j - 1:-1]) if closed else None
    else:
        back = faces[i:j - 1 if j else None:-1]
        ahead = (faces[i:] + faces[:j + 1]) if closed else None
    return min((run for run in (ahead, back) if run is not None), key=len)


def _coordinate(mesh, origin, first, angle, offset, point):
    """Angle of the direction from ``origin`` to ``point`` around the vertex, from the fan's first edge."""
    ux, uy, uz = (p - o for p, o in zip(mesh.positions[first].tolist(), origin))
    wx, wy, wz = (p - o for p, o in zip(point.tolist(), origin))
    cx, cy, cz = uy * wz - uz * wy, uz * wx - ux * wz, ux * wy - uy * wx
    theta = math.atan2(math.sqrt(cx * cx + cy * cy + cz * cz), ux * wx + uy * wy + uz * wz)
    return offset + min(max(theta, 0.0), angle)
