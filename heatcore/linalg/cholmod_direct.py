"""CHOLMOD called directly on cvxopt's factors: one shared symbolic analysis; orderings, analyses, factorizations without the GIL.

A heat solver factors two matrices of one pattern: the heat matrix ``M + t L``
and the grounded Laplacian (:mod:`heatcore.steps.factors`). With the same
fill-reducing ordering, CHOLMOD's symbolic analysis (elimination tree, column
counts, supernodes: 14 ms of a 51k-vertex mesh's 70 ms factorization) is the
same for both, but cvxopt cannot reuse it (``cholmod.numeric`` overwrites the
factor it is given): :func:`copy_factor` copies an analysed factor with
CHOLMOD's own ``cholmod_l_copy_factor`` into a new cvxopt capsule.
:func:`factorize` then fills a factor as ``cholmod.numeric`` does
(``cholmod_l_factorize`` on the lower triangle), but through ctypes, which
lets go of the GIL meanwhile: two factorizations run side by side on two
threads (cvxopt holds the GIL while it factors). :func:`minimum_degree_order`
calls AMD as ``cvxopt.amd.order`` does, and :func:`analyze` CHOLMOD's symbolic
analysis as ``cvxopt.cholmod.symbolic`` does (setting the ``cholmod_common``
fields cvxopt sets, at offsets checked against CHOLMOD's defaults), also
without the GIL. The numbers are
those of cvxopt's own calls: the same routines on the same arrays.

This reads cvxopt's internals (its factor capsule: name, destructor, the
``cholmod_factor`` inside) and calls the CHOLMOD that cvxopt's ``cholmod``
module is linked with, only on the cvxopt versions of
:data:`heatcore.linalg.libraries.READ_INTERNALS_OF`; elsewhere, or where that
library cannot be reached, :func:`available` is False and the supernodal
backend takes cvxopt's own path (same results, slower).

Examples
--------
>>> import numpy as np
>>> from cvxopt import cholmod, matrix, spmatrix
>>> analysis = cholmod.symbolic(spmatrix([4.0, 1.0, 3.0], [0, 1, 1], [0, 0, 1]))  # lower triangle of [[4, 1], [1, 3]]
>>> F = copy_factor(analysis)  # (None where available() is False)
>>> factorize(F, np.array([0, 2, 3]), np.array([0, 1, 1]), np.array([4.0, 1.0, 3.0]))
>>> b = matrix([5.0, 4.0])
>>> cholmod.solve(F, b)
>>> list(b)
[1.0, 1.0]
"""

import ctypes
import os
import sys
import threading

import numpy as np

from ..errors import SolverError
from .libraries import count_fast_path, once, optional, version_is_known, warn_once

#: Bytes reserved for a ``cholmod_common`` (about 3 KB in CHOLMOD 3; the rest is a margin).
COMMON_BYTES = 1 << 16

_CHOLMOD_LONG, _CHOLMOD_REAL, _CHOLMOD_DOUBLE = 2, 1, 0

#: ``cholmod_common`` fields an analysis sets, as (byte offset, C type, CHOLMOD's default): the layout of
#: CHOLMOD 3 (checked against the defaults ``cholmod_l_start`` writes before any is set).
_COMMON_FIELDS = {
    "grow0": (8, ctypes.c_double, 1.2), "maxrank": (32, ctypes.c_size_t, 8), "supernodal_switch": (40, ctypes.c_double, 40.0),
    "supernodal": (48, ctypes.c_int, 1), "zrelax1": (88, ctypes.c_double, 0.1), "nrelax2": (120, ctypes.c_size_t, 48),
    "print": (144, ctypes.c_int, 3), "nmethods": (168, ctypes.c_int, 0), "method0_ordering": (316, ctypes.c_int, 1),
    "method1_ordering": (484, ctypes.c_int, 2), "postorder": (1864, ctypes.c_int, 1),
}

_lock = threading.Lock()  # the copies' cholmod_common, used by one thread at a time


def _new_lock():
    global _lock
    _lock = threading.Lock()  # a forked child has no thread that could hold the parent's


os.register_at_fork(after_in_child=_new_lock)


class _Sparse(ctypes.Structure):
    """``cholmod_sparse`` (the same layout in CHOLMOD 2 to 5)."""

    _fields_ = (
        [(name, ctypes.c_size_t) for name in ("nrow", "ncol", "nzmax")]
        + [(name, ctypes.c_void_p) for name in ("p", "i", "nz", "x", "z")]
        + [(name, ctypes.c_int) for name in ("stype", "itype", "xtype", "dtype", "sorted", "packed")]
    )


class _Library:
    """CHOLMOD's functions as cvxopt links them, a ``cholmod_common`` for copies, and the capsule calls."""

    def __init__(self, library):
        self.copy, self.factorize = library.cholmod_l_copy_factor, library.cholmod_l_factorize
        self.start, self.finish = library.cholmod_l_start, library.cholmod_l_finish
        self.copy.restype, self.copy.argtypes = ctypes.c_void_p, (ctypes.c_void_p, ctypes.c_void_p)
        self.factorize.restype = ctypes.c_int
        self.factorize.argtypes = (ctypes.POINTER(_Sparse), ctypes.c_void_p, ctypes.c_void_p)
        for call in (self.start, self.finish):
            call.restype, call.argtypes = ctypes.c_int, (ctypes.c_void_p,)
        self.common = self.new_common()
        self.analyze = library.cholmod_l_analyze_p
        self.analyze.restype = ctypes.c_void_p
        self.analyze.argtypes = (ctypes.POINTER(_Sparse), ctypes.c_void_p, ctypes.c_void_p, ctypes.c_size_t,
                                 ctypes.c_void_p)
        if any(kind.from_buffer(self.common, offset).value != default
               for offset, kind, default in _COMMON_FIELDS.values()):
            raise OSError("cholmod_common is not laid out as CHOLMOD 3's")
        amd = ctypes.CDLL(sys.modules["cvxopt.amd"].__file__)  # AMD as cvxopt.amd links it
        self.amd_defaults, self.amd_order = amd.amd_l_defaults, amd.amd_l_order
        self.amd_defaults.restype, self.amd_defaults.argtypes = None, (ctypes.c_void_p,)
        self.amd_order.restype = ctypes.c_int64
        self.amd_order.argtypes = (ctypes.c_int64,) + (ctypes.c_void_p,) * 5
        api = ctypes.pythonapi
        self.get_name = ctypes.PYFUNCTYPE(ctypes.c_void_p, ctypes.py_object)(("PyCapsule_GetName", api))
        self.get_pointer = ctypes.PYFUNCTYPE(ctypes.c_void_p, ctypes.py_object, ctypes.c_void_p)(
            ("PyCapsule_GetPointer", api))
        self.get_destructor = ctypes.PYFUNCTYPE(ctypes.c_void_p, ctypes.py_object)(("PyCapsule_GetDestructor", api))
        self.new = ctypes.PYFUNCTYPE(ctypes.py_object, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p)(
            ("PyCapsule_New", api))
        cvxopt = sys.modules["cvxopt"]  # a factor of cvxopt's own: the name and destructor of those made here
        self.example = cvxopt.cholmod.symbolic(cvxopt.spmatrix([1.0], [0], [0]))
        self.name, self.destructor = self.get_name(self.example), self.get_destructor(self.example)

    def new_common(self):
        common = ctypes.create_string_buffer(COMMON_BYTES)
        if not self.start(common):
            raise OSError("cholmod_l_start failed")
        return common

    def factor_pointer(self, capsule):
        """The ``cholmod_factor *`` of a cvxopt factor of a real matrix, and the capsule's name (a C string)."""
        name = self.get_name(capsule)
        if not name or not ctypes.string_at(name).startswith(b"CHOLMOD FACTOR D"):
            raise TypeError("not a cvxopt factor of a real matrix")
        return self.get_pointer(capsule, name), name


@once
def _library():
    """The :class:`_Library`, or None where cvxopt is missing, of another version, or its CHOLMOD out of reach."""
    if optional("cvxopt") is None or not version_is_known("cvxopt", "CHOLMOD called directly"):
        return None
    try:  # the extension's own symbols resolve to the CHOLMOD it was linked with
        return _Library(ctypes.CDLL(sys.modules["cvxopt.cholmod"].__file__))
    except (OSError, AttributeError) as exc:
        warn_once(("CHOLMOD called directly", "library"), "CHOLMOD called directly: cannot reach it (%s); using "
                  "cvxopt's calls (same results, slower)", exc)
        return None


def available():
    """Whether :func:`copy_factor` and :func:`factorize` can run here (cvxopt of a known version, its CHOLMOD reached).

    Examples
    --------
    >>> isinstance(available(), bool)
    True
    """
    return _library() is not None


def copy_factor(factor):
    """A copy of a cvxopt CHOLMOD factor: a symbolic analysis, to factor another matrix of its pattern with.

    Parameters
    ----------
    factor : PyCapsule
        A factor made by ``cvxopt.cholmod.symbolic`` (or ``numeric``).

    Returns
    -------
    PyCapsule or None
        A new factor that cvxopt's ``cholmod.numeric`` and ``cholmod.solve``
        take, and free as their own; None where :func:`available` is False or
        CHOLMOD has no memory for it.

    Examples
    --------
    >>> from cvxopt import cholmod, spmatrix
    >>> analysis = cholmod.symbolic(spmatrix([2.0, 1.0], [0, 1], [0, 1]))
    >>> copy_factor(analysis) is not None
    True
    """
    library = _library()
    if library is None:
        return None
    pointer, name = library.factor_pointer(factor)
    with _lock:
        copied = library.copy(pointer, library.common)
    if not copied:
        return None
    count_fast_path("shared_symbolic")
    return library.new(copied, name, library.get_destructor(factor))  # cvxopt's name and destructor: it frees it


def _lower(indptr, indices, data):
    """The arrays of a matrix's lower triangle by columns, as CHOLMOD reads them, and its ``cholmod_sparse``."""
    indptr = np.ascontiguousarray(indptr, dtype=np.int64)
    indices = np.ascontiguousarray(indices, dtype=np.int64)
    data = np.ascontiguousarray(data, dtype=np.float64)
    n = indptr.size - 1
    matrix = _Sparse(n, n, indices.size, indptr.ctypes.data, indices.ctypes.data, None, data.ctypes.data, None,
                     -1, _CHOLMOD_LONG, _CHOLMOD_REAL, _CHOLMOD_DOUBLE, 1, 1)
    return (indptr, indices, data), matrix


def analyze(indptr, indices, data, permutation):
    """The supernodal symbolic analysis ``cvxopt.cholmod.symbolic`` makes in a given order, without the GIL.

    The same call with the same settings (supernodal, the given ordering and
    no other: cvxopt's with ``options`` ``supernodal=2, nmethods=1``).

    Parameters
    ----------
    indptr, indices, data : arrays
        The matrix's lower triangle by compressed columns (as :func:`factorize`).
    permutation : (n,) int array
        The elimination order.

    Returns
    -------
    PyCapsule
        A cvxopt factor holding the analysis (for ``cholmod.numeric``, :func:`factorize`, :func:`copy_factor`).

    Raises
    ------
    SolverError
        CHOLMOD refused the matrix or the order (or had no memory).
    RuntimeError
        :func:`available` is False.

    Examples
    --------
    >>> F = analyze(np.array([0, 2, 3]), np.array([0, 1, 1]), np.array([4.0, 1.0, 3.0]), np.array([1, 0]))
    >>> factorize(F, np.array([0, 2, 3]), np.array([0, 1, 1]), np.array([4.0, 1.0, 3.0]))
    """
    library = _library()
    if library is None:
        raise RuntimeError("CHOLMOD cannot be called directly here (see available())")
    arrays, matrix = _lower(indptr, indices, data)
    permutation = np.ascontiguousarray(permutation, dtype=np.int64)
    common = library.new_common()
    for name, value in (("supernodal", 2), ("nmethods", 1), ("print", 0)):
        offset, kind, _ = _COMMON_FIELDS[name]
        kind.from_buffer(common, offset).value = value
    try:
        pointer = library.analyze(ctypes.byref(matrix), permutation.ctypes.data, None, 0, common)
    finally:
        library.finish(common)
    if not pointer:
        raise SolverError("sparse Cholesky factorization failed: CHOLMOD's symbolic analysis failed")
    return library.new(pointer, library.name, library.destructor)


def factorize(factor, indptr, indices, data):
    """Fill a cvxopt factor with the Cholesky factor of a matrix, as ``cvxopt.cholmod.numeric`` does, without the GIL.

    Parameters
    ----------
    factor : PyCapsule
        A cvxopt factor holding a symbolic analysis of the matrix's pattern
        (``cvxopt.cholmod.symbolic``, or :func:`copy_factor`).
    indptr, indices, data : arrays
        The matrix's lower triangle in compressed columns (sorted rows),
        what cvxopt hands CHOLMOD for ``uplo="L"``.

    Raises
    ------
    SolverError
        The matrix is not positive definite, or CHOLMOD failed (no memory).
    RuntimeError
        :func:`available` is False.

    Examples
    --------
    >>> from cvxopt import cholmod, spmatrix
    >>> F = cholmod.symbolic(spmatrix([2.0, 1.0], [0, 1], [0, 1]))
    >>> factorize(F, np.array([0, 1, 2]), np.array([0, 1]), np.array([-1.0, 1.0]))
    Traceback (most recent call last):
    heatcore.errors.SolverError: sparse Cholesky factorization failed: the matrix is not positive definite (column 0)
    """
    library = _library()
    if library is None:
        raise RuntimeError("CHOLMOD cannot be called directly here (see available())")
    pointer, _ = library.factor_pointer(factor)
    arrays, matrix = _lower(indptr, indices, data)  # (the arrays stay alive through the call)
    common = library.new_common()  # one per call: its workspace is this thread's
    try:
        done = library.factorize(ctypes.byref(matrix), pointer, common)  # ctypes lets go of the GIL here
    finally:
        library.finish(common)
    header = (ctypes.c_size_t * 2).from_address(pointer)  # cholmod_factor starts with n, minor
    if not done:
        raise SolverError("sparse Cholesky factorization failed (CHOLMOD: out of memory?)")
    if header[1] < header[0]:
        raise SolverError(f"sparse Cholesky factorization failed: the matrix is not positive definite "
                          f"(column {header[1]})")


def minimum_degree_order(indptr, indices):
    """The approximate minimum degree ordering ``cvxopt.amd.order`` gives, without the GIL.

    The same call with the same arrays: AMD's default controls, on the lower
    triangle by compressed columns.

    Parameters
    ----------
    indptr, indices : int arrays
        The matrix's lower triangle (with its diagonal) by compressed columns, sorted rows.

    Returns
    -------
    (n,) int64 array
        ``permutation[k]`` is the ``k``-th unknown eliminated.

    Raises
    ------
    SolverError
        AMD refused the pattern (or had no memory).
    RuntimeError
        :func:`available` is False.

    Examples
    --------
    >>> minimum_degree_order(np.array([0, 2, 3, 4]), np.array([0, 2, 1, 2])).tolist()  # 0-2 joined, 1 alone
    [1, 0, 2]
    """
    library = _library()
    if library is None:
        raise RuntimeError("AMD cannot be called directly here (see available())")
    indptr = np.ascontiguousarray(indptr, dtype=np.int64)
    indices = np.ascontiguousarray(indices, dtype=np.int64)
    control = (ctypes.c_double * 5)()
    library.amd_defaults(control)
    permutation = np.empty(indptr.size - 1, dtype=np.int64)
    status = library.amd_order(permutation.size, indptr.ctypes.data, indices.ctypes.data, permutation.ctypes.data,
                               control, None)  # ctypes lets go of the GIL here
    if status < 0:
        raise SolverError(f"minimum degree ordering failed (AMD status {status})")
    return permutation
