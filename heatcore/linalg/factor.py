"""The Factor interface, and which backend factors a matrix.

Every backend returns a :class:`Factor`: factor once, then ``solve(b)`` for
one right-hand side ``(n,)`` or several ``(n, k)`` on every backend (a backend
that cannot take a matrix loops over the columns). "auto" picks the backend by
the matrix size and by what matters more (:func:`choose_backend`).

The backends live one per module (:mod:`~heatcore.linalg.supernodal`,
:mod:`~heatcore.linalg.qdldl`, :mod:`~heatcore.linalg.cholmod`,
:mod:`~heatcore.linalg.superlu`) and are imported on first use; their
libraries too (:mod:`heatcore.linalg.libraries`).

Examples
--------
>>> import numpy as np, scipy.sparse as sp
>>> f = factor(sp.diags([2.0, 4.0]).tocsc())
>>> f.solve(np.array([2.0, 4.0]))
array([1., 1.])
>>> f.solve(np.eye(2)).shape  # several right-hand sides at once
(2, 2)
"""

import abc
import importlib
import logging
import weakref

import numpy as np
import scipy.sparse as sp

from ..errors import SolverError
from .libraries import optional, warn_once

log = logging.getLogger(__name__)

#: Factorizations and orderings of each live domain, shared by its solvers (see :func:`domain_factors`).
_DOMAIN_FACTORS = weakref.WeakKeyDictionary()

#: From this many unknowns up "auto" uses the supernodal backend where installed.
SUPERNODAL_MIN_SIZE = 100_000
#: Without the supernodal backend, "auto" prefers ``cholmod`` to ``qdldl`` above this size.
QDLDL_MAX_SIZE = 300_000

#: Each backend: its module in this package, its :class:`Factor` class there, and the library
#: it needs (None: SciPy, always there).
BACKENDS = {
    "supernodal": ("supernodal", "SupernodalFactor", "cvxopt"),
    "qdldl": ("qdldl", "QDLDLFactor", "qdldl"),
    "cholmod": ("cholmod", "CholmodFactor", "cholespy"),
    "superlu": ("superlu", "SuperLUFactor", None),
    "gpu": ("gpu", "GPUFactor", "nvmath"),  # by name only: "auto" never picks it
}


class Factor(abc.ABC):
    """A sparse symmetric positive definite matrix, factored once for many solves.

    Attributes
    ----------
    n : int
        The matrix is ``n`` x ``n``.
    backend : str
        The backend that factored it (a key of :data:`BACKENDS`).

    Examples
    --------
    >>> import numpy as np, scipy.sparse as sp
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
    A = sp.csr_matrix(A)
    if not A.has_canonical_format:
        A = A.copy()
        A.sum_duplicates()
    return A


def available_backends():
    """Names of the factorization backends usable here, fastest factorization first.

    Probes (imports) the optional libraries on the first call.

    Returns
    -------
    list of str
        Some of "supernodal", "qdldl", "cholmod", then "superlu" (always), then
        "gpu" where nvmath-python and a CUDA GPU are there.

    Examples
    --------
    >>> "superlu" in available_backends()
    True
    """
    usable = [name for name, (_, _, library) in BACKENDS.items() if library is None or optional(library) is not None]
    if "gpu" in usable and importlib.import_module(".gpu", __package__).gpu_count() == 0:
        usable.remove("gpu")
    return usable


def choose_backend(n, prefer="factor"):
    """The backend "auto" uses for an ``n`` x ``n`` matrix.

    ``supernodal`` from :data:`SUPERNODAL_MIN_SIZE` unknowns up, where
    factoring dominates. Below, ``prefer="factor"`` (a matrix rebuilt often)
    picks ``qdldl`` and ``prefer="solve"`` (a matrix kept for many solves)
    picks ``cholmod``, whose solves are 1.5x faster than ``supernodal``'s.
    ``prefer="once"`` (matrices factored for a single query, as
    :func:`heatcore.geodesic_distance` does) picks ``supernodal`` at every
    size where installed: it factors 2-7x faster than ``qdldl`` and
    ``cholmod`` below :data:`SUPERNODAL_MIN_SIZE` (11,714 unknowns: 8 ms after
    a 6 ms ordering shared by both matrices, against 20 ms and 51 ms), and
    solves a little slower. Without cvxopt, large matrices go to ``cholmod``
    above :data:`QDLDL_MAX_SIZE` (with a hint, once, to install the ``scale``
    extra).

    Parameters
    ----------
    n : int
        The number of unknowns.
    prefer : {"factor", "solve", "once"}
        What matters more: a fast factorization, fast solves, or both
        factorizations of a single query.

    Returns
    -------
    str
        One of :func:`available_backends`.

    Examples
    --------
    >>> choose_backend(10) in available_backends()
    True
    >>> choose_backend(10, "once") in ("supernodal", "qdldl")
    True
    """
    if prefer not in ("factor", "solve", "once"):
        raise SolverError(f"prefer must be 'factor', 'solve' or 'once', not {prefer!r}")
    backends = available_backends()
    if n >= SUPERNODAL_MIN_SIZE or (prefer == "once" and "supernodal" in backends):
        if "supernodal" in backends:
            return "supernodal"
        warn_once(
            "scale extra",
            "factoring %d unknowns without cvxopt: pip install 'heatcore[scale]' makes this several "
            "times faster (supernodal CHOLMOD)",
            n,
            logger=log,
        )
    fast_factor = "qdldl" in backends and (n <= QDLDL_MAX_SIZE or "cholmod" not in backends)
    if prefer != "solve" and fast_factor:
        return "qdldl"
    return "cholmod" if "cholmod" in backends else backends[0]


def one_query_backend(backend, n):
    """The backend for a solver asked a single query: ``backend``, or for "auto" the fastest to factor.

    Parameters
    ----------
    backend : str
        The backend option ("auto" or a name).
    n : int
        The number of unknowns.

    Returns
    -------
    str

    Examples
    --------
    >>> one_query_backend("superlu", 10), one_query_backend("auto", 10) == choose_backend(10, "once")
    ('superlu', True)
    """
    return choose_backend(n, "once") if backend == "auto" else backend


def factor(A, backend="auto", prefer="factor", ordering=None):
    """Factor a sparse symmetric positive definite matrix once.

    Parameters
    ----------
    A : (n, n) sparse matrix
    backend : {"auto", "supernodal", "qdldl", "cholmod", "superlu", "gpu"}
    prefer : {"factor", "solve"}
        What "auto" optimizes: the factorization (a matrix rebuilt often) or
        the solves (a matrix kept for many solves).
    ordering : Ordering, optional
        A fill-reducing ordering from :func:`~heatcore.linalg.fill_reducing_ordering`,
        used by the ``supernodal`` backend (the others order each matrix themselves).

    Returns
    -------
    Factor
        ``solve(b)`` for ``b`` of shape ``(n,)`` or ``(n, k)``.

    Raises
    ------
    SolverError
        The matrix is not positive definite, the backend is unknown, or its
        library is not installed.

    Examples
    --------
    >>> import numpy as np, scipy.sparse as sp
    >>> A = sp.csc_matrix([[4.0, 1.0], [1.0, 3.0]])
    >>> x = factor(A, "superlu").solve([1.0, 2.0])
    >>> bool(np.allclose(A @ x, [1.0, 2.0]))
    True
    """
    if backend == "auto":
        backend = choose_backend(A.shape[0], prefer)
    if backend not in BACKENDS:
        raise SolverError(f"unknown linear-algebra backend {backend!r}; use one of {available_backends()}")
    module, factor_class, library = BACKENDS[backend]
    if library is not None and optional(library) is None:
        extra = {"supernodal": ": pip install 'heatcore[scale]'",
                 "gpu": " (cuDSS): pip install 'heatcore[gpu]'"}.get(backend, "")
        raise SolverError(f"backend {backend!r} needs the {library} package{extra}")
    # The backend's module is imported on first use, like its library.
    return getattr(importlib.import_module(f".{module}", __package__), factor_class)(A, ordering)


def domain_factors(domain):
    """The factorizations and orderings kept for ``domain``, shared by every solver built on it.

    They depend on the domain only (not on ``m`` or the boundary condition),
    live as long as the domain does, and are kept here, not on the domain.

    Examples
    --------
    >>> import numpy as np, heatcore as hc
    >>> mesh = hc.TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0)
    >>> _ = hc.HeatSolver(mesh)
    >>> sorted({key for key, _ in domain_factors(mesh)})
    ['nested', 'ordering', 'poisson']
    """
    return _DOMAIN_FACTORS.setdefault(domain, {})
