"""Complex Hermitian positive definite systems: CHOLMOD's complex factorization, or the real form.

The vector heat method's matrix ``M + t L∇`` is complex Hermitian. Two ways
to factor it:

- ``"supernodal"`` (cvxopt, the ``scale`` extra): CHOLMOD's supernodal
  Cholesky factorization of the complex matrix itself;
- any real backend (``qdldl``, ``cholmod``, ``superlu``) on its *real form*:
  unknown ``2 i`` holds ``Re z_i`` and ``2 i + 1`` holds ``Im z_i``, and each
  entry ``B + iC`` becomes the 2 x 2 block ``[[B, -C], [C, B]]`` (real
  symmetric, since ``C`` is antisymmetric, and positive definite exactly when
  the complex matrix is; the interleaving keeps each vertex's two unknowns
  together for the orderings). Four times the entries of the complex matrix
  and about twice its flops.

Measured (factorization seconds; scripts/bench_vector_heat.py, docs/vector-heat.md):

======================  ======  =================  ===================  ===============
matrix                  n       qdldl (real form)  cholmod (real form)  complex CHOLMOD
======================  ======  =================  ===================  ===============
spot refined once       11,714  0.14               0.16                 0.03
icosphere refined once  40,962  5.81               1.81                 0.18
======================  ======  =================  ===================  ===============

so "auto" takes complex CHOLMOD where cvxopt is installed and the real form
through ``cholmod`` (cholespy) otherwise (qdldl's own ordering of the real
form fills in much more), then ``qdldl``, then ``superlu``.

Examples
--------
>>> import numpy as np, scipy.sparse as sp
>>> A = sp.csr_matrix(np.array([[2.0, 1j], [-1j, 2.0]]))
>>> f = factor_hermitian(A, "superlu")
>>> z = f.solve(np.array([1.0, 1j]))
>>> bool(np.allclose(A @ z, [1.0, 1j]))
True
"""

import numpy as np
import scipy.sparse as sp

from ..errors import SolverError
from .backends import available_backends
from .columns import solve_columns
from .factor import factor
from .libraries import optional


def real_form(A):
    """The real symmetric ``2n x 2n`` form of a complex ``n x n`` matrix, real and imaginary parts interleaved.

    Parameters
    ----------
    A : (n, n) complex sparse matrix

    Returns
    -------
    (2n, 2n) scipy.sparse.csr_matrix
        Entry ``(i, j) = b + ic`` of ``A`` becomes the block ``[[b, -c], [c, b]]``
        at rows ``2i, 2i+1`` and columns ``2j, 2j+1``.

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> real_form(sp.csr_matrix(np.array([[2.0 + 0j, 1j], [-1j, 3.0]]))).toarray().tolist()
    [[2.0, 0.0, 0.0, -1.0], [0.0, 2.0, 1.0, 0.0], [0.0, 1.0, 3.0, 0.0], [-1.0, 0.0, 0.0, 3.0]]
    """
    A = sp.coo_matrix(A)
    r, c = A.row.astype(np.int64), A.col.astype(np.int64)
    b, d = A.data.real, A.data.imag
    rows = np.concatenate([2 * r, 2 * r, 2 * r + 1, 2 * r + 1])
    cols = np.concatenate([2 * c, 2 * c + 1, 2 * c, 2 * c + 1])
    data = np.concatenate([b, -d, d, b])
    n = A.shape[0]
    return sp.csr_matrix((data, (rows, cols)), shape=(2 * n, 2 * n))


def hermitian_backend(backend="auto"):
    """The backend that factors a Hermitian matrix for ``backend`` ("auto": see the module docstring).

    Examples
    --------
    >>> hermitian_backend("qdldl")
    'qdldl'
    >>> hermitian_backend() in available_backends()
    True
    """
    if backend != "auto":
        return backend
    for name in ("supernodal", "cholmod", "qdldl"):
        if name in available_backends():
            return name
    return "superlu"


class HermitianFactor:
    """A complex Hermitian positive definite matrix, factored once.

    Parameters
    ----------
    A : (n, n) complex sparse matrix, Hermitian positive definite
    backend : str, default "auto"
        ``"supernodal"``: complex CHOLMOD (cvxopt); another backend of
        :func:`heatcore.linalg.factor` factors the real form.

    Attributes
    ----------
    n : int
    backend : str

    Raises
    ------
    SolverError
        The matrix is not positive definite, or the backend is not installed.

    Examples
    --------
    >>> import numpy as np, scipy.sparse as sp
    >>> A = sp.csr_matrix(np.array([[4.0, 1 + 1j], [1 - 1j, 3.0]]))
    >>> f = HermitianFactor(A)
    >>> Z = f.solve(np.array([[1.0, 0.0], [0.0, 1j]]))   # two right-hand sides
    >>> bool(np.allclose(A @ Z, [[1.0, 0.0], [0.0, 1j]]))
    True
    """

    def __init__(self, A, backend="auto"):
        self.n = A.shape[0]
        self.backend = hermitian_backend(backend)
        if self.backend == "supernodal":
            self._complex = _complex_cholmod(A)
        else:
            self._complex = None
            self._real = factor(real_form(A), self.backend)

    def solve(self, b):
        """``A^{-1} b`` for ``b`` of shape ``(n,)`` or ``(n, k)``, complex (or real); a complex array."""
        b = np.asarray(b, dtype=np.complex128)
        if b.ndim not in (1, 2) or b.shape[0] != self.n:
            raise ValueError(f"a right-hand side of shape {b.shape} for an {self.n} x {self.n} matrix")
        if b.size == 0:
            return np.zeros(b.shape, dtype=complex)
        if self._complex is not None:
            cvxopt = optional("cvxopt")
            B = cvxopt.matrix(np.asfortranarray(b.reshape(self.n, -1)))
            cvxopt.cholmod.solve(self._complex, B)
            return np.array(B).reshape(b.shape)
        stacked = np.empty((2 * self.n,) + b.shape[1:])
        stacked[0::2], stacked[1::2] = b.real, b.imag
        x = solve_columns(self._real, stacked)
        return x[0::2] + 1j * x[1::2]


def factor_hermitian(A, backend="auto"):
    """Factor a sparse complex Hermitian positive definite matrix once (see :class:`HermitianFactor`).

    Parameters
    ----------
    A : (n, n) complex sparse matrix
    backend : str, default "auto"

    Returns
    -------
    HermitianFactor

    Examples
    --------
    >>> import numpy as np, scipy.sparse as sp
    >>> factor_hermitian(sp.identity(2, dtype=complex, format="csr")).solve(np.array([1j, 2.0]))
    array([0.+1.j, 2.+0.j])
    """
    return HermitianFactor(A, backend)


def _complex_cholmod(A):
    """CHOLMOD's supernodal factor of a complex Hermitian matrix (its lower triangle), through cvxopt."""
    cvxopt = optional("cvxopt")
    if cvxopt is None:
        raise SolverError("backend 'supernodal' needs the cvxopt package: pip install 'heatcore[scale]'")
    from .supernodal import cholmod_options, cvxopt_indices

    lower = sp.tril(A, format="coo")
    C = cvxopt.spmatrix(
        cvxopt.matrix(lower.data.astype(np.complex128)), cvxopt_indices(lower.row), cvxopt_indices(lower.col), A.shape
    )
    try:
        with cholmod_options(supernodal=2, nmethods=0):
            F = cvxopt.cholmod.symbolic(C, uplo="L")
            cvxopt.cholmod.numeric(C, F)
    except ArithmeticError as exc:
        raise SolverError(f"complex Cholesky factorization failed: the matrix is not positive definite ({exc})") from exc
    return F
