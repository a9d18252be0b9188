"""What a command says on stderr: stage timings, the distance summary, one-line warnings.

The ``heatcore`` command (:mod:`heatcore.apps.cli`) logs through the
``heatcore`` logger; :func:`heatcore.apps.cli.main` routes it to stderr as
``heatcore: message`` lines (``--quiet``: warnings and errors only).

Examples
--------
>>> format_seconds(0.0123), format_seconds(2.5)
('12.3 ms', '2.50 s')
>>> distance_summary(np.array([0.0, 1.5, np.inf]))
'max distance 1.5, 1 vertices unreachable (inf)'
"""

import logging
import sys
import time

import numpy as np

from ..progress import DOMAIN_SHARE, Progress

log = logging.getLogger("heatcore.apps.cli")


class timed_stage:
    """Context manager that logs ``<name>: <time>`` (stderr via the ``heatcore`` logger) and records it.

    The times of a run are in ``timed_stage.timings`` (name -> seconds).

    Examples
    --------
    >>> with timed_stage("query"):
    ...     pass
    >>> timed_stage.timings["query"] < 1.0
    True
    """

    timings = {}

    def __init__(self, name):
        self.name = name

    def __enter__(self):
        self.start = time.perf_counter()
        return self

    def __exit__(self, exc_type, exc, tb):
        if exc_type is None:
            seconds = time.perf_counter() - self.start
            timed_stage.timings[self.name] = seconds
            log.info("%s: %s", self.name, format_seconds(seconds))


#: Builds of meshes with at least this many vertices report each stage as it starts (they take seconds).
PROGRESS_FROM_VERTICES = 100_000


def build_progress(n_vertices):
    """Progress callbacks for a domain's build and its solver's (:mod:`heatcore.progress`): each stage
    logged as it starts, ``" 35% factoring the heat matrix (2.10 s)"``, for meshes of at least
    :data:`PROGRESS_FROM_VERTICES` vertices; silent for smaller ones, whose build is quick.

    Returns
    -------
    (Progress, Progress)
        For the domain (the first :data:`heatcore.progress.DOMAIN_SHARE` of the whole) and the solver.

    Examples
    --------
    >>> build_progress(5000)[0].silent
    True
    >>> domain_progress, solver_progress = build_progress(2_000_000)
    >>> solver_progress(0.5, "factoring the heat matrix")  # logged on stderr by the heatcore command
    """
    if n_vertices < PROGRESS_FROM_VERTICES:
        report = Progress(None)
    else:
        start = time.perf_counter()
        report = Progress(lambda fraction, message: log.info(
            "%4.0f%% %s (%s)", 100 * fraction, message, format_seconds(time.perf_counter() - start)))
    return report.part(0.0, DOMAIN_SHARE), report.part(DOMAIN_SHARE, 1.0)


def format_seconds(seconds):
    """A duration for a person: milliseconds below 0.1 s, else seconds.

    Examples
    --------
    >>> format_seconds(0.0004), format_seconds(12.0)
    ('0.4 ms', '12.00 s')
    """
    return f"{seconds * 1000:.1f} ms" if seconds < 0.1 else f"{seconds:.2f} s"


def distance_summary(d):
    """One line on a distance array: its largest finite value and how many vertices were not reached.

    Examples
    --------
    >>> distance_summary(np.array([0.0, 2.0])), distance_summary(np.array([np.inf]))
    ('max distance 2', 'no vertex reached, 1 vertices unreachable (inf)')
    """
    finite = np.isfinite(d)
    text = f"max distance {d[finite].max():.6g}" if finite.any() else "no vertex reached"
    if not finite.all():
        text += f", {int((~finite).sum())} vertices unreachable (inf)"
    return text


class StderrHandler(logging.Handler):
    """Writes ``heatcore: message`` to the current ``sys.stderr`` (captured in tests).

    Examples
    --------
    >>> import contextlib, io
    >>> logger = logging.getLogger("heatcore.example")
    >>> handler = StderrHandler()
    >>> logger.addHandler(handler)
    >>> with contextlib.redirect_stderr(io.StringIO()) as err:
    ...     logger.warning("mesh has 2 duplicate faces")
    >>> print(err.getvalue(), end="")
    heatcore: mesh has 2 duplicate faces
    >>> logger.removeHandler(handler)
    """

    def emit(self, record):
        try:
            sys.stderr.write(f"heatcore: {self.format(record)}\n")
        except Exception:  # pragma: no cover - logging must never raise
            self.handleError(record)


def show_warning(message, category, filename, lineno, file=None, line=None):
    """A :func:`warnings.showwarning` replacement: ``heatcore: warning: message`` on stderr, no source line.

    Examples
    --------
    >>> import contextlib, io
    >>> with contextlib.redirect_stderr(io.StringIO()) as err:
    ...     show_warning("few vertices", UserWarning, "heat.py", 1)
    >>> print(err.getvalue(), end="")
    heatcore: warning: few vertices
    """
    sys.stderr.write(f"heatcore: warning: {message}\n")
