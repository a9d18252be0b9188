"""Fill-reducing orderings computed once and shared among factorizations.

A sparse Cholesky factor's size depends on the order in which unknowns are
eliminated. Matrices with the same sparsity pattern (a Laplacian, the heat
matrix built from it, a principal submatrix of it) can share one ordering
instead of each computing its own:

- :func:`fill_reducing_ordering`: approximate minimum degree (AMD, 0.4 s at
  1M unknowns), for the ``supernodal`` backend;
- :func:`start_nested_dissection`: METIS nested dissection in a background
  thread, from :data:`NESTED_DISSECTION_MIN_SIZE` unknowns up where pymetis
  is installed (seconds longer than AMD, but a smaller factor; heat solvers
  ask for it only when kept for further queries,
  :data:`heatcore.steps.factors.NESTED_DISSECTION_FOR`);
- :meth:`Ordering.restrict` and :func:`restrict_ordering`: the ordering
  induced on a principal submatrix.

The background thread pool is created on the first nested dissection, not at
import. To change the size from which nested dissection is used, set
``heatcore.linalg.ordering.NESTED_DISSECTION_MIN_SIZE`` (the name exported by
:mod:`heatcore.linalg` is a copy, for reading).

Examples
--------
>>> import numpy as np
>>> ordering = Ordering([2, 0, 1])
>>> ordering.restrict(np.array([0, 2])).permutation  # unknown 2 before unknown 0
array([1, 0])
"""

from concurrent.futures import ThreadPoolExecutor

import numpy as np

from . import metis
from .interface import canonical_csr
from .libraries import once

#: From this many unknowns up :func:`start_nested_dissection` orders by METIS (see there).
NESTED_DISSECTION_MIN_SIZE = 500_000


class Ordering:
    """A fill-reducing permutation, and the sparsity pattern it was computed for.

    Matrices with exactly that pattern (a Laplacian, the heat matrix built from
    it, the grounded Laplacian with explicit zeros kept) reuse the converted
    pattern: only their values are copied.

    Parameters
    ----------
    permutation : (n,) int array_like
        ``permutation[k]`` is the ``k``-th unknown eliminated.
    pattern : object, optional
        The backend's converted sparsity pattern, reused by factorizations of
        matrices with exactly that pattern (the ``supernodal`` backend's: the
        pattern as CSR, True on its upper triangle, and its lower triangle in
        cvxopt form).

    Attributes
    ----------
    permutation : (n,) int64 array
    pattern : object or None
    analysis : object or None
        The backend's symbolic analysis of the pattern in this order, kept by
        the first factorization of a matrix with the pattern for the others
        (the ``supernodal`` backend's: a CHOLMOD symbolic factor,
        :mod:`heatcore.linalg.symbolic`).

    Examples
    --------
    >>> Ordering([1, 0, 2]).permutation
    array([1, 0, 2])
    """

    def __init__(self, permutation, pattern=None):
        self.permutation = np.asarray(permutation, dtype=np.int64).ravel()
        self.pattern = pattern
        self.analysis = None

    def forget_pattern(self):
        """Drop the converted pattern and the symbolic analysis (their memory); later factorizations make their own.

        Examples
        --------
        >>> ordering = Ordering([0, 1], pattern="converted")
        >>> ordering.forget_pattern()
        >>> ordering.pattern is None
        True
        """
        self.pattern = self.analysis = None

    def reordered(self, permutation):
        """Another ordering of the same pattern (sharing its converted pattern).

        Parameters
        ----------
        permutation : (n,) int array_like

        Returns
        -------
        Ordering

        Examples
        --------
        >>> other = Ordering([0, 1, 2], pattern="converted").reordered([2, 1, 0])
        >>> other.permutation, other.pattern
        (array([2, 1, 0]), 'converted')
        """
        return Ordering(permutation, self.pattern)

    def restrict(self, rows):
        """The ordering induced on the principal submatrix ``A[rows][:, rows]``.

        Eliminating a subset of the unknowns in the same relative order fills in
        no more than the full elimination does.

        Parameters
        ----------
        rows : (m,) int array
            The kept unknowns, distinct.

        Returns
        -------
        Ordering
            Over ``0..m-1`` (positions in ``rows``), without a converted pattern.

        Examples
        --------
        >>> import numpy as np
        >>> Ordering([3, 1, 0, 2]).restrict(np.array([0, 1, 3])).permutation
        array([2, 1, 0])
        """
        position = np.empty_like(self.permutation)
        position[self.permutation] = np.arange(self.permutation.size)
        return Ordering(np.argsort(position[rows], kind="stable"))


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
        backends that order each matrix themselves. Pass it to
        :func:`~heatcore.linalg.factor` for any matrix whose pattern is
        contained in ``A``'s, or restrict it with :meth:`Ordering.restrict` for
        a principal submatrix (``None`` has no restriction to make: use
        :func:`restrict_ordering`).

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> fill_reducing_ordering(sp.identity(3, format="csc"), "qdldl") is None
    True
    """
    if backend != "supernodal":
        return None
    from . import supernodal  # imported on first use, with cvxopt

    return Ordering(*supernodal.minimum_degree(canonical_csr(A)))


def start_fill_reducing_ordering(A, backend):
    """:func:`fill_reducing_ordering` started: where it can, its minimum degree runs beside the caller.

    The ``supernodal`` backend's AMD runs in a background thread without the
    GIL (:func:`heatcore.linalg.supernodal.minimum_degree`), while the caller
    goes on (a heat solver: its components and time step).

    Parameters
    ----------
    A : (n, n) sparse symmetric matrix
    backend : str

    Returns
    -------
    StartedOrdering
        Its ``result()`` is what :func:`fill_reducing_ordering` returns.

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> start_fill_reducing_ordering(sp.identity(3, format="csr"), "qdldl").result() is None
    True
    """
    if backend != "supernodal":
        return StartedOrdering(None)
    from . import supernodal  # imported on first use, with cvxopt

    return StartedOrdering(*supernodal.minimum_degree(canonical_csr(A), background=True))


class StartedOrdering:
    """An ordering being computed (:func:`start_fill_reducing_ordering`); ``result()`` waits for it.

    Parameters
    ----------
    permutation : int array, Future of ``(permutation, analysis)``, or None
        None: no ordering (a backend that orders each matrix itself); the
        analysis becomes :attr:`Ordering.analysis`.
    pattern : object, optional
        As for :class:`Ordering`.

    Examples
    --------
    >>> StartedOrdering([1, 0]).result().permutation
    array([1, 0])
    """

    def __init__(self, permutation, pattern=None):
        self._permutation, self._pattern, self._ordering = permutation, pattern, None

    def result(self):
        """The :class:`Ordering` (None for no ordering), once computed."""
        if self._ordering is None and self._permutation is not None:
            permutation, analysis = self._permutation, None
            if hasattr(permutation, "result"):  # a Future of the permutation and the backend's analysis in its order
                permutation, analysis = permutation.result()
            self._ordering = Ordering(permutation, self._pattern)
            self._ordering.analysis = analysis
            self._permutation = self._pattern = None
        return self._ordering


def restrict_ordering(ordering, rows):
    """``ordering.restrict(rows)``, or None for no ordering.

    Parameters
    ----------
    ordering : Ordering or None
    rows : (m,) int array

    Returns
    -------
    Ordering or None

    Examples
    --------
    >>> import numpy as np
    >>> restrict_ordering(None, np.arange(2)) is None
    True
    >>> restrict_ordering(Ordering([1, 0]), np.arange(2)).permutation
    array([1, 0])
    """
    return None if ordering is None else ordering.restrict(rows)


@once
def _background():
    """The thread that runs nested dissections, created on first use."""
    return ThreadPoolExecutor(max_workers=1, thread_name_prefix="heatcore-nested-dissection")


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
        ``NESTED_DISSECTION_MIN_SIZE`` unknowns, or no usable METIS (pymetis
        not installed, or a version whose library :mod:`heatcore.linalg.metis`
        was not written for: then with a logged warning).

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> start_nested_dissection(sp.identity(10, format="csr"), "supernodal") is None  # too small to pay
    True
    """
    if backend != "supernodal" or A.shape[0] < NESTED_DISSECTION_MIN_SIZE:
        return None
    reader = metis.node_nd()
    if reader is None:
        return None
    xadj, adjncy = reader.adjacency(canonical_csr(A))
    return _background().submit(reader.nested_dissection, xadj, adjncy)
