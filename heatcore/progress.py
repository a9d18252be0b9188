"""Progress of long builds: each stage reported as ``(fraction, message)`` to a callback.

Building a domain's operators and a solver's factorizations takes seconds on
large meshes. :class:`~heatcore.TriangleMesh` and :class:`~heatcore.HeatSolver`
take ``progress=``, a callable ``progress(fraction, message)`` that they call
at the start of each stage, from the thread that builds:

- ``fraction`` (0 to 1, never decreasing) is how much of the build is done,
  estimated from the stages' typical share of the time (measured on meshes
  of 50k to 650k vertices; a stage that a build skips leaves a jump);
- ``message`` names the stage, for people: ``"intrinsic Delaunay flips"``,
  ``"factoring the heat matrix"``, ... (the names may change between versions;
  do not parse them);
- a last call with fraction 1.0 says the build is complete.

Without a callback (``progress=None``, the default) nothing is reported.
The callback may raise to abort the build between two stages (a front end's
cancel button): the exception propagates unchanged out of the constructor and
nothing half built is returned. A stage itself is not interrupted.

:class:`Progress` wraps a callback; ``part(start, stop)`` maps a sub-build's
0..1 onto ``start..stop`` of the whole, so that a build made of several (a
domain, then its solver) reports one rising fraction.

Examples
--------
>>> import numpy as np, heatcore as hc
>>> seen = []
>>> report = Progress(lambda fraction, message: seen.append((round(fraction, 3), message)))
>>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
>>> mesh = hc.TriangleMesh(V, [[0, 1, 2], [1, 3, 2]], refine=0, progress=report.part(0.0, 0.4))
>>> solver = hc.HeatSolver(mesh, progress=report.part(0.4, 1.0))
>>> seen[0], seen[-1]
((0.0, 'welding coincident vertices'), (1.0, 'heat solver ready'))
>>> fractions = [f for f, _ in seen]
>>> fractions == sorted(fractions)
True
"""

__all__ = ["DOMAIN_SHARE", "Progress"]

#: The domain's share of a whole build (domain, then solver) in the progress fraction: about a
#: quarter of the time with the supernodal backend at 500k vertices, less with the others.
DOMAIN_SHARE = 0.25


class Progress:
    """A progress callback ``callback(fraction, message)``, mapped onto a range of the whole build.

    Calling the object reports a stage: ``progress(fraction, message)`` with
    ``fraction`` in 0..1 of this (sub-)build, passed on as ``start + fraction
    * (stop - start)``. Fractions outside 0..1 are clipped.

    Parameters
    ----------
    callback : callable, Progress or None
        ``callback(fraction, message)``. None: report nothing. Another
        :class:`Progress`: report through it (its range is composed with this one).
    start, stop : float, default 0.0 and 1.0
        The part of the callback's range that this build covers.

    Examples
    --------
    >>> seen = []
    >>> whole = Progress(lambda fraction, message: seen.append((fraction, message)))
    >>> solver_part = whole.part(0.25, 1.0)
    >>> solver_part(0.0, "factoring"); solver_part(1.0, "ready")
    >>> seen
    [(0.25, 'factoring'), (1.0, 'ready')]
    >>> Progress(None)(0.5, "nobody listens")  # silent
    >>> Progress(solver_part).part(0.0, 0.5)(1.0, "half of the solver part")
    >>> seen[-1]
    (0.625, 'half of the solver part')
    """

    def __init__(self, callback=None, start=0.0, stop=1.0):
        if isinstance(callback, Progress):
            start, stop = callback._whole(start), callback._whole(stop)
            callback = callback.callback
        self.callback = callback
        self.start, self.stop = float(start), float(stop)

    def _whole(self, fraction):
        """``fraction`` of this build as a fraction of the callback's whole range."""
        return self.start + min(max(float(fraction), 0.0), 1.0) * (self.stop - self.start)

    def __call__(self, fraction, message):
        if self.callback is not None:
            self.callback(self._whole(fraction), message)

    def part(self, start, stop):
        """The sub-build that covers ``start..stop`` (fractions of this one)."""
        return Progress(self, start, stop)

    @property
    def silent(self):
        """True when nothing is reported (no callback)."""
        return self.callback is None
