"""The vector heat method (Sharp, Soliman and Crane 2019): parallel transport and the logarithmic map.

One concept per module: :mod:`~heatcore.vector_heat.frames` (each vertex's
intrinsic angular coordinates), :mod:`~heatcore.vector_heat.connection` (the
connection Laplacian and the affine
translations), :mod:`~heatcore.vector_heat.basis` (the frames placed
in 3D), :mod:`~heatcore.vector_heat.sources` (source points and their
tangent planes), :mod:`~heatcore.vector_heat.logmap` (the log map's pieces) and
:mod:`~heatcore.vector_heat.solver` (:class:`VectorHeatSolver`).

Examples
--------
>>> import heatcore as hc
>>> solver = hc.VectorHeatSolver(hc.TriangleMesh(*hc.io.load_demo_mesh()))
>>> solver.log_map(0).shape
(2930, 2)
"""

from .solver import TangentBasis, VectorHeatSolver

__all__ = ["TangentBasis", "VectorHeatSolver"]
