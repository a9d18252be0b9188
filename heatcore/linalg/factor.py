"""Factor a matrix with a backend: :func:`factor`.

Every backend returns a :class:`~heatcore.linalg.interface.Factor`: factor
once, then ``solve(b)`` for one right-hand side ``(n,)`` or several ``(n, k)``
on every backend (a backend that cannot take a matrix loops over the
columns). "auto" picks the backend by the matrix size and by what matters
more (:func:`~heatcore.linalg.backends.choose_backend`; a caller with an
intent asks :func:`~heatcore.linalg.backends.resolve_backend`). The interface
and the choice live in their own modules, which import no backend, so the
backends import them and not this module.

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

import importlib

from ..errors import SolverError
from .backends import (  # noqa: F401 (re-exported: the names this module has always offered)
    BACKENDS,
    QDLDL_MAX_SIZE,
    SUPERNODAL_MIN_SIZE,
    available_backends,
    choose_backend,
    resolve_backend,
)
from .interface import Factor, canonical_csr  # noqa: F401 (re-exported, as above)
from .libraries import optional


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


#: :func:`start_factor` runs factorizations of this many unknowns and more beside the caller; smaller ones
#: (a 507-vertex mesh's: 0.2 ms) are made when their result is asked for, as a thread's hand-over costs about that.
BACKGROUND_MIN_SIZE = 5_000


def start_factor(A, backend="auto", prefer="factor", ordering=None):
    """Start factoring a matrix where it can run beside the caller; ``result()`` gives the :class:`Factor`.

    The ``supernodal`` backend with an ``ordering`` (and CHOLMOD within reach:
    :mod:`~heatcore.linalg.cholmod_direct`) makes its symbolic analysis here
    and runs the numeric factorization in a background thread, without the
    GIL, while the caller factors another matrix (from
    :data:`BACKGROUND_MIN_SIZE` unknowns). Every other case factors when
    ``result()`` is first called, as :func:`factor` would.

    Parameters
    ----------
    A, backend, prefer, ordering
        As for :func:`factor`.

    Returns
    -------
    StartedFactor

    Raises
    ------
    SolverError
        As :func:`factor` (from ``result()`` where the work is done there).

    Examples
    --------
    >>> import numpy as np, scipy.sparse as sp
    >>> started = start_factor(sp.diags([2.0, 4.0]).tocsc(), "superlu")
    >>> started.result().solve(np.array([2.0, 4.0]))
    array([1., 1.])
    """
    if backend == "auto":
        backend = choose_backend(A.shape[0], prefer)
    beside = A.shape[0] >= BACKGROUND_MIN_SIZE  # a small one is over before a thread would take it up
    if beside and backend == "supernodal" and ordering is not None and optional("cvxopt") is not None:
        from . import cholmod_direct, supernodal  # imported on first use, with cvxopt

        if cholmod_direct.available():
            return StartedFactor(supernodal.SupernodalFactor(A, ordering, background=True))
    return StartedFactor(None, lambda: factor(A, backend, prefer, ordering))


class StartedFactor:
    """A factorization started by :func:`start_factor`.

    Parameters
    ----------
    started : Factor or None
        A factor whose numeric factorization runs in the background.
    later : callable, optional
        Where none runs: makes the factor, on the first :meth:`result`.

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> started = StartedFactor(None, lambda: factor(sp.identity(2, format="csc"), "superlu"))
    >>> started.result() is started.result()
    True
    """

    def __init__(self, started, later=None):
        self._factor, self._later = started, later

    def result(self):
        """The factor, once done (waiting for it, or making it now).

        Returns
        -------
        Factor

        Raises
        ------
        SolverError
            The factorization failed.
        """
        if self._factor is None:
            self._factor, self._later = self._later(), None
        return self._factor.wait()
