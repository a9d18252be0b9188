"""Paths through waypoints: one geodesic per leg, joined into one :class:`~heatcore.paths.path.GeodesicPath`.

A path through the points ``a, b, c, ...`` is the geodesic from ``a`` to
``b``, then from ``b`` to ``c``, and so on (each leg computed as
:meth:`heatcore.HeatSolver.geodesic_path` computes a path between two points,
its distance fields kept in the solver for the next legs); ``closed`` adds the
leg from the last point back to the first. The legs are joined at the
waypoints into one polyline whose ``leg_lengths`` and ``waypoints`` say where
each leg is. A path through waypoints bends at them: it is shortest leg by
leg, not shortest overall (:func:`heatcore.straighten_path` shortens it
further, the waypoints then no longer kept).

Examples
--------
>>> import numpy as np, heatcore as hc
>>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
>>> solver = hc.HeatSolver(hc.TriangleMesh(V, [[0, 1, 2], [1, 3, 2]]))
>>> path = solver.geodesic_path(points=[0, 1, 3], closed=True)
>>> path.leg_lengths.round(6).tolist(), path.waypoints.tolist(), round(path.length, 6)
([1.0, 1.0, 1.414214], [0, 1, 2, 4], 3.414214)
"""

import numpy as np

from ..errors import InvalidSourceError
from .path import GeodesicPath, geodesic_path


def waypoint_path(solver, points, closed=False, both_ends=True):
    """The path through ``points`` in order (and back to the first, when ``closed``): a :class:`GeodesicPath`.

    Parameters
    ----------
    solver : HeatSolver
        On a :class:`~heatcore.TriangleMesh`.
    points : sequence
        At least two waypoints, each a vertex index or ``(face, barycentric)``.
    closed : bool, default False
        Add a last leg from the last waypoint to the first.
    both_ends : bool, default True
        As for :meth:`heatcore.HeatSolver.geodesic_path`, for every leg.

    Returns
    -------
    GeodesicPath
        ``leg_lengths`` per leg, ``waypoints`` the index of each waypoint in
        ``points`` (closed: the first waypoint again at the end).

    Raises
    ------
    InvalidSourceError
        Fewer than two waypoints, or a bad one (the message names its position).

    Examples
    --------
    >>> import heatcore as hc
    >>> solver = hc.HeatSolver(hc.TriangleMesh(*hc.io.load_demo_mesh()))
    >>> path = waypoint_path(solver, [0, 1453, 20])
    >>> len(path.leg_lengths), bool(abs(path.leg_lengths.sum() - path.length) < 1e-12)
    (2, True)
    """
    points = list(points) if not isinstance(points, np.ndarray) else points.tolist()
    if len(points) < 2:
        raise InvalidSourceError(f"a path through waypoints needs at least two points, got {len(points)}")
    stops = points + points[:1] if closed else points
    legs = []
    for k in range(len(stops) - 1):
        try:
            legs.append(geodesic_path(solver, stops[k], stops[k + 1], both_ends))
        except InvalidSourceError as exc:
            raise InvalidSourceError(f"leg {k} (waypoint {k} to {(k + 1) % len(points)}): {exc}") from None
    return join_paths(legs)


def join_paths(legs):
    """The paths ``legs`` end to end (each starts where the one before ends) as one :class:`GeodesicPath`.

    Examples
    --------
    >>> import numpy as np
    >>> a = GeodesicPath(np.zeros((2, 3)), np.zeros(1, int), np.full((2, 2), -1), np.zeros(2, int), 0.0)
    >>> b = GeodesicPath(np.zeros((3, 3)), np.zeros(2, int), np.full((3, 2), -1), np.zeros(3, int), 0.0)
    >>> joined = join_paths([a, b])
    >>> len(joined), joined.waypoints.tolist()
    (4, [0, 1, 3])
    """
    cut = [slice(None)] + [slice(1, None)] * (len(legs) - 1)
    sizes = np.array([len(leg) - 1 for leg in legs])
    lengths = np.array([leg.length for leg in legs], dtype=float)
    return GeodesicPath(
        np.concatenate([leg.points[c] for leg, c in zip(legs, cut)]),
        np.concatenate([leg.faces for leg in legs]).astype(np.int64),
        np.concatenate([leg.edges[c] for leg, c in zip(legs, cut)]),
        np.concatenate([leg.vertices[c] for leg, c in zip(legs, cut)]),
        float(lengths.sum()),
        lengths,
        np.r_[0, np.cumsum(sizes)].astype(np.int64),
    )
