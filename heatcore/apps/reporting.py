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


#: Builds whose solver will have at least this many vertices report each stage as it starts (they take
#: seconds): the vertices after refinement (:func:`heatcore.domains.refine.work_ahead`), not the file's.
PROGRESS_FROM_VERTICES = 100_000

#: ... or at least this many parts (each part has work of its own: time step, grounding, refinement).
PROGRESS_FROM_PARTS = 1_000


def build_progress(n_vertices, n_parts=1):
    """Progress callbacks for a domain's build and its solver's (:mod:`heatcore.progress`): each stage
    logged as it starts, ``" 35% factoring the heat matrix (2.10 s)"``, where the work ahead is large:
    a solver of at least :data:`PROGRESS_FROM_VERTICES` vertices or :data:`PROGRESS_FROM_PARTS` parts;
    silent for smaller builds, which are quick.

    Parameters
    ----------
    n_vertices : int
        The solver's vertices, after refinement (:func:`heatcore.domains.refine.work_ahead`).
    n_parts : int, default 1

    Returns
    -------
    (Progress, Progress)
        For the domain (the first :data:`heatcore.progress.DOMAIN_SHARE` of the whole) and the solver.

    Examples
    --------
    >>> build_progress(5000)[0].silent, build_progress(5000, n_parts=4000)[0].silent
    (True, False)
    >>> domain_progress, solver_progress = build_progress(2_000_000)
    >>> solver_progress(0.5, "factoring the heat matrix")  # logged on stderr by the heatcore command
    """
    if n_vertices < PROGRESS_FROM_VERTICES and n_parts < PROGRESS_FROM_PARTS:
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


def distance_summary(d, parts=None):
    """One line on a distance array: its largest finite value and how many vertices were not reached.

    Parameters
    ----------
    d : (n,) float array
    parts : (int, int), optional
        The parts holding a source and the mesh's parts (:func:`source_parts`): where vertices are
        unreachable, the line says that the sources are on those parts alone.

    Examples
    --------
    >>> distance_summary(np.array([0.0, 2.0])), distance_summary(np.array([np.inf]))
    ('max distance 2', 'no vertex reached, 1 vertices unreachable (inf)')
    >>> print(distance_summary(np.array([0.0, 2.0, np.inf]), parts=(1, 3)))
    max distance 2, 1 vertices unreachable (inf): the sources are on 1 of the mesh's 3 parts, and distance does not cross between parts
    """
    finite = np.isfinite(d)
    text = f"max distance {d[finite].max():.6g}" if finite.any() else "no vertex reached"
    if not finite.all():
        text += f", {int((~finite).sum())} vertices unreachable (inf)"
        if parts is not None and parts[1] > 1:
            text += (f": the sources are on {parts[0]:,} of the mesh's {parts[1]:,} parts, and distance does not "
                     "cross between parts")
    return text


def source_parts(solver, sources):
    """The connected parts that hold a source, and the mesh's parts (those its one-off build left out too).

    Returns
    -------
    (int, int) or None
        None where the domain does not map input vertices to its own (``vertex_map``).

    Examples
    --------
    >>> import heatcore as hc
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [5, 0, 0], [6, 0, 0], [5, 1, 0]], float)
    >>> solver = hc.HeatSolver(hc.TriangleMesh(V, [[0, 1, 2], [3, 4, 5]], refine=0))
    >>> source_parts(solver, [0])
    (1, 2)
    """
    vertex_map = getattr(solver.domain, "vertex_map", None)
    component = getattr(solver, "component", None)
    if vertex_map is None or component is None:
        return None
    held = np.asarray(vertex_map)[np.asarray(sources, dtype=np.int64)]
    held = held[(held >= 0) & (held < len(component))]
    return int(np.unique(component[held]).size), int(solver.n_components + getattr(solver.domain, "parts_left_out", 0))


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
