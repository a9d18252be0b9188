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
flipping edges", 2020), without changing the mesh.

Examples
--------
>>> import numpy as np, heatcore as hc
>>> from heatcore.paths.surface import PathMesh
>>> from heatcore.paths.trace import Route
>>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
>>> mesh = PathMesh(hc.TriangleMesh(V, [[0, 1, 2], [1, 3, 2]], refine=0))
>>> route = Route([[0], [1]], [1])  # 0 -> 1 -> 3 along two edges
>>> points, faces = straighten(mesh, route, mesh.vertex_point(0), mesh.vertex_point(3))
>>> [p.position.tolist() for p in points]  # the bend at vertex 1 (pi/2 on one side) is cut
[[0.0, 0.0, 0.0], [0.5, 0.5, 0.0], [1.0, 1.0, 0.0]]
"""

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
    points : list of SurfacePoint
    faces : list of int
        The face row of each segment.
    """
    ends = [start] + [mesh.vertex_point(v) for v in route.joints] + [end]
    pieces = []
    for k, faces in enumerate(route.legs):
        pieces.extend(_split(shortest_in_strip(mesh, clean(faces), ends[k], ends[k + 1])))
    limit = max_rounds if max_rounds is not None else sum(len(leg) for leg in route.legs) + 100
    for _ in range(limit):
        fans = [_shortcut(mesh, a, b) for a, b in zip(pieces[:-1], pieces[1:])]
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
                piece = shortest_in_strip(mesh, clean(strip), group[0].points[0], group[-1].points[-1])
                pieces.extend(_split(piece))
    points, faces = list(pieces[0].points), list(pieces[0].faces)
    for piece in pieces[1:]:
        points += piece.points[1:]
        faces += piece.faces
    return points, faces


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


def _split(piece):
    """The pieces of ``piece`` between its bends (each bend starts a new piece)."""
    if not piece.bends:
        return [Piece(piece.points, piece.faces, [], piece.strip)]
    out, p0, s0 = [], 0, 0
    for i, first, last in piece.bends:
        out.append(Piece(piece.points[p0:i + 1], piece.faces[p0:i], [], piece.strip[s0:first + 1]))
        p0, s0 = i, last
    out.append(Piece(piece.points[p0:], piece.faces[p0:], [], piece.strip[s0:]))
    return out


def _shortcut(mesh, a, b):
    """The fan of faces (from ``a``'s last face to ``b``'s first) cutting the bend between ``a`` and ``b``, or None.

    None when the bend has at least ``pi`` on both sides, or when the side
    below ``pi`` cannot be crossed (a boundary, a non-manifold vertex).
    """
    v = a.points[-1].vertex
    fan = mesh.fan(v)
    if fan is None:
        return None
    faces, first, _, angles, closed = fan
    try:
        k_in, k_out = faces.index(a.faces[-1]), faces.index(b.faces[0])
    except ValueError:
        return None
    origin = mesh.positions[v]
    cumulative = np.r_[0.0, np.cumsum(angles)]
    total = float(cumulative[-1])
    alpha = _coordinate(mesh, origin, first[k_in], angles[k_in], cumulative[k_in], a.points[-2].position)
    beta = _coordinate(mesh, origin, first[k_out], angles[k_out], cumulative[k_out], b.points[1].position)
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


def _coordinate(mesh, origin, first, angle, offset, point):
    """Angle of the direction from ``origin`` to ``point`` around the vertex, from the fan's first edge."""
    u = mesh.positions[first] - origin
    w = point - origin
    theta = math.atan2(float(np.linalg.norm(np.cross(u, w))), float(u @ w))
    return float(offset) + min(max(theta, 0.0), angle)
