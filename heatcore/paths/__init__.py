"""Geodesic paths on triangle meshes: descent on the heat distance, then exact straightening.

- :mod:`~heatcore.paths.surface`: the input mesh as paths see it (neighbours, fans, surface points);
- :mod:`~heatcore.paths.trace`: steepest descent on the distance field, the route of faces;
- :mod:`~heatcore.paths.funnel`: the shortest path inside an unfolded strip of faces;
- :mod:`~heatcore.paths.straighten`: bends cut until the path is a geodesic;
- :mod:`~heatcore.paths.path`: :class:`GeodesicPath` and the driver;
- :mod:`~heatcore.paths.fields`: the distance fields a solver keeps for paths
  (:class:`PathFieldCache`, held by the solver as ``path_fields``);
- :mod:`~heatcore.paths.tracing`: :func:`trace_geodesic`, straightest geodesics from a point and a direction;
- :mod:`~heatcore.paths.waypoints`: paths through waypoints, one geodesic per leg;
- :mod:`~heatcore.paths.drawn`: :func:`straighten_path` and :func:`straighten_loop`, drawn paths made geodesics;
- :mod:`~heatcore.paths.edges`: :func:`edge_chain`, mesh edges along a path (front ends select them).

Examples
--------
>>> import heatcore as hc
>>> solver = hc.HeatSolver(hc.TriangleMesh(*hc.io.load_demo_mesh()))
>>> round(solver.geodesic_path(0, 0).length, 3)
0.0
"""

from .drawn import straighten_loop, straighten_path
from .edges import edge_chain
from .fields import PathFieldCache
from .path import GeodesicPath
from .tracing import TracedPath, trace_geodesic

__all__ = ["GeodesicPath", "PathFieldCache", "TracedPath", "edge_chain", "straighten_loop", "straighten_path",
           "trace_geodesic"]
