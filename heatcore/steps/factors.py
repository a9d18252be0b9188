"""The factorizations of one heat solver: the heat matrix and the grounded Laplacian.

:class:`SolverFactors` resolves the ``backend`` option once, for the solver's
intent (:data:`heatcore.settings.INTENTS`: a solver kept for many queries, or
asked one), factors the heat matrix ``M + t L`` of the solver's time step and
boundary condition (:class:`~heatcore.steps.heat_flow.HeatFlow`, step 1; twice on surfaces,
for the short and the long step of :mod:`heatcore.steps.time_step`) and the grounded Laplacian
(:class:`~heatcore.steps.poisson.PinnedPoisson`, step 3). What depends on the domain
alone (fill-reducing orderings, METIS nested dissection started in the background
on large meshes, the Laplacian's factor) is kept in the domain's cache, keyed by the backend it was made for, and
shared by every solver on the domain.

A solver may build them at once (:meth:`SolverFactors.build`) or leave them
until a step first needs them (``accuracy="high"`` with numba needs none):
:meth:`~SolverFactors.heat_flow` and :meth:`~SolverFactors.poisson` build
what is missing.

Examples
--------
>>> import heatcore as hc
>>> solver = hc.HeatSolver(hc.TriangleMesh(*hc.io.load_demo_mesh()))
>>> factors = solver.factors
>>> factors.heat_backend in hc.linalg.available_backends(), factors.built
(True, True)
"""

import logging
import time
from concurrent.futures import Future
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..errors import SolverError
from ..linalg import (
    Ordering,
    StartedFactor,
    StartedOrdering,
    factor,
    fill_reducing_ordering,
    resolve_backend,
    restrict_ordering,
    start_factor,
    start_fill_reducing_ordering,
    start_nested_dissection,
)
from ..progress import Progress
from .boundary_source import BoundarySourceHeat
from .heat_flow import HeatFlow
from .poisson import PinnedPoisson, grounded

log = logging.getLogger("heatcore")

#: The intents whose solvers order the Laplacian by METIS nested dissection where it is large enough
#: (:func:`~heatcore.linalg.start_nested_dissection`): those kept for further queries (a click's solver answers
#: the next clicks and the probe's drags). Its factor is a third smaller and its queries 5-15% faster, but the
#: build waits for METIS, which takes longer than the heat matrix's factorization it runs beside (2 cores: 1.1 s
#: more at 504k vertices, 3.1 s at 1M, 7.8 s against 4.6 s): a single query never pays that back, and keeps
#: minimum degree.
NESTED_DISSECTION_FOR = ("reuse", "interactive")


@dataclass(frozen=True)
class HeatStep:
    """What the heat matrix depends on besides the domain: the solver's time step and boundary condition.

    Attributes
    ----------
    time_step : float or (n,) float array
        ``t`` of each operator vertex, in its part's unit (constant on each component).
    boundary : {"robin", "neumann", "dirichlet"}
    component : (n,) int array
        Connected component of each operator vertex.
    n_components : int
    ground : (n_components,) int array
        The vertex of each component held at 0 in the grounded Laplacian.
    multiples : tuple of float or (n,) float arrays
        The heat steps to factor, in multiples of ``time_step``: ``(1.0,)``, or the short and the long
        step of :mod:`heatcore.steps.time_step` where the distance reads both (a domain's refined parts,
        ``two_step_vertices()``; per vertex where only some parts are refined).

    Examples
    --------
    >>> step = HeatStep(0.5, "neumann", np.zeros(3, int), 1, np.array([0]))
    >>> step.time_step, step.n_components
    (0.5, 1)
    """

    time_step: object
    boundary: str
    component: np.ndarray
    n_components: int
    ground: np.ndarray
    multiples: tuple = (1.0,)


class SolverFactors:
    """The heat and Poisson factorizations of one solver, built once.

    Parameters
    ----------
    ops : Operators
        The domain's operator bundle.
    cache : mutable mapping
        The domain's cache of what is derived from it (orderings and the
        Laplacian's factor, shared by the domain's solvers).
    settings : SolverSettings
        ``backend`` and ``intent`` decide the backends.
    timings : dict
        Where the seconds of each factorization are recorded.

    Attributes
    ----------
    heat_backend, poisson_backend : str
        The backends the heat matrix and the Laplacian are factored with.
    built : bool
        Whether both factorizations are there.

    Examples
    --------
    >>> import heatcore as hc
    >>> solver = hc.HeatSolver(hc.TriangleMesh(*hc.io.load_demo_mesh()), accuracy="high")
    >>> solver.factors.built == (not hc.high_accuracy.high_accuracy_needs_heat())  # numba: deferred
    False
    >>> _ = solver.poisson  # a first use builds them
    >>> solver.factors.built
    True
    """

    def __init__(self, ops, cache, settings, timings):
        self.ops = ops
        self._cache = cache
        self._laplacian = ops.laplacian.tocsr()
        n = ops.n_vertices
        self.heat_backend = resolve_backend(settings.backend, n, intent=settings.intent, stage="factor")
        self.poisson_backend = resolve_backend(settings.backend, n, intent=settings.intent, stage="solve")
        self.timings = timings
        # Nested dissection pays back its wait for METIS over further queries only (NESTED_DISSECTION_FOR).
        self._nested = settings.intent in NESTED_DISSECTION_FOR
        self._heat_flow = self._long_flow = self._poisson = None
        self._deferred = None

    @property
    def built(self):
        """Whether the heat flow and the Poisson factor are built."""
        return self._heat_flow is not None and self._poisson is not None

    def start(self):
        """Start the orderings: minimum degree where it runs beside the caller (the solver's time step), and on
        large meshes, for a solver kept for further queries (:data:`NESTED_DISSECTION_FOR`), the Laplacian's nested
        dissection, which runs while the heat matrix is factored."""
        for backend in dict.fromkeys((self.heat_backend, self.poisson_backend)):
            if ("ordering", backend) not in self._cache:
                self._cache["ordering", backend] = start_fill_reducing_ordering(self._laplacian, backend)
        backend = self.poisson_backend
        if self._nested and ("poisson", backend) not in self._cache and ("nested", backend) not in self._cache:
            self._cache["nested", backend] = start_nested_dissection(self._laplacian, backend)

    def defer(self, heat, progress):
        """Build on first need (:meth:`heat_flow` or :meth:`poisson`), with these :meth:`build` arguments."""
        self._deferred = (heat, progress)

    def build(self, heat, progress):
        """Factor the heat matrix and the Laplacian (the latter taken from the domain's cache where it is there).

        Parameters
        ----------
        heat : HeatStep
            The time step, boundary condition and components of the solver.
        progress : Progress
        """
        self._deferred = None
        backend = self.poisson_backend
        poisson = None
        # Both matrices are assembled before anything waits for the orderings (which may still run, see start()).
        start = time.perf_counter()
        matrices = [heat_matrix(self.ops.mass, multiple * heat.time_step, self.ops.laplacian) for multiple in heat.multiples]
        self.timings["heat factorization"] = time.perf_counter() - start
        if ("poisson", backend) not in self._cache and not isinstance(self._cache.get(("nested", backend)), Future):
            # It runs beside the heat matrix's where the backend lets it (else it is made below, as it would be).
            start = time.perf_counter()
            K = grounded(self._laplacian, heat.ground)
            poisson = start_factor(K, backend, ordering=self._laplacian_ordering(backend))
            self.timings["poisson factorization"] = time.perf_counter() - start
        start = time.perf_counter()
        shares = np.linspace(0.05, 0.7, len(matrices) + 1)
        steps = ("", "long step")[: len(matrices)]  # the short step's messages are one step's
        # Every factorization but the last step's Neumann one is started beside the caller (CHOLMOD runs on one core).
        flows = [self._start_heat(heat, matrix, multiple * heat.time_step, step, progress.part(shares[i], shares[i + 1]),
                                  beside=i < len(matrices) - 1)
                 for i, (matrix, multiple, step) in enumerate(zip(matrices, heat.multiples, steps))]
        flows = [flow() for flow in flows]
        self._heat_flow, self._long_flow = flows[0], (flows[1] if len(flows) > 1 else None)
        self.timings["heat factorization"] += time.perf_counter() - start
        start = time.perf_counter()
        progress(0.7, "factoring the Poisson matrix")
        if ("poisson", backend) not in self._cache:
            if poisson is None:
                poisson = start_factor(grounded(self._laplacian, heat.ground), backend,
                                       ordering=self._laplacian_ordering(backend))
            self._cache["poisson", backend] = poisson.result()
        self._poisson = PinnedPoisson(self._laplacian, self._cache["poisson", backend], heat.ground, heat.component,
                                      heat.n_components, self.factor_free)
        self.timings["poisson factorization"] = self.timings.get("poisson factorization", 0.0) + (
            time.perf_counter() - start)
        for ordering in self._cache.values():
            if isinstance(ordering, Ordering):
                ordering.forget_pattern()  # its memory matters more than re-converting for another m

    def heat_flow(self):
        """Step 1, :class:`~heatcore.steps.heat_flow.HeatFlow` of the (first) step (built here where it was deferred)."""
        self._build_deferred()
        return self._heat_flow

    def long_flow(self):
        """Step 1, :class:`~heatcore.steps.heat_flow.HeatFlow` of the long step, or None (one step; built here where it
        was deferred)."""
        self._build_deferred()
        return self._long_flow

    def poisson(self):
        """Step 3, :class:`~heatcore.steps.poisson.PinnedPoisson` (built here where it was deferred)."""
        self._build_deferred()
        return self._poisson

    def _build_deferred(self):
        if self._deferred is not None:
            heat, progress = self._deferred
            self.start()
            self.build(heat, Progress(progress))

    def _start_heat(self, heat, matrix, step, step_name, progress, beside=False):
        """Start factoring ``matrix``, ``M + step L``, for the boundary condition (Neumann, interior-only Dirichlet, or
        both): the Dirichlet factorization beside the caller, the Neumann one too where ``beside`` (else now).
        ``step_name`` ("long step" or "") names the step in the progress messages. Returns a callable that waits
        for them and gives the step's :class:`~heatcore.steps.heat_flow.HeatFlow`."""
        ops, backend = self.ops, self.heat_backend
        dirichlet, interior = None, None
        if heat.boundary in ("robin", "dirichlet"):
            interior = np.flatnonzero(~ops.boundary)
            if interior.size:
                which = f"{step_name}; " if step_name else ""
                progress(0.0, f"factoring the heat matrix ({which}interior vertices, for the Dirichlet condition)")
                ordering = restrict_ordering(self._ordering(backend), interior)
                dirichlet = start_factor(matrix[interior][:, interior], backend, ordering=ordering)
        # Neumann: the condition itself, half of Robin, or the fallback where Dirichlet sees no heat.
        progress(0.0 if dirichlet is None else 0.5, f"factoring the heat matrix ({step_name})" if step_name
                 else "factoring the heat matrix")
        neumann = start_factor(matrix, backend, ordering=self._ordering(backend)) if beside else StartedFactor(
            factor(matrix, backend, ordering=self._ordering(backend)))

        def flow():
            made = neumann.result()
            return HeatFlow(made, None if dirichlet is None else dirichlet.result(), interior, heat.boundary,
                            heat.component, heat.n_components, BoundarySourceHeat(ops, self._laplacian, step, made))

        return flow

    def _ordering(self, backend):
        """The fill-reducing ordering ``backend`` uses on the domain's matrices (kept in the domain's cache)."""
        ordering = self._cache.get(("ordering", backend), self)
        if ordering is self:
            ordering = fill_reducing_ordering(self._laplacian, backend)
        elif isinstance(ordering, StartedOrdering):
            ordering = ordering.result()
        self._cache["ordering", backend] = ordering
        return ordering

    def _laplacian_ordering(self, backend):
        """The best ordering at hand for the Laplacian: nested dissection where it was started, else the quick one."""
        nested = self._cache.get(("nested", backend))
        if isinstance(nested, Future):
            try:
                nested = self._ordering(backend).reordered(nested.result())
            except SolverError as exc:  # pragma: no cover - METIS ran out of memory, say
                log.warning("%s; using the minimum degree ordering", exc)
                nested = None
            self._cache["nested", backend] = nested
        return nested or self._ordering(backend)

    def factor_free(self, free):
        """Factor of the Laplacian on the ``free`` vertices (a pinned system of many pins), ordered as the Laplacian."""
        ordering = restrict_ordering(self._laplacian_ordering(self.heat_backend), free)
        return factor(self._laplacian[free][:, free], self.heat_backend, ordering=ordering)


def heat_matrix(mass, step, laplacian):
    """``diags(mass) + step * laplacian`` as CSR; on the Laplacian's own pattern where it holds every diagonal entry
    and the sum no zero (the numbers scipy's sum gives: ``mass + step * L_ii`` on the diagonal, ``step * L_ij`` off it).

    ``step``: a float, or one per vertex (constant on each connected part, so the matrix stays symmetric).

    Examples
    --------
    >>> L = sp.csr_matrix(np.array([[1.0, -1.0], [-1.0, 1.0]]))
    >>> heat_matrix(np.array([0.5, 0.5]), 2.0, L).toarray().tolist()
    [[2.5, -2.0], [-2.0, 2.5]]
    """
    L, n = laplacian, laplacian.shape[0]
    if np.ndim(step) == 0 and sp.isspmatrix_csr(L) and L.has_canonical_format:
        diagonal = L.indices == np.repeat(np.arange(n, dtype=L.indices.dtype), np.diff(L.indptr))
        if np.count_nonzero(diagonal) == n:
            data = L.data * step
            data[diagonal] += mass
            if np.all(data != 0):
                return sp.csr_matrix((data, L.indices.copy(), L.indptr.copy()), shape=L.shape)
    scaled = step * L if np.ndim(step) == 0 else sp.diags(step) @ L
    return (sp.diags(mass) + scaled).tocsr()

