"""The heat method, written once over the operator bundle of any domain.

1. heat flow ``(M + t L) u = delta`` for ``t = m h^2``; on a surface's refined parts
   (``domain.two_step_vertices()``) for a short and a long step, 2t and 8t
   (:mod:`heatcore.steps.time_step`). Robin boundary conditions by default: the mean of the
   Neumann and Dirichlet solutions;
2. unit field ``X = -grad u / |grad u|`` per element; on refined parts ``u`` is
   ``log u_short - log u_long``, linear in the distance up to a constant
   (:func:`heatcore.steps.unit_field.log_ratio`);
3. Poisson equation ``L phi = -div X`` with every source pinned to its known
   distance (0 at a source vertex), solved per connected component;
4. vertices that no source reaches get ``inf``.

All factorizations are built in the constructor (with ``accuracy="high"`` and
numba, on first need: its distances come from fast marching, see
:mod:`heatcore.high_accuracy`); :meth:`HeatSolver.distance` only runs triangular
solves and sparse products, :meth:`HeatSolver.distances` many at once. The steps' own numerics live beside this
module, in :mod:`heatcore.steps`: the time step's underflow guard, the heat flow (step 1), the
unit field (step 2), the pinned Poisson solve (step 3) and the blocks of many sources.

Examples
--------
>>> import numpy as np, heatcore as hc
>>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
>>> solver = hc.HeatSolver(hc.TriangleMesh(V, [[0, 1, 2], [1, 3, 2]]))
>>> d = solver.distance([0])
>>> round(float(d[3]), 1)
1.4
"""

import logging
import time
from collections.abc import Mapping

import numpy as np

from .domains.parts import edge_graph, first_of_each, hop_diameters, hop_sweep, vertex_components
from .domains.sources import SourcePins, source_keywords
from .errors import InvalidSourceError, UnsupportedDomainError
from .high_accuracy import high_accuracy_distance, high_accuracy_needs_heat, resolve_accuracy
from .progress import Progress
from .settings import SolverSettings
from .steps.blocks import block_columns, source_sequence
from .steps.factors import HeatStep, SolverFactors
from .steps.poisson import MAX_PRECOMPUTED_PINS
from .steps.source_bounds import source_bounds
from .steps.time_step import LONG_STEP, SHORT_STEP, underflow_safe_m, vertex_time_steps
from .steps.unit_field import (
    log_ratio,
    minus_divergence,
    minus_divergence_columns,
    unit_field,
)
from .voronoi import nearest_source

log = logging.getLogger("heatcore")


class HeatSolver:
    """Prefactored heat-method distance on one domain; cheap queries.

    Parameters
    ----------
    domain : TriangleMesh or another domain with ``operators`` and ``source_pins``
    settings : SolverSettings or Settings, optional
        The options checked once by a front end (:mod:`heatcore.settings`,
        with its ``intent``); the keyword options below build them (checked
        here) or change them.
    m : float, default 1.0
        Time factor: ``t = m h^2`` with ``h`` the mean edge length. Larger
        values give a smoother distance (the smoothed distance of the paper).
    boundary : {"robin", "neumann", "dirichlet"}, default "robin"
        Boundary condition of the heat step on domains with boundary;
        "robin" averages the Neumann and Dirichlet solutions, as the paper
        recommends. Domains without boundary always use Neumann.
    accuracy : {"smooth", "high", "auto"}, default "auto"
        "smooth" is the heat method as the paper describes it (``m`` controls
        smoothing). "high": an eikonal pass (:mod:`heatcore.high_accuracy`),
        0.1-0.3% error; triangle meshes only. "auto": "high" for one query
        (the settings' ``intent``) on a large triangle mesh where numba is
        installed, else "smooth" (:func:`~heatcore.high_accuracy.resolve_accuracy`);
        a solver kept for reuse (the default intent) is "smooth".
    backend : {"auto", "supernodal", "qdldl", "cholmod", "superlu", "gpu"}
        Sparse factorization backend (see :mod:`heatcore.linalg`).
    progress : callable, optional
        ``progress(fraction, message)`` at the start of each stage (connected components, each
        factorization) and with 1.0 at the end; it may raise to abort (:mod:`heatcore.progress`).

    Each connected component gets its own time step ``t = m h^2`` from its
    own mean edge length ``h`` (and its own underflow guard), so a part's
    distances do not depend on the other parts.

    Attributes
    ----------
    t : (n_components,) float array
        The heat time step of each component, ``m h^2`` in the input's units
        (with ``m`` raised where needed, see ``part_m``).
    part_m : (n_components,) float array
        The time factor of each component: ``m``, raised where the component
        is so many edge hops across that heat with time factor ``m`` would
        underflow double precision far from the sources (see
        :func:`~heatcore.steps.time_step.underflow_safe_m`).
    m_effective : float
        The largest of ``part_m``.
    hop_diameter : int
        Edge hops across the widest component (double-sweep estimate, on first use).
    n_components : int
        Connected components of the domain.
    component : (n,) int array
        Component of each operator vertex.
    timings : dict
        Seconds spent in each precomputation stage.
    settings : SolverSettings
        The options it was built with (:mod:`heatcore.settings`), and its intent.
    factors : SolverFactors
        Its factorizations (:mod:`heatcore.steps.factors`).
    path_fields : PathFieldCache or None
        The distance fields its geodesic paths keep (:mod:`heatcore.paths.fields`), from the first path on.

    Examples
    --------
    >>> import heatcore as hc
    >>> V, F = hc.io.load_demo_mesh()
    >>> solver = hc.HeatSolver(hc.TriangleMesh(V, F))
    >>> d0, d1 = solver.distance([0]), solver.distance([10, 20])
    """

    def __init__(self, domain, settings=None, *, progress=None, **options):
        settings = resolve_accuracy(SolverSettings.of(settings, **options), domain)
        if settings.accuracy == "high" and not domain.supports_high_accuracy:
            raise UnsupportedDomainError(f"accuracy='high' is available on triangle meshes, not on {type(domain).__name__}")
        self.settings = settings
        self.accuracy = settings.accuracy
        self.m = settings.m
        self.domain = domain
        self._bounded = 0  # queries bounded near their sources (steps/source_bounds.py)
        self.path_fields = None  # geodesic paths' distance fields, made by the first path (paths/fields.py)
        self.timings = {}
        self._unreferenced = np.flatnonzero(np.asarray(domain.output_vertices) < 0)  # input vertices no element uses
        progress = Progress(progress)
        progress(0.0, "connected components")
        # accuracy="high" with numba needs no heat: the operators (a domain may build them on first use), the time
        # step and the factorizations wait for a first use (heat_flow, poisson, t, ...: see __getattr__).
        if settings.accuracy == "high" and not high_accuracy_needs_heat() and domain.vertex_parts is not None:
            self.n_components, self.component = domain.vertex_parts
            self._waiting = progress
        else:
            self._prepare(progress)
        progress(1.0, "ready to march (no heat to solve)" if "_waiting" in vars(self) else "heat solver ready")

    #: The attributes :meth:`_prepare` sets, which wait for their first use where the solver needs no heat.
    _PREPARED = frozenset(("ops", "has_boundary", "boundary", "factors", "part_m", "m_effective", "t", "_hops",
                           "_element_h", "_two_step", "_gradient_transposed", "_exponent"))

    def __getattr__(self, name):
        """The attributes of :meth:`_prepare`, prepared on first use where the constructor let them wait."""
        waiting = self.__dict__.get("_waiting")
        if name not in self._PREPARED or waiting is None:
            raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")
        self._prepare(waiting, deferred=True)  # the factorizations still wait (and report to it when built)
        return getattr(self, name)

    def _prepare(self, progress, deferred=None):
        """Read the operators, find the time step and start (or defer) the factorizations."""
        self.__dict__.pop("_waiting", None)
        settings, domain = self.settings, self.domain
        ops = self.ops = domain.operators
        start = time.perf_counter()
        n = ops.n_vertices
        self.has_boundary = bool(ops.boundary.any())
        self.boundary = settings.boundary if self.has_boundary else "neumann"  # the same heat where there is none
        # Orderings and the Laplacian's factor depend on the domain only: its cache shares them among its solvers.
        self.factors = SolverFactors(ops, domain.derived, settings, self.timings)
        # accuracy="high" with numba needs no factorization: they wait for a first use (heat_flow, poisson).
        if deferred is None:
            deferred = settings.accuracy == "high" and not high_accuracy_needs_heat()
        if not deferred:
            self.factors.start()

        heat = self._heat_step(ops)
        self._gradient_transposed = ops.gradient.T  # a view: -div X = G^T (volumes * X)
        self._exponent = output_exponent(ops.unit_exponent)
        self.timings["setup"] = time.perf_counter() - start
        if deferred:
            self.factors.defer(heat, progress)
        else:
            self.factors.build(heat, progress)
        boundary = f"boundary={self.boundary}" if self.has_boundary else "no boundary (closed)"
        log.info("heat solver ready: %d operator vertices, %d part%s, t=%.3g..%.3g, %s (%.2f s)", n, self.n_components,
                 "s" * (self.n_components != 1), self.t.min(), self.t.max(), boundary, sum(self.timings.values()))

    def _heat_step(self, ops):
        """Connected components, each one's time factor (``m`` raised by the underflow guard) and time step."""
        n = ops.n_vertices
        # every side of each element, not a star from its first corner: the hop count is the surface's, whatever
        # corner each element lists first (a PolygonMesh and a TriangleMesh of the same triangles get the same t)
        graph = edge_graph(ops.elements, n)
        parts = ops.parts if ops.parts is not None else vertex_components(ops.elements, n, graph)
        self.n_components, self.component = parts
        # The first sweep's bounds are enough where they need no larger m (underflow_safe_m grows with the hops).
        first_sweep = hop_sweep(graph, self.component, self.n_components)
        hops = hop_diameters(graph, self.component, self.n_components, bounds=True, first_sweep=first_sweep)
        self._hops = None
        if (underflow_safe_m(hops) > self.m).any():  # the second sweep
            hops = self._hops = hop_diameters(graph, self.component, self.n_components, first_sweep=first_sweep)
        del graph
        self.part_m = np.maximum(self.m, underflow_safe_m(hops))
        self.m_effective = float(self.part_m.max())
        if self.m_effective > self.m:
            log.info("mesh is %d edge hops across: time factor raised from m=%g to m=%.3g so that the heat stays "
                     "above double-precision underflow everywhere", self.hop_diameter, self.m, self.m_effective)
        ground = first_of_each(self.component, self.n_components)
        h = np.broadcast_to(ops.mean_edge_length, (n,))
        step = vertex_time_steps(self.part_m, self.component, ops.mean_edge_length)  # in each vertex's unit
        self._element_h = h[0] if (h == h[0]).all() else h[ops.elements[:, 0]]
        with np.errstate(over="ignore", under="ignore"):  # a part at 1e200 has t = 1e400: inf in float64, as reported
            self.t = np.ldexp(step[ground], 2 * np.broadcast_to(ops.unit_exponent, (n,))[ground])
        time_step = step[0] if (step == step[0]).all() else step
        self._two_step = two_step = self.domain.two_step_vertices()
        if two_step is None:
            multiples = (1.0,)
        else:  # a mask: the parts left unrefined keep one step of t (their short step), as if alone
            multiples = (SHORT_STEP if two_step is True else np.where(two_step, SHORT_STEP, 1.0), LONG_STEP)
        return HeatStep(time_step, self.boundary, self.component, self.n_components, ground, multiples)

    @property
    def hop_diameter(self):
        """Edge hops across the widest component (double-sweep estimate; swept on first use where the time step
        did not need it)."""
        if self._hops is None:
            n = self.ops.n_vertices
            self._hops = hop_diameters(edge_graph(self.ops.elements, n), self.component, self.n_components)
        return int(self._hops.max())

    @property
    def heat_flow(self):
        """Step 1, :class:`~heatcore.steps.heat_flow.HeatFlow` of the short step (built on first use where it was
        deferred)."""
        return self.factors.heat_flow()

    @property
    def long_flow(self):
        """Step 1, :class:`~heatcore.steps.heat_flow.HeatFlow` of the long step, None where the domain takes one step
        (built on first use where it was deferred)."""
        return self.factors.long_flow()

    @property
    def poisson(self):
        """Step 3, :class:`~heatcore.steps.poisson.PinnedPoisson` (built on this first use where it was deferred)."""
        return self.factors.poisson()

    def distance(self, vertices=None, **sources):
        """Geodesic distance from the given sources to every input vertex.

        Parameters
        ----------
        vertices : int or sequence of int, optional
            Source vertex indices.
        **sources
            Other kinds of sources, those the domain lists in its
            ``source_kinds``: ``points=(element_indices, barycentric)``
            (points inside faces or tets), ``edges`` (vertex pairs) and
            ``region`` (faces or polygons, or boundary triangles of a tet
            mesh; the distance is to their union). The old names
            ``face_points``, ``tet_points``, ``faces`` and ``boundary_faces``
            still work, with a ``DeprecationWarning``.

        Returns
        -------
        (n,) float array
            Distance per input vertex; ``inf`` where no source can be reached
            (another connected component, or a vertex used by no element).
        """
        kinds = source_keywords(sources, stacklevel=3)
        return self.distances([{"vertices": vertices, **kinds}])[0]

    def distance_from_pins(self, pins):
        """Distance at every operator vertex, in the input's units, for prepared :class:`~heatcore.domains.sources.SourcePins`.

        The pins hold distances in the operators' units (see
        :class:`~heatcore.domains.operators.Operators`), as the domain builds them.
        """
        return self._distances_from_pins([pins])[:, 0]

    def distances(self, sources_block, *, max_memory_mb=None):
        """Geodesic distances from each of ``k`` sources: one row per source, computed together.

        Row ``i`` is :meth:`distance` of ``sources_block[i]`` (bit for bit on
        the ``qdldl`` and ``cholmod`` backends, else within 1e-10 relative;
        ``inf`` at the same places), but the sources go through one
        multi-column heat solve (an ``(n, k)`` right-hand side), one unit
        field vectorized over the columns and one multi-column Poisson solve
        instead of ``k`` queries (sources per second against a loop over
        :meth:`distance`: docs/batch.md). A row never depends on the other
        sources of its block. Each column
        keeps its own pins (a shift with one pin per component, the small
        dense systems with several; a source with more than
        ``MAX_PRECOMPUTED_PINS`` pinned vertices is solved on its own, as
        :meth:`distance` does) and its own unreachable components (``inf``).
        With ``accuracy="high"`` the eikonal pass runs per source afterwards.

        Parameters
        ----------
        sources_block : sequence
            The sources, each a vertex index (int), a sequence of vertex
            indices (one source made of several vertices: the distance to the
            nearest), a mapping of :meth:`distance`'s keywords
            (``{"edges": [[0, 1]]}``), or prepared
            :class:`~heatcore.domains.sources.SourcePins`.
        max_memory_mb : float, optional
            Bound on the working memory (MB) of the solves: the block is
            solved in chunks of columns that fit (:meth:`block_columns`; at
            least one column). Default ``QUERY_MEMORY_MB`` (256). The returned
            ``(k, n)`` rows come on top.

        Returns
        -------
        (k, n) float array
            ``n`` input vertices; ``inf`` where a source cannot be reached. An
            empty block gives an empty ``(0, n)`` array.

        Raises
        ------
        InvalidSourceError
            A bad source, with the error :meth:`distance` raises for it, or a
            ``sources_block`` that is not a sequence of sources.

        Examples
        --------
        >>> import heatcore as hc
        >>> solver = hc.HeatSolver(hc.TriangleMesh(*hc.io.load_demo_mesh()))
        >>> D = solver.distances([0, 17, [5, 9]])
        >>> D.shape
        (3, 2930)
        >>> bool(abs(D[2] - solver.distance([5, 9])).max() <= 1e-10 * D[2].max())
        True
        >>> solver.distances([]).shape
        (0, 2930)
        """
        sources, block = source_sequence(sources_block), []
        for source in sources:  # a loop, not a comprehension: warnings point at the caller
            block.append(self._block_source_pins(source))
        outputs = np.asarray(self.domain.output_vertices)
        rows = np.empty((len(block), outputs.size))
        for chunk in self._chunks(block, max_memory_mb):
            phi = self._distances_from_pins([block[j] for j in chunk])  # (n, k), columns contiguous
            rows[chunk] = phi.T[:, outputs]
        rows[:, self._unreferenced] = np.inf  # they read index -1 above
        for row, source in zip(rows, sources):
            bounds = self._block_source_bounds(source)
            if bounds is not None:
                bounds.apply(row)
        return rows

    def _chunks(self, block, max_memory_mb):
        """The block's sources solved together, as lists of positions: a source with more than
        ``MAX_PRECOMPUTED_PINS`` pins alone (it factors a pinned system of its own), the others by
        :meth:`block_columns`."""
        solo = [j for j, pins in enumerate(block) if pins.vertices.size > MAX_PRECOMPUTED_PINS]
        columns = sorted(set(range(len(block))).difference(solo))
        width = self.block_columns(max_memory_mb) if columns and "_waiting" not in self.__dict__ else 1
        return [[j] for j in solo] + [columns[start : start + width] for start in range(0, len(columns), width)]

    def block_columns(self, max_memory_mb=None):
        """Sources of one vertex each that :meth:`distances` solves at once (:func:`heatcore.steps.blocks.block_columns`).

        Examples
        --------
        >>> import heatcore as hc
        >>> hc.HeatSolver(hc.TriangleMesh(*hc.io.load_demo_mesh())).block_columns(max_memory_mb=8)
        5
        """
        return block_columns(self.ops, len(self.domain.output_vertices), max_memory_mb)

    def _block_source_pins(self, source):
        """:class:`SourcePins` of one source of a block (see :meth:`distances`)."""
        if isinstance(source, SourcePins):
            return source
        if isinstance(source, Mapping):  # distance()'s keywords
            kinds = dict(source)
            return self.domain.source_pins(kinds.pop("vertices", None), **source_keywords(kinds, stacklevel=4))
        return self.domain.source_pins(source)

    def _block_source_bounds(self, source):
        """:class:`~heatcore.steps.source_bounds.SourceBounds` of one source of a block (None for prepared pins)."""
        if isinstance(source, SourcePins):
            return None
        if isinstance(source, Mapping):
            kinds = dict(source)
            return self._source_bounds(kinds.pop("vertices", None), kinds)
        return self._source_bounds(source, {})

    def _source_bounds(self, vertices, kinds):
        """The bounds near a source; from the second one on, the domain looks up the elements at a vertex (its
        index costs about one pass over the elements: a one-off query pays none)."""
        self._bounded += 1
        if self._bounded > 1:
            self.domain.index_straight_neighbours()
        return source_bounds(self.domain, self.component, vertices, kinds)

    def _distances_from_pins(self, block):
        """Distances from each of the prepared pins in ``block``, as columns ``(n, k)`` at the operator vertices."""
        if self.accuracy != "high":
            return self._heat_distances(block)
        heat = []  # the block's heat distances, computed on first need (the pass without numba)

        def heat_column(j):
            if not heat:
                heat.append(self._heat_distances(block))
            return np.ascontiguousarray(heat[0][:, j])

        phi = np.empty((self.domain.n_vertices, len(block)))
        for j, pins in enumerate(block):
            phi[:, j] = high_accuracy_distance(self.domain, pins, lambda j=j: heat_column(j))
        return phi

    def _heat_distances(self, block):
        """:meth:`_distances_from_pins` by the heat method: one column's solves, or multi-column ones."""
        n, k = self.ops.n_vertices, len(block)
        if k == 1:
            pins = block[0]
            u = self._direction_field(pins.heat)
            b = minus_divergence(self.ops, self._gradient_transposed, u, self._element_h)
            reached = None if self.n_components == 1 else np.isin(self.component, self.component[pins.vertices])
            phi = self.poisson.solve(b, pins, reached)[:, None]
        else:
            impulse = np.empty((n, k), order="F")  # columns contiguous: what one-column backends read
            for j, pins in enumerate(block):
                impulse[:, j] = pins.heat
            u = np.asfortranarray(self._direction_field(impulse))  # columns contiguous
            del impulse
            b = minus_divergence_columns(self.ops, self._gradient_transposed, u, self._element_h)
            del u
            phi = self.poisson.solve_block(b, block)
        np.maximum(phi, 0.0, out=phi)
        if self.n_components > 1:
            hit = np.zeros((self.n_components, k), dtype=bool)
            for j, pins in enumerate(block):
                hit[self.component[pins.vertices], j] = True
            phi[~hit[self.component]] = np.inf
        return phi if self._exponent is None else np.ldexp(phi, self._exponent)

    def nearest_source(self, sources, *, return_distance=False, max_memory_mb=None):
        """The index (into ``sources``) of the nearest source at every vertex: :func:`heatcore.voronoi.nearest_source`."""
        return nearest_source(self, sources, return_distance=return_distance, max_memory_mb=max_memory_mb)

    def geodesic_path(self, source=None, target=None, *, points=None, closed=False, both_ends=True):
        """The shortest path on the surface from ``source`` to ``target``, or through ``points`` (triangle meshes).

        Parameters
        ----------
        source, target : int or (int, (3,) array_like)
            A vertex index, or a surface point ``(face, barycentric)``: a face
            index of the input mesh and three barycentric coordinates (>= 0,
            summing to 1).
        points : sequence, optional
            Waypoints instead of ``source`` and ``target`` (each a vertex or
            ``(face, barycentric)``): one path, a geodesic from each waypoint
            to the next (:mod:`heatcore.paths.waypoints`).
        closed : bool, default False
            With ``points``: a last leg back to the first waypoint.
        both_ends : bool, default True
            Also descend on the distance from ``target`` (a second query,
            kept for the next path) and keep the shorter result. False: one
            query per source, paths from it 5-10 times faster, and the
            largest excess over the exact length about 0.5% instead of 0.1%
            (docs/paths.md).

        Returns
        -------
        GeodesicPath
            ``points`` from ``source`` to ``target`` on the input faces,
            ``faces``/``edges``/``vertices`` crossed, ``length``, and per leg
            ``leg_lengths`` and ``waypoints`` (indices into ``points``). The
            same point twice gives a one-point path of length 0.

        Raises
        ------
        UnsupportedDomainError
            The solver's domain is not a :class:`~heatcore.TriangleMesh`.
        InvalidSourceError
            A bad index or coordinates, a vertex no face uses, or a target in
            another connected part than the source (the message names both).

        Notes
        -----
        The distance from ``source`` is one query of the solver's
        factorizations, kept for further targets from the same source. The
        path is a geodesic (straight across every edge, bending only at
        saddle or boundary vertices) in the homotopy class the heat distance
        points to: the shortest path except where two routes are within the
        heat distance's error of each other (docs/paths.md has the figures).
        """
        from .paths.path import geodesic_path  # paths import this module
        from .paths.waypoints import waypoint_path

        if points is not None:
            if source is not None or target is not None:
                raise InvalidSourceError("give either source and target or points, not both")
            return waypoint_path(self, points, closed, both_ends)
        if source is None or target is None:
            raise InvalidSourceError("a path needs a source and a target, or points")
        return geodesic_path(self, source, target, both_ends)

    def straighten_path(self, path):
        """Shorten a path on the surface, ends and homotopy class kept, to a locally shortest geodesic (triangle meshes).

        ``path``: vertex indices joined by edges, or a path object with
        ``points`` and ``faces`` (a :class:`~heatcore.GeodesicPath`, a
        :class:`~heatcore.TracedPath`). Returns a :class:`~heatcore.GeodesicPath`;
        see :func:`heatcore.straighten_path` and docs/paths.md. No query of
        the factorizations: the straightening reads only the mesh.
        """
        from .paths.drawn import straighten_on  # paths import this module

        return straighten_on(self.domain, path)

    def straighten_loop(self, loop):
        """Shorten a closed curve on the surface to a closed geodesic in its class (triangle meshes).

        ``loop`` as ``path`` of :meth:`straighten_path`, closed by the edge
        back to its first vertex if it is not. See :func:`heatcore.straighten_loop`.
        """
        from .paths.drawn import straighten_loop_on  # paths import this module

        return straighten_loop_on(self.domain, loop)

    def trace(self, start, direction, length):
        """The straightest path on the surface from ``start`` along ``direction`` for ``length`` (triangle meshes).

        ``start``: a vertex index or ``(face, barycentric)``; ``direction``: a
        3D vector (projected on the tangent plane) or ``(x, y)`` in the start
        vertex's tangent basis (:meth:`VectorHeatSolver.tangent_basis`). The
        path crosses the input faces straight, leaves a vertex with half its
        angle on either side, and stops after ``length`` or at the boundary.
        Returns a :class:`~heatcore.paths.tracing.TracedPath` (``points``,
        ``faces``, ``end``, ``length``, ``stopped``); see
        :func:`heatcore.trace_geodesic` and docs/paths.md. No query of the
        factorizations: the walk reads only the mesh.
        """
        from .paths.tracing import trace  # paths import this module

        return trace(self.domain, start, direction, length)

    def heat(self, impulse):
        """Heat after one backward Euler step from ``impulse`` ((n,), or (n, k): k columns at once): of length ``t``,
        or on refined parts (``domain.two_step_vertices()``) the short step ``SHORT_STEP t``
        (:mod:`heatcore.steps.time_step`)."""
        return self.heat_flow.solve(impulse)

    def _direction_field(self, impulse):
        """The field whose gradient gives the distance's direction: the heat, or on refined parts the
        :func:`~heatcore.steps.unit_field.log_ratio` of the short and the long step's heat."""
        long_flow = self.long_flow
        u = self.heat(impulse)
        if long_flow is None:
            return u
        field = log_ratio(u, long_flow.solve(impulse))
        if self._two_step is not True:  # parts left unrefined: their own heat (rows of a mask)
            field[~self._two_step] = u[~self._two_step]
        return field

    def unit_field(self, u):
        """``-grad u / |grad u|`` per element, 0 where the gradient vanishes or is not finite (see :mod:`heatcore.steps.unit_field`)."""
        return unit_field(self.ops, u, 1.0, self._element_h)


def output_exponent(unit_exponent):
    """What ``np.ldexp`` takes to bring ``(n, k)`` distances from the operators' units to the input's: a column
    ``(n, 1)``, one number where every vertex has the same unit, or None where that is the input's own.

    Examples
    --------
    >>> output_exponent(np.zeros(3, int)) is None, output_exponent(np.full(3, 2)), output_exponent(np.arange(2)).shape
    (True, 2, (2, 1))
    """
    exponent = np.unique(unit_exponent)
    if exponent.size > 1:
        return np.asarray(unit_exponent)[:, None]
    return None if exponent[0] == 0 else int(exponent[0])
