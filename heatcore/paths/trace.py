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
>>> phi = np.linalg.norm(V, axis=1)  # distance from vertex 0
>>> route = descend(mesh, phi, face_gradients(mesh, phi), mesh.vertex_point(3), mesh.vertex_point(0))
>>> route.legs, route.joints
([[1, 0]], [])
"""

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import dijkstra

#: Steps of the smooth descent without a new lowest value of phi before it goes on down the linear pieces.
STALL = 50
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


class _Walk:
    """The state of one descent (see :func:`descend`)."""

    def __init__(self, mesh, phi, grad, goal, smooth):
        self.mesh, self.phi, self.grad, self.goal = mesh, phi, grad, goal
        self.vertex_grad = vertex_gradients(mesh, grad) if smooth else None
        self.goal_faces = set(mesh.star(goal))
        self.legs, self.joints = [[]], []
        self.fallback = False

    def direction(self, f, b):
        """The way down at barycentric coordinates ``b`` of face ``f`` (a 3D vector, not projected)."""
        if self.vertex_grad is None:
            return -self.grad[f]
        return -(b @ self.vertex_grad[self.mesh.faces[f]])

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
        mesh = self.mesh
        if self.legs[-1]:  # a vertex on the way (not the start): a joint
            if v == self.goal.vertex:
                return True
            self.joints.append(v)
            self.legs.append([])
        last = self.finish_in(mesh.faces_of(v).tolist())
        if last is not None:
            self.legs[-1].append(last)
            return True
        return False

    def at_vertex(self, v):
        """Arrived at vertex ``v``: the next state, or None when the goal is reached."""
        if self.arrive(v):
            return None
        mesh = self.mesh
        best, step = 0.0, None
        if self.vertex_grad is not None:  # the face whose corner holds the smooth field's direction
            w = -self.vertex_grad[v]
            for f in mesh.faces_of(v).tolist():
                b = (mesh.faces[f] == v).astype(float)
                db = mesh.grad_bary[f] @ w
                if (db[b == 1.0] < 0).all() and (db[b == 0.0] >= 0).all():
                    speed = float(np.linalg.norm(db))
                    if speed > best:
                        best, step = speed, ("face", f, b, db)
        for f in mesh.faces_of(v).tolist() if step is None else ():  # steepest way down the linear pieces
            corners = mesh.faces[f]
            c = int(np.flatnonzero(corners == v)[0])
            db = mesh.grad_bary[f] @ -self.grad[f]
            others = np.delete(db, c)
            if db[c] < 0 and (others >= 0).all():
                slope = float(np.linalg.norm(self.grad[f]))
                if slope > best:
                    best, step = slope, ("face", f, (corners == v).astype(float), db)
            for u in corners[corners != v].tolist():
                slope = (self.phi[v] - self.phi[u]) / np.linalg.norm(mesh.positions[u] - mesh.positions[v])
                if slope > best:
                    best, step = slope, ("edge", f, u)
        if step is None:
            return ("stuck", v)
        if step[0] == "edge":
            self.add(step[1])
            return ("vertex", step[2])
        _, f, b, db = step
        self.add(f)
        return self.move(f, b, db)

    def at_point(self, f, b):
        """At the point with barycentric coordinates ``b`` in face ``f`` (inside it or on its edge)."""
        mesh = self.mesh
        zero = np.flatnonzero(b == 0.0)
        if zero.size >= 2:
            return ("vertex", int(mesh.faces[f, np.argmax(b)]))
        candidates = [(f, b)]
        if zero.size == 1:
            c = int(zero[0])
            j = (c + 1) % 3  # the edge opposite corner c runs from corner c + 1 to c + 2
            g = int(mesh.neighbor[f, j])
            if g >= 0:
                bg = np.zeros(3)
                corners = mesh.faces[f]
                for k in (j, (j + 1) % 3):
                    bg[np.flatnonzero(mesh.faces[g] == corners[k])[0]] = b[k]
                candidates.append((g, bg))
        last = self.finish_in([h for h, _ in candidates])
        if last is not None:
            self.add(last)
            return None
        best, choice = -1.0, None
        for h, bh in candidates:
            db = mesh.grad_bary[h] @ self.direction(h, bh)
            if (db[bh == 0.0] > 0).all() and (db < 0).any():
                speed = float(np.linalg.norm(db))
                if speed > best:
                    best, choice = speed, (h, bh, db)
        if choice is None:
            self.add(f)
            if zero.size == 0:  # a flat face: down to its lowest corner
                return ("vertex", int(mesh.faces[f][np.argmin(self.phi[mesh.faces[f]])]))
            corners = mesh.faces[f][b > 0]  # a valley along the edge: slide to its lower end
            return ("vertex", int(corners[np.argmin(self.phi[corners])]))
        h, bh, db = choice
        self.add(h)
        return self.move(h, bh, db)

    def move(self, f, b, db):
        """Go straight from ``b`` along the barycentric velocity ``db``: to the boundary of face ``f``, or one step."""
        leaving = db < 0
        times = np.where(leaving, -b / np.where(leaving, db, -1.0), np.inf)
        i = int(np.argmin(times))
        if self.vertex_grad is not None:  # the smooth field turns inside a face: steps of half an edge
            velocity = float(np.linalg.norm(db @ self.mesh.positions[self.mesh.faces[f]]))
            step = self.mesh.step[f] / velocity if velocity > 0 else np.inf
            if step < times[i]:
                out = b + step * db
                out[out < SNAP] = 0.0
                return ("point", f, out / out.sum())
        out = b + times[i] * db
        out[i] = 0.0
        out[out < SNAP] = 0.0
        total = out.sum()
        if total <= 0:
            return ("vertex", int(self.mesh.faces[f, np.argmax(b)]))
        return ("point", f, out / total)

    def dijkstra(self, v):
        """The rest of the route along a shortest edge path from vertex ``v`` to the goal."""
        self.fallback = True
        mesh = self.mesh
        graph = mesh.__dict__.get("edge_graph")
        if graph is None:
            graph = mesh.__dict__["edge_graph"] = edge_graph(mesh)
        dist, pred = dijkstra(graph, indices=v, return_predecessors=True)
        targets = np.unique(mesh.faces[list(self.goal_faces)])
        end = int(targets[np.argmin(dist[targets])])
        chain = [end]
        while chain[-1] != v:
            chain.append(int(pred[chain[-1]]))
        chain.reverse()
        for a, b in zip(chain[:-1], chain[1:]):
            self.legs[-1].append(mesh.edge_faces(a, b)[0])
            if b == self.goal.vertex:
                return
            self.joints.append(b)
            self.legs.append([])
        self.legs[-1].append(self.finish_in(mesh.faces_of(end).tolist()))


def descend(mesh, phi, grad, start, goal, max_steps=None, smooth=False):
    """The :class:`Route` of steepest descent on ``phi`` from ``start`` to ``goal`` (``phi``'s minimum).

    Parameters
    ----------
    mesh : PathMesh
    phi : (n,) float array
        Distance from ``goal`` at the welded vertices, finite on ``start``'s part.
    grad : (m, 3) float array
        :func:`face_gradients` of ``phi``.
    start, goal : SurfacePoint
        Different points of one part.
    max_steps : int, optional
        Steps before the walk goes on along a Dijkstra edge path (default: 4 per face, plus 100).

    Returns
    -------
    Route
        From ``start`` to ``goal``.
    """
    walk = _Walk(mesh, phi, grad, goal, smooth)
    limit = max_steps if max_steps is not None else 4 * mesh.faces.shape[0] + 100
    state = ("vertex", start.vertex) if start.vertex >= 0 else ("point", start.face, start.bary)
    lowest, stall = np.inf, 0
    for _ in range(limit):
        if state is None:
            return Route(walk.legs, walk.joints, walk.fallback)
        if state[0] == "point" and walk.vertex_grad is not None:  # the smooth field may circle a sink
            level = float(state[2] @ phi[mesh.faces[state[1]]])
            lowest, stall = (level, 0) if level < lowest else (lowest, stall + 1)
            if stall > STALL:
                walk.vertex_grad = None  # on down the linear pieces, where phi decreases strictly
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
            v = int(mesh.faces[f][np.argmin(phi[mesh.faces[f]])])
            if not walk.legs[-1] or walk.legs[-1][-1] != f:
                walk.legs[-1].append(f)
            state = ("vertex", v)
        if state[0] == "vertex":
            if not walk.arrive(state[1]):
                walk.dijkstra(state[1])
        else:
            walk.dijkstra(state[1])
    return Route(walk.legs, walk.joints, walk.fallback)


def vertex_gradients(mesh, grad):
    """Gradient at each vertex: the mean of its faces' gradients, weighted by their corner angles.

    Examples
    --------
    >>> import numpy as np, heatcore as hc
    >>> from heatcore.paths.surface import PathMesh
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
    >>> mesh = PathMesh(hc.TriangleMesh(V, [[0, 1, 2], [1, 3, 2]], refine=0))
    >>> vertex_gradients(mesh, face_gradients(mesh, V[:, 0]))[3].tolist()  # phi = x
    [1.0, 0.0, 0.0]
    """
    n = mesh.positions.shape[0]
    w = mesh.angles.ravel()
    out = np.zeros((n, 3))
    np.add.at(out, mesh.faces.ravel(), w[:, None] * np.repeat(grad, 3, axis=0))
    total = np.bincount(mesh.faces.ravel(), weights=w, minlength=n)
    return out / np.where(total > 0, total, 1.0)[:, None]


def edge_graph(mesh):
    """Sparse symmetric matrix of edge lengths between the welded vertices of ``mesh``.

    Examples
    --------
    >>> import numpy as np, heatcore as hc
    >>> from heatcore.paths.surface import PathMesh
    >>> mesh = PathMesh(hc.TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0))
    >>> float(edge_graph(mesh)[0, 1].round(4))
    1.4142
    """
    F = mesh.faces
    pairs = np.unique(np.sort(np.stack([F.ravel(), F[:, [1, 2, 0]].ravel()], axis=1), axis=1), axis=0)
    a, b = pairs[:, 0], pairs[:, 1]
    w = np.maximum(np.linalg.norm(mesh.positions[a] - mesh.positions[b], axis=1), 1e-300)
    n = mesh.positions.shape[0]
    return sp.csr_matrix((np.r_[w, w], (np.r_[a, b], np.r_[b, a])), shape=(n, n))
