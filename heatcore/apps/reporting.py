"""What a command says on stderr: stage timings, the distance summary, one-line warnings.

The ``heatcore`` command (:mod:`heatcore.apps.cli`) logs through the
``heatcore`` logger; :func:`heatcore.apps.cli.main` routes it to stderr as
``heatcore: message`` lines (``--quiet``: warnings and errors only).

Examples
--------
>>> _seconds(0.0123), _seconds(2.5)
('12.3 ms', '2.50 s')
>>> _summary(np.array([0.0, 1.5, np.inf]))
'max distance 1.5, 1 vertices unreachable (inf)'
"""

import logging
import sys
import time

import numpy as np

log = logging.getLogger("heatcore.apps.cli")


class _stage:
    """Context manager that logs ``<name>: <time>`` (stderr via the ``heatcore`` logger) and records it."""

    timings = {}

    def __init__(self, name):
        self.name = name

    def __enter__(self):
        self.start = time.perf_counter()
        return self

    def __exit__(self, exc_type, exc, tb):
        if exc_type is None:
            seconds = time.perf_counter() - self.start
            _stage.timings[self.name] = seconds
            log.info("%s: %s", self.name, _seconds(seconds))


def _seconds(seconds):
    return f"{seconds * 1000:.1f} ms" if seconds < 0.1 else f"{seconds:.2f} s"


def _summary(d):
    finite = np.isfinite(d)
    text = f"max distance {d[finite].max():.6g}" if finite.any() else "no vertex reached"
    if not finite.all():
        text += f", {int((~finite).sum())} vertices unreachable (inf)"
    return text


class _StderrHandler(logging.Handler):
    """Writes ``heatcore: message`` to the current ``sys.stderr`` (captured in tests)."""

    def emit(self, record):
        try:
            sys.stderr.write(f"heatcore: {self.format(record)}\n")
        except Exception:  # pragma: no cover - logging must never raise
            self.handleError(record)


def _show_warning(message, category, filename, lineno, file=None, line=None):
    sys.stderr.write(f"heatcore: warning: {message}\n")
