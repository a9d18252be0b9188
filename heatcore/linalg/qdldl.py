"""Simplicial LDL^T factorization with AMD ordering, through qdldl: a fast factorization.

For small and medium matrices rebuilt often (nefertiti's heat matrix, 50k
vertices: 0.14 s against 0.30 s for the ``cholmod`` backend), with slower
solves (3.6 ms against 2.8 ms). qdldl solves one right-hand side at a time:
several are solved column by column. qdldl is imported on first use.

Examples
--------
>>> import numpy as np, scipy.sparse as sp
>>> A = sp.csc_matrix([[4.0, 1.0], [1.0, 3.0]])
>>> x = QDLDLFactor(A).solve([1.0, 2.0])
>>> bool(np.allclose(A @ x, [1.0, 2.0]))
True
"""

import scipy.sparse as sp

from ..errors import SolverError
from .interface import Factor
from .libraries import optional


class QDLDLFactor(Factor):
    """An LDL^T factor held by qdldl.

    Parameters
    ----------
    A : (n, n) sparse symmetric positive definite matrix
        Only its upper triangle is read.
    ordering : ignored
        qdldl orders the matrix itself (AMD).

    Raises
    ------
    SolverError
        The factorization fails, or qdldl is not installed.

    Examples
    --------
    >>> import numpy as np, scipy.sparse as sp
    >>> QDLDLFactor(sp.diags([2.0, 4.0]).tocsc()).solve(np.ones((2, 2)))
    array([[0.5 , 0.5 ],
           [0.25, 0.25]])
    """

    backend = "qdldl"

    def __init__(self, A, ordering=None):
        qdldl = optional("qdldl")
        if qdldl is None:
            raise SolverError("backend 'qdldl' needs the qdldl package")
        A = sp.csc_matrix(A)
        self.n = A.shape[0]
        try:
            self._solver = qdldl.Solver(sp.triu(A, format="csc"), upper=True)
        except (ValueError, RuntimeError) as exc:
            raise SolverError(f"sparse LDL^T factorization failed: {exc}") from exc

    def _solve(self, b):
        return self._solve_columns(b, self._solver.solve)
