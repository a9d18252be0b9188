"""The signed heat method (Feng and Crane 2024): signed distance to curves on a surface.

:class:`SignedHeatSolver` in :mod:`heatcore.signed_heat.solver`; the curves'
sources in :mod:`~heatcore.signed_heat.curves`, the unit field in
:mod:`~heatcore.signed_heat.face_field`, the level-set constraints in
:mod:`~heatcore.signed_heat.level_sets`.
"""

from .solver import SignedHeatSolver

__all__ = ["SignedHeatSolver"]
