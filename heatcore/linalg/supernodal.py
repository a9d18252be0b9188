"""CHOLMOD's supernodal Cholesky factorization, through cvxopt (the ``scale`` extra).

By far the fastest factorization of large matrices: BLAS on dense supernodes
(800k-vertex mesh: about 2.5 s, against 10 s for the ``cholmod`` backend and
21 s for ``qdldl``). It takes a fill-reducing ordering computed once
(:func:`minimum_degree`, or a METIS nested dissection) for every matrix with
the same sparsity pattern, and solves a right-hand side with few nonzeros
(the heat step's impulse) by a sparse forward solve
(:mod:`heatcore.linalg.sparse_rhs`).

cvxopt configures CHOLMOD through one global dict, ``cvxopt.cholmod.options``;
each factorization here sets what it needs and puts back what was there
(:func:`cholmod_options`). cvxopt is imported on first use.

Examples
--------
>>> import numpy as np, scipy.sparse as sp
>>> A = sp.csc_matrix([[4.0, 1.0], [1.0, 3.0]])
>>> x = SupernodalFactor(A).solve([1.0, 2.0])
>>> bool(np.allclose(A @ x, [1.0, 2.0]))
True
"""

import contextlib
import functools
import os
import threading
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import scipy.sparse as sp

from ..errors import SolverError
from .backends import SUPERNODAL_MIN_SIZE
from .interface import Factor, canonical_csr
from .libraries import optional
from .memory import release_free_memory
from . import cholmod_direct
from .cholmod_direct import copy_factor
from .sparse_rhs import SparseForwardSolver, is_sparse

#: CHOLMOD's codes of the systems ``L x = b``, ``L^T x = b``, ``x = P b``, ``x = P^T b`` (``cholmod.solve``'s ``sys``).
CHOLMOD_L, CHOLMOD_LT, CHOLMOD_P, CHOLMOD_PT = 4, 5, 7, 8

_options_lock = threading.Lock()


def _cvxopt():
    cvxopt = optional("cvxopt")
    if cvxopt is None:
        raise SolverError("backend 'supernodal' needs the cvxopt package: pip install 'heatcore[scale]'")
    return cvxopt


@contextlib.contextmanager
def cholmod_options(**values):
    """Set ``cvxopt.cholmod.options`` inside a ``with`` block, then put back what was there.

    Options absent before are removed again; the block holds a lock, so two
    threads factoring at once do not see each other's options (cvxopt holds
    the GIL while it factors: nothing is lost by waiting).

    Parameters
    ----------
    **values
        CHOLMOD options by name (``supernodal``, ``nmethods``, ...).

    Examples
    --------
    >>> from cvxopt import cholmod
    >>> before = dict(cholmod.options)
    >>> with cholmod_options(supernodal=2):
    ...     cholmod.options["supernodal"]
    2
    >>> cholmod.options == before
    True
    """
    options = _cvxopt().cholmod.options
    with _options_lock:
        saved = {key: options[key] for key in values if key in options}
        options.update(values)
        try:
            yield options
        finally:
            for key in values:
                if key in saved:
                    options[key] = saved[key]
                else:
                    options.pop(key, None)


def cvxopt_indices(a):
    """An integer array as a cvxopt integer matrix (cvxopt's index width is platform dependent).

    Examples
    --------
    >>> list(cvxopt_indices([2, 0, 1]))  # doctest: +SKIP
    [2, 0, 1]
    """
    cvxopt = _cvxopt()
    return cvxopt.matrix(np.asarray(a, dtype=np.asarray(cvxopt.matrix(0, (1, 1), "i")).dtype))


def _to_cvxopt(A):
    """The lower triangle of a sparse symmetric matrix as a ``cvxopt.spmatrix``."""
    cvxopt = _cvxopt()
    if sp.isspmatrix_csr(A):  # sp.tril's entries, in its order, without a COO copy of the whole matrix
        rows = np.repeat(np.arange(A.shape[0], dtype=A.indices.dtype), np.diff(A.indptr))
        lower = rows >= A.indices
        row, col, data = rows[lower], A.indices[lower], A.data[lower]
    else:
        lower = sp.tril(A, format="coo")
        row, col, data = lower.row, lower.col, lower.data
    return cvxopt.spmatrix(cvxopt.matrix(data.astype(np.float64)), cvxopt_indices(row), cvxopt_indices(col), A.shape)


def minimum_degree(A, background=False):
    """An approximate minimum degree ordering of ``A`` (CHOLMOD's AMD), and its converted pattern.

    Parameters
    ----------
    A : (n, n) csr_matrix
        Symmetric, canonical (sorted indices, no duplicates); only its pattern matters.
    background : bool, default False
        Run AMD, and CHOLMOD's symbolic analysis in its order, in a
        background thread without the GIL where they can be called directly
        (:mod:`heatcore.linalg.cholmod_direct`): the caller goes on meanwhile.

    Returns
    -------
    permutation : (n,) int array, or with ``background`` (where it runs there) a Future of
        ``(permutation, analysis)``: the order and CHOLMOD's symbolic analysis of ``A`` in it
    pattern : tuple
        ``A``'s pattern as CSR (True on its upper triangle) and its lower
        triangle in cvxopt form, or where CHOLMOD is called directly None and
        the lower triangle by columns (``indptr``, ``indices``, and the
        positions of its entries in ``A.data``): factorizations of matrices
        with exactly this pattern take only their values.

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> permutation, pattern = minimum_degree(sp.identity(3, format="csr"))
    >>> sorted(np.asarray(permutation).ravel().tolist())
    [0, 1, 2]
    """
    rows = np.repeat(np.arange(A.shape[0]), np.diff(A.indptr))
    upper = A.indices >= rows
    upper_entries = sp.csr_matrix((upper, A.indices, A.indptr), shape=A.shape)
    if cholmod_direct.available():  # the calls cvxopt makes, on the same arrays; no cvxopt matrix needed
        lower = _lower_columns(A, upper)
        pattern = (upper_entries, None, (lower[0], lower[1], np.flatnonzero(upper)))
        if background:
            return _factor_thread().submit(_ordered_and_analysed, lower), pattern
        return cholmod_direct.minimum_degree_order(*lower[:2]), pattern
    lower = _to_cvxopt(A)
    return _cvxopt().amd.order(lower), (upper_entries, lower)


def _ordered_and_analysed(lower):
    """``(permutation, analysis)``: AMD's order of the lower triangle ``lower`` and CHOLMOD's analysis in that order."""
    permutation = cholmod_direct.minimum_degree_order(*lower[:2])
    return permutation, cholmod_direct.analyze(*lower, permutation)


def _lower_triangle(A, ordering):
    """``A``'s lower triangle in cvxopt form, reusing the ordering's converted pattern where ``A`` has it."""
    pattern = _same_pattern(A, ordering)
    if pattern is not None and pattern[1] is not None:
        csr, lower = pattern[:2]
        # The lower triangle by columns is the upper triangle by rows (A is symmetric).
        lower.V = _cvxopt().matrix(A.data[csr.data.astype(bool)])
        return lower
    return _to_cvxopt(A)


def _same_pattern(A, ordering):
    """The ordering's converted pattern where ``A`` (canonical CSR) has exactly that pattern, else None."""
    pattern = None if ordering is None else ordering.pattern
    if pattern is not None and np.array_equal(A.indptr, pattern[0].indptr) and np.array_equal(A.indices,
                                                                                               pattern[0].indices):
        return pattern
    return None


def _lower_columns(A, upper):
    """``A``'s lower triangle by compressed columns, ``(indptr, indices, data)``: its upper triangle by rows, the
    entries ``upper`` (a bool per stored entry) marks (A is symmetric)."""
    before = np.empty(upper.size + 1, dtype=np.int64)
    before[0] = 0
    np.cumsum(upper, out=before[1:])
    return before[A.indptr], A.indices[upper], A.data[upper]


def _analysis(lower, ordering, pattern):
    """A symbolic factor of the lower triangle ``lower`` in the ordering's order: a copy of the ordering's analysis
    where the matrix has its ``pattern`` and one is kept (:func:`~heatcore.linalg.cholmod_direct.copy_factor`), else
    a new one (then a copy kept for the next matrix of the pattern: a factorization overwrites its factor)."""
    if pattern is not None and ordering.analysis is not None:
        analysis = copy_factor(ordering.analysis)
        if analysis is not None:
            return analysis
    analysis = cholmod_direct.analyze(*lower, ordering.permutation)
    if pattern is not None:
        ordering.analysis = copy_factor(analysis)
    return analysis


#: Threads that run background orderings and factorizations: CHOLMOD factors on one core (cvxopt's BLAS is
#: serial), so the Laplacian's and the Dirichlet heat matrix's factorizations run beside the caller's at once.
FACTOR_THREADS = 2

_threads_lock = threading.Lock()
_threads = {}  # the background thread's executor, made on first use; forgotten in a forked child (no thread there)
os.register_at_fork(after_in_child=_threads.clear)


def _factor_thread():
    """The threads that run background orderings and factorizations (:class:`SupernodalFactor`'s ``background``)."""
    with _threads_lock:
        if "factor" not in _threads:
            _threads["factor"] = ThreadPoolExecutor(max_workers=FACTOR_THREADS, thread_name_prefix="heatcore-factor")
        return _threads["factor"]


class SupernodalFactor(Factor):
    """A supernodal Cholesky factor ``A = P^T L L^T P`` held by cvxopt.

    Parameters
    ----------
    A : (n, n) sparse symmetric positive definite matrix
    ordering : Ordering, optional
        The elimination order (with a converted pattern and a symbolic
        analysis to reuse where ``A`` has exactly that pattern: the first
        such factorization keeps its analysis in ``ordering.analysis``); by
        default CHOLMOD chooses.
    background : bool, default False
        Where CHOLMOD can be called directly (:mod:`heatcore.linalg.cholmod_direct`)
        and an ``ordering`` is given, run the numeric factorization in a
        background thread, which lets go of the GIL: the caller factors
        another matrix meanwhile. The first solve (or :meth:`wait`) waits
        for it.

    Raises
    ------
    SolverError
        ``A`` is not positive definite, or cvxopt is not installed (with
        ``background``: raised by :meth:`wait` and the solves).

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> f = SupernodalFactor(sp.diags([1.0, 2.0, 4.0]).tocsc())
    >>> f.solve(np.array([[1.0], [2.0], [4.0]])).ravel()
    array([1., 1., 1.])
    """

    backend = "supernodal"

    def __init__(self, A, ordering=None, background=False):
        cholmod = _cvxopt().cholmod
        self.n = A.shape[0]
        self._pending = None
        A = canonical_csr(A)
        if self.n >= SUPERNODAL_MIN_SIZE:  # a large factor: worth the heap walk (1.5 ms even when small)
            release_free_memory()
        try:
            if ordering is None:
                C = _to_cvxopt(A)
                with cholmod_options(supernodal=2, nmethods=0):  # supernodal; CHOLMOD's default orderings
                    self._factor = cholmod.symbolic(C, uplo="L")
                    cholmod.numeric(C, self._factor)
            elif not cholmod_direct.available():
                C = _lower_triangle(A, ordering)
                with cholmod_options(supernodal=2, nmethods=1):  # supernodal; the given ordering, no other tried
                    self._factor = cholmod.symbolic(C, p=cvxopt_indices(ordering.permutation), uplo="L")
                    cholmod.numeric(C, self._factor)
            else:  # CHOLMOD called directly: a shared analysis, the numeric factorization without the GIL
                pattern = _same_pattern(A, ordering)
                if pattern is not None and len(pattern) > 2:  # the lower triangle's columns, kept: only values taken
                    indptr, indices, entries = pattern[2]
                    lower = (indptr, indices, A.data[entries])
                else:
                    rows = None if pattern is not None else np.repeat(np.arange(self.n), np.diff(A.indptr))
                    upper = pattern[0].data.astype(bool) if pattern is not None else A.indices >= rows
                    lower = _lower_columns(A, upper)
                self._factor = _analysis(lower, ordering, pattern)
                numeric = functools.partial(cholmod_direct.factorize, self._factor, *lower)
                if background:
                    self._pending = _factor_thread().submit(numeric)
                else:
                    numeric()
        except ArithmeticError as exc:
            raise SolverError(f"sparse Cholesky factorization failed: the matrix is not positive definite ({exc})") from exc
        except ValueError as exc:
            raise SolverError(f"sparse Cholesky factorization failed: {exc}") from exc

    def wait(self):
        """Wait for a numeric factorization started in the ``background`` (none: return at once).

        Returns
        -------
        SupernodalFactor
            Itself.

        Raises
        ------
        SolverError
            The factorization failed (then again on every later call).
        """
        pending = self._pending
        if pending is not None:
            pending.result()
            self._pending = None
        return self

    @functools.cached_property
    def _sparse_forward(self):
        """The :class:`~heatcore.linalg.sparse_rhs.SparseForwardSolver` over this factor (None where it cannot
        read it), made on the first sparse right-hand side: a factor that only ever sees dense ones (the
        Poisson step's) never pays for reading its supernodes."""
        return SparseForwardSolver.from_cvxopt(self.wait()._factor, self.n)

    def _sparse_enough(self, b):
        """Whether ``b`` (n,) may take the sparse forward solve (which may still decline it)."""
        return is_sparse(b) and self._sparse_forward is not None

    def forward(self, b):
        """The first half of a solve, ``y = L^-1 P b`` for one right-hand side (sparse ones by the sparse path).

        Examples
        --------
        >>> import scipy.sparse as sp
        >>> f = SupernodalFactor(sp.csc_matrix([[4.0, 1.0], [1.0, 3.0]]))
        >>> bool(np.allclose(f.backward(f.forward(np.array([1.0, 2.0]))), f.solve([1.0, 2.0])))
        True
        """
        b = np.asarray(b, dtype=np.float64).reshape(self.n)
        if self._sparse_enough(b):
            y = self._sparse_forward.forward(b)
            if y is not None:
                return y
        return self._system(b, CHOLMOD_P, CHOLMOD_L)

    def backward(self, y):
        """The second half of a solve, ``x = P^T L^-T y``: ``backward(forward(b))`` is ``solve(b)``."""
        return self._system(np.asarray(y, dtype=np.float64).reshape(self.n), CHOLMOD_LT, CHOLMOD_PT)

    def _system(self, b, *systems):
        self.wait()
        cvxopt = _cvxopt()
        B = cvxopt.matrix(np.asfortranarray(b.reshape(self.n, 1)))
        for system in systems:
            cvxopt.cholmod.solve(self._factor, B, sys=system)
        return np.array(B).ravel()

    def _solve(self, b):
        self.wait()
        cvxopt = _cvxopt()
        if b.ndim == 1 and self._sparse_enough(b):
            y = self._sparse_forward.forward(b)  # None unless b is sparse enough to pay
            if y is not None:  # the backward half, L^T x = y, then x -> P^T x
                Y = cvxopt.matrix(y)
                cvxopt.cholmod.solve(self._factor, Y, sys=CHOLMOD_LT)
                return self._sparse_forward.unpermute(np.asarray(Y).ravel())
        B = cvxopt.matrix(np.asfortranarray(b.reshape(self.n, -1)))
        cvxopt.cholmod.solve(self._factor, B)
        return np.array(B).reshape(b.shape)
