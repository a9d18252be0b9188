"""The interface every heat-method domain offers to :class:`~heatcore.HeatSolver`.

A domain has ``operators`` (an :class:`~heatcore.operators.Operators` bundle),
``source_pins(vertices=None, **kinds)`` returning
:class:`~heatcore.sources.SourcePins`, ``output_vertices`` (the operator vertex
of each input vertex, ``-1`` where the input vertex is used by no element) and
``n_input_vertices``. :class:`MeshDomain` supplies the last two for domains
that keep their input ``vertices`` and a ``vertex_map``.
"""


class MeshDomain:
    """Base of the mesh domains: input ``vertices`` plus a ``vertex_map`` to operator vertices."""

    @property
    def n_input_vertices(self):
        """Number of vertices of the mesh as given."""
        return self.vertices.shape[0]

    @property
    def output_vertices(self):
        """Operator vertex of each input vertex (``-1`` where unreferenced)."""
        return self.vertex_map
