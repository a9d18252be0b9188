"""Step 3 of the heat method: the Poisson equation ``L phi = -div X`` with every source pinned.

The Laplacian is singular on each connected component (constants), so it is
factored once *grounded*: one vertex per component held at 0
(:func:`grounded`). A query then solves the grounded system and makes the
solution take the known distances at the pinned vertices: a shift where a
component has one pin, and where it has several, point loads at its pins and a
constant (one small dense system per component, so that no rounding crosses
parts). A source of more than ``MAX_PRECOMPUTED_PINS`` pinned vertices gets
a factorization of the pinned system of its own. Several pins cost one solve
per pin more (their unit responses); on a factor with two halves (the
supernodal backend: ``forward``/``backward``) they cost one solve in all
(:meth:`PinnedPoisson._solve_in_halves`). The responses of the most recently
pinned vertices are kept (:class:`~heatcore.steps.column_cache.ColumnCache`;
their forward halves on a factor with two halves): a point source dragged
across neighbouring faces (the Blender add-on's probe) pins the same corners again.

Examples
--------
>>> import numpy as np, scipy.sparse as sp
>>> L = sp.csr_matrix(np.array([[1.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]]))  # a path
>>> from heatcore.linalg import factor
>>> pinned = PinnedPoisson(L, factor(grounded(L, np.array([0]))), np.array([0]), np.zeros(3, int), 1, None)
>>> pinned.apply_pins(pinned.solve_grounded(np.zeros(3)), np.array([2]), np.array([5.0])).tolist()
[5.0, 5.0, 5.0]
"""

import numpy as np
import scipy.sparse as sp

from ..linalg import solve_columns
from .column_cache import ColumnCache

#: Up to this many pinned vertices, the pinned Poisson solve reuses the
#: prefactored Laplacian (one multi-right-hand-side solve); beyond, it factors
#: the pinned system for that query.
MAX_PRECOMPUTED_PINS = 256


def grounded(L, ground):
    """``L`` with the rows and columns of the ground vertices replaced by the identity.

    Solving with it gives ``x = 0`` at the ground vertices and ``L x = b``
    elsewhere; it is positive definite when each component has one ground.
    The sparsity pattern of ``L`` is kept (explicit zeros), so that it shares
    ``L``'s fill-reducing ordering and converted pattern.

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> L = sp.csr_matrix(np.array([[1.0, -1.0], [-1.0, 1.0]]))
    >>> grounded(L, np.array([0])).toarray().tolist()
    [[1.0, 0.0], [0.0, 1.0]]
    """
    K = sp.csr_matrix(L, copy=True)
    K.sum_duplicates()
    is_ground = np.zeros(K.shape[0], dtype=bool)
    is_ground[ground] = True
    # The entries of the ground rows, found from their row pointers (not by a row index per entry).
    counts = np.diff(K.indptr)[ground]
    before = np.concatenate(([0], np.cumsum(counts)[:-1]))
    in_rows = np.repeat(K.indptr[ground] - before, counts) + np.arange(counts.sum())
    K.data[is_ground[K.indices]] = 0.0
    K.data[in_rows] = 0.0
    on_ground_diagonal = in_rows[K.indices[in_rows] == np.repeat(ground, counts)]
    if on_ground_diagonal.size == ground.size:
        K.data[on_ground_diagonal] = 1.0
        return K
    return (K + sp.diags(is_ground.astype(float))).tocsr()  # a ground without a diagonal entry


class PinnedPoisson:
    """The Poisson step of one solver: its grounded factor, and pins applied per query.

    Parameters
    ----------
    laplacian : (n, n) sparse matrix
    factor : Factor
        Of :func:`grounded` ``(laplacian, ground)``.
    ground : (n_components,) int array
        One vertex per component, held at 0 by ``factor``.
    component : (n,) int array
        Component of each vertex.
    n_components : int
    factor_free : callable or None
        ``factor_free(free)`` factors ``laplacian[free][:, free]`` (sources of
        more than ``MAX_PRECOMPUTED_PINS`` pinned vertices); None: never needed.

    Examples
    --------
    >>> import heatcore as hc
    >>> solver = hc.HeatSolver(hc.TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0))
    >>> isinstance(solver.poisson, PinnedPoisson)
    True
    """

    def __init__(self, laplacian, factor, ground, component, n_components, factor_free):
        self.laplacian = laplacian
        self.factor = factor
        self.ground = ground
        self.component = component
        self.n_components = n_components
        self.factor_free = factor_free
        self._responses = ColumnCache(laplacian.shape[0])  # vertex -> its grounded unit response
        self._forward_units = ColumnCache(laplacian.shape[0])  # vertex -> the forward half of it (two-half factors)

    def solve(self, b, pins, reached):
        """``phi`` minimizing the Dirichlet-energy misfit to ``b`` with ``phi[pins.vertices] = pins.values``.

        ``reached``: the vertices of the components the pins are in (None: all).
        """
        P, d = pins.vertices, pins.values
        if P.size > MAX_PRECOMPUTED_PINS:
            everywhere = np.ones(self.laplacian.shape[0], dtype=bool)
            return self._factor_pinned(b, P, d, everywhere if reached is None else reached)
        phi = self._solve_in_halves(b, P, d) if P.size > 1 else None
        if phi is None:
            phi = self.apply_pins(self.solve_grounded(b), P, d)
        phi[P] = d  # exactly
        return phi

    def solve_block(self, b, block):
        """:meth:`solve` of the ``k`` columns of ``b`` (n, k), column ``j`` pinned by ``block[j]``; ``b`` is overwritten.

        One multi-column grounded solve (:func:`heatcore.linalg.solve_columns`), then each column's pins
        (:meth:`apply_pins`). Sources of more than ``MAX_PRECOMPUTED_PINS`` pins go through :meth:`solve`.
        """
        b[self.ground] = 0.0
        phi = solve_columns(self.factor, b)  # as solve_grounded, for every column
        for j, pins in enumerate(block):
            column = phi[:, j]  # a view: pinned in place
            self.apply_pins(column, pins.vertices, pins.values)
            column[pins.vertices] = pins.values  # exactly
        return phi

    def solve_grounded(self, rhs):
        """Solve ``L x = rhs`` per component with ``x = 0`` at each component's ground vertex (``rhs`` is overwritten)."""
        rhs[self.ground] = 0.0  # callers pass arrays of their own
        return self.factor.solve(rhs)

    def unit_responses(self, vertices):
        """Grounded solutions ``L^-1 e_v`` for the vertices ``v``, as columns.

        Columns of recently pinned vertices are reused; the others are solved
        together and kept (:class:`~heatcore.steps.column_cache.ColumnCache`).

        Examples
        --------
        >>> import heatcore as hc
        >>> poisson = hc.HeatSolver(hc.TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0)).poisson
        >>> Z = poisson.unit_responses(np.array([1, 2]))
        >>> Z.shape, bool((poisson.unit_responses(np.array([2]))[:, 0] == Z[:, 1]).all())
        ((3, 2), True)
        """
        return self._responses.columns(vertices, self._solve_units)

    def _solve_units(self, vertices):
        E = np.zeros((self.laplacian.shape[0], vertices.size))
        E[vertices, np.arange(vertices.size)] = 1.0
        return self.solve_grounded(E)  # column j is zero outside the component of its vertex

    def apply_pins(self, psi, P, d):
        """Make the grounded solution ``psi`` take the values ``d`` at the pins ``P`` (in place); returns ``psi``."""
        # One pin in a component: a shift. Several: point loads mu at its pins and a constant,
        # one small dense system per component, so that no rounding crosses parts.
        if P.size == 1 and self.n_components == 1:  # the shift of _pin_loads, without its bookkeeping
            psi += d[0] - psi[P[0]]
            return psi
        several = self._several(P)
        Z = self.unit_responses(P[several]) if several.size else None
        mu, shift = self._pin_loads(psi[P], None if Z is None else Z[P[several]], P, d, several)
        if several.size:
            psi += Z @ mu
        psi += shift[self.component] if self.n_components > 1 else shift[0]
        return psi

    def _several(self, P):
        """Positions in ``P`` of the pins that share their component with another pin."""
        _, local, count = np.unique(self.component[P], return_inverse=True, return_counts=True)
        return np.flatnonzero(count[local] > 1)

    def _pin_loads(self, psi_at_pins, responses, P, d, several):
        """Point loads ``mu`` at the pins ``P[several]`` and the shift of each component that give the pinned values.

        ``psi_at_pins``: the grounded solution at ``P``; ``responses``: the pins'
        unit responses at the pins ``P[several]`` (a square block).
        """
        comp_of_pin = self.component[P]
        shift = np.zeros(self.n_components)
        single = np.ones(P.size, dtype=bool)
        single[several] = False
        shift[comp_of_pin[single]] = d[single] - psi_at_pins[single]
        mu = np.zeros(several.size)
        for c in np.unique(comp_of_pin[several]):
            cols = np.flatnonzero(comp_of_pin[several] == c)
            k = cols.size
            A = np.zeros((k + 1, k + 1))
            A[:k, :k] = responses[np.ix_(cols, cols)]
            A[:k, k] = A[k, :k] = 1.0
            rows = several[cols]
            sol = np.linalg.lstsq(A, np.r_[d[rows] - psi_at_pins[rows], 0.0], rcond=None)[0]
            mu[cols], shift[c] = sol[:k], sol[k]
        return mu, shift

    def _solve_in_halves(self, b, P, d):
        """:meth:`solve` of several pins with the factor's two halves, ``K = P^T L L^T P``: one solve in all.

        With ``y = L^-1 P b`` and ``u_v = L^-1 P e_v`` (a sparse forward solve
        per pin), the grounded solution at the pins is ``u_v . y`` and the pins'
        unit responses there are ``u_v . u_w``; the point loads ``mu`` follow as
        in :meth:`apply_pins`, and one backward solve of ``y + sum mu_v u_v``
        gives the result: the cost of one solve, where :meth:`apply_pins` adds a
        full solve per pin. Returns None where the factor has no halves or the
        pins' forward solves are more than their cache keeps.
        """
        forward, backward = getattr(self.factor, "forward", None), getattr(self.factor, "backward", None)
        if forward is None or backward is None or P.size > self._forward_units.keep:
            return None
        b[self.ground] = 0.0
        y = forward(b)
        U = self._forward_units.columns(P, self._forward_halves)  # kept: a dragged point pins again
        several = self._several(P)
        loaded = U if several.size == P.size else U[:, several]
        mu, shift = self._pin_loads(U.T @ y, loaded.T @ loaded, P, d, several)
        y += loaded @ mu
        x = backward(y)
        x += shift[self.component] if self.n_components > 1 else shift[0]
        return x

    def _forward_halves(self, vertices):
        """``L^-1 P e_v`` per vertex (sparse forward solves), as columns; 0 for a ground vertex (held at 0)."""
        n = self.laplacian.shape[0]
        grounded = np.zeros(n, dtype=bool)
        grounded[self.ground] = True
        U = np.zeros((n, vertices.size), order="F")
        unit = np.zeros(n)
        for j, v in enumerate(vertices.tolist()):
            if not grounded[v]:
                unit[v] = 1.0
                U[:, j] = self.factor.forward(unit)
                unit[v] = 0.0
        return U

    def _factor_pinned(self, b, P, d, reached):
        """Pinned Poisson solve with a factorization of its own (many pinned vertices)."""
        phi = np.zeros(self.laplacian.shape[0])
        phi[P] = d
        free = reached.copy()
        free[P] = False
        idx = np.flatnonzero(free)
        if idx.size:
            L = self.laplacian
            rhs = b[idx] - L[idx][:, P] @ d
            phi[idx] = self.factor_free(idx).solve(rhs)
        return phi
