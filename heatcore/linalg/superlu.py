"""SciPy's SuperLU in symmetric mode: the backend that is always there.

The fallback where none of the others is installed. No pivoting and the
minimum degree ordering of ``A + A^T`` keep it a Cholesky-like factorization
of a symmetric positive definite matrix.

Examples
--------
>>> import numpy as np, scipy.sparse as sp
>>> A = sp.csc_matrix([[4.0, 1.0], [1.0, 3.0]])
>>> x = SuperLUFactor(A).solve([1.0, 2.0])
>>> bool(np.allclose(A @ x, [1.0, 2.0]))
True
"""

import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..errors import SolverError
from .interface import Factor


class SuperLUFactor(Factor):
    """An LU factor held by SciPy's SuperLU (which takes ``(n,)`` and ``(n, k)`` right-hand sides).

    Parameters
    ----------
    A : (n, n) sparse symmetric positive definite matrix
    ordering : ignored
        SuperLU orders the matrix itself.

    Raises
    ------
    SolverError
        The matrix is singular.

    Examples
    --------
    >>> import numpy as np, scipy.sparse as sp
    >>> SuperLUFactor(sp.diags([2.0, 4.0]).tocsc()).solve(np.array([1.0, 1.0]))
    array([0.5 , 0.25])
    """

    backend = "superlu"

    def __init__(self, A, ordering=None):
        try:
            # Symmetric mode with no pivoting keeps the fill-reducing ordering of A + A^T.
            self._lu = spla.splu(
                sp.csc_matrix(A), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0, options={"SymmetricMode": True}
            )
        except RuntimeError as exc:
            raise SolverError(f"sparse LU factorization failed: {exc}") from exc
        self.n = A.shape[0]

    def _solve(self, b):
        return self._lu.solve(b)
