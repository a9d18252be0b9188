"""The input triangle mesh as paths see it: faces, neighbours across edges, vertex fans, points.

Paths run on the faces of the mesh as the user gave it, not on the refined or
intrinsic triangulation the heat operators use. :class:`PathMesh` holds what
the descent, the unfolding and the funnel need, built once per mesh with
vectorized numpy:

- the kept faces (those :class:`~heatcore.TriangleMesh` did not drop) on
  *welded* vertex ids (the operator vertices of the input vertices), so that a
  path crosses texture seams, and their positions;
- the face across each edge (``-1`` on boundary and non-manifold edges: a path
  never unfolds across those, it may only pass through their end vertices);
- the faces around each vertex, corner angles, and the gradients of the three
  barycentric coordinates of each face (the gradient of a linear function on a
  face is ``values @ grad_bary[f]``).

Edge ``j`` of a face runs from corner ``j`` to corner ``j + 1``.

A :class:`SurfacePoint` is a point of the surface: a vertex, a point inside
an edge, or a point inside a face.

Examples
--------
>>> import numpy as np, heatcore as hc
>>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
>>> mesh = PathMesh(hc.TriangleMesh(V, [[0, 1, 2], [1, 3, 2]], refine=0))
>>> mesh.neighbor.tolist()  # face 0's edge 1 (from vertex 1 to 2) is shared with face 1
[[-1, 1, -1], [-1, -1, 0]]
>>> mesh.point(1, [0.5, 0.5, 0.0]).edge  # the middle of face 1's first edge
(1, 3)
"""

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..domains.intrinsic import NEXT, PREV, halfedge_twins
from ..domains.sources import barycentric_array, index_list
from ..errors import InvalidSourceError


@dataclass(frozen=True, eq=False)
class SurfacePoint:
    """A point on the surface, located on a vertex, inside an edge or inside a face.

    Attributes
    ----------
    position : (3,) float array
    vertex : int
        The (welded) vertex the point is, or -1.
    edge : tuple of int or None
        ``(a, b)``: the point is ``P[a] + t (P[b] - P[a])`` with ``0 < t < 1``.
    t : float
        The point's parameter on ``edge``.
    face : int
        A face (row of :attr:`PathMesh.faces`) holding the point (-1 for
        points inside an edge found by the funnel); the only one for a point
        inside a face.
    bary : (3,) float array or None
        Barycentric coordinates in ``face``.

    Examples
    --------
    >>> import numpy as np, heatcore as hc
    >>> mesh = PathMesh(hc.TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0))
    >>> p = mesh.point(0, [0.2, 0.3, 0.5])
    >>> p.vertex, p.edge, p.position.round(2).tolist()
    (-1, None, [0.2, 0.3, 0.5])
    """

    position: np.ndarray
    vertex: int = -1
    edge: tuple = None
    t: float = 0.0
    face: int = -1
    bary: np.ndarray = None

    def key(self):
        """What identifies the point: ``("v", vertex)``, ``("e", a, b, t)`` or ``("f", face, *bary)``."""
        if self.vertex >= 0:
            return ("v", self.vertex)
        if self.edge is not None:
            a, b = self.edge
            return ("e", a, b, self.t) if a < b else ("e", b, a, 1.0 - self.t)
        return ("f", self.face, *self.bary.tolist())


class PathMesh:
    """Topology and geometry of a :class:`~heatcore.TriangleMesh`'s input faces for paths.

    Parameters
    ----------
    domain : TriangleMesh

    Attributes
    ----------
    faces : (m, 3) int array
        The kept faces on welded vertex ids.
    face_ids : (m,) int array
        Input face index of each row of ``faces``.
    positions : (n, 3) float array
        Position of each welded vertex.
    input_vertex : (n,) int array
        An input vertex of each welded vertex.
    neighbor, neighbor_edge : (m, 3) int arrays
        Face across edge ``j`` and that edge's index in it; -1 where none.
    angles : (m, 3) float array
        Corner angles.
    grad_bary : (m, 3, 3) float array
        ``grad_bary[f, i]`` is the gradient of barycentric coordinate ``i`` (0 on degenerate faces).
    diagonal : float
        Bounding-box diagonal.

    Examples
    --------
    >>> import heatcore as hc
    >>> mesh = PathMesh.of(hc.TriangleMesh(*hc.io.load_demo_mesh(), refine=0))
    >>> mesh.faces.shape, bool((mesh.neighbor >= 0).all())  # spot is closed
    ((5856, 3), True)
    """

    def __init__(self, domain):
        kept = np.flatnonzero(domain.face_map >= 0)
        vmap = np.asarray(domain.vertex_map)
        used = np.flatnonzero(vmap >= 0)
        n = int(vmap.max()) + 1
        self.input_vertex = np.empty(n, dtype=np.int64)
        self.input_vertex[vmap[used]] = used
        self.vertex_map = vmap
        self.face_ids = kept
        self.face_row = np.asarray(domain.face_map)
        self.faces = F = vmap[domain.faces[kept]].astype(np.int64)
        self.positions = P = np.asarray(domain.vertices, dtype=float)[self.input_vertex]
        self.diagonal = float(np.linalg.norm(P.max(axis=0) - P.min(axis=0))) if n else 0.0
        m = F.shape[0]
        # Edges: edge j of a face runs from corner j to j + 1, the half-edge opposite corner j + 2 (PREV[j]) of
        # halfedge_twins, whose twins are paired whatever their directions (oriented=False).
        twin = halfedge_twins(F, oriented=False).reshape(m, 3)[:, PREV]
        self.neighbor = np.where(twin >= 0, twin // 3, -1)
        self.neighbor_edge = np.where(twin >= 0, NEXT[twin % 3], -1)
        # Faces around each vertex (CSR).
        corner_vertex = F.ravel()
        by_vertex = np.argsort(corner_vertex, kind="stable")
        self.vertex_faces = by_vertex // 3
        self.vertex_start = np.r_[0, np.cumsum(np.bincount(corner_vertex, minlength=n))]
        # Corner angles and gradients of the barycentric coordinates.
        Q = P[F]
        e1, e2 = Q[:, 1] - Q[:, 0], Q[:, 2] - Q[:, 0]
        g11, g12, g22 = (e1 * e1).sum(1), (e1 * e2).sum(1), (e2 * e2).sum(1)
        det = g11 * g22 - g12 * g12
        good = det > 1e-30 * np.maximum(g11 * g22, 1e-300)
        inv = np.where(good, 1.0 / np.where(good, det, 1.0), 0.0)
        d1 = ((g22 * inv)[:, None] * e1 - (g12 * inv)[:, None] * e2)
        d2 = ((g11 * inv)[:, None] * e2 - (g12 * inv)[:, None] * e1)
        self.grad_bary = np.stack([-d1 - d2, d1, d2], axis=1)
        self.angles = np.stack([_angle(Q[:, (c + 1) % 3] - Q[:, c], Q[:, (c + 2) % 3] - Q[:, c]) for c in range(3)],
                               axis=1)
        #: Length of edge ``j`` (from corner ``j`` to ``j + 1``) of each face.
        self.edge_lengths = np.linalg.norm(Q[:, [1, 2, 0]] - Q, axis=2)
        self._fans, self._around, self._lists, self._graph, self._layouts = {}, {}, None, None, None

    @classmethod
    def of(cls, domain):
        """The :class:`PathMesh` of ``domain``, built once and kept in the domain's cache (as long as it lives)."""
        return domain.derived.get_or_build(("path mesh", None), lambda: cls(domain))

    # ----------------------------------------------------------------- points

    def vertex_point(self, v):
        """The :class:`SurfacePoint` at welded vertex ``v``."""
        f = int(self.vertex_faces[self.vertex_start[v]])
        bary = (self.faces[f] == v).astype(float)
        return SurfacePoint(self.positions[v], vertex=int(v), face=f, bary=bary)

    def point(self, row, bary):
        """The :class:`SurfacePoint` with barycentric coordinates ``bary`` in face row ``row``.

        One coordinate 1 gives the vertex, one coordinate 0 a point inside an edge.
        """
        bary = np.asarray(bary, dtype=float)
        corners = self.faces[row]
        position = bary @ self.positions[corners]
        zero = bary == 0.0
        if zero.sum() >= 2:
            return self.vertex_point(int(corners[np.argmax(bary)]))
        if zero.any():
            c = int(np.flatnonzero(zero)[0])
            a, b = int(corners[(c + 1) % 3]), int(corners[(c + 2) % 3])
            t = float(bary[(c + 2) % 3])
            return SurfacePoint(position, edge=(a, b), t=t, face=int(row), bary=bary)
        return SurfacePoint(position, face=int(row), bary=bary)

    def edge_point(self, a, b, t):
        """The point ``P[a] + t (P[b] - P[a])``: a vertex for ``t`` 0 or 1, else inside the edge."""
        if t <= 0.0:
            return self.vertex_point(a)
        if t >= 1.0:
            return self.vertex_point(b)
        pa, pb = self.positions[a], self.positions[b]
        return SurfacePoint(pa + t * (pb - pa), edge=(a, b), t=float(t))

    def user_point(self, spec, what):
        """A :class:`SurfacePoint` from a user's input vertex index or ``(face, barycentric)`` pair.

        Raises
        ------
        InvalidSourceError
            An index out of range, a vertex no face uses, a dropped face, bad coordinates.
        """
        try:
            return self._user_point(spec, what)
        except InvalidSourceError as exc:
            if str(exc).startswith(what):
                raise
            raise InvalidSourceError(f"{what}: {exc}") from None

    def _user_point(self, spec, what):
        if isinstance(spec, (tuple, list)) and len(spec) == 2 and np.ndim(spec[1]) == 1:
            face = int(index_list([spec[0]], self.face_row.size, "face")[0])
            bary = barycentric_array([spec[1]], 1, 3)[0]
            row = int(self.face_row[face])
            if row < 0:
                raise InvalidSourceError(f"face {face} was ignored (it has repeated vertices, after welding, or "
                                         f"duplicates another face), so a point on it cannot be a {what}; "
                                         "use a vertex or another face")
            return self.point(row, bary)
        if np.ndim(spec) != 0:
            raise InvalidSourceError(f"{what} must be a vertex index or a pair (face, barycentric coordinates), "
                                     f"got {spec!r}")
        v = int(index_list([spec], self.vertex_map.size, "vertex")[0])
        if self.vertex_map[v] < 0:
            raise InvalidSourceError(f"vertex {v} is not used by any face, so it cannot be a {what}")
        return self.vertex_point(int(self.vertex_map[v]))

    # ----------------------------------------------------------------- topology

    def lists(self):
        """``faces``, ``neighbor`` and ``edge_lengths`` as :class:`Rows` (what loops over one face read fastest)."""
        if self._lists is None:
            self._lists = (Rows(self.faces), Rows(self.neighbor), Rows(self.edge_lengths))
        return self._lists

    def layouts(self):
        """Each face laid out in the plane, and the plane isometries that glue neighbours' layouts.

        Returns
        -------
        local : (m, 3) complex array
            Face ``f``'s corners: corner 0 at 0, corner 1 on the positive real
            axis, corner 2 above it.
        rotation, shift : (m, 3) complex arrays
        mirror : (m, 3) bool array
            Across edge ``j`` of face ``f``, the neighbour's layout ``z`` maps
            to ``rotation * z + shift`` (``conj(z)`` for ``z`` where
            ``mirror``: the two faces are oriented alike) in ``f``'s layout,
            the shared edge on itself and the neighbour on its far side.
        """
        if self._layouts is None:
            F, Q = self.faces, self.positions[self.faces]
            m = F.shape[0]
            e1, e2 = Q[:, 1] - Q[:, 0], Q[:, 2] - Q[:, 0]
            l01 = np.linalg.norm(e1, axis=1)
            with np.errstate(invalid="ignore", divide="ignore"):
                ex = np.where(l01[:, None] > 0, e1 / np.where(l01 > 0, l01, 1.0)[:, None], [1.0, 0.0, 0.0])
            x2 = (e2 * ex).sum(axis=1)
            y2 = np.sqrt(np.maximum((e2 * e2).sum(axis=1) - x2 * x2, 0.0))
            local = np.stack([np.zeros(m), l01, x2], axis=1) + 1j * np.stack([np.zeros(m), np.zeros(m), y2], axis=1)
            rotation = np.ones((m, 3), dtype=complex)
            shift = np.zeros((m, 3), dtype=complex)
            mirror = np.zeros((m, 3), dtype=bool)
            f, j = np.nonzero(self.neighbor >= 0)
            g, k = self.neighbor[f, j], self.neighbor_edge[f, j]
            za_f, zb_f = local[f, j], local[f, (j + 1) % 3]
            same = F[g, k] == F[f, j]  # both faces run along the edge the same way: a mirror image
            za_g = np.where(same, local[g, k], local[g, (k + 1) % 3])
            zb_g = np.where(same, local[g, (k + 1) % 3], local[g, k])
            za_g, zb_g = np.where(same, np.conj(za_g), za_g), np.where(same, np.conj(zb_g), zb_g)
            with np.errstate(invalid="ignore", divide="ignore"):
                r = (zb_f - za_f) / (zb_g - za_g)
                r = r / np.abs(r)
            r = np.where(np.isfinite(r), r, 1.0)
            rotation[f, j] = r
            shift[f, j] = za_f - r * za_g
            mirror[f, j] = same
            self._layouts = (local, rotation, shift, mirror)
        return self._layouts

    def faces_around(self, v):
        """Face rows around vertex ``v``, a Python list (cached)."""
        out = self._around.get(v)
        if out is None:
            out = self._around[v] = self.faces_of(v).tolist()
        return out

    def edge_graph(self):
        """Sparse matrix of edge lengths between the welded vertices (built on first use)."""
        if self._graph is None:
            F = self.faces
            pairs = np.unique(np.sort(np.stack([F.ravel(), F[:, [1, 2, 0]].ravel()], axis=1), axis=1), axis=0)
            a, b = pairs[:, 0], pairs[:, 1]
            w = np.maximum(np.linalg.norm(self.positions[a] - self.positions[b], axis=1), 1e-300)
            n = self.positions.shape[0]
            self._graph = sp.csr_matrix((np.r_[w, w], (np.r_[a, b], np.r_[b, a])), shape=(n, n))
        return self._graph

    def faces_of(self, v):
        """Face rows around vertex ``v``."""
        return self.vertex_faces[self.vertex_start[v]:self.vertex_start[v + 1]]

    def edge_faces(self, a, b):
        """Face rows holding both ``a`` and ``b``."""
        faces = self.faces_of(a)
        return faces[(self.faces[faces] == b).any(axis=1)].tolist()

    def star(self, p):
        """Face rows holding point ``p``."""
        if p.vertex >= 0:
            return self.faces_of(p.vertex).tolist()
        if p.edge is not None:
            return self.edge_faces(*p.edge)
        return [p.face]

    def contains(self, row, p):
        """Whether face row ``row`` holds point ``p``."""
        corners = self.lists()[0][row]
        if p.vertex >= 0:
            return p.vertex in corners
        if p.edge is not None:
            return p.edge[0] in corners and p.edge[1] in corners
        return row == p.face

    def bary_in(self, row, p):
        """Barycentric coordinates of point ``p`` in face row ``row`` (which holds it)."""
        corners = self.faces[row]
        if p.vertex >= 0:
            return (corners == p.vertex).astype(float)
        if p.edge is not None:
            a, b = p.edge
            return (corners == a) * (1.0 - p.t) + (corners == b) * p.t
        return p.bary

    def fan(self, v):
        """Faces around vertex ``v`` in order, or None where they do not form one fan (non-manifold).

        Returns
        -------
        (faces, first, second, angles, closed) or None
            ``faces[k]`` has the edges ``(v, first[k])`` and ``(v, second[k])``
            at ``v`` with ``second[k] == first[k + 1]``; ``closed``: the fan
            goes all around (an inner vertex), else it runs from boundary to boundary.
        """
        if v in self._fans:
            return self._fans[v]
        around = self.faces_of(v)
        fan = None
        if around.size:
            f0 = int(around[0])
            c0 = int(np.flatnonzero(self.faces[f0] == v)[0])
            w0 = int(self.faces[f0, (c0 + 1) % 3])
            forward, closed = self._walk(v, f0, w0)
            if not closed:
                backward, _ = self._walk(v, f0, self._other(f0, v, w0))
                forward = [(f, b, a) for f, a, b in reversed(backward[1:])] + forward
            if len(forward) == around.size and len({f for f, _, _ in forward}) == around.size:
                faces = [f for f, _, _ in forward]
                angles = [float(self.angles[f, int(np.flatnonzero(self.faces[f] == v)[0])]) for f in faces]
                fan = (faces, [a for _, a, _ in forward], [b for _, _, b in forward], angles, closed)
        self._fans[v] = fan
        return fan

    def _other(self, f, v, w):
        """The corner of face ``f`` that is neither ``v`` nor ``w``."""
        corners = self.faces[f].tolist()
        rest = [c for c in corners if c != v and c != w]
        return rest[0] if rest else w

    def _walk(self, v, f0, w0):
        """Faces around ``v`` from ``f0`` (entered by its edge ``(v, w0)``) across edges at ``v``."""
        out, f, w = [], f0, w0
        for _ in range(self.faces_of(v).size + 1):
            x = self._other(f, v, w)
            out.append((f, w, x))
            corners = self.faces[f].tolist()
            cv, cx = corners.index(v), corners.index(x)
            j = cv if (cv + 1) % 3 == cx else cx  # edge j runs from corner j to j + 1
            g = int(self.neighbor[f, j])
            if g < 0:
                return out, False
            if g == f0:
                return out, True
            f, w = g, x
        return out, False


class Rows(dict):
    """Rows of an array as Python lists, converted on first use and kept (loops read them fastest).

    Examples
    --------
    >>> rows = Rows(np.arange(6).reshape(3, 2))
    >>> rows[2], len(rows)
    ([4, 5], 1)
    """

    def __init__(self, array):
        super().__init__()
        self.array = array

    def __missing__(self, i):
        row = self[i] = self.array[i].tolist()
        return row


def _angle(u, v):
    """Angles between the rows of ``u`` and ``v``."""
    return np.arctan2(np.linalg.norm(np.cross(u, v), axis=-1), (u * v).sum(-1))


def angle_between(u, v):
    """Angle between two 3D vectors.

    Examples
    --------
    >>> round(angle_between(np.array([1.0, 0, 0]), np.array([0.0, 2, 0])), 6)
    1.570796
    """
    return float(np.arctan2(np.linalg.norm(np.cross(u, v)), float(u @ v)))
