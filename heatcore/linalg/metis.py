"""METIS nested dissection through ctypes, on the METIS library inside pymetis.

pymetis's own ``nested_dissection`` holds the GIL, so running it in a thread
gains nothing (measured slower). Called through ctypes, ``METIS_NodeND``
releases the GIL and runs while the caller factors another matrix.

This reads pymetis's private extension module (the library file, its index
width, its table of option positions), so it is used only on the pymetis
versions in :data:`heatcore.linalg.libraries.READ_INTERNALS_OF`; on another
version, or where the library is not as expected, :func:`node_nd` returns
None with a logged warning and the caller keeps minimum degree (same results,
a larger factor). Nothing is loaded before the first call.

Examples
--------
>>> import numpy as np, scipy.sparse as sp
>>> path = sp.diags([np.ones(5), np.ones(5)], [-1, 1], shape=(6, 6), format="csr")  # a path graph
>>> reader = node_nd()  # None without pymetis
>>> reader is None or sorted(reader.nested_dissection(*reader.adjacency(path)).tolist()) == list(range(6))
True
"""

import ctypes
import importlib

import numpy as np

from ..errors import SolverError
from .libraries import count_fast_path, once, optional, version_is_known, warn_once

#: The length of METIS's options array (``METIS_NOPTIONS`` in metis.h 5.1 and 5.2).
METIS_NOPTIONS = 40
#: ``METIS_OK``.
METIS_OK = 1


class NodeND:
    """``METIS_NodeND`` of a METIS shared library, with the options heatcore uses.

    Parameters
    ----------
    function : ctypes function
        ``METIS_NodeND``.
    index_type : numpy dtype
        METIS's ``idx_t`` (32 or 64 bits).
    options : (METIS_NOPTIONS,) array of index_type

    Examples
    --------
    >>> reader = node_nd()
    >>> reader is None or reader.index_type in (np.int32, np.int64)
    True
    """

    def __init__(self, function, index_type, options):
        self.function, self.index_type, self.options = function, index_type, options

    def adjacency(self, A):
        """The graph of ``A``'s off-diagonal pattern, in METIS's CSR form.

        Parameters
        ----------
        A : (n, n) csr_matrix
            Symmetric pattern, canonical (sorted, no duplicates).

        Returns
        -------
        xadj : (n + 1,) array of index_type
        adjncy : array of index_type

        Examples
        --------
        >>> import scipy.sparse as sp
        >>> reader = node_nd()
        >>> reader is None or reader.adjacency(sp.csr_matrix(np.ones((2, 2))))[1].tolist() == [1, 0]
        True
        """
        n = A.shape[0]
        rows = np.repeat(np.arange(n), np.diff(A.indptr))
        off_diagonal = A.indices != rows
        xadj = np.zeros(n + 1, dtype=self.index_type)
        np.cumsum(np.bincount(rows[off_diagonal], minlength=n), out=xadj[1:])
        return xadj, A.indices[off_diagonal].astype(self.index_type)

    def nested_dissection(self, xadj, adjncy):
        """The nested dissection permutation of a graph, computed without holding the GIL.

        Parameters
        ----------
        xadj, adjncy : arrays of index_type
            The graph, as :meth:`adjacency` gives it.

        Returns
        -------
        (n,) int64 array
            ``permutation[k]`` is the ``k``-th vertex eliminated.

        Raises
        ------
        SolverError
            METIS reports a failure.

        Examples
        --------
        >>> reader = node_nd()
        >>> import scipy.sparse as sp
        >>> reader is None or reader.nested_dissection(*reader.adjacency(sp.identity(3, format="csr"))).size == 3
        True
        """
        n = xadj.size - 1
        size = np.array([n], dtype=self.index_type)
        permutation, inverse = np.empty(n, dtype=self.index_type), np.empty(n, dtype=self.index_type)
        arrays = [size, xadj, adjncy, None, self.options, permutation, inverse]
        status = self.function(*(None if a is None else ctypes.c_void_p(a.ctypes.data) for a in arrays))
        if status != METIS_OK:
            raise SolverError(f"METIS nested dissection failed (status {status})")
        count_fast_path("metis_nested_dissection")
        return permutation.astype(np.int64)


def _load():
    """:class:`NodeND` on pymetis's METIS, or None (no pymetis; a version or build this was not written for)."""
    pymetis = optional("pymetis")
    if pymetis is None or not version_is_known("pymetis", "METIS nested dissection"):
        return None
    try:
        internal = importlib.import_module("pymetis._internal")  # private: its name may change
        library = ctypes.CDLL(internal.__file__)
        function, set_defaults = library.METIS_NodeND, library.METIS_SetDefaultOptions
        index_type = {32: np.int32, 64: np.int64}[internal._idx_type_width()]
        keys = internal.options_indices
        options = np.zeros(METIS_NOPTIONS, dtype=index_type)
        set_defaults(ctypes.c_void_p(options.ctypes.data))
        # One refinement pass and random matching: 4.4 s instead of 5.2 s on a 1M-vertex sphere,
        # for a factor as small as with METIS's defaults.
        options[[keys.NITER, keys.CTYPE, keys.NO2HOP]] = [1, 0, 1]
    except (ImportError, AttributeError, KeyError, OSError, TypeError) as exc:
        warn_once(
            ("metis", "library"),
            "METIS nested dissection: cannot use the METIS inside pymetis (%s); ordering by minimum degree "
            "instead (same results, larger factors)",
            exc,
        )
        return None
    return NodeND(function, index_type, options)


@once
def node_nd():
    """The METIS nested dissection heatcore calls, loaded on the first call; None where unusable.

    Returns
    -------
    NodeND or None
        None without pymetis, or (with a warning logged once) on a pymetis
        whose private library this was not written for.

    Examples
    --------
    >>> node_nd() is node_nd()  # loaded once
    True
    """
    return _load()
