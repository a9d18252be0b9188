"""The :class:`Factor` interface every backend implements, and the matrix form the backends read.

This module imports no backend and no backend choice: each backend module
(:mod:`~heatcore.linalg.supernodal`, :mod:`~heatcore.linalg.qdldl`,
:mod:`~heatcore.linalg.cholmod`, :mod:`~heatcore.linalg.superlu`,
:mod:`~heatcore.linalg.gpu`) subclasses :class:`Factor` from here, and
:func:`heatcore.linalg.factor` imports the backends, so no import runs in a
circle.

Examples
--------
>>> import numpy as np, scipy.sparse as sp
>>> from heatcore.linalg import factor
>>> f = factor(sp.diags([2.0, 4.0]).tocsc(), "superlu")
>>> isinstance(f, Factor), f.solve(np.array([2.0, 4.0])).tolist()
(True, [1.0, 1.0])
"""

import abc

import numpy as np
import scipy.sparse as sp


class Factor(abc.ABC):
    """A sparse symmetric positive definite matrix, factored once for many solves.

    Attributes
    ----------
    n : int
        The matrix is ``n`` x ``n``.
    backend : str
        The backend that factored it (a key of :data:`heatcore.linalg.backends.BACKENDS`).

    Examples
    --------
    >>> import numpy as np, scipy.sparse as sp
    >>> from heatcore.linalg import factor
    >>> f = factor(sp.identity(3, format="csc"), "superlu")
    >>> isinstance(f, Factor), f.n, f.backend
    (True, 3, 'superlu')
    """

    backend = None
    n = 0

    def solve(self, b):
        """``A^{-1} b`` for one right-hand side or several.

        Parameters
        ----------
        b : (n,) or (n, k) array_like
            One right-hand side, or ``k`` of them as columns (``k`` may be 0).

        Returns
        -------
        (n,) or (n, k) float array
            The same shape as ``b``; a new array.

        Raises
        ------
        ValueError
            ``b`` has another number of rows or more than two dimensions.

        Examples
        --------
        >>> import numpy as np, scipy.sparse as sp
        >>> from heatcore.linalg import factor
        >>> f = factor(sp.diags([1.0, 2.0, 4.0]).tocsc(), "superlu")
        >>> f.solve([1.0, 2.0, 4.0])
        array([1., 1., 1.])
        >>> f.solve(np.full((3, 2), 4.0))
        array([[4., 4.],
               [2., 2.],
               [1., 1.]])
        """
        b = np.asarray(b, dtype=np.float64)
        if b.ndim not in (1, 2) or b.shape[0] != self.n:
            raise ValueError(f"a right-hand side of shape {b.shape} for an {self.n} x {self.n} matrix: "
                             f"expected ({self.n},) or ({self.n}, k)")
        if b.size == 0:
            return np.zeros(b.shape)
        return self._solve(b)

    def wait(self):
        """Wait until the factorization is done (one started in the background); return the factor.

        Only the ``supernodal`` backend factors in the background
        (:func:`heatcore.linalg.start_factor`); the others are done when made.

        Returns
        -------
        Factor
            Itself.

        Raises
        ------
        SolverError
            A factorization made in the background failed.

        Examples
        --------
        >>> import scipy.sparse as sp
        >>> from heatcore.linalg import factor
        >>> f = factor(sp.identity(2, format="csc"), "superlu")
        >>> f.wait() is f
        True
        """
        return self

    @abc.abstractmethod
    def _solve(self, b):
        """The backend's solve: ``b`` is a float64 array of shape ``(n,)`` or ``(n, k)``, ``k >= 1``."""

    def _solve_columns(self, b, solve_one):
        """``b`` solved one column at a time by ``solve_one`` (for backends that take one right-hand side)."""
        if b.ndim == 1:
            return solve_one(b)
        return np.column_stack([solve_one(np.ascontiguousarray(column)) for column in b.T])


def canonical_csr(A):
    """``A`` as CSR with sorted indices and no duplicates (``A`` itself where it already is).

    Parameters
    ----------
    A : sparse matrix

    Returns
    -------
    scipy.sparse.csr_matrix

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> A = sp.coo_matrix(([1.0, 2.0], ([0, 0], [1, 1])), shape=(2, 2))
    >>> canonical_csr(A).toarray().tolist()
    [[0.0, 3.0], [0.0, 0.0]]
    """
    if not (sp.issparse(A) and A.format == "csr"):  # a CSR matrix is taken as it is: a new wrapper costs its checks
        A = sp.csr_matrix(A)
    if not A.has_canonical_format:
        A = A.copy()
        A.sum_duplicates()
    return A
