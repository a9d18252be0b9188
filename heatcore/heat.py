"""The heat method, written once over the operator bundle of any domain.

1. heat flow ``(M + t L) u = delta`` for ``t = m h^2`` (Robin boundary
   conditions by default: the mean of the Neumann and Dirichlet solutions);
2. unit field ``X = -grad u / |grad u|`` per element;
3. Poisson equation ``L phi = -div X`` with every source pinned to its known
   distance (0 at a source vertex), solved per connected component;
4. vertices that no source reaches get ``inf``.

All factorizations are built in the constructor; :meth:`HeatSolver.distance`
only runs triangular solves and sparse products.

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
import weakref
from collections.abc import Iterable, Mapping
from concurrent.futures import Future

import numpy as np
import scipy.sparse as sp

from .domains.parts import first_of_each, hop_diameters, vertex_components, vertex_graph
from .domains.sources import SourcePins, source_keywords
from .errors import InvalidOptionError, InvalidSourceError, SolverError
from .options import check
from .linalg import (
    Ordering,
    choose_backend,
    factor,
    fill_reducing_ordering,
    restrict_ordering,
    start_nested_dissection,
)

log = logging.getLogger("heatcore")

#: Factorizations and orderings of each live domain, shared by its solvers (see :func:`domain_factors`).
_DOMAIN_FACTORS = weakref.WeakKeyDictionary()

#: The solver's options, declared in :mod:`heatcore.options`.
OPTION_NAMES = ("m", "boundary", "accuracy", "backend")

#: A heat gradient smaller than this times ``u / h`` is rounding noise (an exact
#: saddle of the heat) and gets no direction in the unit field.
SADDLE_GRADIENT = 1e-9

#: Up to this many pinned vertices, the pinned Poisson solve reuses the
#: prefactored Laplacian (one multi-right-hand-side solve); beyond, it factors
#: the pinned system for that query.
MAX_PRECOMPUTED_PINS = 256

#: Default bound (MB) on the working memory of :meth:`HeatSolver.distances`:
#: blocks of sources are solved in chunks of columns that fit.
QUERY_MEMORY_MB = 256
#: At most this many sources per chunk of :meth:`HeatSolver.distances`: the
#: time per source falls up to 8-32 columns and rises beyond, as the
#: per-column arrays leave the processor's cache (measured with 128 sources:
#: 1.4-1.6x a loop of queries at 8-32 columns on spot, nefertiti and a
#: 20k-vertex grid; 1.0-1.3x at 128).
MAX_BLOCK_COLUMNS = 16
#: Multi-column solves of :meth:`HeatSolver.distances` go in calls of at most
#: this many columns: CHOLMOD's simplicial solve (the cholmod backend) takes 4
#: columns at a time through another kernel than 1 to 3, with another rounding,
#: so with at most 3 every column is bit for bit its one-column solve and a
#: row never depends on the block it was computed in (measured cost: within
#: the noise of one multi-column call; see docs/batch.md).
EXACT_SOLVE_COLUMNS = 3
#: Backends whose factor solves one column at a time faster in :meth:`HeatSolver.distances`: the
#: supernodal factor solves a sparse right-hand side (a vertex's heat impulse) by a sparse forward
#: solve, for one column only (measured on nefertiti: blocks 10% slower with 3 columns per call).
ONE_COLUMN_BACKENDS = ("supernodal",)
#: The unit field of a block is computed in tiles of columns whose element
#: arrays take about this many bytes: elementwise passes over arrays that stay
#: in the processor's cache (measured fastest on nefertiti and spot).
UNIT_FIELD_TILE_BYTES = 4 * 2**20


class HeatSolver:
    """Prefactored heat-method distance on one domain; cheap queries.

    Parameters
    ----------
    domain : TriangleMesh or another domain with ``operators`` and ``source_pins``
    m : float, default 1.0
        Time factor: ``t = m h^2`` with ``h`` the mean edge length. Larger
        values give a smoother distance (the smoothed distance of the paper).
    boundary : {"robin", "neumann", "dirichlet"}, default "robin"
        Boundary condition of the heat step on domains with boundary;
        "robin" averages the Neumann and Dirichlet solutions, as the paper
        recommends. Domains without boundary always use Neumann.
    accuracy : {"smooth", "high"}, default "smooth"
        "smooth" is the heat method as the paper describes it (``m`` controls
        smoothing). "high" follows it with an ordered eikonal pass that uses
        the heat distance as the order (:mod:`heatcore.eikonal`); triangle
        meshes only.
    backend : {"auto", "supernodal", "qdldl", "cholmod", "superlu"}
        Sparse factorization backend (see :mod:`heatcore.linalg`).

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
        :func:`underflow_safe_m`).
    m_effective : float
        The largest of ``part_m``.
    hop_diameter : int
        Edge hops across the widest component (double-sweep estimate).
    n_components : int
        Connected components of the domain.
    component : (n,) int array
        Component of each operator vertex.
    timings : dict
        Seconds spent in each precomputation stage.

    Examples
    --------
    >>> import heatcore as hc
    >>> V, F = hc.io.load_demo_mesh()
    >>> solver = hc.HeatSolver(hc.TriangleMesh(V, F))
    >>> d0, d1 = solver.distance([0]), solver.distance([10, 20])
    """

    def __init__(self, domain, *, m=1.0, boundary="robin", accuracy="smooth", backend="auto"):
        m, boundary, accuracy, backend = (check(k, v) for k, v in zip(OPTION_NAMES, (m, boundary, accuracy, backend)))
        if accuracy == "high" and not domain.supports_high_accuracy:
            raise InvalidOptionError(f"accuracy='high' is available on triangle meshes, not on {type(domain).__name__}")
        self.accuracy = accuracy
        self.domain = domain
        self.m = float(m)
        ops = self.ops = domain.operators
        self.timings = {}
        start = time.perf_counter()
        n = ops.n_vertices
        self.boundary = boundary if ops.boundary.any() else "neumann"
        self._backend = backend
        self._laplacian = ops.laplacian.tocsr()
        # Factorizations and orderings that depend on the domain only (not on m or
        # the boundary condition) are shared by every solver built on it.
        self._domain_cache = domain_factors(domain)
        poisson_backend = self._resolve(backend, "solve")
        if ("poisson", backend) not in self._domain_cache and ("nested", poisson_backend) not in self._domain_cache:
            # On large meshes: a better ordering for the Poisson factor, computed in the
            # background while the heat matrix is factored (with the quick ordering).
            self._domain_cache["nested", poisson_backend] = start_nested_dissection(self._laplacian, poisson_backend)

        graph = vertex_graph(ops.elements, n)
        self.n_components, self.component = vertex_components(ops.elements, n, graph)
        hops = hop_diameters(graph, self.component, self.n_components)
        del graph
        self.hop_diameter = int(hops.max())
        self.part_m = np.maximum(self.m, underflow_safe_m(hops))
        self.m_effective = float(self.part_m.max())
        if self.m_effective > self.m:
            log.info(
                "mesh is %d edge hops across: time factor raised from m=%g to m=%.3g so that the heat "
                "stays above double-precision underflow everywhere",
                self.hop_diameter,
                self.m,
                self.m_effective,
            )
        ground = first_of_each(self.component, self.n_components)
        self._ground = ground
        h = np.broadcast_to(ops.mean_edge_length, (n,))
        step = self.part_m[self.component] * h * h  # in each vertex's unit; constant on each component
        self._time_step = step[0] if (step == step[0]).all() else step
        self._element_h = h[0] if (h == h[0]).all() else h[ops.elements[:, 0]]
        self.t = np.ldexp(step[ground], 2 * np.broadcast_to(ops.unit_exponent, (n,))[ground])
        self._gradient_transposed = ops.gradient.T  # a view: -div X = G^T (volumes * X)
        self._factor_heat(self._resolve(backend, "factor"))
        self.timings["heat factorization"] = time.perf_counter() - start

        start = time.perf_counter()
        # The Poisson factorization is kept for every query, so it is made for fast solves.
        if ("poisson", backend) not in self._domain_cache:
            grounded = _grounded(self._laplacian, ground)
            poisson = factor(grounded, poisson_backend, ordering=self._laplacian_ordering(poisson_backend))
            self._domain_cache["poisson", backend] = poisson
        self._poisson = self._domain_cache["poisson", backend]
        self.timings["poisson factorization"] = time.perf_counter() - start
        for key, ordering in self._domain_cache.items():
            if isinstance(ordering, Ordering):
                ordering.forget_pattern()  # its memory matters more than re-converting for another m
        log.info(
            "heat solver ready: %d operator vertices, %d components, t=%.3g..%.3g, boundary=%s (%.2f s)",
            n,
            self.n_components,
            self.t.min(),
            self.t.max(),
            self.boundary,
            sum(self.timings.values()),
        )

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
        pins = self.domain.source_pins(vertices, **source_keywords(sources, stacklevel=3))
        phi = np.append(self.distance_from_pins(pins), np.inf)
        return phi[self.domain.output_vertices]  # index -1 (unreferenced) reads the appended inf

    def distance_from_pins(self, pins):
        """Distance at every operator vertex, in the input's units, for prepared :class:`~heatcore.domains.sources.SourcePins`.

        The pins hold distances in the operators' units (see
        :class:`~heatcore.domains.operators.Operators`), as the domain builds them.
        """
        u = self.heat(pins.heat)
        b = self._gradient_transposed @ self._scaled_unit_field(u, self.ops.volumes).ravel()  # = -div X
        reached = None if self.n_components == 1 else np.isin(self.component, self.component[pins.vertices])
        phi = self._pinned_poisson(b, pins, reached)
        phi[pins.vertices] = pins.values
        np.maximum(phi, 0.0, out=phi)
        if reached is not None:
            phi[~reached] = np.inf
        phi = np.ldexp(phi, self.ops.unit_exponent)
        if self.accuracy == "high":
            from .eikonal import refine_distance

            phi = refine_distance(self.domain, phi, pins)
        return phi

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
        block = []
        for source in _source_sequence(sources_block):  # a loop, not a comprehension: warnings point at the caller
            block.append(self._block_source_pins(source))
        outputs = np.asarray(self.domain.output_vertices)
        rows = np.empty((len(block), outputs.size))
        solo = [j for j, pins in enumerate(block) if pins.vertices.size > MAX_PRECOMPUTED_PINS]
        for j in solo:  # factors a pinned system of its own, as distance() does
            rows[j] = np.append(self.distance_from_pins(block[j]), np.inf)[outputs]
        columns = sorted(set(range(len(block))).difference(solo))
        width = self.block_columns(max_memory_mb)
        for start in range(0, len(columns), width):
            chunk = columns[start : start + width]
            phi = self._distances_from_pins([block[j] for j in chunk])  # (n, k), columns contiguous
            extended = np.empty((len(chunk), phi.shape[0] + 1))
            extended[:, :-1] = phi.T
            extended[:, -1] = np.inf  # index -1 (unreferenced) reads inf
            rows[chunk] = extended[:, outputs]
        return rows

    def block_columns(self, max_memory_mb=None):
        """Sources of one vertex each that :meth:`distances` solves at once within ``max_memory_mb``.

        At most ``MAX_BLOCK_COLUMNS`` (16): wider blocks are no faster per
        source (their arrays leave the processor's cache).

        The working memory is about ``8 * (8 n + n_input)`` bytes per column
        (the heat impulse and the heat fields of both boundary conditions,
        ``-div X``, the Poisson solution, the output row) plus one tile of the
        unit field, ``8 * (dim + 5) * n_elements`` bytes per column of the tile
        (its columns: as many as fit in ``UNIT_FIELD_TILE_BYTES``, at least
        one). A source whose pinned vertices share a component adds ``8 n`` per
        pinned vertex while its column is pinned (its unit responses, as in
        :meth:`distance`). Measured peak (tracemalloc, the output rows
        included) of a full block at the 256 MB default: 42% of it on spot,
        54% on nefertiti, 88% on a 20k-vertex grid with boundary (Robin).

        Parameters
        ----------
        max_memory_mb : float, optional
            Default ``QUERY_MEMORY_MB``.

        Returns
        -------
        int
            At least 1.

        Examples
        --------
        >>> import heatcore as hc
        >>> solver = hc.HeatSolver(hc.TriangleMesh(*hc.io.load_demo_mesh()))
        >>> solver.block_columns(), solver.block_columns(max_memory_mb=8), solver.block_columns(max_memory_mb=1)
        (16, 5, 1)
        """
        limit = (QUERY_MEMORY_MB if max_memory_mb is None else max_memory_mb) * 2**20
        ops = self.ops
        tile = 8 * (ops.dim + 5) * ops.elements.shape[0] * self._unit_field_tile()
        fit = int((limit - tile) // (8 * (8 * ops.n_vertices + len(self.domain.output_vertices))))
        return max(1, min(fit, MAX_BLOCK_COLUMNS))

    def _unit_field_tile(self):
        """Columns per tile of the block unit field: its arrays (``8 (dim + 5)`` bytes per element and column) within ``UNIT_FIELD_TILE_BYTES``."""
        ops = self.ops
        return max(1, int(UNIT_FIELD_TILE_BYTES // (8 * (ops.dim + 5) * ops.elements.shape[0])))

    def _block_source_pins(self, source):
        """:class:`SourcePins` of one source of a block (see :meth:`distances`)."""
        if isinstance(source, SourcePins):
            return source
        if isinstance(source, Mapping):  # distance()'s keywords
            kinds = dict(source)
            return self.domain.source_pins(kinds.pop("vertices", None), **source_keywords(kinds, stacklevel=4))
        return self.domain.source_pins(source)

    def _distances_from_pins(self, block):
        """:meth:`distance_from_pins` of several sources as columns ``(n, k)``, with multi-column solves."""
        n, k = self.ops.n_vertices, len(block)
        impulse = np.empty((n, k), order="F")  # columns contiguous: what one-column backends read
        for j, pins in enumerate(block):
            impulse[:, j] = pins.heat
        u = np.asfortranarray(self.heat(impulse))  # columns contiguous
        del impulse
        # b = -div X per column: the unit field vectorized over tiles of columns whose element arrays stay
        # in cache (one column per tile on large meshes); the sparse products column by column (scipy's
        # one-column product is the faster one).
        gradient, first, dim = self.ops.gradient, self.ops.elements[:, 0], self.ops.dim
        b = np.empty((n, k), order="F")
        width = self._unit_field_tile()
        for start in range(0, k, width):
            tile = range(start, min(start + width, k))
            if len(tile) == 1:
                b[:, start] = self._gradient_transposed @ self._scaled_unit_field(u[:, start], self.ops.volumes).ravel()
                continue
            g = np.empty((dim, len(tile), first.size))  # components first: contiguous passes over the tile
            u_first = np.empty((len(tile), first.size))
            for i, j in enumerate(tile):
                g[:, i, :] = (gradient @ u[:, j]).reshape(first.size, dim).T
                u_first[i] = u[:, j][first]
            g = self._scale_to_unit(g, u_first, self.ops.volumes)
            for i, j in enumerate(tile):
                b[:, j] = self._gradient_transposed @ g[:, i, :].T.ravel()  # element-major, as G's rows
        del u
        b[self._ground] = 0.0
        phi = _solve_columns(self._poisson, b)  # as _solve_grounded, for every column
        del b
        for j, pins in enumerate(block):
            column = phi[:, j]  # a view: pinned in place, with the small dense systems of _pinned_poisson
            self._apply_pins(column, pins.vertices, pins.values, self._unit_responses)
            column[pins.vertices] = pins.values
        np.maximum(phi, 0.0, out=phi)
        if self.n_components > 1:
            hit = np.zeros((self.n_components, k), dtype=bool)
            for j, pins in enumerate(block):
                hit[self.component[pins.vertices], j] = True
            phi[~hit[self.component]] = np.inf
        exponent = self.ops.unit_exponent
        phi = np.ldexp(phi, exponent[:, None] if np.ndim(exponent) else exponent)
        if self.accuracy == "high":
            from .eikonal import refine_distance

            for j, pins in enumerate(block):
                phi[:, j] = refine_distance(self.domain, np.ascontiguousarray(phi[:, j]), pins)
        return phi

    def heat(self, impulse):
        """Heat after one backward Euler step of length ``t`` from ``impulse`` ((n,), or (n, k): k columns at once)."""
        u_neumann = _solve_columns(self._heat_neumann, impulse)
        if self.boundary == "neumann":
            return u_neumann
        u = np.zeros_like(impulse)
        if self._heat_dirichlet is not None:
            u[self._interior] = _solve_columns(self._heat_dirichlet, impulse[self._interior])
        # A component whose heat all sits on the boundary gets none under
        # Dirichlet conditions: use the Neumann solution there.
        cold = _component_sums(self.component, np.abs(u), self.n_components) == 0
        if self.boundary == "robin":
            u = 0.5 * (u + u_neumann)
        fallback = cold[self.component]
        u[fallback] = u_neumann[fallback]
        return u

    def unit_field(self, u):
        """``-grad u / |grad u|`` per element, 0 where the gradient vanishes or is not finite."""
        return self._scaled_unit_field(u, 1.0)

    def _scaled_unit_field(self, u, weights):
        """``weights`` times :meth:`unit_field` (one pass fewer over the elements than multiplying after)."""
        g = (self.ops.gradient @ u).reshape(-1, self.ops.dim)
        return self._scale_to_unit(g.T, u[self.ops.elements[:, 0]], weights).T

    def _scale_to_unit(self, g, u_first, weights):
        """Turn heat gradients into ``-weights * g / |g|`` in place (0 where they vanish or are noise).

        ``g`` holds the gradient's components axis first: ``(dim, n_elements)``,
        or ``(dim, k, n_elements)`` for ``k`` heat fields at once (each gets
        exactly the arithmetic of one); ``u_first`` is the heat at each
        element's first vertex, ``(n_elements,)`` or ``(k, n_elements)``.
        Returns ``g`` (a new array where non-finite gradients were zeroed).
        """
        norm2 = _squared_row_norms(g)
        if not np.isfinite(norm2.sum()):  # rare: a non-finite gradient gets no direction
            g = np.where(np.isfinite(g), g, 0.0)
            norm2 = _squared_row_norms(g)
        norm = np.sqrt(norm2)
        # Far from the sources u (and so g) can be 1e-200, whose square
        # underflows: recompute those norms with hypot, which does not.
        tiny = np.nonzero(norm2 < 1e-280)
        if tiny[0].size:
            redo = np.hypot(g[0][tiny], g[1][tiny])
            for axis in range(2, len(g)):
                redo = np.hypot(redo, g[axis][tiny])
            norm[tiny] = np.where(redo > 0, redo, np.inf)  # a zero gradient gets X = 0
        # A gradient below the rounding of u itself (an exact saddle of the heat, as at the far point
        # of a symmetric part: 2e-15 of u per edge length there, 5e-3 and more elsewhere) has no
        # direction: X = 0 there, not a direction made of rounding noise that any change of
        # elimination order (another part beside it) would turn elsewhere.
        norm[norm * self._element_h < SADDLE_GRADIENT * u_first] = np.inf
        scale = np.negative(weights) / norm
        for component in g:  # axis by axis: 3x faster than broadcasting over rows of 2 or 3
            component *= scale
        return g

    def _factor_heat(self, backend):
        """Factor ``M + t L`` for the boundary condition (Neumann, interior-only Dirichlet, or both)."""
        ops = self.ops
        step = self._time_step
        heat_matrix = (sp.diags(ops.mass) + (step * ops.laplacian if np.ndim(step) == 0 else sp.diags(step) @ ops.laplacian)).tocsr()
        self._heat_dirichlet = None
        if self.boundary in ("robin", "dirichlet"):
            self._interior = np.flatnonzero(~ops.boundary)
            if self._interior.size:
                ordering = restrict_ordering(self._ordering(backend), self._interior)
                interior_matrix = heat_matrix[self._interior][:, self._interior]
                self._heat_dirichlet = factor(interior_matrix, backend, ordering=ordering)
        # Neumann: the condition itself, half of Robin, or the fallback where Dirichlet sees no heat.
        self._heat_neumann = factor(heat_matrix, backend, ordering=self._ordering(backend))

    def _resolve(self, backend, prefer):
        """The backend that ``backend`` stands for on this domain's matrices."""
        return choose_backend(self.ops.n_vertices, prefer) if backend == "auto" else backend

    def _ordering(self, backend):
        """The fill-reducing ordering ``backend`` uses on this domain's matrices (cached on the domain)."""
        if ("ordering", backend) not in self._domain_cache:
            self._domain_cache["ordering", backend] = fill_reducing_ordering(self._laplacian, backend)
        return self._domain_cache["ordering", backend]

    def _laplacian_ordering(self, backend):
        """The best ordering at hand for the Laplacian: nested dissection where it was started, else the quick one."""
        nested = self._domain_cache.get(("nested", backend))
        if isinstance(nested, Future):
            try:
                nested = self._ordering(backend).reordered(nested.result())
            except SolverError as exc:  # pragma: no cover - METIS ran out of memory, say
                log.warning("%s; using the minimum degree ordering", exc)
                nested = None
            self._domain_cache["nested", backend] = nested
        return nested or self._ordering(backend)

    def _solve_grounded(self, rhs):
        """Solve ``L x = rhs`` per component with ``x = 0`` at each component's ground vertex."""
        rhs[self._ground] = 0.0  # callers pass arrays of their own
        return self._poisson.solve(rhs)

    def _pinned_poisson(self, b, pins, reached):
        """Minimize the Dirichlet-energy misfit with ``phi[pins.vertices] = pins.values``."""
        P, d = pins.vertices, pins.values
        if P.size > MAX_PRECOMPUTED_PINS:
            everywhere = np.ones(self.ops.n_vertices, dtype=bool)
            return self._factor_pinned(b, P, d, everywhere if reached is None else reached)
        return self._apply_pins(self._solve_grounded(b), P, d, self._unit_responses)

    def _unit_responses(self, vertices):
        """Grounded solutions ``L^-1 e_v`` for the operator vertices ``v``, as columns."""
        E = np.zeros((self.ops.n_vertices, vertices.size))
        E[vertices, np.arange(vertices.size)] = 1.0
        return self._solve_grounded(E)  # column j is zero outside the component of its vertex

    def _several_pins(self, P):
        """The pins of ``P`` that share their component with another pin (mask), and each pin's component."""
        comp_of_pin = self.component[P]
        _, local, count = np.unique(comp_of_pin, return_inverse=True, return_counts=True)
        return count[local] > 1, comp_of_pin

    def _apply_pins(self, psi, P, d, responses):
        """Make the grounded solution ``psi`` take the values ``d`` at the pins ``P`` (in place).

        ``responses(vertices)`` gives :meth:`_unit_responses` of the pins that
        share a component with another pin.
        """
        # One pin in a component: a shift. Several: point loads mu at its pins and a constant,
        # one small dense system per component, so that no rounding crosses parts.
        multiple, comp_of_pin = self._several_pins(P)
        single = ~multiple
        shift = np.zeros(self.n_components)
        shift[comp_of_pin[single]] = d[single] - psi[P[single]]
        several = np.flatnonzero(multiple)
        if several.size:
            Z = responses(P[several])
            mu = np.zeros(several.size)
            for c in np.unique(comp_of_pin[several]):
                cols = np.flatnonzero(comp_of_pin[several] == c)
                k = cols.size
                A = np.zeros((k + 1, k + 1))
                A[:k, :k] = Z[P[several[cols]]][:, cols]
                A[:k, k] = A[k, :k] = 1.0
                sol = np.linalg.lstsq(A, np.r_[d[several[cols]] - psi[P[several[cols]]], 0.0], rcond=None)[0]
                mu[cols], shift[c] = sol[:k], sol[k]
            psi += Z @ mu
        psi += shift[self.component] if self.n_components > 1 else shift[0]
        return psi

    def _factor_pinned(self, b, P, d, reached):
        """Pinned Poisson solve with a factorization of its own (many pinned vertices)."""
        phi = np.zeros(self.ops.n_vertices)
        phi[P] = d
        free = reached.copy()
        free[P] = False
        idx = np.flatnonzero(free)
        if idx.size:
            L = self._laplacian
            rhs = b[idx] - L[idx][:, P] @ d
            backend = self._resolve(self._backend, "factor")
            ordering = restrict_ordering(self._laplacian_ordering(backend), idx)
            phi[idx] = factor(L[idx][:, idx], backend, ordering=ordering).solve(rhs)
        return phi


def domain_factors(domain):
    """The factorizations and orderings kept for ``domain``, shared by every solver built on it.

    They depend on the domain only (not on ``m`` or the boundary condition),
    live as long as the domain does, and are kept here, not on the domain.

    Examples
    --------
    >>> import numpy as np, heatcore as hc
    >>> mesh = hc.TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0)
    >>> _ = hc.HeatSolver(mesh)
    >>> sorted({key for key, _ in domain_factors(mesh)})
    ['nested', 'ordering', 'poisson']
    """
    return _DOMAIN_FACTORS.setdefault(domain, {})


def _squared_row_norms(g):
    """``(g**2).sum(axis=0)`` for a few components, component by component (twice as fast as over rows)."""
    norm2 = g[0] * g[0]
    for component in g[1:]:
        norm2 += component * component
    return norm2


def _source_sequence(sources_block):
    """The sources of a block as a list; a typed error for anything that is not a sequence of sources."""
    single = isinstance(sources_block, (str, bytes, Mapping, SourcePins)) or not isinstance(sources_block, Iterable)
    if single or isinstance(sources_block, np.ndarray) and sources_block.ndim == 0:
        raise InvalidSourceError(
            f"sources_block must be a sequence of sources (one per row), got {type(sources_block).__name__}; "
            "for one source use distance()"
        )
    return list(sources_block)


def _solve_columns(factor, rhs):
    """``factor.solve(rhs)``; ``(n, k)`` in calls of ``EXACT_SOLVE_COLUMNS`` columns, or one by one (supernodal)."""
    width = 1 if getattr(factor, "backend", None) in ONE_COLUMN_BACKENDS else EXACT_SOLVE_COLUMNS
    if rhs.ndim == 1 or 1 < rhs.shape[1] <= width:
        return factor.solve(rhs)
    out = np.empty(rhs.shape, order="F")
    for start in range(0, rhs.shape[1], width):
        if width == 1:
            out[:, start] = factor.solve(rhs[:, start])  # one dimension: what takes the sparse path
        else:
            out[:, start : start + width] = factor.solve(rhs[:, start : start + width])
    return out


def _component_sums(component, values, n_components):
    """Sums of ``values`` ((n,) or (n, k)) over each component: (n_components,) or (n_components, k)."""
    if values.ndim == 1:
        return np.bincount(component, weights=values, minlength=n_components)
    k = values.shape[1]
    index = (component[:, None] * k + np.arange(k)).ravel()
    return np.bincount(index, weights=values.ravel(), minlength=n_components * k).reshape(n_components, k)


def _grounded(L, ground):
    """``L`` with the rows and columns of the ground vertices replaced by the identity.

    Solving with it gives ``x = 0`` at the ground vertices and ``L x = b``
    elsewhere; it is positive definite when each component has one ground.
    The sparsity pattern of ``L`` is kept (explicit zeros), so that it shares
    ``L``'s fill-reducing ordering and converted pattern.
    """
    K = sp.csr_matrix(L, copy=True)
    K.sum_duplicates()
    is_ground = np.zeros(K.shape[0], dtype=bool)
    is_ground[ground] = True
    rows = np.repeat(np.arange(K.shape[0]), np.diff(K.indptr))
    K.data[is_ground[rows] | is_ground[K.indices]] = 0.0
    on_ground_diagonal = (rows == K.indices) & is_ground[rows]
    if on_ground_diagonal.sum() == ground.size:
        K.data[on_ground_diagonal] = 1.0
        return K
    return (K + sp.diags(is_ground.astype(float))).tocsr()  # a ground without a diagonal entry


#: Decimal orders of magnitude the heat may fall over the mesh: double
#: precision underflows near 1e-308, and the heat must stay well above it.
HEAT_DECADES_BUDGET = 250.0
#: Decimal orders of magnitude the heat falls per edge hop, relative to the 1D
#: backward-Euler rate; measured on intrinsic Delaunay meshes (0.55 decades per
#: hop at m = 1, where the 1D rate is 0.42).
HOP_DECAY_FACTOR = 1.3


def heat_decay_per_hop(m):
    """Decimal orders of magnitude one backward-Euler heat step of ``t = m h^2`` falls per hop (1D).

    Parameters
    ----------
    m : float or float array
        Time factor (unitless).

    Returns
    -------
    float or float array
        ``-log10`` of the heat's ratio between neighbouring vertices of a 1D grid.

    Examples
    --------
    >>> round(float(heat_decay_per_hop(1.0)), 3)
    0.418
    >>> bool(heat_decay_per_hop(10.0) < heat_decay_per_hop(1.0))  # a longer step spreads the heat further
    True
    """
    ratio = 2 * m / ((1 + 2 * m) + np.sqrt(1 + 4 * m))  # root of m r^2 - (1 + 2m) r + m = 0
    return -np.log10(ratio)


def underflow_safe_m(hop_diameter, budget=HEAT_DECADES_BUDGET):
    """Smallest time factor keeping the heat representable across ``hop_diameter`` hops.

    With ``t = m h^2`` the heat falls by a constant factor per edge hop (about
    0.38 in 1D at m = 1), so on a mesh hundreds of hops across it underflows
    double precision and its gradient is noise. This returns the smallest
    ``m`` whose decay over the diameter stays within ``budget`` decades.

    Parameters
    ----------
    hop_diameter : int or array of int
        Edge hops across (one value per component).
    budget : float
        Decimal orders of magnitude the heat may fall.

    Returns
    -------
    float, or a float array of the shape of ``hop_diameter``

    Examples
    --------
    >>> bool(underflow_safe_m(300) < 1.0)
    True
    >>> round(float(underflow_safe_m(700)), 2)
    2.42
    >>> underflow_safe_m(np.array([300, 700])).round(2).tolist()
    [0.38, 2.42]
    """
    hops = np.asarray(hop_diameter, dtype=float)

    def too_cold(m):
        return hops * HOP_DECAY_FACTOR * heat_decay_per_hop(m) > budget

    lo, hi = np.full(hops.shape, 1e-9), np.ones(hops.shape)
    while too_cold(hi).any():
        grow = too_cold(hi)
        lo, hi = np.where(grow, hi, lo), np.where(grow, 2.0 * hi, hi)
    for _ in range(60):  # bisection on log m; the decay falls as m grows
        mid = np.sqrt(lo * hi)
        cold = too_cold(mid)
        lo, hi = np.where(cold, mid, lo), np.where(cold, hi, mid)
    return float(hi) if hi.ndim == 0 else hi
