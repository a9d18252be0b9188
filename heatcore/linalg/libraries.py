"""The optional libraries behind the backends: loaded on first use, once, from any thread.

Importing :mod:`heatcore.linalg` loads none of them (no import of cvxopt, pymetis,
cholespy or qdldl, no ``ctypes.CDLL``, no thread). The first call that needs a
library imports it (:func:`optional`); later calls get the cached module.

heatcore reads two libraries' internals through ctypes: the ``cholmod_factor``
that cvxopt holds (:mod:`heatcore.linalg.sparse_rhs`) and the METIS inside
pymetis (:mod:`heatcore.linalg.metis`). Each reader was written against the
versions in :data:`READ_INTERNALS_OF` and takes its fast path only there
(:func:`version_is_known`); on another version it logs a warning once and
the caller takes the plain path (same results, slower). :data:`fast_path_counts`
counts the fast paths taken, so that a test can tell a fast path that silently
stopped being taken from one that is not needed.

Examples
--------
>>> optional("a_library_that_is_not_installed") is None
True
>>> optional("numpy") is optional("numpy")  # imported once, cached
True
"""

import collections
import functools
import importlib
import importlib.metadata
import importlib.util
import logging
import threading

log = logging.getLogger(__name__)

#: Each optional library, with the submodules that importing it must load too.
SUBMODULES = {
    "cvxopt": ("cvxopt.cholmod", "cvxopt.amd"),
    "nvmath": ("nvmath.sparse.advanced",),
}

#: The versions whose internals heatcore's ctypes readers were written against and
#: checked on (the versions the Blender extension bundles, see
#: ``scripts/build_blender_extension.py``). Another version takes the plain path with a
#: warning: to allow it, run ``tests/test_linalg_fast_paths.py`` on it and add it here.
READ_INTERNALS_OF = {
    "cvxopt": ("1.3.3",),  # the layout of CHOLMOD's cholmod_factor in its bundled SuiteSparse
    "pymetis": ("2025.2.2",),  # METIS_NodeND and its options array in pymetis's _internal library
}

#: How often each fast path that reads a library's internals was taken in this process.
fast_path_counts = collections.Counter()

_lock = threading.RLock()
_modules = {}  # name -> module, or None where it cannot be imported
_warned = set()


def optional(name):
    """An optional library, imported on the first call and cached; None where it cannot be imported.

    Parameters
    ----------
    name : str
        A top-level module name; the submodules listed for it in :data:`SUBMODULES`
        are imported with it.

    Returns
    -------
    module or None
        None where the library is not installed, or installed but broken (then
        with a logged warning: a broken install should not silently make
        heatcore slower).

    Examples
    --------
    >>> optional("scipy").__name__
    'scipy'
    >>> optional("no_such_library_here") is None
    True
    """
    try:
        return _modules[name]
    except KeyError:
        pass
    with _lock:
        if name not in _modules:
            _modules[name] = _import(name)
        return _modules[name]


def _import(name):
    try:
        module = importlib.import_module(name)
        for submodule in SUBMODULES.get(name, ()):
            importlib.import_module(submodule)
    except ImportError as exc:
        if installed(name):
            log.warning("%s is installed but cannot be imported (%s); heatcore does without it", name, exc)
        return None
    return module


def installed(name):
    """Whether a library is installed, without importing it.

    Parameters
    ----------
    name : str
        A top-level module name.

    Returns
    -------
    bool

    Examples
    --------
    >>> installed("numpy"), installed("no_such_library_here")
    (True, False)
    """
    try:
        return importlib.util.find_spec(name) is not None
    except (ImportError, ValueError):  # pragma: no cover - a broken package
        return False


def version(name):
    """The installed version of a library, as its distribution states it, or None.

    Parameters
    ----------
    name : str
        A distribution name (the same as the module name for the libraries here).

    Returns
    -------
    str or None

    Examples
    --------
    >>> import numpy
    >>> version("numpy") == numpy.__version__
    True
    >>> version("no_such_library_here") is None
    True
    """
    module = _modules.get(name)
    if getattr(module, "__version__", None):
        return str(module.__version__)
    try:
        return importlib.metadata.version(name)
    except importlib.metadata.PackageNotFoundError:
        return None


def version_is_known(name, reader):
    """Whether ``reader`` may read ``name``'s internals: its version is in :data:`READ_INTERNALS_OF`.

    On another version, logs a warning (once per library) that ``reader`` is
    off and the plain path is taken.

    Parameters
    ----------
    name : str
        The library, a key of :data:`READ_INTERNALS_OF`.
    reader : str
        What reads it, for the warning (for example "sparse right-hand sides").

    Returns
    -------
    bool

    Examples
    --------
    >>> version_is_known("no_such_library_here", "an example")
    False
    """
    found = version(name)
    if found in READ_INTERNALS_OF.get(name, ()):
        return True
    warn_once(
        (name, found),
        "%s: %s %s is not a version heatcore's reader of its internals was written for (%s); "
        "using the plain path instead (same results, slower)",
        reader,
        name,
        found,
        ", ".join(READ_INTERNALS_OF.get(name, ())) or "none",
    )
    return False


def warn_once(key, message, *args, logger=None):
    """Log a warning the first time ``key`` is seen in this process.

    Parameters
    ----------
    key : hashable
        What makes two warnings the same.
    message, *args
        As for :meth:`logging.Logger.warning`.
    logger : logging.Logger, optional
        Where to log it (by default this module's logger).

    Returns
    -------
    bool
        Whether the warning was logged now.

    Examples
    --------
    >>> warn_once("doctest", "said once"), warn_once("doctest", "said once")
    (True, False)
    """
    with _lock:
        if key in _warned:
            return False
        _warned.add(key)
    (logger or log).warning(message, *args)
    return True


def count_fast_path(name):
    """Count one use of a fast path in :data:`fast_path_counts`.

    Parameters
    ----------
    name : str
        The fast path ("sparse_forward", "metis_nested_dissection").

    Examples
    --------
    >>> before = fast_path_counts["example"]
    >>> count_fast_path("example")
    >>> fast_path_counts["example"] - before
    1
    """
    with _lock:
        fast_path_counts[name] += 1


def once(function):
    """Decorate a function of no arguments: run it on the first call only (thread-safe), then cache.

    For the lazily built things: a ctypes handle, a thread pool.

    Parameters
    ----------
    function : callable
        Takes no arguments.

    Returns
    -------
    callable
        Returns ``function()``'s first result on every call; its ``loaded()``
        tells whether that first call has happened.

    Examples
    --------
    >>> calls = []
    >>> @once
    ... def build():
    ...     calls.append(1)
    ...     return "built"
    >>> build.loaded()
    False
    >>> build(), build(), len(calls), build.loaded()
    ('built', 'built', 1, True)
    """
    result = []
    lock = threading.Lock()

    @functools.wraps(function)
    def cached():
        if not result:
            with lock:
                if not result:
                    result.append(function())
        return result[0]

    cached.loaded = lambda: bool(result)
    return cached
