"""Forward solves with a sparse right-hand side on a CHOLMOD supernodal factor.

The heat step's right-hand side is the source impulse: one nonzero per source
vertex (three for a point on a face). With ``A = P^T L L^T P``, the forward
solve ``L y = P b`` then has nonzeros only on the supernodes from the sources'
up to the root of the elimination tree: 16 of the 129k supernodes of a
1M-vertex sphere's heat factor, 5 ms instead of the 70 ms that a full forward
solve takes to stream the 0.9 GB factor through memory. The backward solve
``L^T x = y`` still needs all of it, so the heat solve costs 40% less.

CHOLMOD's own sparse solve (``cholmod_solve2`` with ``Bset``) converts a
supernodal factor to simplicial form first, and cvxopt exposes neither;
:class:`SparseForwardSolver` reads the factor that cvxopt holds (a capsule
around a ``cholmod_factor``) in place, without copying it. It does so only on
the cvxopt versions it was written for
(:data:`heatcore.linalg.libraries.READ_INTERNALS_OF`), and checks that the
factor's header is consistent with the layout described here before using it;
on another version, or a factor it cannot read, it logs a warning (once) and
the heat step solves densely (same results, slower).

Examples
--------
>>> import numpy as np, scipy.sparse as sp, scipy.sparse.linalg as spla
>>> from heatcore import linalg
>>> T = sp.diags([-1.0, 2.5, -1.0], [-1, 0, 1], shape=(30, 30))
>>> A = (sp.kron(T, sp.identity(30)) + sp.kron(sp.identity(30), T)).tocsc()  # a 30 x 30 grid
>>> solver = SparseForwardSolver.from_cvxopt(linalg.factor(A, "supernodal")._factor, 900)
>>> b = np.zeros(900)
>>> b[0] = 1.0
>>> y = solver.forward(b)  # L^{-1} P b: nonzero on the corner's path to the root only
>>> int(np.count_nonzero(y)) < 100
True
>>> bool(np.isclose(y @ y, spla.spsolve(A, b)[0], rtol=1e-12))  # y.y = b^T A^{-1} b
True
"""

import ctypes

import numpy as np
from scipy.linalg.blas import dtrsv

from .libraries import count_fast_path, once, version_is_known, warn_once

#: What a reader of a foreign factor may raise where the factor is not one it can read.
_UNREADABLE = (ValueError, TypeError, IndexError, OverflowError, ctypes.ArgumentError)

#: Above this many nonzeros a right-hand side is treated as dense...
MAX_NONZEROS = 10_000
#: ...or above this share of its entries (the Poisson step's right-hand side:
#: a factor that sees only such ones is never read, see :func:`is_sparse`).
MAX_NONZERO_SHARE = 0.5
#: A sparse forward solve gives up (and the caller solves densely) once the
#: supernodes it must visit hold this share of the factor's entries...
MAX_FACTOR_SHARE = 0.5
#: ...or this share of its supernodes: each costs a Python step (about 10 us) where
#: CHOLMOD's loop spends 0.5 us. Measured on a sphere's heat factor, 135k and 1M
#: vertices: 2-30 random sources take 0.15-0.5 of a dense forward solve's time,
#: 1000 sources 0.9-2.4.
MAX_SUPERNODE_SHARE = 0.02

_CHOLMOD_LONG, _CHOLMOD_INT, _CHOLMOD_REAL, _CHOLMOD_DOUBLE = 2, 0, 1, 0


class _CholmodFactor(ctypes.Structure):
    """``cholmod_factor`` (the same layout in CHOLMOD 2 to 5)."""

    _fields_ = (
        [("n", ctypes.c_size_t), ("minor", ctypes.c_size_t)]
        + [(name, ctypes.c_void_p) for name in ("Perm", "ColCount", "IPerm")]
        + [("nzmax", ctypes.c_size_t)]
        + [(name, ctypes.c_void_p) for name in ("p", "i", "x", "z", "nz", "next", "prev")]
        + [(name, ctypes.c_size_t) for name in ("nsuper", "ssize", "xsize", "maxcsize", "maxesize")]
        + [(name, ctypes.c_void_p) for name in ("super", "pi", "px", "s")]
        + [(name, ctypes.c_int) for name in ("ordering", "is_ll", "is_super", "is_monotonic", "itype", "xtype", "dtype")]
    )


@once
def _capsule_api():
    """``PyCapsule_GetName`` and ``PyCapsule_GetPointer`` with their own prototypes.

    (Setting ``restype``/``argtypes`` on ``ctypes.pythonapi``'s shared function
    objects would change them for everyone else in the process.)
    """
    get_name = ctypes.PYFUNCTYPE(ctypes.c_char_p, ctypes.py_object)(("PyCapsule_GetName", ctypes.pythonapi))
    get_pointer = ctypes.PYFUNCTYPE(ctypes.c_void_p, ctypes.py_object, ctypes.c_char_p)(
        ("PyCapsule_GetPointer", ctypes.pythonapi)
    )
    return get_name, get_pointer


def _capsule_pointer(capsule):
    """The C pointer inside a PyCapsule."""
    get_name, get_pointer = _capsule_api()
    return get_pointer(capsule, get_name(capsule))


def _view(address, size, dtype):
    """A numpy array over ``size`` items of C memory (no copy)."""
    if not address:
        raise ValueError("null array in the factor")
    ctype = np.ctypeslib.as_ctypes_type(dtype)
    return np.ctypeslib.as_array(ctypes.cast(address, ctypes.POINTER(ctype)), shape=(size,))


def _decline(reason, detail):
    warn_once(
        ("sparse right-hand sides", reason),
        "sparse right-hand sides: cannot read the CHOLMOD factor (%s: %s); solving densely (same results, slower)",
        reason,
        detail,
    )


def is_sparse(b):
    """Whether a right-hand side ``b`` (n,) has few enough nonzeros for :meth:`SparseForwardSolver.forward` to try.

    Examples
    --------
    >>> is_sparse(np.array([0.0, 1.0, 0.0])), is_sparse(np.ones(3))
    (True, False)
    """
    return bool(np.count_nonzero(b) <= min(MAX_NONZEROS, MAX_NONZERO_SHARE * b.size))


class SparseForwardSolver:
    """``y = L^{-1} P b`` for a sparse ``b``, on a supernodal factor ``A = P^T L L^T P``.

    Parameters
    ----------
    owner : object
        Whatever keeps the factor's memory alive (the cvxopt capsule).
    structure : _CholmodFactor
        The factor's header.

    Attributes
    ----------
    permutation : (n,) int array
        ``P`` as CHOLMOD keeps it: ``(P b)[k] = b[permutation[k]]``.

    Examples
    --------
    >>> from heatcore import linalg
    >>> import scipy.sparse as sp
    >>> f = linalg.factor(sp.identity(4, format="csc"), "supernodal")
    >>> sorted(SparseForwardSolver.from_cvxopt(f._factor, 4).permutation.tolist())
    [0, 1, 2, 3]
    """

    def __init__(self, owner, structure):
        L = structure
        if not (L.is_super == 1 and L.is_ll == 1 and L.xtype == _CHOLMOD_REAL and L.dtype == _CHOLMOD_DOUBLE):
            raise ValueError("not a real double-precision supernodal LL' factor")
        if L.itype not in (_CHOLMOD_INT, _CHOLMOD_LONG) or L.minor != L.n or L.nsuper < 1:
            raise ValueError("unexpected factor header")
        index = np.int64 if L.itype == _CHOLMOD_LONG else np.int32
        n, nsuper = L.n, L.nsuper
        self._owner = owner
        self.permutation = _view(L.Perm, n, index)
        self._first_column = _view(L.super, nsuper + 1, index)
        self._row_start = _view(L.pi, nsuper + 1, index)
        self._value_start = _view(L.px, nsuper + 1, index)
        if not (
            self._first_column[0] == 0
            and self._first_column[-1] == n
            and self._row_start[-1] == L.ssize
            and self._value_start[-1] <= L.xsize
            and np.all(np.diff(self._first_column) > 0)
        ):
            raise ValueError("inconsistent supernode arrays")
        self._rows = _view(L.s, L.ssize, index)
        self._values = _view(L.x, L.xsize, np.float64)
        self._n_columns = np.diff(self._first_column)
        self._n_rows = np.diff(self._row_start)
        # Entries each supernode's solve reads: the lower triangle of its diagonal block, and the rows below.
        self._sizes = self._n_columns * (self._n_columns + 1) // 2 + (self._n_rows - self._n_columns) * self._n_columns
        # A supernode's parent holds the first row below its diagonal block.
        parent = np.full(nsuper, -1, dtype=np.int64)
        has_parent = self._n_rows > self._n_columns
        below = self._rows[self._row_start[:-1][has_parent] + self._n_columns[has_parent]]
        parent[has_parent] = self._supernode_of(below)
        if np.any(parent[has_parent] <= np.flatnonzero(has_parent)):
            raise ValueError("supernodes not in elimination-tree order")
        self._parent = parent
        self._position = np.empty(n, dtype=np.int64)  # position[i] = k where permutation[k] = i
        self._position[self.permutation] = np.arange(n)
        self._max_size = MAX_FACTOR_SHARE * self._sizes.sum()
        self._max_supernodes = max(64, MAX_SUPERNODE_SHARE * nsuper)

    @classmethod
    def from_cvxopt(cls, capsule, n):
        """For a numeric factor from ``cvxopt.cholmod``; None if it is not one this can read.

        Parameters
        ----------
        capsule : PyCapsule
            The factor ``cvxopt.cholmod.symbolic`` returned, after ``numeric``.
        n : int
            The matrix size, checked against the factor's.

        Returns
        -------
        SparseForwardSolver or None
            None (with a warning logged once per reason) on a cvxopt version
            this was not written for, or a factor whose header is not as expected.

        Examples
        --------
        >>> from heatcore import linalg
        >>> import scipy.sparse as sp
        >>> f = linalg.factor(sp.identity(5, format="csc"), "supernodal")
        >>> SparseForwardSolver.from_cvxopt(f._factor, 5) is not None
        True
        """
        if not version_is_known("cvxopt", "sparse right-hand sides"):
            return None
        try:
            structure = _CholmodFactor.from_address(_capsule_pointer(capsule))
        except _UNREADABLE as exc:
            _decline("not a cvxopt factor", exc)
            return None
        if structure.n != n:
            _decline("a factor of another size", f"{structure.n} unknowns, expected {n}")
            return None
        try:
            return cls(capsule, structure)
        except _UNREADABLE as exc:
            _decline("an unexpected factor layout", exc)
            return None

    def _supernode_of(self, columns):
        return np.searchsorted(self._first_column, columns, side="right") - 1

    def _reach(self, columns):
        """Supernodes with nonzeros in ``L^{-1} e_k`` for the columns ``k``, ascending; None if too many."""
        starts = np.unique(self._supernode_of(columns))
        if starts.size > self._max_supernodes or self._sizes[starts].sum() > self._max_size:
            return None  # the walk below visits each of them: it would give up too (a dense right-hand side)
        visited = set()
        size = 0
        for supernode in starts.tolist():
            while supernode >= 0 and supernode not in visited:
                visited.add(supernode)
                size += self._sizes[supernode]
                if size > self._max_size or len(visited) > self._max_supernodes:
                    return None
                supernode = self._parent[supernode]
        return sorted(visited)

    def unpermute(self, y):
        """``P^T y``: the ``x`` with ``x[permutation] = y``, by a gather (twice as fast as that scatter).

        Examples
        --------
        >>> from heatcore import linalg
        >>> import scipy.sparse as sp
        >>> solver = linalg.factor(sp.diags(np.arange(1.0, 6.0)).tocsc(), "supernodal")._sparse_forward
        >>> y = np.arange(5.0)
        >>> x = np.empty(5)
        >>> x[solver.permutation] = y
        >>> bool((solver.unpermute(y) == x).all())
        True
        """
        return y[self._position]

    def forward(self, b):
        """``L^{-1} P b`` for a right-hand side with few nonzeros, or None where a dense solve is faster.

        Parameters
        ----------
        b : (n,) float array

        Returns
        -------
        (n,) float array or None
            In the factor's (permuted) order.

        Examples
        --------
        >>> from heatcore import linalg
        >>> import scipy.sparse as sp
        >>> solver = linalg.factor(sp.diags(np.full(5, 4.0)).tocsc(), "supernodal")._sparse_forward
        >>> solver.forward(np.array([0.0, 0.0, 2.0, 0.0, 0.0]))[solver.permutation == 2]  # L = 2 I
        array([1.])
        """
        if not is_sparse(b):
            return None
        nonzero = np.flatnonzero(b)
        columns = self._position[nonzero]
        reach = self._reach(columns)
        if reach is None:
            return None
        count_fast_path("sparse_forward")
        y = np.zeros(b.size)
        y[columns] = b[nonzero]
        for supernode in reach:
            first, end = self._first_column[supernode], self._first_column[supernode + 1]
            n_columns, n_rows = end - first, self._n_rows[supernode]
            start = self._value_start[supernode]
            # Column-major n_rows x n_columns: the diagonal block, then the rows below.
            block = self._values[start : start + n_rows * n_columns].reshape(n_columns, n_rows).T
            y[first:end] = solved = dtrsv(block[:n_columns], y[first:end], lower=1)
            if n_rows > n_columns:
                below = self._rows[self._row_start[supernode] + n_columns : self._row_start[supernode + 1]]
                y[below] -= block[n_columns:] @ solved
        return y
