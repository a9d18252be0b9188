"""The interface every heat-method domain offers to :class:`~heatcore.HeatSolver`.

A domain has ``operators`` (an :class:`~heatcore.domains.operators.Operators` bundle),
``source_pins(vertices=None, **kinds)`` returning
:class:`~heatcore.domains.sources.SourcePins`, ``output_vertices`` (the operator vertex
of each input vertex, ``-1`` where the input vertex is used by no element) and
``n_input_vertices``. :class:`MeshDomain` supplies the last two for domains
that keep their input ``vertices`` and a ``vertex_map``.
"""

from ..errors import InvalidSourceError


class MeshDomain:
    """Base of the mesh domains: input ``vertices`` plus a ``vertex_map`` to operator vertices."""

    #: What the mesh is made of, for messages ("face", "polygon", "tet").
    element_name = "element"

    @property
    def n_input_vertices(self):
        """Number of vertices of the mesh as given."""
        return self.vertices.shape[0]

    @property
    def output_vertices(self):
        """Operator vertex of each input vertex (``-1`` where unreferenced)."""
        return self.vertex_map

    def _referenced(self, v):
        """Operator vertices of input vertices ``v``; a typed error for one no element uses."""
        mapped = self.vertex_map[v]
        if (mapped < 0).any():
            bad = int(v[mapped < 0][0])
            raise InvalidSourceError(f"vertex {bad} is not used by any {self.element_name}, so it cannot be a source")
        return mapped
