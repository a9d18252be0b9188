"""Heat from sources on the boundary: a Robin condition, shaped by the source, that keeps their heat.

The default boundary condition is the mean of the Neumann and the
Dirichlet heat (:mod:`heatcore.steps.heat_flow`). Heat injected at a boundary vertex is
all lost by the Dirichlet solve (the boundary is held at 0), so for a source
on the boundary that mean falls back to pure Neumann heat, whose gradient runs
along every wall, also along walls the distance leaves at an angle: the
distance comes out too long there (docs/tet.md). For such sources, on domains
whose operators give a ``boundary_surface`` (tet meshes),
:class:`BoundarySourceHeat` solves a Robin problem instead::

    (M + t L + t B) u = impulse,   du/dn + kappa u = 0 on the boundary,

``B`` the boundary mass weighted by ``kappa``. The coefficient follows the
source: one backward-Euler heat step decays like ``exp(-d / sqrt(t))`` away
from it, so on a wall ``du/dn = -(n . grad d) u / sqrt(t)``, and

    kappa(x) = c max(0, n . (x - s) / |x - s|) / sqrt(t)

with ``s`` the source vertex nearest to ``x`` and ``n`` the wall's outward
normal (per boundary triangle): 0 on a wall through the source (the rays run
along it, Neumann is exact there), ``c / sqrt(t)`` on a wall that faces it.
``c`` is :data:`ROBIN_COEFFICIENT` (measured; the model says 1).

The matrix depends on the source, so it is not factored: ``B`` is a small
diagonal on the boundary, and conjugate gradients preconditioned with the
Neumann factor converge in a few iterations (:data:`ROBIN_TOLERANCE`), each
one more pair of triangular solves and a sparse product. No factorization and
no memory beyond a few vectors; interior sources never come here.

Examples
--------
>>> import numpy as np, heatcore as hc
>>> from heatcore.domains.tet import TetMesh
>>> from scipy.spatial import Delaunay
>>> P = np.random.default_rng(0).normal(size=(600, 3))
>>> P[:200] /= np.linalg.norm(P[:200], axis=1)[:, None]           # a ball: 200 points on the sphere
>>> P[200:] *= 0.9 / np.linalg.norm(P[200:], axis=1).max()
>>> mesh = TetMesh(P, Delaunay(P).simplices)
>>> pole = int(np.argmax(P[:, 2]))                                 # a source on the boundary
>>> exact = np.linalg.norm(P - P[pole], axis=1)
>>> def error(solver):
...     d = solver.distance([pole])
...     return round(float(np.mean(np.abs(d - exact)[exact > 0] / exact[exact > 0])), 3)
>>> error(hc.HeatSolver(mesh)), error(hc.HeatSolver(mesh, boundary="dirichlet"))  # Robin; Neumann heat (as before)
(0.026, 0.044)
"""

import numpy as np
from scipy.spatial import cKDTree

from ..linalg import solve_columns

#: ``c`` in the Robin coefficient ``kappa = c cos / sqrt(t)``. Measured on
#: boundary sources of a jittered cube (face, edge, corner), an L prism (three
#: walls), a ball (pole) and Delaunay meshes of random points: 0.5 is best on
#: the random meshes, 1 on the L prism's floor, 0.75 keeps all near their best (docs/tet.md).
ROBIN_COEFFICIENT = 0.75

#: Conjugate gradients stop when no vertex's heat changes by more than this
#: fraction in an iteration (the heat falls by orders of magnitude across the
#: mesh, and the unit field needs its direction everywhere: a residual norm would
#: stop before the far heat is right), or after :data:`ROBIN_MAX_ITERATIONS`
#: (measured: the distance's error settles after 3-4 iterations). A boundary
#: source's query then costs 5 Neumann solves instead of one Neumann and one
#: Dirichlet solve: 2-4x an interior source's query (docs/tet.md).
ROBIN_TOLERANCE = 1e-2
ROBIN_MAX_ITERATIONS = 4


class BoundarySourceHeat:
    """Robin heat for sources with no heat inside the domain (see the module docstring).

    Parameters
    ----------
    ops : Operators
        The domain's operators; without ``boundary_surface`` the Neumann heat is used.
    laplacian : (n, n) sparse matrix
        ``ops.laplacian`` as CSR.
    time_step : float or (n,) float array
        ``t`` (per vertex where the components differ).
    neumann : Factor
        The factor of ``M + t L`` (the preconditioner).

    Examples
    --------
    >>> import numpy as np, scipy.sparse as sp
    >>> from heatcore.domains.tet import TetMesh
    >>> from heatcore.linalg import factor
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    >>> ops = TetMesh(V, [[0, 1, 2, 3]]).operators
    >>> neumann = factor((sp.diags(ops.mass) + ops.laplacian).tocsr(), "superlu")
    >>> impulse = np.array([1.0, 0, 0, 0])
    >>> u_neumann = neumann.solve(impulse)
    >>> u = BoundarySourceHeat(ops, ops.laplacian.tocsr(), 1.0, neumann).heat(impulse, u_neumann, np.ones(4, bool))
    >>> bool(u.sum() < u_neumann.sum())    # heat left through the walls facing the source
    True
    """

    def __init__(self, ops, laplacian, time_step, neumann):
        self.surface = getattr(ops, "boundary_surface", None)
        self._ops = ops
        self._laplacian = laplacian
        self._time_step = time_step
        self._neumann = neumann
        self.iterations = 0  # of the last Robin solve

    def heat(self, impulse, u_neumann, cold):
        """The heat to use where ``cold`` (entries whose component has no heat inside), ``(n,)`` or ``(n, k)``.

        ``u_neumann`` itself where the domain gives no boundary surface; else a
        copy whose columns with a cold source hold the Robin heat.
        """
        if self.surface is None or not cold.any():
            return u_neumann
        u = u_neumann.copy()
        if impulse.ndim == 1:
            u[:] = self.robin(impulse, u_neumann, cold)
            return u
        for j in np.flatnonzero(cold.any(axis=0)):
            u[:, j] = self.robin(np.ascontiguousarray(impulse[:, j]), np.ascontiguousarray(u_neumann[:, j]), cold[:, j])
        return u

    def robin(self, impulse, u_neumann, cold):
        """Robin heat of one column: conjugate gradients on ``(A + D) u = impulse`` from ``u_neumann = A^-1 impulse``."""
        sources = np.flatnonzero((impulse != 0) & cold)
        if sources.size == 0:
            return u_neumann
        leak = self.leak(sources)
        step, L, mass = self._time_step, self._laplacian, self._ops.mass
        u = u_neumann.copy()
        r = -leak * u  # impulse - (A + D) u, with A u = impulse
        z = solve_columns(self._neumann, r)
        p, rz = z.copy(), float(r @ z)
        for self.iterations in range(1, ROBIN_MAX_ITERATIONS + 1):
            Ap = mass * p + step * (L @ p) + leak * p
            curvature = float(p @ Ap)
            if not curvature > 0:  # converged to round-off
                break
            alpha = rz / curvature
            u += alpha * p
            if self.iterations == ROBIN_MAX_ITERATIONS or np.all(np.abs(alpha * p) <= ROBIN_TOLERANCE * np.abs(u)):
                break  # (no solve for a direction that would not be used)
            r -= alpha * Ap
            z = solve_columns(self._neumann, r)
            rz, previous = float(r @ z), rz
            p = z + (rz / previous) * p
        return u

    def leak(self, sources):
        """The diagonal ``t B``: ``c sqrt(t) sum_f max(0, a_f . (x - s) / |x - s|) / 3`` per vertex ``x`` of boundary triangles ``f``.

        ``a_f`` the triangle's outward area vector, ``s`` the source vertex nearest to ``x``.
        """
        surface = self.surface
        corners = surface.faces.ravel()
        x = surface.positions[corners]
        if sources.size == 1:
            ray = x - surface.positions[sources[0]]
        else:
            _, nearest = cKDTree(surface.positions[sources]).query(x)
            ray = x - surface.positions[sources[nearest]]
        length = np.linalg.norm(ray, axis=1)
        facing = np.einsum("ij,ij->i", ray, np.repeat(surface.area_vectors, 3, axis=0))
        cosine_area = np.divide(np.maximum(facing, 0.0), 3.0 * length, out=np.zeros_like(length), where=length > 0)
        total = np.bincount(corners, weights=cosine_area, minlength=self._ops.n_vertices)
        return ROBIN_COEFFICIENT * np.sqrt(self._time_step) * total
