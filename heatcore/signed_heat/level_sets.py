"""The last step of the signed heat method: integrate the unit field, with the curves as level sets.

The unit field ``X`` is integrated by the Poisson equation the heat method
solves, ``L phi = G^T (volumes * X)`` (:mod:`heatcore.steps.poisson`). Its
solution is defined up to a constant per connected part; how the curves fix it
is the *level-set constraint* (Feng and Crane 2024, section 5):

- ``"zero"``: every curve point lies on one level set (the zero set): the
  minimizer of the Poisson energy among fields constant on the curves;
- ``"multiple"``: each curve lies on a level set of its own (constants free);
- ``"none"``: no constraint, the plain Poisson solution.

Each point of a curve is a row of ``C`` (its carrying vertices' hat weights).
The constrained minimizer is ``phi = K^-1 (b - C^T mu)`` with ``K`` the
grounded Laplacian the heat method factored, and the loads ``mu`` and level
values ``c`` from the small dense system ``C K^-1 C^T mu + E c = C K^-1 b``,
``E^T mu = 0`` (``E``: which level set each point is on). Curves of vertices
only, on one level set, go through the solver's own pinned solve instead
(:meth:`~heatcore.steps.poisson.PinnedPoisson.solve`: any number of pins).

Examples
--------
>>> import numpy as np, scipy.sparse as sp, heatcore as hc
>>> poisson = hc.HeatSolver(hc.TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0)).poisson
>>> C = sp.csr_matrix(np.array([[0.5, 0.5, 0.0], [0.0, 0.0, 1.0]]))   # a side's midpoint and the third corner
>>> phi = constrained_poisson(poisson, np.array([1.0, -1.0, 0.0]), C, np.zeros(2, int))
>>> bool(abs(np.diff(C @ phi))[0] < 1e-12)   # on one level set
True
"""

from typing import NamedTuple

import numpy as np
import scipy.sparse as sp

#: Level-set constraints, as the option names them.
LEVEL_SETS = ("zero", "multiple", "none")

#: Columns of ``K^-1 C^T`` solved at a time (memory: ``8 n`` bytes each).
CONSTRAINT_COLUMNS = 128


class ZeroPins(NamedTuple):
    """Pins at value 0, in the form :meth:`~heatcore.steps.poisson.PinnedPoisson.solve` takes.

    Examples
    --------
    >>> ZeroPins(np.array([3]), np.zeros(1)).values.tolist()
    [0.0]
    """

    vertices: np.ndarray
    values: np.ndarray


def constraint_rows(carriers, n):
    """The ``(k, n)`` sparse matrix whose row ``j`` reads a field at point ``j`` (its hat weights).

    Examples
    --------
    >>> constraint_rows([(np.array([0, 2]), np.array([0.5, 0.5])), (np.array([1]), np.ones(1))], 3).toarray().tolist()
    [[0.5, 0.0, 0.5], [0.0, 1.0, 0.0]]
    """
    rows = np.repeat(np.arange(len(carriers)), [v.size for v, _ in carriers])
    cols = np.concatenate([v for v, _ in carriers])
    vals = np.concatenate([w for _, w in carriers])
    return sp.csr_matrix((vals, (rows, cols)), shape=(len(carriers), n))


def constrained_poisson(poisson, b, C, level_set):
    """``phi`` minimizing the Poisson energy with the points of each level set at one (free) value.

    Parameters
    ----------
    poisson : PinnedPoisson
        The solver's Poisson step (its grounded factor).
    b : (n,) float array
        Right-hand side ``G^T (volumes * X)``.
    C : (k, n) sparse matrix
        :func:`constraint_rows` of the curve points.
    level_set : (k,) int array
        The level set of each point (0 .. g - 1).

    Returns
    -------
    (n,) float array
        Defined up to one constant per connected part (the caller shifts it).

    Examples
    --------
    >>> import heatcore as hc
    >>> poisson = hc.HeatSolver(hc.TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0)).poisson
    >>> C = sp.csr_matrix(np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]))   # two vertices: pinned together
    >>> phi = constrained_poisson(poisson, np.array([1.0, 0.0, -1.0]), C, np.zeros(2, int))
    >>> bool(abs(phi[0] - phi[1]) < 1e-12)
    True
    """
    C = sp.csr_matrix(C)
    single = np.diff(C.indptr) == 1
    if level_set.max(initial=0) == 0 and single.all() and np.allclose(C.data, 1.0):
        vertices = np.unique(C.indices)
        return poisson.solve(np.array(b, dtype=float), ZeroPins(vertices, np.zeros(vertices.size)), None)
    k, g = C.shape[0], int(level_set.max(initial=0)) + 1
    psi = poisson.solve_grounded(np.array(b, dtype=float))
    CZC = np.empty((k, k))
    for start in range(0, k, CONSTRAINT_COLUMNS):
        block = C[start:start + CONSTRAINT_COLUMNS].T.toarray()
        block[poisson.ground] = 0.0
        CZC[:, start:start + block.shape[1]] = C @ poisson.factor.solve(block)  # one wide solve: no column alone
    E = np.zeros((k, g))
    E[np.arange(k), level_set] = 1.0
    system = np.block([[CZC, E], [E.T, np.zeros((g, g))]])
    loads = np.linalg.lstsq(system, np.r_[C @ psi, np.zeros(g)], rcond=None)[0][:k]
    return poisson.solve_grounded(np.asarray(b - C.T @ loads, dtype=float))
