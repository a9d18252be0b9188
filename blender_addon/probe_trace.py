"""The probe tool's *Trace*: from a point on the surface, the straightest geodesic towards the mouse.

Alt+click on the mesh starts a trace there; while the button is held, the
trace follows the mouse: it leaves the start in the direction of the surface
point under the cursor (in 3D, projected on the tangent plane at the start)
and runs as far as the straight line between them is long, straight across
faces and edges (``HeatSolver.trace``), stopping early at the boundary. Enter
writes it as the curve object ``"<name> Geodesic Trace"``.

Examples
--------
>>> start_trace(probe, 12, (0.2, 0.3, 0.5))      # doctest: +SKIP
>>> trace_to(probe, 40, (0.3, 0.3, 0.4)).length  # doctest: +SKIP
0.81
"""

import numpy as np

from .adapters import AddonError
from .curves import write_curves


def _solver_point(domain, face, barycentric):
    """A surface point (a loop triangle and barycentric weights) in the solver's own coordinates."""
    return np.asarray(barycentric, dtype=np.float64) @ domain.vertices[domain.faces[int(face)]]


def start_trace(probe, face, barycentric):
    """Start a trace at a surface point (a loop triangle of the mesh, barycentric weights); nothing drawn yet."""
    if not hasattr(probe.run.solver, "trace"):
        raise AddonError("tracing needs heatcore's HeatSolver.trace, which this copy of heatcore does not have")
    probe.trace_start = (int(face), np.asarray(barycentric, dtype=np.float64).reshape(3))
    probe.trace = None


def trace_to(probe, face, barycentric):
    """Trace from the start towards a surface point, as far as the straight line to it; drawn, and returned.

    Returns heatcore's ``TracedPath`` in the measured space (None where the point is the start).
    """
    if probe.trace_start is None:
        raise AddonError("no trace started: Alt+click on the mesh first")
    solver = probe.run.solver
    start = probe.trace_start
    direction = _solver_point(solver.domain, face, barycentric) - _solver_point(solver.domain, *start)
    length = float(np.linalg.norm(direction))
    if not length > 0:
        return None
    probe.trace = probe.run.placement.path(solver.trace(start, direction, length))
    probe.show()
    return probe.trace


def write_trace(probe, obj):
    """Write the trace (if any) as the curve object ``"<name> Geodesic Trace"``; returns it, or None."""
    if probe.trace is None:
        return None
    return write_curves(obj, "Trace", [probe.overlay_data().path])
