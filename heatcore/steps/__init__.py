"""The heat method's steps, each with its own numerics; :mod:`heatcore.heat` composes them.

- :mod:`~heatcore.steps.time_step`: the time step's guard against heat that underflows;
- :mod:`~heatcore.steps.heat_flow`: step 1, the heat flow under the boundary condition;
- :mod:`~heatcore.steps.boundary_source`: step 1's Robin heat for sources on a tet mesh's boundary;
- :mod:`~heatcore.steps.unit_field`: step 2, the unit field and its divergence;
- :mod:`~heatcore.steps.poisson`: step 3, the Poisson equation with the sources pinned;
- :mod:`~heatcore.steps.blocks`: how many sources one multi-column query takes;
- :mod:`~heatcore.steps.column_cache`: the columns kept per vertex for queries that come back to it.

Steps import domains' data types and linalg, never the solver.
"""
