"""Which backend factors a matrix: the backends, the sizes that decide, and the caller's intent.

:func:`resolve_backend` is the one place a ``backend`` option becomes a
backend name: a name passes unchanged; "auto" is decided by the matrix size,
what the caller means to do with the factor (``intent``: reuse it for many
queries, or answer one) and the matrix's ``stage`` (the heat matrix is
factored and solved a few times per query, the Laplacian kept for many
solves). :func:`choose_backend` is the size rule underneath.

This module keeps no state, imports no backend at import time and knows no
geometry.

Examples
--------
>>> resolve_backend("superlu", 10)
'superlu'
>>> resolve_backend("auto", 10, intent="one query", stage="solve") == choose_backend(10, "factor")
True
"""

import logging

from ..errors import InvalidOptionError, SolverError
from ..settings import INTENTS
from .libraries import optional, warn_once

log = logging.getLogger(__name__)

#: The matrices of a solver: one factored for its solves (``"factor"``), one kept for many (``"solve"``).
STAGES = ("factor", "solve")

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
    if "gpu" in usable:
        from .gpu import gpu_count

        if gpu_count() == 0:  # the gpu backend's module, imported here on first use like the others
            usable.remove("gpu")
    return usable


def choose_backend(n, prefer="factor"):
    """The backend "auto" uses for an ``n`` x ``n`` matrix.

    ``prefer="factor"`` (a matrix factored per solver and solved a few times
    per query: the heat matrix, and both matrices of a single query) picks
    ``supernodal`` at every size where installed: it factors 2-7x faster
    than ``qdldl`` and ``cholmod`` below :data:`SUPERNODAL_MIN_SIZE` (11,714
    unknowns: 8 ms after a 6 ms ordering shared by both matrices, against 20
    ms and 51 ms) and its solves are as fast as ``qdldl``'s (49,971 unknowns:
    a kept solver's query 13.0 ms with the supernodal heat factor, 16.4 ms
    with ``qdldl``'s). Without cvxopt it picks ``qdldl``, or ``cholmod``
    above :data:`QDLDL_MAX_SIZE` (with a hint, once, to install the
    ``scale`` extra). ``prefer="solve"`` (a matrix kept for many solves: the
    Laplacian of a solver kept for queries) picks ``cholmod`` below
    :data:`SUPERNODAL_MIN_SIZE`, whose solves are 1.5x faster than
    ``supernodal``'s once its slower factorization is paid, and
    ``supernodal`` from there up.

    Parameters
    ----------
    n : int
        The number of unknowns.
    prefer : {"factor", "solve"}
        What matters more: a fast factorization or fast solves.

    Returns
    -------
    str
        One of :func:`available_backends`.

    Examples
    --------
    >>> choose_backend(10) in available_backends()
    True
    >>> choose_backend(10, "factor") in ("supernodal", "qdldl")
    True
    """
    if prefer not in ("factor", "solve"):
        raise SolverError(f"prefer must be 'factor' or 'solve', not {prefer!r}")
    backends = available_backends()
    if n >= SUPERNODAL_MIN_SIZE or prefer == "factor":
        if "supernodal" in backends:
            return "supernodal"
        if n >= SUPERNODAL_MIN_SIZE:
            warn_once(
                "scale extra",
                "factoring %d unknowns without cvxopt: pip install 'heatcore[scale]' makes this several "
                "times faster (supernodal CHOLMOD)",
                n,
                logger=log,
            )
    fast_factor = "qdldl" in backends and (n <= QDLDL_MAX_SIZE or "cholmod" not in backends)
    if prefer == "factor" and fast_factor:
        return "qdldl"
    return "cholmod" if "cholmod" in backends else backends[0]


def resolve_backend(backend, n, *, intent="reuse", stage="factor"):
    """The backend that factors an ``n`` x ``n`` matrix: ``backend``, or for "auto" the one for the intent and stage.

    Parameters
    ----------
    backend : str
        The ``backend`` option: "auto" or a backend name (passed on unchanged;
        :func:`heatcore.linalg.factor` checks it).
    n : int
        The number of unknowns.
    intent : {"reuse", "one query", "interactive"}
        ``"one query"``: the matrices are factored for a single query, so
        both stages take the fastest factorization
        (:func:`choose_backend` with ``"factor"``), as do those of
        ``"interactive"`` (a solver kept for the next clicks, whose first
        answer is waited for). ``"reuse"``: a solver kept
        for many queries, each stage its own (``choose_backend(n, stage)``).
    stage : {"factor", "solve"}
        ``"factor"``: a matrix factored per solver (the heat matrix);
        ``"solve"``: one kept for many solves (the Laplacian).

    Returns
    -------
    str

    Raises
    ------
    InvalidOptionError
        ``intent`` or ``stage`` is not one of the above.

    Examples
    --------
    >>> resolve_backend("qdldl", 10, intent="one query", stage="solve")
    'qdldl'
    >>> resolve_backend("auto", 10, stage="solve") == choose_backend(10, "solve")
    True
    """
    if intent not in INTENTS:
        raise InvalidOptionError(f"intent must be one of {INTENTS}, not {intent!r}")
    if stage not in STAGES:
        raise InvalidOptionError(f"stage must be one of {STAGES}, not {stage!r}")
    if backend != "auto":
        return backend
    return choose_backend(n, stage if intent == "reuse" else "factor")
