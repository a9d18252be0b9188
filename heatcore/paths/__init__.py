"""Geodesic paths on triangle meshes: descent on the heat distance, then exact straightening.

- :mod:`~heatcore.paths.surface`: the input mesh as paths see it (neighbours, fans, surface points);
- :mod:`~heatcore.paths.trace`: steepest descent on the distance field, the route of faces;
- :mod:`~heatcore.paths.funnel`: the shortest path inside an unfolded strip of faces;
- :mod:`~heatcore.paths.straighten`: bends cut until the path is a geodesic;
- :mod:`~heatcore.paths.path`: :class:`GeodesicPath` and the driver;
- :mod:`~heatcore.paths.fields`: the distance fields a solver keeps for paths
  (:class:`PathFieldCache`, held by the solver as ``path_fields``);
- :mod:`~heatcore.paths.edges`: :func:`edge_chain`, mesh edges along a path (front ends select them).

Examples
--------
>>> import heatcore as hc
>>> solver = hc.HeatSolver(hc.TriangleMesh(*hc.io.load_demo_mesh()))
>>> round(solver.geodesic_path(0, 0).length, 3)
0.0
"""

from .edges import edge_chain
from .fields import PathFieldCache
from .path import GeodesicPath

__all__ = ["GeodesicPath", "PathFieldCache", "edge_chain"]
