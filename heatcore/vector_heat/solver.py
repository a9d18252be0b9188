"""``VectorHeatSolver``: parallel transport and the logarithmic map by the vector heat method.

The vector heat method (Sharp, Soliman and Crane, "The Vector Heat Method",
ACM TOG 2019) diffuses tangent vectors for a short time with the
connection Laplacian ``L∇`` (:mod:`heatcore.vector_heat.connection`):
``(M + t L∇) Y = Y0``. The direction of ``Y`` is the parallel transport of
the source vectors along shortest geodesics; magnitudes come from two scalar
heat flows, ``(M + t L) u = |Y0|`` and ``(M + t L) φ = δ``, as ``u / φ``. Every
operator lives on the domain's intrinsic Delaunay triangulation (of the
refined mesh, as the scalar heat method uses it), so the scalar heat flows
are the ones :class:`~heatcore.HeatSolver` factors, and its distance gives
the log map's radius (:mod:`heatcore.vector_heat.logmap`).

Examples
--------
>>> import numpy as np, heatcore as hc
>>> V, F = hc.io.load_demo_mesh()
>>> solver = VectorHeatSolver(hc.TriangleMesh(V, F))
>>> X = solver.transport(0, [1.0, 0.0, 0.0])   # a tangent vector per vertex, in 3D
>>> X.shape, bool(np.allclose(np.linalg.norm(X, axis=1)[1:], np.linalg.norm(X[0])))
((2930, 3), True)
"""

import functools
import time
from typing import NamedTuple

import numpy as np
import scipy.sparse as sp

from ..domains.triangle import TriangleMesh
from ..errors import InvalidSourceError, UnsupportedDomainError
from ..heat import HeatSolver
from ..high_accuracy import resolve_accuracy
from ..linalg import factor, solve_columns
from ..linalg.hermitian import factor_hermitian
from ..settings import SolverSettings
from ..steps.factors import heat_matrix
from ..steps.time_step import vertex_time_steps
from .basis import tangent_frames
from .connection import connection_laplacian, translation_matrix
from .frames import vertex_frames
from .logmap import flow_angle, log_coordinates, point_offsets, source_impulse
from .sources import reference_angle, single_source, tangent_sources

#: Whose defaults fill the options not given (``heatcore.options``: the log map's radius is the eikonal pass's
#: distance by default: a decal is placed once, and its radii are 0.08% off on an icosphere where the smooth
#: distance's are 0.5%).
FRONT_END = "vector heat"


class TangentBasis(NamedTuple):
    """Each input vertex's unit normal and tangent directions, (n, 3) each (zero rows: vertices no face uses).

    Coordinates ``(x, y)`` at a vertex are the 3D vector ``x e1 + y e2``;
    ``e2 = normal x e1``.

    Examples
    --------
    >>> import numpy as np, heatcore as hc
    >>> basis = VectorHeatSolver(hc.TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0)).tangent_basis()
    >>> bool(np.allclose(np.cross(basis.normal, basis.e1), basis.e2))
    True
    """

    normal: np.ndarray
    e1: np.ndarray
    e2: np.ndarray


class VectorHeatSolver:
    """Prefactored vector heat method on a triangle mesh: transport, log map, tangent basis.

    Parameters
    ----------
    domain : TriangleMesh
        Its intrinsic Delaunay triangulation (refined as the domain was
        built: ``refine="auto"`` by default) carries every operator.
    settings : SolverSettings or Settings, optional
        The solver options as a front end hands them over
        (:mod:`heatcore.settings`: ``Settings.of("vector heat", ...)``); the
        keywords below (checked once) change them. Without, the keywords
        build them with the vector heat method's defaults.
    m : float, default 1.0
        Time factor, ``t = m h^2`` as in :class:`~heatcore.HeatSolver`
        (the same ``t`` for the vector and the scalar heat flows).
    boundary, accuracy, backend
        As in :class:`~heatcore.HeatSolver`, for the distance that gives the
        log map's radius, but ``accuracy="high"`` by default: the eikonal
        pass (radii 5 to 15 times closer to exact geodesics; a log map takes
        0.05-0.5 s instead of 0.01-0.09 s on meshes of 3k-50k vertices;
        docs/vector-heat.md). ``accuracy="smooth"``: the heat method's. ``backend`` also
        factors the vector heat matrix (in its real form,
        :mod:`heatcore.linalg.hermitian`).

    Attributes
    ----------
    domain : TriangleMesh
    settings : SolverSettings
    accuracy : {"smooth", "high"}
        As resolved ("auto" is "smooth": the solver is kept for reuse).
    distance_solver : HeatSolver
        The scalar heat method on the same domain (radii, magnitudes).
    timings : dict
        Seconds spent in each precomputation stage.

    Raises
    ------
    UnsupportedDomainError
        ``domain`` is not a :class:`~heatcore.TriangleMesh` (point clouds,
        polygon and tet meshes have no vertex frames here yet).

    Examples
    --------
    >>> import numpy as np, heatcore as hc
    >>> V, F = hc.io.load_demo_mesh()
    >>> solver = VectorHeatSolver(hc.TriangleMesh(V, F))
    >>> uv = solver.log_map(0)               # (n, 2): geodesic polar coordinates around vertex 0
    >>> X2 = solver.transport(0, [0.0, 1.0, 0.0], basis=True)   # (n, 2), in each vertex's basis
    >>> normal, e1, e2 = solver.tangent_basis()
    >>> X3 = X2[:, :1] * e1 + X2[:, 1:] * e2                    # the same vectors in 3D
    >>> bool(np.allclose(X3, solver.transport(0, [0.0, 1.0, 0.0])))
    True
    """

    def __init__(self, domain, settings=None, **options):
        settings = SolverSettings(FRONT_END, **options) if settings is None else SolverSettings.of(settings, **options)
        if not isinstance(domain, TriangleMesh):
            raise UnsupportedDomainError(
                f"the vector heat method runs on triangle meshes (TriangleMesh), not on a {domain.domain_name}"
            )
        settings = resolve_accuracy(settings, domain)
        self.domain = domain
        self.settings = settings
        self.accuracy = settings.accuracy
        self.distance_solver = HeatSolver(domain, settings)
        self.timings = dict(self.distance_solver.timings)
        start = time.perf_counter()
        cache = domain.derived  # the frames and the vector heat factor are kept with the domain
        self._frames, self._connection, self._translation, self._basis = cache.get_or_build(
            ("vector frames", None), lambda: _frames_of(domain)
        )
        self.timings["vector frames"] = time.perf_counter() - start
        ops, hs = domain.operators, self.distance_solver
        # The distance's time step t = m h^2 (h of the refined mesh), and the Neumann heat M + t L for the
        # scalar flows: the distance solver's own (also half of its Robin heat), except on refined parts,
        # where its steps are 2t and 8t (domain.two_step_vertices()). With h of the mesh as given the
        # angles of the log map were 1.7-2.1 times further from exact geodesics on spot, cheburashka and
        # fandisk, though closer to the longitude on an icosphere (docs/vector-heat.md).
        self._step = vertex_time_steps(hs.part_m, hs.component, ops.mean_edge_length)

    @functools.cached_property
    def _flow(self):
        """The factor of the Neumann heat ``M + t L`` of the scalar flows (built on first use: the signed heat
        method never needs it): the distance solver's own where no part is refined, else one of its own."""
        hs, ops = self.distance_solver, self.domain.operators
        if self.domain.two_step_vertices() is None:
            return hs.heat_flow.neumann
        return self.domain.derived.get_or_build(
            ("vector scalar heat", (hs.m, self.settings.backend)),
            lambda: factor(heat_matrix(ops.mass, self._step, ops.laplacian.tocsr()), hs.factors.heat_backend),
        )

    @property
    def frames(self):
        """The :class:`~heatcore.vector_heat.frames.VertexFrames` of the domain's intrinsic triangulation."""
        return self._frames

    @property
    def operator_basis(self):
        """:class:`TangentBasis` of every operator vertex (the refined mesh's), in the operators' length unit."""
        return TangentBasis(*self._basis)

    def flow_factor(self, time_scale=1.0):
        """The factor of the vector heat flow ``M + s t L∇`` for a time ``s t`` (kept in the domain's cache).

        ``time_scale`` ``s`` scales the time ``t = m h^2`` of each connected part
        whose ``m`` is the solver's; a part whose ``m`` was raised against
        underflow (``HeatSolver.part_m``) keeps its time. Built at first use
        (``timings["vector heat factorization"]``), then found in the cache.

        Returns
        -------
        Factor
            ``solve(rhs)`` gives the flow of ``(n,)`` or ``(n, k)`` complex
            right-hand sides in the operator vertices' frames.
        """
        hs, ops = self.distance_solver, self.domain.operators
        part_m = np.where(hs.part_m > hs.m, hs.part_m, time_scale * hs.m)
        step = vertex_time_steps(part_m, hs.component, ops.mean_edge_length)
        key = (hs.m, self.settings.backend) if time_scale == 1.0 else (hs.m, self.settings.backend, float(time_scale))

        def build():
            start = time.perf_counter()
            factor = factor_hermitian((sp.diags(ops.mass.astype(complex)) + sp.diags(step) @ self._connection).tocsr(),
                                      self.settings.backend)
            self.timings["vector heat factorization"] = time.perf_counter() - start
            return factor

        return self.domain.derived.get_or_build(("vector heat", key), build)

    def diffuse(self, rhs, time_scale=1.0):
        """The vector heat flow ``(M + s t L∇)^-1 rhs``: complex coordinates in the operator vertices' frames.

        ``rhs`` is ``(n,)`` or ``(n, k)`` complex, ``n`` the operator vertices;
        ``time_scale`` ``s`` as in :meth:`flow_factor`.
        """
        return self.flow_factor(time_scale).solve(rhs)

    def tangent_basis(self):
        """Each input vertex's :class:`TangentBasis` ``(normal, e1, e2)``: the frame of 2D coordinates.

        Returns
        -------
        TangentBasis
            Three (n, 3) arrays; rows of zeros at vertices no face uses.
        """
        return TangentBasis(*(self._on_input(b) for b in self._basis))

    def sources(self, source=None, *, points=None):
        """The :class:`~heatcore.vector_heat.sources.TangentSource` of each source vertex and point."""
        return tangent_sources(self.domain, self._basis, source, points)

    def transport(self, source=None, vector=None, *, points=None, basis=False):
        """Parallel transport of tangent vectors from their sources to every vertex.

        Parameters
        ----------
        source : int or sequence of int, optional
            Source vertices.
        vector : (3,) or (k, 3) array_like
            The vector at each source (vertices first, then points), in 3D;
            its part normal to the surface is dropped.
        points : (face_indices, barycentric) pair, optional
            Sources on faces.
        basis : bool, default False
            Return 2D coordinates in each vertex's :meth:`tangent_basis`
            instead of 3D vectors.

        Returns
        -------
        (n, 3) or (n, 2) float array
            The transported vector at each input vertex: the direction of
            the vector heat flow, the length of the source vector (with
            several sources, their lengths interpolated by ``u / φ``). Zero
            at vertices no source reaches (another connected component, a
            vertex no face uses).

        Raises
        ------
        InvalidSourceError
            A bad source, a vector count that does not match the sources, or
            a vector with no tangent part (zero, or normal to the surface).
        """
        found = self.sources(source, points=points)
        vectors = np.asarray(vector, dtype=float) if vector is not None else None
        if vectors is None or vectors.shape not in ((3,), (len(found), 3)):
            shape = None if vectors is None else vectors.shape
            raise InvalidSourceError(f"give one 3D vector per source: {len(found)} sources, vectors of shape {shape}")
        vectors = vectors.reshape(len(found), 3)
        n = self.domain.operators.n_vertices
        rhs = np.zeros(n, dtype=complex)
        heat = np.zeros((n, 2))
        lengths = []
        for s, v in zip(found, vectors):
            z = s.coordinates(v, f"vector at {s.label}")
            rhs += source_impulse(self._basis, s, z.real * s.e1 + z.imag * s.e2, n)
            np.add.at(heat, (s.vertices, 0), s.weights * abs(z))
            np.add.at(heat, (s.vertices, 1), s.weights)
            lengths.append(abs(z))
        Y = self.flow_factor().solve(rhs)
        if len(found) == 1:
            length = np.full(n, lengths[0])
        else:
            u = solve_columns(self._flow, heat)
            with np.errstate(divide="ignore", invalid="ignore"):
                length = u[:, 0] / u[:, 1]
        size = np.abs(Y)
        reached = self._reached(found) & (size > 0) & np.isfinite(length)
        X = np.zeros(n, dtype=complex)
        X[reached] = Y[reached] / size[reached] * length[reached]
        if basis:
            return self._on_input(np.column_stack([X.real, X.imag]))
        _, e1, e2 = self._basis
        return self._on_input(X.real[:, None] * e1 + X.imag[:, None] * e2)

    def log_map(self, source=None, *, points=None, reference=None):
        """The logarithmic map from one source: geodesic polar coordinates as ``(n, 2)`` points of its tangent plane.

        Parameters
        ----------
        source : int, optional
            The source vertex.
        points : (face_indices, barycentric) pair, optional
            Or one point on a face.
        reference : (3,) array_like, optional
            A direction at the source (3D, projected on its tangent plane)
            that becomes the +x axis. Default: ``e1`` of the source vertex's
            :meth:`tangent_basis`, or a face's first side (corner 0 to 1).

        Returns
        -------
        (n, 2) float array
            For each input vertex ``y``: ``r (cos θ, sin θ)`` with ``r`` the
            geodesic distance (the solver's ``accuracy``) and ``θ`` the angle
            at the source of the geodesic towards ``y``. ``(inf, inf)`` where
            no geodesic arrives (another connected component, a vertex no
            face uses).

        Raises
        ------
        InvalidSourceError
            No source, several, or a bad one.
        InvalidOptionError
            A reference direction that is zero or normal to the surface at the source.
        """
        found = single_source(self.domain, self._basis, source, points)
        turn = reference_angle(found, reference)
        n = self.domain.operators.n_vertices
        impulse = np.zeros(n)
        np.add.at(impulse, found.vertices, found.weights)
        u = solve_columns(self._flow, impulse)
        affine = point_offsets(self.domain.subdivision.vertices, self._basis, found, n) - self._step * (self._translation @ u)
        flows = self.flow_factor().solve(np.column_stack([source_impulse(self._basis, found, found.e1, n), affine]))
        angle = flow_angle(flows[:, 1], flows[:, 0]) - turn
        if source is None:
            distance = self.distance_solver.distance(points=points)
        else:
            distance = self.distance_solver.distance(np.atleast_1d(source))
        return log_coordinates(distance, self._on_input(angle))

    def _reached(self, found):
        """Operator vertices in a connected component holding one of the sources."""
        hs = self.distance_solver
        if hs.n_components == 1:
            return np.ones(hs.component.size, dtype=bool)
        return np.isin(hs.component, hs.component[np.concatenate([s.vertices for s in found])])

    def _on_input(self, values):
        """Rows of operator vertices read at the input vertices; zeros where no face uses one."""
        index = self.domain.output_vertices
        out = np.zeros((index.size,) + values.shape[1:], dtype=values.dtype)
        out[index >= 0] = values[index[index >= 0]]
        return out


def _frames_of(domain):
    """What the vector heat method derives from ``domain`` once: vertex frames, the connection Laplacian, the
    translation matrix and the input vertices' tangent basis."""
    tri, sub = domain.intrinsic, domain.subdivision
    frames = vertex_frames(tri, domain.operators.n_vertices)
    basis = tangent_frames(sub.vertices, sub.faces, tri, frames)
    return frames, connection_laplacian(tri, frames), translation_matrix(tri, frames), basis
