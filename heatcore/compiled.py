"""numba, the ``fast`` extra: the one place that compiles heatcore's loops, and decides when a build uses them.

numba is imported on first need (0.12-0.25 s), by :func:`available` or by
importing a module of compiled loops (:mod:`heatcore.fast_marching`,
:mod:`heatcore.domains.build_kernels`), and each compiled loop is loaded
from numba's disk cache on its first call (the first one in a process about
0.2 s, later ones a few milliseconds). Without numba,
:func:`available` is False and :func:`compiled` leaves a function as it is
(plain Python; the callers take their numpy path instead).

Examples
--------
>>> use_build_kernels(1_000)  # a small mesh's build: numpy (importing numba costs more than it saves)
False
"""

from .linalg.libraries import optional

#: Faces from which a triangle mesh's build uses :mod:`heatcore.domains.build_kernels` (where numba is installed).
#: On a 1M-vertex sphere (2M faces) a fresh process's build took 2.2 s with them against 4.0 s (much of it the
#: page faults of numpy's 48 MB temporaries; after other large allocations numpy's is about as fast: 1.6 s);
#: importing numba and loading them costs about 0.3 s in a fresh process, which fewer faces do not win back.
LARGE_BUILD_FACES = 400_000


def available():
    """Whether numba is installed (imports it).

    Examples
    --------
    >>> isinstance(available(), bool)
    True
    """
    return optional("numba") is not None


def compiled(function):
    """``function`` compiled by numba on its first call (cached on disk next to its module where that is
    writable), or as it is without numba.

    Examples
    --------
    A module-level function (numba caches those only), as in :mod:`heatcore.fast_marching`::

        @compiled
        def _march_loop(start, rows, corners, layout, d, is_pinned, pinned, tol): ...

    >>> compiled.__name__
    'compiled'
    """
    numba = optional("numba")
    return function if numba is None else numba.njit(cache=True, nogil=True, error_model="numpy")(function)


def use_build_kernels(n_faces):
    """Whether a build of ``n_faces`` faces takes :mod:`heatcore.domains.build_kernels` (the caller imports it).

    It does from :data:`LARGE_BUILD_FACES` faces on, where numba is installed;
    its results are bit for bit the numpy path's.

    Examples
    --------
    >>> use_build_kernels(LARGE_BUILD_FACES) == available()
    True
    """
    return n_faces >= LARGE_BUILD_FACES and available()
