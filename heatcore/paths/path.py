"""The geodesic path between two points of a triangle mesh: :class:`GeodesicPath` and the method's driver.

Method (docs/paths.md):

1. the distance from the source, and (``both_ends``) from the target: one
   query of the solver's factorizations each, refined by the eikonal pass
   (:class:`~heatcore.paths.fields.PathField`, kept in the solver's
   ``path_fields`` for further paths);
2. routes: steepest descent on the source's distance from the target and from
   each vertex around it, and (``both_ends``) on the target's distance from
   the source and around it (:func:`candidate_routes`,
   :func:`~heatcore.paths.trace.descend`); a route fixes on which side of every
   hill and hole a path goes;
3. each route straightened into a geodesic: strips unfolded, funnels, bends
   with less than ``pi`` on one side cut on that side until none is left
   (:func:`~heatcore.paths.straighten.straighten`), exact to rounding in the
   route's homotopy class; the shortest is kept (:func:`shortest_of_routes`).

Examples
--------
>>> import numpy as np, heatcore as hc
>>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
>>> solver = hc.HeatSolver(hc.TriangleMesh(V, [[0, 1, 2], [1, 3, 2]]))
>>> path = solver.geodesic_path(0, 3)
>>> path.points.tolist(), round(path.length, 12)
([[0.0, 0.0, 0.0], [0.5, 0.5, 0.0], [1.0, 1.0, 0.0]], 1.414213562373)
"""

from dataclasses import dataclass

import numpy as np

from ..domains.triangle import TriangleMesh
from ..errors import InvalidSourceError, UnsupportedDomainError
from .fields import PathField
from .funnel import Piece
from .straighten import straighten
from .surface import PathMesh
from .trace import Route, descend


@dataclass(frozen=True, eq=False)
class GeodesicPath:
    """A path on a triangle mesh's surface: a polyline whose every segment lies in one face.

    Attributes
    ----------
    points : (k, 3) float array
        From the source (first) to the target (last); ``k == 1`` when they are the same point.
    faces : (k - 1,) int array
        The input face each segment lies in.
    edges : (k, 2) int array
        The input edge (two input vertex indices, ascending) each point lies
        inside; ``[-1, -1]`` for points at a vertex or inside a face.
    vertices : (k,) int array
        The input vertex each point is, or -1.
    length : float
        Sum of the segments' lengths: the length of a path on the surface,
        never less than the geodesic distance.
    leg_lengths : (w - 1,) float array
        Length of each leg between consecutive waypoints (one leg for a
        path between two points); they add up to ``length``.
    waypoints : (w,) int array
        Index into ``points`` of each waypoint (``[0, k - 1]`` for a path
        between two points).

    Examples
    --------
    >>> import heatcore as hc
    >>> solver = hc.HeatSolver(hc.TriangleMesh(*hc.io.load_demo_mesh()))
    >>> path = solver.geodesic_path(0, 1453)
    >>> path.points.shape[1], int(path.vertices[0]), int(path.vertices[-1]), path.faces.size == len(path.points) - 1
    (3, 0, 1453, True)
    >>> bool(abs(path.length - solver.distance([0])[1453]) < 0.02 * path.length)  # the heat distance is close
    True
    """

    points: np.ndarray
    faces: np.ndarray
    edges: np.ndarray
    vertices: np.ndarray
    length: float
    leg_lengths: np.ndarray = None
    waypoints: np.ndarray = None

    def __post_init__(self):
        if self.leg_lengths is None:  # one leg: from the first point to the last
            object.__setattr__(self, "leg_lengths", np.array([self.length]))
        if self.waypoints is None:
            object.__setattr__(self, "waypoints", np.array([0, len(self.points) - 1], dtype=np.int64))

    def __len__(self):
        return len(self.points)

    @classmethod
    def from_piece(cls, mesh, piece):
        """The path of a :class:`~heatcore.paths.funnel.Piece` (welded vertices and face rows mapped to the input's)."""
        xyz = np.asarray(piece.xyz, dtype=float).reshape(-1, 3)
        vertices = np.where(piece.vertex >= 0, mesh.input_vertex[np.maximum(piece.vertex, 0)], -1)
        inside = (piece.vertex < 0) & (piece.edge[:, 0] >= 0)
        edges = np.full((len(xyz), 2), -1, dtype=np.int64)
        edges[inside] = np.sort(mesh.input_vertex[piece.edge[inside]], axis=1)
        length = float(np.linalg.norm(np.diff(xyz, axis=0), axis=1).sum())
        return cls(xyz, mesh.face_ids[np.asarray(piece.faces, dtype=np.int64)], edges, vertices, length)


def geodesic_path(solver, source, target, both_ends=True):
    """The geodesic path from ``source`` to ``target`` on ``solver``'s triangle mesh.

    See :meth:`heatcore.HeatSolver.geodesic_path`.

    Examples
    --------
    >>> import heatcore as hc
    >>> solver = hc.HeatSolver(hc.TriangleMesh(*hc.io.load_demo_mesh()))
    >>> geodesic_path(solver, 5, 5).length
    0.0
    """
    domain = solver.domain
    if not isinstance(domain, TriangleMesh):
        raise UnsupportedDomainError(
            f"geodesic paths are computed on triangle meshes (heatcore.TriangleMesh), not on a "
            f"{domain.domain_name} ({type(domain).__name__})"
        )
    mesh = PathMesh.of(domain)
    s = mesh.user_point(source, "source")
    t = mesh.user_point(target, "target")
    part_s, part_t = (int(solver.component[mesh.faces[p.face, 0]]) for p in (s, t))
    if part_s != part_t:
        raise InvalidSourceError(
            f"the target ({_describe(target)}) lies in part {part_t} of the mesh and the source "
            f"({_describe(source)}) in part {part_s}: no path on the surface joins two parts"
        )
    if s.key() == t.key() or np.array_equal(s.position, t.position):
        return GeodesicPath.from_piece(mesh, Piece.single(s))
    routes = [route.reversed() for route in candidate_routes(mesh, PathField.of(solver, s), s, t)]
    if both_ends:  # and down the distance from the target, from around the source
        routes += candidate_routes(mesh, PathField.of(solver, t), t, s)
    return GeodesicPath.from_piece(mesh, shortest_of_routes(mesh, routes, s, t))


def candidate_routes(mesh, field, s, t):
    """Routes from ``t`` down to ``s``: the descent from ``t``, and one from each vertex around ``t``.

    The descent decides on which side of every hill a route goes; where two
    sides are close in length, a descent from a neighbouring start may take
    the other one. The routes from the vertices around ``t`` start with the
    face holding ``t`` and that vertex.

    Examples
    --------
    >>> import heatcore as hc
    >>> solver = hc.HeatSolver(hc.TriangleMesh(*hc.io.load_demo_mesh()))
    >>> mesh = PathMesh.of(solver.domain)
    >>> s, t = mesh.vertex_point(0), mesh.vertex_point(1453)
    >>> routes = candidate_routes(mesh, PathField.of(solver, s), s, t)
    >>> 1 < len(routes) <= 1 + len(mesh.faces_of(1453))
    True
    """
    routes = [descend(mesh, field.descent, t, s)]
    t_faces = mesh.star(t)
    if set(t_faces) & set(mesh.star(s)):  # one face holds both: the straight segment
        return routes
    for u in np.unique(mesh.faces[t_faces]).tolist():
        if u == t.vertex or u == s.vertex:
            continue
        rest = descend(mesh, field.descent, mesh.vertex_point(u), s)
        first = next(f for f in t_faces if (mesh.faces[f] == u).any())
        routes.append(Route([[first]] + rest.legs, [u] + rest.joints, rest.fallback))
    return routes


def shortest_of_routes(mesh, routes, s, t):
    """The shortest of the geodesics the ``routes`` (from ``s`` to ``t``) straighten to (a :class:`Piece`).

    A route given twice (the same faces and vertices) is straightened once.

    Examples
    --------
    >>> import heatcore as hc
    >>> solver = hc.HeatSolver(hc.TriangleMesh(*hc.io.load_demo_mesh()))
    >>> mesh = PathMesh.of(solver.domain)
    >>> s, t = mesh.vertex_point(0), mesh.vertex_point(1453)
    >>> routes = [route.reversed() for route in candidate_routes(mesh, PathField.of(solver, s), s, t)]
    >>> piece = shortest_of_routes(mesh, routes, s, t)
    >>> len(piece.xyz) == len(piece.faces) + 1
    True
    """
    best, best_length, seen = None, np.inf, set()
    for route in routes:
        key = tuple(f for leg in route.legs for f in leg), tuple(route.joints)
        if key in seen:
            continue
        seen.add(key)
        piece = straighten(mesh, route, s, t)
        length = float(np.linalg.norm(np.diff(piece.xyz, axis=0), axis=1).sum())
        if length < best_length:
            best, best_length = piece, length
    return best


def _describe(spec):
    """A user's point in words: ``vertex 3`` or ``face 7 at (0.2, 0.3, 0.5)``."""
    if isinstance(spec, (tuple, list)) and len(spec) == 2:
        return f"face {spec[0]} at ({', '.join(f'{float(b):g}' for b in spec[1])})"
    return f"vertex {int(spec)}"
