"""Sparse symmetric positive definite factorizations behind one interface.

``factor(A).solve(b)`` picks the fastest installed backend for the job:

- ``supernodal`` (CHOLMOD's supernodal Cholesky with BLAS, through
  ``cvxopt``; the ``scale`` extra): by far the fastest factorization of large
  matrices (800k-vertex mesh: about 2.5 s, against 10 s for
  ``cholmod`` and 21 s for ``qdldl``), and it accepts a fill-reducing ordering
  computed once (:func:`fill_reducing_ordering`, minimum degree) for every
  matrix with the same sparsity pattern, or a nested dissection computed in
  the background (:func:`start_nested_dissection`, METIS) where that pays;
- ``qdldl`` (simplicial LDL^T with AMD ordering): a fast factorization for
  small and medium meshes (nefertiti, 50k vertices: 0.14 s against 0.30 s for
  ``cholmod``), with slower solves (3.6 ms against 2.8 ms);
- ``cholmod`` (CHOLMOD through ``cholespy``): the fastest solves;
- ``superlu`` (SciPy, always present): the fallback.

"auto" uses ``supernodal`` for both purposes from ``SUPERNODAL_MIN_SIZE``
unknowns up, where factoring dominates. Below, ``prefer="factor"`` (a matrix
that is rebuilt often) picks qdldl and ``prefer="solve"`` (a matrix kept for
many solves) picks ``cholmod``, whose solves are 1.5x faster than
``supernodal``'s.

Factor once, solve many times: solves accept one right-hand side ``(n,)`` or
several ``(n, k)``.

Examples
--------
>>> import scipy.sparse as sp, numpy as np
>>> A = sp.diags([2.0, 3.0]).tocsc()
>>> factor(A).solve(np.array([2.0, 3.0]))
array([1., 1.])
"""

import ctypes
import ctypes.util
import logging
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..errors import SolverError
from .sparse_rhs import SparseForwardSolver

try:  # pragma: no cover - depends on the platform's wheels
    import cholespy
except ImportError:  # pragma: no cover
    cholespy = None
try:  # pragma: no cover
    import qdldl
except ImportError:  # pragma: no cover
    qdldl = None
try:  # pragma: no cover - the optional "scale" extra
    import cvxopt
    from cvxopt import amd as cvxopt_amd
    from cvxopt import cholmod as cvxopt_cholmod
except ImportError:  # pragma: no cover
    cvxopt = None
try:  # pragma: no cover - the optional "scale" extra
    import pymetis
    import pymetis._internal
except ImportError:  # pragma: no cover
    pymetis = None

log = logging.getLogger(__name__)

#: From this many unknowns up "auto" uses the supernodal backend where installed.
SUPERNODAL_MIN_SIZE = 100_000
#: From this many unknowns up :func:`start_nested_dissection` orders by METIS (see there).
NESTED_DISSECTION_MIN_SIZE = 500_000
#: CHOLMOD's code for the system ``L^T x = b`` (``cholmod.solve``'s ``sys``).
CHOLMOD_LT = 5
#: Without the supernodal backend, "auto" prefers ``cholmod`` to ``qdldl`` above this size.
QDLDL_MAX_SIZE = 300_000


def available_backends():
    """Names of the factorization backends usable here."""
    names = [("supernodal", cvxopt), ("qdldl", qdldl), ("cholmod", cholespy)]
    return [name for name, module in names if module is not None] + ["superlu"]


def choose_backend(n, prefer="factor"):
    """The backend "auto" uses for an ``n`` x ``n`` matrix (see the module docstring)."""
    backends = available_backends()
    if n >= SUPERNODAL_MIN_SIZE:
        if "supernodal" in backends:
            return "supernodal"
        _hint_scale_extra(n)
    fast_factor = "qdldl" in backends and (n <= QDLDL_MAX_SIZE or "cholmod" not in backends)
    if prefer == "factor" and fast_factor:
        return "qdldl"
    return "cholmod" if "cholmod" in backends else backends[0]


class Ordering:
    """A fill-reducing permutation, and the sparsity pattern it was computed for.

    Matrices with exactly that pattern (a Laplacian, the heat matrix built from
    it, the grounded Laplacian with explicit zeros kept) reuse the converted
    pattern: only their values are copied.

    Attributes
    ----------
    permutation : (n,) int array
    """

    def __init__(self, permutation, pattern=None):
        self.permutation = np.asarray(permutation, dtype=np.int64).ravel()
        self._pattern = pattern  # (the pattern as CSR, True on its upper triangle; the lower triangle in cvxopt)

    def forget_pattern(self):
        """Drop the converted pattern (its memory); later factorizations convert their matrix."""
        self._pattern = None

    def reordered(self, permutation):
        """Another ordering of the same pattern (sharing its converted pattern)."""
        return Ordering(permutation, self._pattern)

    def restrict(self, rows):
        """The ordering induced on the principal submatrix ``A[rows][:, rows]``.

        Eliminating a subset of the unknowns in the same relative order fills in
        no more than the full elimination does.
        """
        position = np.empty_like(self.permutation)
        position[self.permutation] = np.arange(self.permutation.size)
        return Ordering(np.argsort(position[rows], kind="stable"))

    def lower_triangle(self, A):
        """``A``'s lower triangle in cvxopt form, reusing the pattern where ``A`` has it."""
        if self._pattern is not None:
            csr, lower = self._pattern
            if np.array_equal(A.indptr, csr.indptr) and np.array_equal(A.indices, csr.indices):
                # The lower triangle by columns is the upper triangle by rows (A is symmetric).
                lower.V = cvxopt.matrix(A.data[csr.data.astype(bool)])
                return lower
        return _to_cvxopt(A)


_hinted = False


def _hint_scale_extra(n):
    """Say once per process that large matrices factor several times faster with the scale extra."""
    global _hinted
    if not _hinted:
        _hinted = True
        log.warning(
            "factoring %d unknowns without cvxopt: pip install 'heatcore[scale]' makes this several "
            "times faster (supernodal CHOLMOD)",
            n,
        )


def fill_reducing_ordering(A, backend):
    """A fill-reducing ordering of ``A`` for ``backend``, to share among matrices.

    Parameters
    ----------
    A : (n, n) sparse symmetric matrix
        Only its sparsity pattern matters.
    backend : str
        A backend name (not "auto").

    Returns
    -------
    Ordering or None
        An approximate minimum degree ordering for ``supernodal``; None for the
        backends that order each matrix themselves. Pass it to :func:`factor`
        for any matrix whose pattern is contained in ``A``'s, or restrict it with
        :meth:`Ordering.restrict` for a principal submatrix (``None`` has no
        restriction to make: use :func:`restrict_ordering`).
    """
    if backend != "supernodal":
        return None
    A = _canonical_csr(A)
    lower = _to_cvxopt(A)
    rows = np.repeat(np.arange(A.shape[0]), np.diff(A.indptr))
    upper_entries = sp.csr_matrix((A.indices >= rows, A.indices, A.indptr), shape=A.shape)
    return Ordering(cvxopt_amd.order(lower), (upper_entries, lower))


def _metis_node_nd():
    """METIS_NodeND of the METIS that pymetis ships, as a ctypes function (which releases the GIL), or None."""
    if pymetis is None:
        return None
    try:
        library = ctypes.CDLL(pymetis._internal.__file__)
        node_nd, set_defaults = library.METIS_NodeND, library.METIS_SetDefaultOptions
        index_type = {32: np.int32, 64: np.int64}[pymetis._internal._idx_type_width()]
        keys = pymetis._internal.options_indices
        options = np.zeros(40, dtype=index_type)  # METIS_NOPTIONS
        set_defaults(ctypes.c_void_p(options.ctypes.data))
        # One refinement pass and random matching: 4.4 s instead of 5.2 s on a 1M-vertex sphere,
        # for a factor as small as with METIS's defaults.
        options[[keys.NITER, keys.CTYPE, keys.NO2HOP]] = [1, 0, 1]
    except (AttributeError, KeyError, OSError):  # pragma: no cover - another pymetis build
        return None
    return node_nd, index_type, options


_node_nd = _metis_node_nd()
_background = ThreadPoolExecutor(max_workers=1, thread_name_prefix="heatcore-nested-dissection")


def start_nested_dissection(A, backend):
    """Start a METIS nested dissection of ``A``'s pattern in a background thread.

    Nested dissection takes seconds longer than minimum degree on meshes
    (1M-vertex sphere: 4.4 s against 0.4 s), but the factor it leads to is a
    third smaller (0.76 GB against 1.18 GB), factors about twice as fast and
    solves 10% faster. METIS runs here without the GIL, so the caller factors
    another matrix meanwhile (the heat solver: its heat matrix, with the AMD
    ordering) and uses this ordering where it pays most (the Poisson factor,
    kept for every query).

    Parameters
    ----------
    A : (n, n) sparse symmetric matrix
        Only its sparsity pattern matters.
    backend : str
        A backend name (not "auto").

    Returns
    -------
    concurrent.futures.Future or None
        Its result is the permutation (``permutation[k]`` is the ``k``-th
        unknown eliminated), for :meth:`Ordering.reordered`. None where it does
        not pay or cannot run: a backend other than ``supernodal``, fewer than
        ``NESTED_DISSECTION_MIN_SIZE`` unknowns, or no ``pymetis``.
    """
    if backend != "supernodal" or A.shape[0] < NESTED_DISSECTION_MIN_SIZE or _node_nd is None:
        return None
    node_nd, index_type, options = _node_nd
    A = _canonical_csr(A)
    n = A.shape[0]
    rows = np.repeat(np.arange(n), np.diff(A.indptr))
    off_diagonal = A.indices != rows
    xadj = np.zeros(n + 1, dtype=index_type)
    np.cumsum(np.bincount(rows[off_diagonal], minlength=n), out=xadj[1:])
    adjncy = A.indices[off_diagonal].astype(index_type)

    def run():
        size = np.array([n], dtype=index_type)
        permutation, inverse = np.empty(n, dtype=index_type), np.empty(n, dtype=index_type)
        arrays = [size, xadj, adjncy, None, options, permutation, inverse]
        status = node_nd(*(None if a is None else ctypes.c_void_p(a.ctypes.data) for a in arrays))
        if status != 1:  # METIS_OK
            raise SolverError(f"METIS nested dissection failed (status {status})")
        return permutation.astype(np.int64)

    return _background.submit(run)


def restrict_ordering(ordering, rows):
    """``ordering.restrict(rows)``, or None for no ordering."""
    return None if ordering is None else ordering.restrict(rows)


def _canonical_csr(A):
    """``A`` as CSR with sorted indices and no duplicates."""
    A = sp.csr_matrix(A)
    if not A.has_canonical_format:
        A = A.copy()
        A.sum_duplicates()
    return A


def _cvxopt_indices(a):
    """An integer array as a cvxopt integer matrix (cvxopt's index width is platform dependent)."""
    return cvxopt.matrix(np.asarray(a, dtype=np.asarray(cvxopt.matrix(0, (1, 1), "i")).dtype))


def _to_cvxopt(A):
    """The lower triangle of a sparse symmetric matrix as a ``cvxopt.spmatrix``."""
    lower = sp.tril(A, format="coo")
    return cvxopt.spmatrix(
        cvxopt.matrix(lower.data.astype(np.float64)), _cvxopt_indices(lower.row), _cvxopt_indices(lower.col), A.shape
    )


def _libc_malloc_trim():
    """glibc's ``malloc_trim``, or None on other C libraries."""
    try:
        return ctypes.CDLL(ctypes.util.find_library("c")).malloc_trim
    except (AttributeError, OSError, TypeError):  # pragma: no cover - macOS, Windows, musl
        return None


_malloc_trim = _libc_malloc_trim()


def release_free_memory():
    """Give the heap memory that is free but still held back to the operating system.

    The C heap keeps much of what a mesh build frees (1M vertices: about 0.4 GB,
    in chunks that a factor's large arrays cannot reuse); returning it before
    a large factorization lowers the peak memory by that much. glibc only; a
    no-op elsewhere.
    """
    if _malloc_trim is not None:
        _malloc_trim(0)


class _SupernodalFactor:
    def __init__(self, A, ordering=None):
        self.n = A.shape[0]
        A = _canonical_csr(A)
        C = _to_cvxopt(A) if ordering is None else ordering.lower_triangle(A)
        release_free_memory()
        cvxopt_cholmod.options["supernodal"] = 2  # always supernodal
        try:
            if ordering is None:
                cvxopt_cholmod.options["nmethods"] = 0  # CHOLMOD's default choice of ordering
                self._factor = cvxopt_cholmod.symbolic(C, uplo="L")
            else:
                cvxopt_cholmod.options["nmethods"] = 1  # the given ordering, no other tried
                self._factor = cvxopt_cholmod.symbolic(C, p=_cvxopt_indices(ordering.permutation), uplo="L")
            cvxopt_cholmod.numeric(C, self._factor)
            self._sparse_forward = SparseForwardSolver.from_cvxopt(self._factor, self.n)
        except ArithmeticError as exc:
            raise SolverError(f"sparse Cholesky factorization failed: the matrix is not positive definite ({exc})") from exc
        except ValueError as exc:
            raise SolverError(f"sparse Cholesky factorization failed: {exc}") from exc

    def solve(self, b):
        b = np.asarray(b, dtype=np.float64)
        if b.ndim == 1 and self._sparse_forward is not None:
            y = self._sparse_forward.forward(b)  # None unless b is sparse enough to pay
            if y is not None:  # the backward half, L^T x = y, then x -> P^T x
                Y = cvxopt.matrix(y)
                cvxopt_cholmod.solve(self._factor, Y, sys=CHOLMOD_LT)
                x = np.empty(self.n)
                x[self._sparse_forward.permutation] = np.asarray(Y).ravel()
                return x
        B = cvxopt.matrix(np.asfortranarray(b.reshape(self.n, -1)))
        cvxopt_cholmod.solve(self._factor, B)
        return np.array(B).reshape(b.shape)


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


class _QDLDLFactor:
    def __init__(self, A):
        A = sp.csc_matrix(A)
        self.n = A.shape[0]
        try:
            self._solver = qdldl.Solver(sp.triu(A, format="csc"), upper=True)
        except (ValueError, RuntimeError) as exc:
            raise SolverError(f"sparse LDL^T factorization failed: {exc}") from exc

    def solve(self, b):
        b = np.asarray(b, dtype=np.float64)
        if b.ndim == 1:
            return self._solver.solve(b)
        return np.column_stack([self._solver.solve(np.ascontiguousarray(col)) for col in b.T])


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


def factor(A, backend="auto", prefer="factor", ordering=None):
    """Factor a sparse symmetric positive definite matrix once.

    Parameters
    ----------
    A : (n, n) sparse matrix
    backend : {"auto", "qdldl", "cholmod", "superlu"}
    prefer : {"factor", "solve"}
        What "auto" optimizes: the factorization (a matrix rebuilt often) or
        the solves (a matrix kept for many solves).
    ordering : Ordering, optional
        A fill-reducing ordering from :func:`fill_reducing_ordering`, used by
        the ``supernodal`` backend (the others order each matrix themselves).

    Returns
    -------
    object with ``solve(b)`` for ``b`` of shape ``(n,)`` or ``(n, k)``.
    """
    if backend == "auto":
        backend = choose_backend(A.shape[0], prefer)
    if backend == "supernodal":
        if cvxopt is None:
            raise SolverError("backend 'supernodal' needs the cvxopt package: pip install 'heatcore[scale]'")
        return _SupernodalFactor(A, ordering)
    if backend == "qdldl":
        if qdldl is None:
            raise SolverError("backend 'qdldl' needs the qdldl package")
        return _QDLDLFactor(A)
    if backend == "cholmod":
        if cholespy is None:
            raise SolverError("backend 'cholmod' needs the cholespy package")
        return _CholmodFactor(A)
    if backend == "superlu":
        return _SuperLUFactor(A)
    raise SolverError(f"unknown linear-algebra backend {backend!r}; use one of {available_backends()}")
