"""Step 1 of the heat method: one backward Euler step of heat, ``(M + t L) u = impulse``.

:class:`HeatFlow` holds the factorizations of the heat matrix for the
solver's boundary condition (Neumann; Dirichlet on the interior vertices; Robin
as the mean of the two) and solves for any impulse. Under the Robin condition,
heat that lies all on the boundary (the Dirichlet solve sees none of it) takes
the Robin heat of :mod:`heatcore.steps.boundary_source` where the domain gives a
boundary surface (tet meshes), else the Neumann heat.

Examples
--------
>>> import numpy as np, scipy.sparse as sp
>>> from heatcore.linalg import factor
>>> A = sp.csr_matrix(np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 2.0]]))
>>> flow = HeatFlow(factor(A), None, None, "neumann", np.zeros(3, int), 1)
>>> bool(np.allclose(A @ flow.solve(np.array([0.25, 0.75, 0.0])), [0.25, 0.75, 0.0]))
True
"""

import numpy as np

from ..linalg import solve_columns


class HeatFlow:
    """The heat step of one solver: its factorizations and boundary condition.

    Parameters
    ----------
    neumann : Factor
        Of ``M + t L`` on every vertex (the Neumann condition; half of Robin,
        and the fallback where Dirichlet sees no heat).
    dirichlet : Factor or None
        Of ``M + t L`` restricted to the ``interior`` vertices (Robin and
        Dirichlet conditions; None: no interior vertex, or Neumann).
    interior : (k,) int array or None
        The vertices not on the boundary.
    boundary : {"neumann", "robin", "dirichlet"}
    component : (n,) int array
        Connected component of each vertex.
    n_components : int
    boundary_source : BoundarySourceHeat, optional
        The heat of sources on the boundary under the Robin condition (default: the Neumann heat).

    Examples
    --------
    >>> import heatcore as hc
    >>> flow = hc.HeatSolver(hc.TriangleMesh(*hc.io.load_demo_mesh())).heat_flow
    >>> flow.boundary, flow.neumann.backend in ("supernodal", "qdldl", "cholmod", "superlu")
    ('neumann', True)
    """

    def __init__(self, neumann, dirichlet, interior, boundary, component, n_components, boundary_source=None):
        self.neumann = neumann
        self.dirichlet = dirichlet
        self.interior = interior
        self.boundary = boundary
        self.component = component
        self.n_components = n_components
        self.boundary_source = boundary_source

    def solve(self, impulse):
        """Heat after one step from ``impulse`` ((n,), or (n, k): k columns at once)."""
        return self._combine(*self._parts(impulse), impulse)

    def _parts(self, impulse):
        """The Neumann heat, and the Dirichlet heat (0 on the boundary; None under the Neumann condition)."""
        u_neumann = solve_columns(self.neumann, impulse)
        if self.boundary == "neumann":
            return u_neumann, None
        u_dirichlet = np.zeros_like(impulse)
        if self.dirichlet is not None and impulse[self.interior].any():  # else all heat is on the boundary
            u_dirichlet[self.interior] = solve_columns(self.dirichlet, impulse[self.interior])
        return u_neumann, u_dirichlet

    def _combine(self, u_neumann, u_dirichlet, impulse):
        """The heat of the boundary condition from its parts (see :meth:`_parts`)."""
        if u_dirichlet is None:
            return u_neumann
        # A component whose heat all sits on the boundary gets none under Dirichlet conditions: use
        # the Neumann solution there, or under Robin the Robin heat of steps.boundary_source.
        fallback = (component_sums(self.component, np.abs(u_dirichlet), self.n_components) == 0)[self.component]
        u = 0.5 * (u_dirichlet + u_neumann) if self.boundary == "robin" else u_dirichlet
        if self.boundary == "robin" and self.boundary_source is not None:
            u_neumann = self.boundary_source.heat(impulse, u_neumann, fallback)
        u[fallback] = u_neumann[fallback]
        return u


def component_sums(component, values, n_components):
    """Sums of ``values`` ((n,) or (n, k)) over each component: (n_components,) or (n_components, k).

    Examples
    --------
    >>> component_sums(np.array([0, 1, 0]), np.array([1.0, 2.0, 3.0]), 2).tolist()
    [4.0, 2.0]
    """
    if values.ndim == 1:
        return np.bincount(component, weights=values, minlength=n_components)
    k = values.shape[1]
    index = (component[:, None] * k + np.arange(k)).ravel()
    return np.bincount(index, weights=values.ravel(), minlength=n_components * k).reshape(n_components, k)
