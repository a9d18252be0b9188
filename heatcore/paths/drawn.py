"""Paths that users draw, made geodesics: edge paths and polylines straightened, loops made closed geodesics.

:func:`straighten_path` takes a path on the surface (a list of vertices, each
joined to the next by a mesh edge, or a polyline whose segments lie in faces,
such as a :class:`~heatcore.paths.path.GeodesicPath` or a
:class:`~heatcore.paths.tracing.TracedPath`) and shortens it, its two ends
kept, to a locally shortest geodesic in its homotopy class. The path is read
as a route of faces (:func:`route_of`): the faces it crosses, split into legs
at the vertices it passes through. From there it is the same machinery as for
a path between two points (:func:`~heatcore.paths.straighten.straighten`):
the route's strips are unfolded, their funnels give the shortest path inside
each, and every bend with less than ``pi`` on one side is cut on that side,
round after round, until every bend has at least ``pi`` on both sides. Each
step moves the path across faces and vertices of the surface, never across a
hole or the boundary, so the homotopy class is kept, and each step shortens.

:func:`straighten_loop` does the same for a closed curve, whose base point is
free: the loop is straightened from a point back to the same point (a
geodesic except at that point, where it may make a corner). Then, in rounds,
the loop is rerouted to start at its crossing of an edge about halfway
round, where it is straight, so that the old corner is cut like any other
bend, and the new base is slid along that edge to where the loop through it
is shortest (a bounded Brent search): there the loop is straight at its base
as well. The rounds end when one shortens the loop by less than a relative
``1e-12``. The result is a closed geodesic in the loop's free homotopy class
(around a cylinder: a circle of the cylinder; around a neck: the waist).
Moving the base halfway round without the search also converges, but only
linearly (on a hyperboloid's neck about 1% of the excess per round).

Examples
--------
>>> import numpy as np, heatcore as hc
>>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
>>> path = straighten_path(V, [[0, 1, 2], [1, 3, 2]], [0, 1, 3])  # along two edges, then straightened
>>> path.points.tolist(), round(path.length, 12)
([[0.0, 0.0, 0.0], [0.5, 0.5, 0.0], [1.0, 1.0, 0.0]], 1.414213562373)
"""

import numpy as np
from scipy.optimize import minimize_scalar

from ..domains.triangle import TriangleMesh
from ..errors import InvalidSourceError, UnsupportedDomainError
from .funnel import Piece
from .path import GeodesicPath
from .straighten import straighten
from .surface import PathMesh
from .trace import Route

#: A loop is settled when a round shortens it by less than this, relative to its length.
LOOP_TOL = 1e-12
#: A crossing this close to an edge's end (in the edge's parameter) is taken as that vertex.
SNAP = 1e-12
#: Step along the base's edge (in its parameter) that tells whether sliding the base shortens a loop.
SLIDE_STEP = 1e-4
#: Rounds of moving a loop's base point at most.
LOOP_ROUNDS = 200


def straighten_path(V, F, path, *, weld=0.0):
    """Shorten a path on a triangle mesh, its ends and homotopy class kept, to a locally shortest geodesic.

    Parameters
    ----------
    V : (n, 3) array_like of float
    F : (m, 3) array_like of int
    path : sequence of int, or a path object
        Vertex indices, each joined to the next by an edge of ``F``; or an
        object with ``points`` and ``faces`` (input face of each segment), and
        optionally ``vertices`` (the vertex each point is, or -1), such as a
        :class:`GeodesicPath` or :class:`~heatcore.paths.tracing.TracedPath`.
    weld : float, default 0.0
        Weld tolerance, as for distances (0: coincident vertices only).

    Returns
    -------
    GeodesicPath
        From the path's first point to its last: no longer than the path,
        straight across every edge, and bending only at vertices with at
        least ``pi`` on both sides (saddles, the boundary).

    Raises
    ------
    InvalidSourceError
        A vertex out of range or unused, two consecutive vertices that share
        no edge, a polyline whose consecutive segments share no edge or vertex.

    Examples
    --------
    >>> import numpy as np
    >>> V = np.array([[0, 0, 0], [2, 0, 0], [2, 1, 0], [0, 1, 0], [1, 0.5, 0]], float)
    >>> F = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]
    >>> round(straighten_path(V, F, [0, 1, 2]).length, 12)  # around the corner at 1: the diagonal
    2.2360679775
    """
    return straighten_on(TriangleMesh(V, F, refine=0, weld=weld), path)


def straighten_loop(V, F, loop, *, weld=0.0):
    """Shorten a closed curve on a triangle mesh to a closed geodesic in its free homotopy class.

    Parameters
    ----------
    V : (n, 3) array_like of float
    F : (m, 3) array_like of int
    loop : sequence of int, or a path object
        As ``path`` of :func:`straighten_path`; closed (the last point the
        first) or closed here by the edge from the last vertex to the first.
    weld : float, default 0.0

    Returns
    -------
    GeodesicPath
        A closed polyline (last point the first) that is a geodesic at every
        point, its start included; a loop that can be shrunk to a point
        shrinks to one point (length 0).

    Examples
    --------
    >>> import numpy as np
    >>> from heatcore.paths.drawn import straighten_loop
    >>> angle = 2 * np.pi * np.arange(8) / 8
    >>> V = np.array([[np.cos(a), np.sin(a), z] for z in (0.0, 1.0) for a in angle])
    >>> F = [f for i in range(8) for f in ([i, (i + 1) % 8, 8 + (i + 1) % 8], [i, 8 + (i + 1) % 8, 8 + i])]
    >>> zigzag = [0, 1, 9, 10, 2, 3, 11, 12, 4, 5, 13, 14, 6, 7, 15, 8]  # up and down between the rings
    >>> round(float(straighten_loop(V, F, zigzag).length / (16 * np.sin(np.pi / 8))), 12)  # the octagon's perimeter
    1.0
    """
    return straighten_loop_on(TriangleMesh(V, F, refine=0, weld=weld), loop)


def straighten_on(domain, path):
    """:func:`straighten_path` on a :class:`~heatcore.TriangleMesh` (as :meth:`heatcore.HeatSolver.straighten_path`).

    Examples
    --------
    >>> import numpy as np, heatcore as hc
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
    >>> round(straighten_on(hc.TriangleMesh(V, [[0, 1, 2], [1, 3, 2]]), [2, 0, 1, 3]).length, 12)
    1.0
    """
    mesh = _path_mesh(domain)
    rows, vertex, xyz = _read(mesh, path, closed=False)
    if len(rows) == 0:
        return GeodesicPath.from_piece(mesh, Piece.single(_end_point(mesh, rows, vertex, xyz, 0)))
    route, start, end = route_of(mesh, rows, vertex, xyz)
    return _result(mesh, straighten(mesh, route, start, end))


def straighten_loop_on(domain, loop, max_rounds=LOOP_ROUNDS):
    """:func:`straighten_loop` on a :class:`~heatcore.TriangleMesh` (as :meth:`heatcore.HeatSolver.straighten_loop`).

    Examples
    --------
    >>> import numpy as np, heatcore as hc
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
    >>> straighten_loop_on(hc.TriangleMesh(V, [[0, 1, 2], [1, 3, 2]]), [0, 1, 3, 2]).length  # shrinks to a point
    0.0
    """
    mesh = _path_mesh(domain)
    rows, vertex, xyz = _read(mesh, loop, closed=True)
    if len(rows) == 0:
        return GeodesicPath.from_piece(mesh, Piece.single(_end_point(mesh, rows, vertex, xyz, 0)))
    route, start, _ = route_of(mesh, rows, vertex, xyz)
    piece = straighten(mesh, route, start, start)
    length = _length(piece.xyz)
    for _ in range(max_rounds):
        base = _halfway(piece)
        if base is None:  # shrunk to a point, or only vertices left
            break
        moved = _slide_base(mesh, piece, base)
        new_length = _length(moved.xyz)
        if new_length > length:
            break
        piece, shortened, length = moved, length - new_length, new_length
        if shortened <= LOOP_TOL * length:
            break
    return _result(mesh, piece)


def route_of(mesh, rows, vertex, xyz):
    """The :class:`Route` of a polyline on ``mesh``, with its start and end :class:`SurfacePoint`.

    Parameters
    ----------
    mesh : PathMesh
    rows : (k - 1,) int array
        The face row of each segment.
    vertex : (k,) int array
        The welded vertex each point is, or -1.
    xyz : (k, 3) float array

    Returns
    -------
    (Route, SurfacePoint, SurfacePoint)
        A new leg starts wherever two consecutive faces share no edge: at the
        vertex between them.

    Examples
    --------
    >>> import numpy as np, heatcore as hc
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
    >>> mesh = PathMesh(hc.TriangleMesh(V, [[0, 1, 2], [1, 3, 2]], refine=0))
    >>> route, start, end = route_of(mesh, np.array([0, 1]), np.array([0, 1, 3]), V[[0, 1, 3]])
    >>> route.legs, start.vertex, end.vertex  # faces 0 and 1 share the edge 1-2: one leg
    ([[0, 1]], 0, 3)
    """
    F, N = mesh.faces, mesh.neighbor
    legs, joints = [[int(rows[0])]], []
    for i in range(1, len(rows)):
        f, g = int(legs[-1][-1]), int(rows[i])
        if f == g:
            continue
        if (N[f] == g).any():
            legs[-1].append(g)
            continue
        v = int(vertex[i])
        if v < 0 or not ((F[f] == v).any() and (F[g] == v).any()):
            common = np.intersect1d(F[f], F[g])
            if common.size == 0:
                raise InvalidSourceError(f"segments {i - 1} and {i} of the path share no edge and no vertex: "
                                         "a path must run on the surface, each segment starting where the "
                                         "one before ends")
            v = int(common[np.argmin(np.linalg.norm(mesh.positions[common] - xyz[i], axis=1))])
        joints.append(v)
        legs.append([g])
    start = _end_point(mesh, rows, vertex, xyz, 0)
    end = _end_point(mesh, rows, vertex, xyz, -1)
    return Route(legs, joints), start, end


def _result(mesh, piece):
    """The :class:`GeodesicPath` of ``piece``; one point where it has shrunk to one (a loop with the same ends)."""
    if len(piece.xyz) > 1 and not np.abs(np.diff(piece.xyz, axis=0)).any() and piece.start.key() == piece.end.key():
        piece = Piece.single(piece.start)
    return GeodesicPath.from_piece(mesh, _without_repeats(mesh, piece))


def _without_repeats(mesh, piece):
    """``piece`` with its crossings within ``SNAP`` of an edge's end put on that vertex, and no segment of length 0.

    The funnel may cross an edge a rounding error away from a vertex it then
    passes: that crossing is the vertex, one point, where the path bends.
    """
    xyz, vertex, edge, t = piece.xyz.copy(), piece.vertex.copy(), piece.edge.copy(), piece.t.copy()
    inner = np.arange(len(xyz))[1:-1]
    crossing = inner[(vertex[inner] < 0) & (edge[inner, 0] >= 0)]
    near = crossing[(t[crossing] <= SNAP) | (t[crossing] >= 1.0 - SNAP)]
    vertex[near] = np.where(t[near] <= SNAP, edge[near, 0], edge[near, 1])
    xyz[near], edge[near], t[near] = mesh.positions[vertex[near]], -1, 0.0
    same = ~np.abs(np.diff(xyz, axis=0)).any(axis=1)
    if not same.any() or same.all():
        return Piece(xyz, vertex, edge, t, piece.faces, [], [], piece.start, piece.end)
    gone = np.flatnonzero(same) + 1  # the second of two equal points, or the first where the second is the end
    gone[gone == len(xyz) - 1] -= 1
    kept = np.setdiff1d(np.arange(len(xyz)), gone)
    return Piece(xyz[kept], vertex[kept], edge[kept], t[kept], np.delete(piece.faces, np.flatnonzero(same)), [], [],
                 piece.start, piece.end)


def _path_mesh(domain):
    if not isinstance(domain, TriangleMesh):
        raise UnsupportedDomainError(
            f"paths are straightened on triangle meshes (heatcore.TriangleMesh), not on a {domain.domain_name} "
            f"({type(domain).__name__})"
        )
    return PathMesh.of(domain)


def _read(mesh, path, closed):
    """``(rows, vertex, xyz)`` of a user's path: face rows of the segments, welded vertices, points."""
    if hasattr(path, "points") and hasattr(path, "faces"):
        xyz = np.asarray(path.points, dtype=float).reshape(-1, 3)
        faces = np.asarray(path.faces, dtype=np.int64).ravel()
        if faces.size != len(xyz) - 1 or (faces.size and (faces.min() < 0 or faces.max() >= mesh.face_row.size)):
            raise InvalidSourceError("a path's faces must be one input face index per segment")
        rows = mesh.face_row[faces]
        if (rows < 0).any():
            raise InvalidSourceError("the path crosses a face the mesh ignored (repeated vertices or a duplicate)")
        given = getattr(path, "vertices", None)
        vertex = np.full(len(xyz), -1, dtype=np.int64)
        if given is not None:
            given = np.asarray(given, dtype=np.int64)
            vertex = np.where(given >= 0, mesh.vertex_map[np.maximum(given, 0)], -1)
        if closed and not np.array_equal(xyz[0], xyz[-1]):
            raise InvalidSourceError("a loop given as a polyline must end where it starts")
        return rows, vertex, xyz
    vertices = _vertex_list(mesh, path)
    if closed and vertices[0] != vertices[-1]:
        vertices = np.r_[vertices, vertices[:1]]
    a, b = vertices[:-1], vertices[1:]
    rows = np.empty(a.size, dtype=np.int64)
    for i, (u, w) in enumerate(zip(a.tolist(), b.tolist())):
        faces = mesh.edge_faces(u, w)
        if not faces:
            raise InvalidSourceError(f"vertices {i} and {i + 1} of the path (input vertices "
                                     f"{mesh.input_vertex[u]} and {mesh.input_vertex[w]}) share no edge of the mesh")
        rows[i] = faces[0]
    return rows, vertices, mesh.positions[vertices]


def _vertex_list(mesh, path):
    """Welded vertices of a vertex-index path, consecutive repeats dropped."""
    spec = np.asarray(path)
    if spec.ndim != 1 or spec.size == 0 or not np.issubdtype(spec.dtype, np.integer):
        raise InvalidSourceError("a path is a list of vertex indices (or an object with points and faces), "
                                 f"got {path!r}"[:200])
    welded = np.array([mesh.user_point(int(v), f"vertex {i} of the path").vertex for i, v in enumerate(spec)])
    keep = np.r_[True, welded[1:] != welded[:-1]]
    return welded[keep]


def _end_point(mesh, rows, vertex, xyz, i):
    """The :class:`SurfacePoint` of the path's point ``i`` (0 or -1)."""
    if vertex[i] >= 0:
        return mesh.vertex_point(int(vertex[i]))
    row = int(rows[i])
    corners = mesh.positions[mesh.faces[row]]
    uv = np.linalg.lstsq((corners[1:] - corners[0]).T, xyz[i] - corners[0], rcond=None)[0]
    bary = np.clip(np.r_[1.0 - uv.sum(), uv], 0.0, None)
    bary[np.abs(bary) < 1e-14] = 0.0
    return mesh.point(row, bary / bary.sum())


def _length(xyz):
    return float(np.linalg.norm(np.diff(xyz, axis=0), axis=1).sum())


def _halfway(piece):
    """Index of a point inside an edge (or, where there is none, a vertex) near half the loop's length, or None."""
    inner = np.arange(1, len(piece.xyz) - 1)
    inside = inner[(piece.vertex[inner] < 0) & (piece.edge[inner, 0] >= 0)]
    if inside.size == 0:
        inside = inner[piece.vertex[inner] >= 0]
    if inside.size == 0:
        return None
    run = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(piece.xyz, axis=0), axis=1))]
    return int(inside[np.argmin(np.abs(run[inside] - 0.5 * run[-1]))])


def _slide_base(mesh, piece, b):
    """The shortest of the loops from a point of the edge through ``piece``'s point ``b`` back to that point.

    The loop is rerouted to start at ``b`` (inside an edge): straightened from
    there, the corner at its old start is cut like any bend. The base is then
    slid along its edge to where the loop is shortest (bounded Brent search on
    the edge's parameter, the route of faces kept): there the loop is straight
    at its base too, a closed geodesic, unless the best place is an end of the
    edge (the next round moves the base again). The search runs only where a
    step of ``SLIDE_STEP`` either way shortens the loop (and the edge's end
    is tried where it stops that close to it); elsewhere it is
    straight at its base already (or as short all along the edge, as round a
    cylinder). A vertex base (a loop with no edge crossing) is not slid.
    """
    rows, vertex, xyz, base_point = _rotated(mesh, piece, b)
    route, _, _ = route_of(mesh, rows, vertex, xyz)
    if base_point.vertex >= 0:  # a loop along edges and through vertices only: rerouted, not slid
        return straighten(mesh, route, base_point, base_point)
    a, c = (int(x) for x in piece.edge[b])

    def loop_at(t):
        point = mesh.edge_point(a, c, t)
        return straighten(mesh, route, point, point)

    best = straighten(mesh, route, base_point, base_point)
    t0, length = float(piece.t[b]), _length(best.xyz)
    nearby = [_length(loop_at(t).xyz) for t in (max(t0 - SLIDE_STEP, 0.0), min(t0 + SLIDE_STEP, 1.0)) if t != t0]
    if not nearby or min(nearby) >= length * (1.0 - LOOP_TOL):  # straight at its base already (or flat there)
        return best
    found = minimize_scalar(lambda t: _length(loop_at(t).xyz), bounds=(0.0, 1.0), method="bounded",
                            options={"xatol": 1e-13})
    t = float(found.x)
    candidates = [best, loop_at(t)]
    if min(t, 1.0 - t) <= SLIDE_STEP:  # the search stops short of the edge's ends: a vertex base may be shorter
        candidates.append(loop_at(round(t)))
    return min(candidates, key=lambda candidate: _length(candidate.xyz))


def _rotated(mesh, piece, b):
    """The closed ``piece`` started at its point ``b`` (inside an edge, or a vertex): rows, vertex, xyz, that point."""
    k = len(piece.xyz)
    order = np.r_[np.arange(b, k - 1), np.arange(0, b + 1)]
    rows = np.r_[piece.faces[b:], piece.faces[:b]]
    if piece.vertex[b] >= 0:
        return rows, piece.vertex[order], piece.xyz[order], mesh.vertex_point(int(piece.vertex[b]))
    a, c = (int(x) for x in piece.edge[b])
    return rows, piece.vertex[order], piece.xyz[order], mesh.edge_point(a, c, float(piece.t[b]))
