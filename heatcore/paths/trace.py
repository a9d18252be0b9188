"""Descent on the distance field: the faces a path from the target down to the source crosses.

The distance ``phi`` from the source is linear on each face, so ``-grad phi``
is a constant direction per face. :func:`descend` follows it from the target:

* inside a face it moves straight along ``-grad phi`` to the face's edge, and
  crosses into the face beyond when that face's descent direction also leads
  away from the edge;
* where both faces' directions lead into their common edge (a valley of the
  piecewise linear field) it slides along the edge to its lower end;
* at a vertex it leaves along the steepest way down: into a face whose
  direction points into its corner, or along an edge to a lower neighbour;
* it stops in the first face that holds the source.

``phi`` decreases strictly along the way, so the walk cannot loop. A vertex
lower than all its neighbours (the heat distance may have a tiny spurious
minimum) or a walk that takes too many steps (one spiralling into a vertex)
goes on along the edges of a shortest edge path (Dijkstra) to the source.

The result is a :class:`Route`: the faces crossed, split into legs at the
vertices the walk went through (consecutive faces of a leg share an edge; the
faces on either side of a vertex need not). Its exact position does not
matter: :mod:`heatcore.paths.straighten` makes it a geodesic. What the descent
decides is on which side of each hill and hole the path goes, which the heat
distance knows globally.

Examples
--------
>>> import numpy as np, heatcore as hc
>>> from heatcore.paths.surface import PathMesh
>>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
>>> mesh = PathMesh(hc.TriangleMesh(V, [[0, 1, 2], [1, 3, 2]], refine=0))
>>> field = DescentField(mesh, np.linalg.norm(V, axis=1))  # distance from vertex 0
>>> route = descend(mesh, field, mesh.vertex_point(3), mesh.vertex_point(0))
>>> route.legs, route.joints
([[1, 0]], [])
"""

import itertools
import math
from dataclasses import dataclass, field

import numpy as np
from scipy.sparse.csgraph import dijkstra

from .surface import Rows

#: Barycentric coordinates below this are taken as 0 (the walk is on the edge or at the corner).
SNAP = 1e-13


@dataclass
class Route:
    """Faces crossed from the start to the goal, in legs separated by vertices.

    Attributes
    ----------
    legs : list of list of int
        Face rows of each leg; consecutive faces of a leg share an edge.
    joints : list of int
        The vertex between leg ``i`` and leg ``i + 1``.
    fallback : bool
        Whether part of the route is a Dijkstra edge path (the descent got stuck).

    Examples
    --------
    >>> Route([[0], [3, 4]], [7]).reversed()
    Route(legs=[[4, 3], [0]], joints=[7], fallback=False)
    """

    legs: list
    joints: list
    fallback: bool = field(default=False)

    def reversed(self):
        """The same route run from the goal to the start."""
        return Route([leg[::-1] for leg in reversed(self.legs)], self.joints[::-1], self.fallback)


def face_gradients(mesh, phi):
    """Gradient of the piecewise linear ``phi`` (values at the welded vertices) on each face.

    Examples
    --------
    >>> import numpy as np, heatcore as hc
    >>> from heatcore.paths.surface import PathMesh
    >>> mesh = PathMesh(hc.TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0))
    >>> face_gradients(mesh, np.array([0.0, 1.0, 0.0])).round(4).tolist()  # grows towards (0, 1, 0)
    [[-0.3333, 0.6667, -0.3333]]
    """
    return np.einsum("fi,fik->fk", phi[mesh.faces], mesh.grad_bary)


class DescentField:
    """A distance field ready for descents: values, and each face's way down as barycentric rates.

    Parameters
    ----------
    mesh : PathMesh
    phi : (n,) float array
        Distance at the welded vertices.

    Attributes
    ----------
    phi : (n,) float array
    grad : (m, 3) float array
        :func:`face_gradients` of ``phi``.
    rate : Rows
        Per face, the rates of change of the barycentric coordinates when
        moving along ``-grad phi`` (lists: the walk reads them one by one).
    slope : Rows
        ``|grad phi|`` per face.
    values : Rows
        ``phi`` per vertex.

    Examples
    --------
    >>> import numpy as np, heatcore as hc
    >>> from heatcore.paths.surface import PathMesh
    >>> mesh = PathMesh(hc.TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0))
    >>> [round(r, 4) for r in DescentField(mesh, np.array([0.0, 1.0, 1.0])).rate[0]]  # down towards vertex 0
    [0.6667, -0.3333, -0.3333]
    """

    def __init__(self, mesh, phi):
        self.phi = np.asarray(phi, dtype=float)
        self.grad = face_gradients(mesh, self.phi)
        self.rate = Rows(np.einsum("fik,fk->fi", mesh.grad_bary, -self.grad))
        self.slope = Rows(np.linalg.norm(self.grad, axis=1))
        self.values = Rows(self.phi)
        #: Where each descent went on from each vertex it passed: ``{vertex: (legs, joints, fallback)}``.
        self.after = {}

    def remember(self, start, route):
        """Record where ``route`` (a descent from ``start``) went on from each of its vertices."""
        if start.vertex >= 0:
            self.after.setdefault(start.vertex, (route.legs, route.joints, route.fallback))
        for i, v in enumerate(route.joints):
            self.after.setdefault(v, (route.legs[i + 1:], route.joints[i + 1:], route.fallback))


class _Walk:
    """The state of one descent (see :func:`descend`)."""

    def __init__(self, mesh, field, goal):
        self.mesh, self.field, self.goal = mesh, field, goal
        self.F, self.N, self.lengths = mesh.lists()
        self.goal_faces = set(mesh.star(goal))
        self.legs, self.joints = [[]], []
        self.fallback = False

    def finish_in(self, faces):
        """A face of ``faces`` holding the goal, or None."""
        for f in faces:
            if f in self.goal_faces:
                return f
        return None

    def add(self, f):
        """Face ``f`` is crossed next."""
        if not self.legs[-1] or self.legs[-1][-1] != f:
            self.legs[-1].append(f)

    def arrive(self, v):
        """Arrived at vertex ``v``: a joint (unless it is the start); True when the goal is reached from it."""
        if self.legs[-1]:  # a vertex on the way (not the start): a joint
            if v == self.goal.vertex:
                return True
            self.joints.append(v)
            self.legs.append([])
        last = self.finish_in(self.mesh.faces_around(v))
        if last is not None:
            self.legs[-1].append(last)
            return True
        return False

    def at_vertex(self, v):
        """Arrived at vertex ``v``: the next state, or None when the goal is reached."""
        if self.arrive(v):
            return None
        known = self.field.after.get(v)
        if known is not None:  # an earlier descent went on from here: the same way
            legs, joints, fallback = known
            self.legs[-1].extend(legs[0])
            self.legs.extend(list(leg) for leg in legs[1:])
            self.joints.extend(joints)
            self.fallback |= fallback
            return None
        field, F = self.field, self.F
        rate, slope, phi = field.rate, field.slope, field.values
        best, step = 0.0, None
        for f in self.mesh.faces_around(v):  # the steepest way down: into a face, or along an edge
            corners = F[f]
            c = corners.index(v)
            r = rate[f]
            if r[c] < 0 and r[(c + 1) % 3] >= 0 and r[(c + 2) % 3] >= 0 and slope[f] > best:
                best, step = slope[f], ("face", f, [1.0 if k == c else 0.0 for k in range(3)])
            for k in ((c + 1) % 3, (c + 2) % 3):
                u = corners[k]
                edge = k if k == (c + 2) % 3 else c  # edge j runs from corner j to j + 1
                down = (phi[v] - phi[u]) / self.lengths[f][edge] if self.lengths[f][edge] > 0 else 0.0
                if down > best:
                    best, step = down, ("edge", f, u)
        if step is None:
            return ("stuck", v)
        self.add(step[1])
        if step[0] == "edge":
            return ("vertex", step[2])
        return self.move(step[1], step[2])

    def at_point(self, f, b):
        """At the point with barycentric coordinates ``b`` in face ``f`` (inside it or on its edge)."""
        zeros = [i for i in range(3) if b[i] == 0.0]
        if len(zeros) >= 2:
            return ("vertex", self.F[f][b.index(max(b))])
        candidates = [(f, b)]
        if zeros:
            j = (zeros[0] + 1) % 3  # the edge opposite corner c runs from corner c + 1 to c + 2
            g = self.N[f][j]
            if g >= 0:
                corners, other = self.F[f], self.F[g]
                bg = [0.0, 0.0, 0.0]
                bg[other.index(corners[j])] = b[j]
                bg[other.index(corners[(j + 1) % 3])] = b[(j + 1) % 3]
                candidates.append((g, bg))
        last = self.finish_in([h for h, _ in candidates])
        if last is not None:
            self.add(last)
            return None
        rate, slope = self.field.rate, self.field.slope
        best, choice = -1.0, None
        for h, bh in candidates:
            r = rate[h]
            if all(r[i] > 0 for i in range(3) if bh[i] == 0.0) and min(r) < 0 and slope[h] > best:
                best, choice = slope[h], (h, bh)
        if choice is None:
            self.add(f)
            phi = self.field.values
            corners = [v for v, w in zip(self.F[f], b) if w > 0 or not zeros]
            return ("vertex", min(corners, key=lambda v: phi[v]))  # a valley along an edge, or a flat face
        self.add(choice[0])
        return self.move(*choice)

    def move(self, f, b):
        """Go straight down from ``b`` to the boundary of face ``f``."""
        r = self.field.rate[f]
        t, i = math.inf, -1
        for k in range(3):
            if r[k] < 0 and -b[k] / r[k] < t:
                t, i = -b[k] / r[k], k
        out = [b[k] + t * r[k] for k in range(3)]
        out[i] = 0.0
        out = [x if x >= SNAP else 0.0 for x in out]
        total = sum(out)
        if total <= 0:
            return ("vertex", self.F[f][b.index(max(b))])
        return ("point", f, [x / total for x in out])

    def dijkstra(self, v):
        """The rest of the route along a shortest edge path from vertex ``v`` to the goal."""
        self.fallback = True
        mesh = self.mesh
        dist, pred = dijkstra(mesh.edge_graph(), indices=v, return_predecessors=True)
        targets = np.unique(mesh.faces[list(self.goal_faces)])
        end = int(targets[np.argmin(dist[targets])])
        chain = [end]
        while chain[-1] != v:
            chain.append(int(pred[chain[-1]]))
        chain.reverse()
        for a, b in itertools.pairwise(chain):
            self.legs[-1].append(mesh.edge_faces(a, b)[0])
            if b == self.goal.vertex:
                return
            self.joints.append(b)
            self.legs.append([])
        self.legs[-1].append(self.finish_in(mesh.faces_around(end)))


def descend(mesh, field, start, goal, max_steps=None):
    """The :class:`Route` of steepest descent on a distance field from ``start`` to its source ``goal``.

    Parameters
    ----------
    mesh : PathMesh
    field : DescentField
        Distance from ``goal``, finite on ``start``'s part.
    start, goal : SurfacePoint
        Different points of one part.
    max_steps : int, optional
        Steps before the walk goes on along a Dijkstra edge path (default: 4 per face, plus 100).

    Returns
    -------
    Route
        From ``start`` to ``goal``.

    Examples
    --------
    >>> import numpy as np, heatcore as hc
    >>> from heatcore.paths.surface import PathMesh
    >>> V, F = hc.io.load_demo_mesh()
    >>> mesh = PathMesh(hc.TriangleMesh(V, F, refine=0))
    >>> field = DescentField(mesh, np.linalg.norm(V - V[0], axis=1))  # straight-line distance from vertex 0
    >>> route = descend(mesh, field, mesh.vertex_point(1453), mesh.vertex_point(0))
    >>> bool((mesh.faces[route.legs[-1][-1]] == 0).any())  # the last face holds vertex 0
    True
    """
    walk = _Walk(mesh, field, goal)
    limit = max_steps if max_steps is not None else 4 * mesh.faces.shape[0] + 100
    state = ("vertex", start.vertex) if start.vertex >= 0 else ("point", start.face, start.bary.tolist())
    for _ in range(limit):
        if state is None:
            break
        if state[0] == "vertex":
            state = walk.at_vertex(state[1])
        elif state[0] == "point":
            state = walk.at_point(state[1], state[2])
        else:  # stuck at a vertex lower than its neighbours
            walk.dijkstra(state[1])
            state = None
    if state is not None:  # too many steps: from the nearest vertex on along edges
        if state[0] == "point":
            f = state[1]
            walk.add(f)
            state = ("vertex", min(walk.F[f], key=lambda v: field.values[v]))
        if state[0] != "vertex" or not walk.arrive(state[1]):
            walk.dijkstra(state[1])
    route = Route(walk.legs, walk.joints, walk.fallback)
    field.remember(start, route)
    return route
