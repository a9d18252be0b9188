"""CHOLMOD's Cholesky factorization through cholespy: the fastest solves.

For matrices kept for many solves below the supernodal backend's sizes (the
Poisson factor of a mesh under 100k vertices), and for large matrices where
cvxopt is not installed. cholespy is imported on first use.

Examples
--------
>>> import numpy as np, scipy.sparse as sp
>>> A = sp.csc_matrix([[4.0, 1.0], [1.0, 3.0]])
>>> x = CholmodFactor(A).solve([1.0, 2.0])
>>> bool(np.allclose(A @ x, [1.0, 2.0]))
True
"""

import numpy as np
import scipy.sparse as sp

from ..errors import SolverError
from .interface import Factor
from .libraries import optional


class CholmodFactor(Factor):
    """A Cholesky factor held by cholespy (which takes ``(n,)`` and ``(n, k)`` right-hand sides).

    Parameters
    ----------
    A : (n, n) sparse symmetric positive definite matrix
    ordering : ignored
        CHOLMOD orders the matrix itself.

    Raises
    ------
    SolverError
        ``A`` is not positive definite, or cholespy is not installed.

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> CholmodFactor(sp.diags([2.0, 4.0]).tocsc()).solve(np.ones((2, 3)))[:, 0]
    array([0.5 , 0.25])
    """

    backend = "cholmod"

    def __init__(self, A, ordering=None):
        cholespy = optional("cholespy")
        if cholespy is None:
            raise SolverError("backend 'cholmod' needs the cholespy package")
        A = sp.csc_matrix(A)
        A.sum_duplicates()
        A.sort_indices()
        self.n = A.shape[0]
        try:
            self._solver = cholespy.CholeskySolverD(
                self.n,
                A.indptr.astype(np.int32),
                A.indices.astype(np.int32),
                A.data.astype(np.float64),
                cholespy.MatrixType.CSC,
            )
        except (ValueError, RuntimeError) as exc:
            raise SolverError(f"sparse Cholesky factorization failed: {exc}") from exc

    def _solve(self, b):
        b = np.ascontiguousarray(b)  # cholespy takes C-ordered arrays only
        x = np.empty_like(b)
        self._solver.solve(b, x)
        return x
