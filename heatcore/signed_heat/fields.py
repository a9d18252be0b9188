"""Where the signed heat method's vectors live: per domain, its points, its flow and its divergence.

The solver (:mod:`heatcore.signed_heat.solver`) asks a field for four things:
the curve points as the operators see them (``nodes``), the operator
vertices' tangent basis (``operator_basis``), the vector heat flow
(``diffuse``, for a share of the heat method's time) and the divergence of
the normalized flow (``divergence``); and the ``surface`` and
``poisson_solver`` the operators and the Poisson factor come from.

- :class:`MeshField`: a triangle mesh, through the vector heat method's own
  frames and factor (:class:`~heatcore.vector_heat.VectorHeatSolver`) on its
  ``surface``, the refined mesh on curved triangles
  (:mod:`~heatcore.signed_heat.surface`); the flow is read on the intrinsic
  triangles (:mod:`~heatcore.signed_heat.face_field`) and the divergence is
  the heat method's, ``G^T (volumes * X)``.
- :class:`CloudField`: a point cloud, with tangent planes from its oriented
  normals and the connection Laplacian of its Laplacian's weights (each edge
  turning a vector by the least rotation between the two normals); the flow
  is read on the Laplacian's own (intrinsic) triangles as on a mesh: the mean
  of the three corners' 3D vectors, laid out on the triangle as the gradient
  operator lays it out, scaled to length 1, and the divergence is the heat
  method's ``G^T (volumes * X)``.

Examples
--------
>>> import numpy as np, heatcore as hc
>>> field = MeshField(hc.TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0), hc.SolverSettings("api"))
>>> field.divergence(np.zeros(3, dtype=complex)).tolist()
[0.0, 0.0, 0.0]
"""

import numpy as np
import scipy.sparse as sp

from ..errors import InvalidSourceError
from ..heat import HeatSolver
from ..linalg.hermitian import factor_hermitian
from ..steps.time_step import vertex_time_steps
from ..vector_heat.solver import TangentBasis, VectorHeatSolver
from ..vector_heat.sources import tangent_sources
from .curves import CurveNodes, curve_nodes
from .face_field import unit_face_field
from .surface import curved_refinement

#: Where a signed curve is open (its ends are not one point), the vector flow runs for this share of the
#: heat method's time ``t = m h^2``; closed curves flow for ``t``. Near an open curve's ends the field is
#: a blend of the normals around, as wide as the flow spreads (``sqrt t``): a broken curve's error grows
#: with the time, a closed curve's shrinks. Measured (docs/signed.md): the disc's circle broken in four,
#: 0.227% of its radius at ``t`` and 0.185% at ``t/2`` (potpourri3d 0.197%); 11 broken circles on other
#: discs and icospheres (seeds, radii, gaps), 5 further than potpourri3d at ``t``, none at ``t/2``; the
#: closed circles would lose at ``t/2``: 0.017% -> 0.021% (the disc's), 0.022% -> 0.033% (an icosphere's).
OPEN_CURVE_TIME = 0.5


class MeshField:
    """The signed heat method's vectors on a :class:`~heatcore.TriangleMesh` (see the module).

    Examples
    --------
    >>> import numpy as np, heatcore as hc
    >>> from heatcore.signed_heat.curves import parse_curve
    >>> field = MeshField(hc.TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0), hc.SolverSettings("api"))
    >>> field.nodes([parse_curve([0, 1])]).curve.tolist()
    [0, 0]
    """

    def __init__(self, domain, settings):
        self.domain = domain
        self.surface = curved_refinement(domain)
        if self.surface.operators.n_vertices != domain.operators.n_vertices:  # parts dropped: not the same vertices
            self.surface = domain
        self.vector_solver = VectorHeatSolver(self.surface, settings)
        self.poisson_solver = self.vector_solver.distance_solver
        self.operator_basis = self.vector_solver.operator_basis
        self.positions = self.surface.subdivision.vertices
        self._settings = settings
        self._distance_solver = self.poisson_solver if self.surface is domain else None
        self.vector_solver.flow_factor()  # closed curves' flow, prefactored; open curves' at first use
        self.timings = dict(self.vector_solver.timings)

    @property
    def distance_solver(self):
        """The heat method on the domain as given (for unsigned sources), built at first use where it is not
        the Poisson solver's."""
        if self._distance_solver is None:
            self._distance_solver = HeatSolver(self.domain, self._settings)
        return self._distance_solver

    def nodes(self, parsed):
        """:class:`~heatcore.signed_heat.curves.CurveNodes` of the curves, with the refined vertices on each
        segment along a mesh edge as points of their own (in order).

        Without them a square loop of edges on a 21 x 21 grid (refined) was 2.3% of the grid's half-width from
        the signed distance to the square instead of 0.76% (the refined vertices between two points were neither
        sources nor on the zero set); points inside faces gained nothing from points between them (the errors
        of docs/signed.md the same to 0.001 points).
        """
        nodes = curve_nodes(parsed, lambda v, p: tangent_sources(self.domain, self.operator_basis, v, p))
        if self.surface is not self.domain:  # the same carriers, on the curved refinement
            nodes = _on_surface(nodes, self.positions, self.operator_basis.normal)
        if self.domain.levels == 0:
            return nodes
        kinds = np.concatenate([c.kinds for c in parsed])
        vertices = np.concatenate([c.vertices for c in parsed])
        j = np.flatnonzero((nodes.curve[1:] == nodes.curve[:-1]) & kinds[1:] & kinds[:-1])
        inner = edge_interior_vertices(self.domain, vertices[j], vertices[j + 1])
        if not any(v.size for v in inner):
            return nodes
        return _inserted(nodes, j, inner, self.positions, self.operator_basis.normal)

    def diffuse(self, rhs, time_scale=1.0):
        """The vector heat flow of ``rhs`` for ``time_scale`` times the heat method's time."""
        return self.vector_solver.diffuse(rhs, time_scale)

    def divergence(self, Y):
        """``G^T (volumes * X)`` of the unit field ``X`` read from the vertex vectors ``Y`` on the triangles."""
        ops = self.surface.operators
        X = unit_face_field(self.surface.intrinsic, self.vector_solver.frames, Y)
        return ops.gradient.T @ (ops.volumes[:, None] * X).ravel()


class CloudField:
    """The signed heat method's vectors on a :class:`~heatcore.PointCloud` (see the module).

    Curve points are point indices (a cloud has no faces).

    Examples
    --------
    >>> import numpy as np, heatcore as hc
    >>> P = np.column_stack([np.random.default_rng(0).random((300, 2)), np.zeros(300)])
    >>> field = CloudField(hc.PointCloud(P, refine=0), hc.SolverSettings("api"))
    >>> bool(np.allclose(field.operator_basis.normal[:, 2], 1.0))
    True
    """

    def __init__(self, domain, settings):
        self.domain = domain
        self.surface = domain
        self.distance_solver = self.poisson_solver = HeatSolver(domain, settings)
        self.timings = dict(self.distance_solver.timings)
        self.positions = domain.operator_positions
        frames = domain.derived.get_or_build(("cloud connection", None), lambda: _cloud_connection(domain))
        self.operator_basis, self._connection = frames
        self._backend = settings.backend
        self.flow_factor()  # closed curves' flow, prefactored

    def flow_factor(self, time_scale=1.0):
        """The factor of ``M + s t L∇`` (as :meth:`heatcore.VectorHeatSolver.flow_factor`), kept with the domain."""
        ops, hs = self.domain.operators, self.distance_solver
        part_m = np.where(hs.part_m > hs.m, hs.part_m, time_scale * hs.m)
        step = vertex_time_steps(part_m, hs.component, ops.mean_edge_length)
        return self.domain.derived.get_or_build(
            ("signed vector heat", (hs.m, self._backend, float(time_scale))),
            lambda: factor_hermitian((sp.diags(ops.mass.astype(complex)) + sp.diags(step) @ self._connection).tocsr(),
                                     self._backend),
        )

    def nodes(self, parsed):
        """:class:`~heatcore.signed_heat.curves.CurveNodes` of curves of point indices."""
        carriers, owner = [], []
        for c, curve in enumerate(parsed):
            if not curve.kinds.all():
                raise InvalidSourceError("a curve on a point cloud is a sequence of point indices (it has no faces)")
            carriers += [(np.array([o]), np.ones(1)) for o in self._operator_points(curve.vertices).tolist()]
            owner += [c] * curve.n_nodes
        vertices = np.array([v[0] for v, _ in carriers])
        return CurveNodes(carriers, self.positions[vertices], self.operator_basis.normal[vertices],
                          np.array(owner, dtype=np.int64))

    def diffuse(self, rhs, time_scale=1.0):
        """The vector heat flow of ``rhs`` for ``time_scale`` times the heat method's time."""
        return self.flow_factor(time_scale).solve(rhs)

    def divergence(self, Y):
        """``G^T (volumes * X)`` of the unit field ``X`` read from the vertex vectors ``Y`` on the triangles.

        Each triangle's vector is the mean of its corners' 3D vectors, laid out
        on the triangle by the gradient of the corners' positions (the layout
        vector whose dot product with each side is the 3D vector's with that
        side's chord), then scaled to length 1 (zero where it vanishes).

        Measured on a Fibonacci sphere of 3000 points with points on its equator
        (tests/test_signed_heat.py): 0.029% from the signed distance, where the
        divergence of the vertex vectors along the Laplacian's edges,
        ``-Σ_j w_ij (X_i + X_j)/2 . (p_j - p_i)``, normalized at the vertices, gave
        0.058% (potpourri3d's: 0.035%); a disc of rings 0.024% instead of 0.027%.
        """
        _, e1, e2 = self.operator_basis
        ops = self.domain.operators
        corners = ops.elements
        mean = (Y.real[:, None] * e1 + Y.imag[:, None] * e2)[corners].mean(axis=1)
        layout = (ops.gradient @ self.positions).reshape(corners.shape[0], 2, 3)
        X = np.einsum("fij,fj->fi", layout, mean)
        size = np.linalg.norm(X, axis=1)
        X = np.where(size[:, None] > 1e-300, X / np.maximum(size, 1e-300)[:, None], 0.0)
        return ops.gradient.T @ (ops.volumes[:, None] * X).ravel()

    def _operator_points(self, points):
        from ..domains.sources import index_list

        points = index_list(points, self.domain.n_input_vertices, "point")
        op = self.domain.output_vertices[points]
        if (op < 0).any():
            raise InvalidSourceError(f"point {int(points[op < 0][0])} is isolated (in no triangle): it cannot be on a curve")
        return op


def edge_interior_vertices(domain, a, b):
    """The refined vertices strictly inside each input edge ``a[i] - b[i]``, in order from ``a[i]`` (list of arrays).

    Empty where the pair is no edge of the mesh, or the mesh is not refined.

    Examples
    --------
    >>> import heatcore as hc
    >>> mesh = hc.TriangleMesh(np.eye(3), [[0, 1, 2]], refine=2)
    >>> X = mesh.subdivision.vertices
    >>> [np.round(X[v], 2).tolist() for v in edge_interior_vertices(mesh, np.array([0]), np.array([1]))[0]]
    [[0.75, 0.25, 0.0], [0.5, 0.5, 0.0], [0.25, 0.75, 0.0]]
    """
    sub = domain.subdivision
    oa, ob = domain.output_vertices[a], domain.output_vertices[b]
    n = sub.vertices.shape[0]
    keys = sub.edges[:, 0] * n + sub.edges[:, 1]
    query = np.minimum(oa, ob) * n + np.maximum(oa, ob)
    pos = np.clip(np.searchsorted(keys, query), 0, max(keys.size - 1, 0))
    found = (keys.size > 0) & (keys[pos] == query) & (oa >= 0) & (ob >= 0)
    on = np.flatnonzero(sub.vertex_edge >= 0)
    ends = sub.edges[sub.vertex_edge[on]]
    X = sub.vertices
    t = np.einsum("ij,ij->i", X[on] - X[ends[:, 0]], X[ends[:, 1]] - X[ends[:, 0]])
    order = np.lexsort((t, sub.vertex_edge[on]))
    on, grouped = on[order], sub.vertex_edge[on][order]
    out = []
    for i in range(len(a)):
        if not found[i]:
            out.append(np.zeros(0, dtype=np.int64))
            continue
        lo, hi = np.searchsorted(grouped, pos[i]), np.searchsorted(grouped, pos[i], side="right")
        run = on[lo:hi]
        out.append(run if oa[i] == sub.edges[pos[i], 0] else run[::-1])
    return out


def _on_surface(nodes, positions, normals):
    """``nodes`` with each point's position and normal the hat-weighted ones of its carriers."""
    X = np.array([w @ positions[v] for v, w in nodes.carriers]).reshape(-1, 3)
    N = np.array([w @ normals[v] for v, w in nodes.carriers]).reshape(-1, 3)
    N /= np.maximum(np.linalg.norm(N, axis=1), 1e-300)[:, None]
    return nodes._replace(positions=X, normals=N)


def _inserted(nodes, after, inner, positions, normals):
    """``nodes`` with the vertices ``inner[k]`` (one carrier each) inserted after node ``after[k]``."""
    carriers, X, N, curve = [], [], [], []
    extra = dict(zip(after.tolist(), inner))
    for i, carrier in enumerate(nodes.carriers):
        carriers.append(carrier)
        X.append(nodes.positions[i:i + 1])
        N.append(nodes.normals[i:i + 1])
        curve.append(nodes.curve[i:i + 1])
        more = extra.get(i)
        if more is not None and more.size:
            carriers += [(np.array([v]), np.ones(1)) for v in more.tolist()]
            X.append(positions[more])
            N.append(normals[more])
            curve.append(np.full(more.size, nodes.curve[i]))
    return CurveNodes(carriers, np.concatenate(X), np.concatenate(N), np.concatenate(curve))


def tangent_frames(normals):
    """``(e1, e2)``: unit tangents of each unit normal, ``e2 = normal x e1``, ``e1`` away from the normal's main axis.

    Examples
    --------
    >>> e1, e2 = tangent_frames(np.array([[0.0, 0.0, 1.0]]))
    >>> e1.tolist(), e2.tolist()
    ([[0.0, 1.0, 0.0]], [[-1.0, 0.0, 0.0]])
    """
    least = np.eye(3)[np.argmin(np.abs(normals), axis=1)]
    e1 = np.cross(normals, least)
    e1 /= np.linalg.norm(e1, axis=1)[:, None]
    return e1, np.cross(normals, e1)


def cloud_connection_laplacian(L, normals, e1, e2):
    """The Hermitian connection Laplacian with the weights of ``L`` and the least rotation between normals.

    A vector at ``i`` goes to ``j`` by the rotation that takes ``n_i`` to ``n_j``
    about their common perpendicular; as coordinates it turns by ``ρ_ij``, the
    angle of the carried ``e1_i`` in ``j``'s frame (Hermitian as in
    :func:`heatcore.vector_heat.connection.connection_laplacian`).

    Examples
    --------
    >>> L = sp.csr_matrix(np.array([[1.0, -1.0], [-1.0, 1.0]]))
    >>> n = np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 1.0]])
    >>> C = cloud_connection_laplacian(L, n, *tangent_frames(n))
    >>> np.real_if_close(C.toarray()).tolist()
    [[1.0, -1.0], [-1.0, 1.0]]
    """
    L = sp.coo_matrix(L)
    upper = L.row < L.col
    i, j, w = L.row[upper], L.col[upper], -L.data[upper]
    ni, nj, v = normals[i], normals[j], e1[i]
    c = np.maximum(1.0 + np.einsum("ij,ij->i", ni, nj), 1e-12)  # opposite normals: no least rotation; kept finite
    carried = v - (np.einsum("ij,ij->i", v, nj) / c)[:, None] * (ni + nj)
    rotation = np.exp(1j * np.arctan2(np.einsum("ij,ij->i", carried, e2[j]), np.einsum("ij,ij->i", carried, e1[j])))
    n = L.shape[0]
    rows = np.concatenate([i, j, j, i])
    cols = np.concatenate([i, j, i, j])
    data = np.concatenate([w, w, -w * rotation, -w * rotation.conj()]).astype(np.complex128)
    return sp.csr_matrix((data, (rows, cols)), shape=(n, n))


def _cloud_connection(domain):
    normals = domain.oriented_normals()
    e1, e2 = tangent_frames(normals)
    return TangentBasis(normals, e1, e2), cloud_connection_laplacian(domain.operators.laplacian, normals, e1, e2)
