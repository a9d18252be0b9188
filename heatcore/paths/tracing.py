"""Straightest geodesics: a path traced from a surface point along a tangent direction.

The walk runs on the input faces of a :class:`~heatcore.TriangleMesh` (welded as for
paths, :class:`~heatcore.paths.surface.PathMesh`). Inside a face it is a straight
segment in the face's planar layout; across an edge the next face is unfolded
around the shared edge (the layouts' plane isometries of
:meth:`PathMesh.layouts`), so the direction is kept as if the two faces were one
plane. A path that meets a vertex (within ``VERTEX_SNAP`` of an edge's end)
leaves it so that the angle on either side is half the vertex's total angle
(the *straightest* geodesic of Polthier and Schmies, 1998): straight on at a
flat vertex, well defined at cone and saddle vertices where no straight
continuation exists. The walk stops after ``length`` or where it meets the
boundary (a boundary edge, a boundary or non-manifold vertex).

Directions: a 3D vector is projected on the tangent plane at the start (the
face's plane inside a face; at a vertex, its angle-weighted normal's plane,
mapped onto the fan of faces wedge by wedge: the angle between two projected
edges is spread linearly over the true corner angle, exact on a flat vertex).
Two coordinates ``(x, y)`` are the vector ``x e1 + y e2`` of the start vertex's
tangent basis (:meth:`heatcore.VectorHeatSolver.tangent_basis`), or inside a
face of the face's own basis: ``e1`` along its first edge (corner 0 to 1),
``e2 = normal x e1``.

Examples
--------
>>> import numpy as np, heatcore as hc
>>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
>>> path = trace_geodesic(V, [[0, 1, 2], [1, 3, 2]], (0, [0.6, 0.2, 0.2]), [1.0, 1.0, 0.0], 0.5)
>>> path.points.round(4).tolist(), path.faces.tolist(), path.stopped
([[0.2, 0.2, 0.0], [0.5, 0.5, 0.0], [0.5536, 0.5536, 0.0]], [0, 1], 'length')
>>> face, bary = path.end
>>> face, round(path.length, 12)
(1, 0.5)
"""

from dataclasses import dataclass

import numpy as np

from ..domains.triangle import TriangleMesh
from ..errors import (
    InvalidOptionError,
    InvalidSourceError,
    SolverError,
    UnsupportedDomainError,
)
from .surface import PathMesh

#: A crossing within this fraction of an edge's length from its end goes through the vertex.
VERTEX_SNAP = 1e-10

#: Faces crossed before a walk is given up as stuck (a trace of ordinary length crosses far fewer).
MAX_STEPS = 10_000_000


@dataclass(frozen=True, eq=False)
class TracedPath:
    """A traced straightest geodesic.

    Attributes
    ----------
    points : (k, 3) float array
        The start, every point where the path crosses an edge or passes a
        vertex, and the end; each segment lies in one input face.
    faces : (k - 1,) int array
        The input face of each segment.
    end : (int, (3,) float array)
        The end as a surface point ``(face, barycentric)`` of the input mesh
        (a start for another trace or a path).
    length : float
        Length travelled (the sum of the segments' lengths).
    stopped : {"length", "boundary"}
        Why the walk ended: it went ``length``, or it met the boundary first.

    Examples
    --------
    >>> import numpy as np
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    >>> path = trace_geodesic(V, [[0, 1, 2]], 0, [1.0, 1.0, 0.0], 5.0)   # out of vertex 0, to the far edge
    >>> path.stopped, round(path.length, 6), path.end[1].round(6).tolist()
    ('boundary', 0.707107, [0.0, 0.5, 0.5])
    """

    points: np.ndarray
    faces: np.ndarray
    end: tuple
    length: float
    stopped: str


def trace_geodesic(V, F, start, direction, length, *, weld=0.0):
    """The straightest path on a triangle mesh from ``start`` along ``direction``, in one call.

    Parameters
    ----------
    V : (n, 3) array_like of float
    F : (m, 3) array_like of int
    start : int or (int, (3,) array_like)
        A vertex index, or a surface point ``(face, barycentric)``.
    direction : (3,) or (2,) array_like of float
        A 3D vector (projected on the tangent plane at ``start``) or 2D
        coordinates in the start's tangent basis (module docstring); its
        length does not matter.
    length : float
        How far to go (>= 0).
    weld : float, default 0.0
        Weld tolerance, as for distances (0: coincident vertices only).

    Returns
    -------
    TracedPath

    Examples
    --------
    >>> import numpy as np
    >>> V = np.array([[0, 0, 0], [2, 0, 0], [0, 2, 0]], float)
    >>> trace_geodesic(V, [[0, 1, 2]], (0, [0.5, 0.25, 0.25]), [1.0, 0.0, 0.0], 0.5).points.tolist()
    [[0.5, 0.5, 0.0], [1.0, 0.5, 0.0]]
    """
    return trace(TriangleMesh(V, F, refine=0, weld=weld), start, direction, length)


def trace(domain, start, direction, length):
    """The straightest path on ``domain``'s input faces from ``start`` along ``direction``.

    See :func:`trace_geodesic` and :meth:`heatcore.HeatSolver.trace`.

    Raises
    ------
    UnsupportedDomainError
        ``domain`` is not a :class:`~heatcore.TriangleMesh`.
    InvalidSourceError
        A bad start (index, coordinates, a vertex no face uses), or a
        direction that is zero, not finite or normal to the surface there.
    InvalidOptionError
        ``length`` negative or not finite.

    Examples
    --------
    >>> import numpy as np, heatcore as hc
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    >>> trace(hc.TriangleMesh(V, [[0, 1, 2]]), 0, [1.0, 0.0], 0.25).points.round(12).tolist()   # e1: along 0-1
    [[0.0, 0.0, 0.0], [0.25, 0.0, 0.0]]
    """
    if not isinstance(domain, TriangleMesh):
        raise UnsupportedDomainError(
            f"geodesics are traced on triangle meshes (heatcore.TriangleMesh), not on a {domain.domain_name} "
            f"({type(domain).__name__}); a polygon mesh read as a TriangleMesh (fan triangles) can be traced"
        )
    length = float(length) if np.ndim(length) == 0 else np.nan
    if not (np.isfinite(length) and length >= 0.0):
        raise InvalidOptionError(f"length must be a finite number >= 0, got {length}")
    mesh = PathMesh.of(domain)
    p = mesh.user_point(start, "start")
    walk = Walk(mesh)
    if length == 0.0:
        walk.points.append(p.position)
        return walk.result(p, "length")
    first = walk.start(p, _direction(domain, mesh, p, start, direction))
    if first is None:
        return walk.result(p, "boundary")
    face, z, d, corner = first
    return walk.run(face, z, d, corner, length)


def _direction(domain, mesh, p, start, direction):
    """``direction`` as a 3D vector, or as ``(x, y)`` in a face's layout for a 2D direction at a face point."""
    d = np.asarray(direction, dtype=float).ravel() if np.ndim(direction) == 1 else np.zeros(0)
    if d.size not in (2, 3) or not np.isfinite(d).all():
        raise InvalidSourceError(f"direction must be 2 or 3 finite numbers, got {direction!r}")
    if not np.abs(d).max() > 0.0:
        raise InvalidSourceError("direction is zero: give a tangent vector at the start")
    if d.size == 3 or p.vertex < 0:
        return d
    basis = input_tangent_basis(domain)
    v = int(start) if np.ndim(start) == 0 else int(mesh.input_vertex[p.vertex])
    return d[0] * basis[1][v] + d[1] * basis[2][v]


def input_tangent_basis(domain):
    """Each input vertex's ``(normal, e1, e2)``, as :meth:`heatcore.VectorHeatSolver.tangent_basis` gives them.

    Built from the domain's intrinsic triangulation without the vector heat
    factorization, and kept in the domain's cache.

    Examples
    --------
    >>> import numpy as np, heatcore as hc
    >>> normal, e1, e2 = input_tangent_basis(hc.TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0))
    >>> bool(np.allclose(np.cross(normal, e1), e2))
    True
    """
    from ..vector_heat.basis import tangent_frames
    from ..vector_heat.frames import vertex_frames

    def build():
        tri, sub = domain.intrinsic, domain.subdivision
        frames = vertex_frames(tri, domain.operators.n_vertices)
        index = domain.output_vertices
        out = []
        for b in tangent_frames(sub.vertices, sub.faces, tri, frames):
            rows = np.zeros((index.size, 3))
            rows[index >= 0] = b[index[index >= 0]]
            out.append(rows)
        return tuple(out)

    return domain.derived.get_or_build(("vector frames", "input tangent basis"), build)


def cross(a, b):
    """The 2D cross product of complex numbers read as plane vectors.

    Examples
    --------
    >>> cross(1 + 0j, 1j)
    1.0
    """
    return a.real * b.imag - a.imag * b.real


class Walk:
    """The face-to-face walk of one trace, its points and faces recorded as it goes.

    Examples
    --------
    >>> import numpy as np, heatcore as hc
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    >>> mesh = PathMesh(hc.TriangleMesh(V, [[0, 1, 2]], refine=0))
    >>> walk = Walk(mesh)
    >>> face, z, d, corner = walk.start(mesh.point(0, [0.5, 0.25, 0.25]), np.array([0.0, -1.0, 0.0]))
    >>> walk.run(face, z, d, corner, 1.0).points.tolist()
    [[0.25, 0.25, 0.0], [0.25, 0.0, 0.0]]
    """

    def __init__(self, mesh):
        self.mesh = mesh
        self.local, self.rotation, self.shift, self.mirror = mesh.layouts()
        self.points, self.faces, self.travelled = [], [], 0.0

    # ---------------------------------------------------------------- start

    def start(self, p, direction):
        """``(face, z, d, corner)`` to walk from ``p``, or None where ``direction`` leaves the surface at once.

        ``direction``: a 3D vector, or a 2D one in the layout of ``p.face``.
        """
        self.points.append(p.position)
        if p.vertex >= 0:
            if direction.size == 2:
                raise InvalidSourceError("a 2D direction at a vertex needs its tangent basis")  # _direction gives 3D
            found = self.vertex_start(p.vertex, direction)
            if found is None:
                return None
            face, d = found
            corner = int(np.flatnonzero(self.mesh.faces[face] == p.vertex)[0])
            return face, self.local[face, corner], d, corner
        face = int(p.face)
        d = complex(*direction) if direction.size == 2 else self.in_layout(face, direction)
        z = complex(p.bary @ self.local[face])
        return face, z, d / abs(d), -1

    def in_layout(self, face, vector):
        """A 3D vector projected on face ``face``'s plane, as a complex number in its layout."""
        Q = self.mesh.positions[self.mesh.faces[face]]
        ex = Q[1] - Q[0]
        ex = ex / np.linalg.norm(ex)
        normal = np.cross(Q[1] - Q[0], Q[2] - Q[0])
        ey = np.cross(normal / np.linalg.norm(normal), ex)
        d = complex(float(vector @ ex), float(vector @ ey))
        if not abs(d) > 1e-12 * np.linalg.norm(vector):
            raise InvalidSourceError("direction is normal to the surface at the start: give a tangent vector")
        return d

    def vertex_start(self, v, vector):
        """``(face, d)`` leaving vertex ``v`` along 3D ``vector``, or None where it points off the surface."""
        fan = self.mesh.fan(v)
        if fan is None:
            raise InvalidSourceError(f"start: vertex {int(self.mesh.input_vertex[v])} is non-manifold (its faces do "
                                     "not form one fan): start from a point inside a face there")
        faces, first, second, angles, closed = fan
        P = self.mesh.positions
        normal = sum(a * _unit(np.cross(P[f] - P[v], P[s] - P[v])) for f, a, s in zip(first, angles, second))
        normal = _unit(normal)
        ends = first + ([] if closed else [second[-1]])
        q = [P[w] - P[v] for w in ends] + [vector]
        q = [x - (x @ normal) * normal for x in q]
        if not np.linalg.norm(q[-1]) > 1e-12 * np.linalg.norm(vector):
            raise InvalidSourceError("direction is normal to the surface at the start: give a tangent vector")
        ex = _unit(q[0])
        ey = np.cross(normal, ex)
        alpha = np.array([np.arctan2(x @ ey, x @ ex) for x in q])
        steps = np.angle(np.exp(1j * np.diff(alpha[:-1])))
        sign = 1.0 if steps.sum() >= 0 else -1.0
        edges = np.r_[0.0, np.cumsum(sign * steps)]  # projected angle of each fan edge
        if closed:
            edges = np.r_[edges, 2.0 * np.pi]
        target = (sign * alpha[-1]) % (2.0 * np.pi)
        k = int(np.searchsorted(edges, target, side="right")) - 1
        if k >= len(faces):
            return None  # between the last and the first boundary edge: off the surface
        width = edges[k + 1] - edges[k]
        fraction = (target - edges[k]) / width if width > 0 else 0.0
        starts = np.r_[0.0, np.cumsum(angles)]
        return self.fan_direction(v, fan, starts[k] + angles[k] * min(max(fraction, 0.0), 1.0))

    # ---------------------------------------------------------------- walk

    def run(self, face, z, d, corner, remaining):
        """Walk from ``z`` (in ``face``'s layout, at its ``corner`` or -1) along unit ``d`` for ``remaining``."""
        entry = -1
        for _ in range(MAX_STEPS):
            s, j = self.exit(face, z, d, corner, entry)
            if j < 0 or s >= remaining:
                s = remaining if j >= 0 else 0.0  # no edge ahead: a degenerate face, taken as the boundary
                z = z + s * d
                self.faces.append(face)
                self.travelled += s
                bary = self.bary(face, z)
                self.points.append(bary @ self.mesh.positions[self.mesh.faces[face]])
                return self.result((face, bary), "length" if j >= 0 else "boundary")
            a, b = self.local[face, j], self.local[face, (j + 1) % 3]
            u = min(max(((z + s * d - a) * np.conj(b - a)).real / abs(b - a) ** 2, 0.0), 1.0)
            self.faces.append(face)
            self.travelled += s
            remaining -= s
            if u < VERTEX_SNAP or u > 1.0 - VERTEX_SNAP:
                c = j if u < VERTEX_SNAP else (j + 1) % 3
                v = int(self.mesh.faces[face, c])
                self.points.append(self.mesh.positions[v])
                found = self.through_vertex(face, c, d)
                if found is None:
                    return self.result((face, np.eye(3)[c]), "boundary")
                face, d = found
                corner = int(np.flatnonzero(self.mesh.faces[face] == v)[0])
                z, entry = self.local[face, corner], -1
                continue
            bary = np.zeros(3)
            bary[j], bary[(j + 1) % 3] = 1.0 - u, u
            self.points.append(bary @ self.mesh.positions[self.mesh.faces[face]])
            g = int(self.mesh.neighbor[face, j])
            if g < 0:
                return self.result((face, bary), "boundary")
            face, z, d, entry = self.across(face, j, u, d)
            corner = -1
        raise SolverError(f"tracing gave up after {MAX_STEPS} faces (a degenerate mesh?)")

    def exit(self, face, z, d, corner, entry):
        """``(s, j)``: the walk leaves ``face`` after ``s`` through edge ``j`` (-1: no edge ahead)."""
        best, best_j = np.inf, -1
        for j in range(3):
            if j == entry or (corner >= 0 and j != (corner + 1) % 3):
                continue
            a, b = self.local[face, j], self.local[face, (j + 1) % 3]
            outward = -cross(b - a, d)
            if outward > 0.0:
                s = max(cross(b - a, z - a) / outward, 0.0)
                if s < best:
                    best, best_j = s, j
        return best, best_j

    def across(self, face, j, u, d):
        """The point at ``u`` on edge ``j`` of ``face`` and direction ``d`` in the neighbour's layout."""
        g, k = int(self.mesh.neighbor[face, j]), int(self.mesh.neighbor_edge[face, j])
        same = self.mesh.faces[g, k] == self.mesh.faces[face, j]
        t = u if same else 1.0 - u
        z = self.local[g, k] + t * (self.local[g, (k + 1) % 3] - self.local[g, k])
        d = d / self.rotation[face, j]
        if self.mirror[face, j]:
            d = np.conj(d)
        return g, z, d / abs(d), k

    def through_vertex(self, face, c, d):
        """``(face, d)`` leaving the vertex at corner ``c`` of ``face`` with half its total angle on either side.

        None at a boundary or non-manifold vertex (the walk stops there).
        """
        v = int(self.mesh.faces[face, c])
        fan = self.mesh.fan(v)
        if fan is None or not fan[4]:
            return None
        faces, first, _, angles, _ = fan
        k = faces.index(face)
        corner_first = int(np.flatnonzero(self.mesh.faces[face] == first[k])[0])
        w = self.local[face, corner_first] - self.local[face, c]
        back = abs(np.angle(-d / w))  # the way back, from the fan edge (v, first[k])
        starts = np.r_[0.0, np.cumsum(angles)]
        total = starts[-1]
        return self.fan_direction(v, fan, (starts[k] + min(back, angles[k]) + 0.5 * total) % total)

    def fan_direction(self, v, fan, gamma):
        """``(face, d)``: the direction at angle ``gamma`` around vertex ``v``'s fan, from its first edge."""
        faces, first, second, angles, _ = fan
        starts = np.cumsum(angles)
        k = min(int(np.searchsorted(starts, gamma, side="right")), len(faces) - 1)
        face = faces[k]
        corners = self.mesh.faces[face].tolist()
        z = self.local[face]
        w1, w2 = z[corners.index(first[k])] - z[corners.index(v)], z[corners.index(second[k])] - z[corners.index(v)]
        turn = 1.0 if cross(w1, w2) >= 0 else -1.0
        offset = gamma - (starts[k] - angles[k])
        return face, w1 / abs(w1) * np.exp(1j * turn * offset)

    # ---------------------------------------------------------------- result

    def bary(self, face, z):
        """Barycentric coordinates of layout point ``z`` in ``face`` (clipped onto the face)."""
        c0, c1, c2 = self.local[face]
        total = cross(c1 - c0, c2 - c0)
        bary = np.array([cross(c1 - z, c2 - z), cross(c2 - z, c0 - z), cross(c0 - z, c1 - z)]) / total
        bary = np.maximum(bary, 0.0)
        return bary / bary.sum()

    def result(self, end, stopped):
        """The :class:`TracedPath` walked so far, ending at surface point ``end`` (a SurfacePoint or (row, bary))."""
        if not isinstance(end, tuple):
            end = (end.face, self.mesh.bary_in(end.face, end))
        row, bary = end
        return TracedPath(points=np.array(self.points, dtype=float).reshape(-1, 3),
                          faces=self.mesh.face_ids[np.asarray(self.faces, dtype=np.int64)],
                          end=(int(self.mesh.face_ids[row]), np.asarray(bary, dtype=float)),
                          length=float(self.travelled), stopped=stopped)


def _unit(x):
    """``x`` scaled to length 1 (unchanged if 0)."""
    n = np.linalg.norm(x)
    return x / n if n > 0 else x
