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
``supernodal``'s. A caller says what it means to do, not which rule applies:
``resolve_backend(backend, n, intent=..., stage=...)`` (``intent`` "reuse"
or "one query") gives the backend of each matrix.

Factor once, solve many times: every backend's :meth:`Factor.solve` accepts
one right-hand side ``(n,)`` or several ``(n, k)``.

Modules: :mod:`~heatcore.linalg.interface` (the :class:`Factor` interface),
:mod:`~heatcore.linalg.backends` (the backend choice),
:mod:`~heatcore.linalg.factor` (:func:`factor`, which imports the backends);
one per backend (:mod:`~heatcore.linalg.supernodal`,
:mod:`~heatcore.linalg.qdldl`, :mod:`~heatcore.linalg.cholmod`,
:mod:`~heatcore.linalg.superlu`); :mod:`~heatcore.linalg.ordering`;
:mod:`~heatcore.linalg.metis`, :mod:`~heatcore.linalg.sparse_rhs` and
:mod:`~heatcore.linalg.cholmod_direct` (the readers of another library's
internals, through ctypes: the only ones in heatcore; the last calls cvxopt's
CHOLMOD and AMD without the GIL, so that :func:`start_factor` and
:func:`start_fill_reducing_ordering` run beside the caller); :mod:`~heatcore.linalg.memory`; :mod:`~heatcore.linalg.libraries`
(optional libraries loaded on first use, the versions the readers know, the
fast-path counters). Importing this package loads no optional library, opens
no shared library and starts no thread; linalg keeps nothing per matrix or
domain (what is derived from a domain lives in its own cache,
:class:`heatcore.domains.derived.DerivedCache`). The size thresholds exported here are
copies for reading: set them on their modules (for example
``heatcore.linalg.ordering.NESTED_DISSECTION_MIN_SIZE``). The name ``factor``
here is the function; the module is ``sys.modules["heatcore.linalg.factor"]``.

Examples
--------
>>> import scipy.sparse as sp, numpy as np
>>> A = sp.diags([2.0, 3.0]).tocsc()
>>> factor(A).solve(np.array([2.0, 3.0]))
array([1., 1.])
"""

from .backends import (
    QDLDL_MAX_SIZE,
    SUPERNODAL_MIN_SIZE,
    available_backends,
    choose_backend,
    resolve_backend,
)
from .columns import solve_columns
from .factor import StartedFactor, factor, start_factor
from .interface import Factor
from .memory import release_free_memory
from .ordering import (
    NESTED_DISSECTION_MIN_SIZE,
    Ordering,
    StartedOrdering,
    fill_reducing_ordering,
    restrict_ordering,
    start_fill_reducing_ordering,
    start_nested_dissection,
)

__all__ = [
    "NESTED_DISSECTION_MIN_SIZE",
    "QDLDL_MAX_SIZE",
    "SUPERNODAL_MIN_SIZE",
    "Factor",
    "Ordering",
    "StartedFactor",
    "StartedOrdering",
    "available_backends",
    "choose_backend",
    "factor",
    "fill_reducing_ordering",
    "release_free_memory",
    "resolve_backend",
    "restrict_ordering",
    "solve_columns",
    "start_factor",
    "start_fill_reducing_ordering",
    "start_nested_dissection",
]
