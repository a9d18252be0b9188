"""Sparse symmetric positive definite factorizations behind one interface.

``factor(A).solve(b)`` uses CHOLMOD through ``cholespy`` when it is installed
(wheels exist for Linux x86-64, macOS and Windows) and SciPy's SuperLU
otherwise. Factor once, solve many times: solves accept one right-hand side
``(n,)`` or several ``(n, k)``.

Examples
--------
>>> import scipy.sparse as sp, numpy as np
>>> A = sp.diags([2.0, 3.0]).tocsc()
>>> factor(A).solve(np.array([2.0, 3.0]))
array([1., 1.])
"""

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .errors import SolverError

try:  # pragma: no cover - depends on the platform's wheels
    import cholespy
except ImportError:  # pragma: no cover
    cholespy = None


def available_backends():
    """Names of the factorization backends usable here, fastest first."""
    return (["cholmod"] if cholespy is not None else []) + ["superlu"]


class _CholmodFactor:
    def __init__(self, A):
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

    def solve(self, b):
        b = np.ascontiguousarray(b, dtype=np.float64)
        x = np.empty_like(b)
        self._solver.solve(b, x)
        return x


class _SuperLUFactor:
    def __init__(self, A):
        try:
            # Symmetric mode with no pivoting keeps the fill-reducing ordering of A + A^T.
            self._lu = spla.splu(
                sp.csc_matrix(A), permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0, options={"SymmetricMode": True}
            )
        except RuntimeError as exc:
            raise SolverError(f"sparse LU factorization failed: {exc}") from exc
        self.n = A.shape[0]

    def solve(self, b):
        return self._lu.solve(np.asarray(b, dtype=np.float64))


def factor(A, backend="auto"):
    """Factor a sparse symmetric positive definite matrix once.

    Parameters
    ----------
    A : (n, n) sparse matrix
    backend : {"auto", "cholmod", "superlu"}

    Returns
    -------
    object with ``solve(b)`` for ``b`` of shape ``(n,)`` or ``(n, k)``.
    """
    if backend == "auto":
        backend = available_backends()[0]
    if backend == "cholmod":
        if cholespy is None:
            raise SolverError("backend 'cholmod' needs the cholespy package")
        return _CholmodFactor(A)
    if backend == "superlu":
        return _SuperLUFactor(A)
    raise SolverError(f"unknown linear-algebra backend {backend!r}; use one of {available_backends()}")
