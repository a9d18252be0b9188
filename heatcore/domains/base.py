"""The interface every heat-method domain implements for :class:`~heatcore.HeatSolver`.

A domain (triangle mesh, polygon mesh, tet mesh, point cloud) supplies:

- ``operators``: an :class:`~heatcore.domains.operators.Operators` bundle;
- ``n_input_vertices`` and ``output_vertices``: the operator vertex of each
  input vertex (``-1`` where no element uses it);
- ``source_pins(vertices=None, *, points=None, edges=None, region=None)``:
  the sources a user names, as :class:`~heatcore.domains.sources.SourcePins`,
  built by the one builder :func:`~heatcore.domains.sources.build_source_pins`
  from the kinds the domain lists in ``source_kinds`` (each kind ``k`` is a
  method ``_pin_k(value, builder)``);
- capabilities, declared and not guessed: ``supports_high_accuracy`` and
  :meth:`Domain.eikonal_triangles` for the ``accuracy="high"`` pass.

:class:`MeshDomain` adds what the mesh domains share: their input
``vertices`` and a ``vertex_map`` to operator vertices.

Examples
--------
>>> import numpy as np
>>> from heatcore.domains import TriangleMesh
>>> mesh = TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0)
>>> isinstance(mesh, Domain), mesh.source_kinds
(True, ('vertices', 'edges', 'region', 'points'))
>>> mesh.source_pins([0]).vertices.tolist()
[0]
"""

from abc import ABC, abstractmethod

from ..errors import InvalidSourceError
from .sources import build_source_pins, index_list


class Domain(ABC):
    """What the heat method runs on: operators, the input-to-operator vertex map, and source pins.

    Subclasses set ``operators`` (an attribute or a property) and implement
    :attr:`n_input_vertices`, :attr:`output_vertices` and one ``_pin_KIND``
    method per kind in ``source_kinds``.

    Examples
    --------
    >>> import numpy as np
    >>> from heatcore.domains import PointCloud, TetMesh
    >>> issubclass(PointCloud, Domain), issubclass(TetMesh, Domain)
    (True, True)
    """

    #: What the domain is made of, for messages ("face", "polygon", "tet", "point").
    element_name = "element"
    #: The domain, for messages ("triangle mesh", "point cloud", ...).
    domain_name = "domain"
    #: The source kinds this domain takes, in the order they are pinned
    #: (the vocabulary: :data:`~heatcore.domains.sources.SOURCE_KINDS`).
    source_kinds = ("vertices",)
    #: Whether :meth:`eikonal_triangles` gives the triangles the ``accuracy="high"`` pass sweeps.
    supports_high_accuracy = False
    #: True: unit heat once per source vertex however often it is named; False: heat adds up.
    unit_heat_once = False

    @property
    @abstractmethod
    def n_input_vertices(self):
        """Number of vertices (or points) of the domain as given."""

    @property
    @abstractmethod
    def output_vertices(self):
        """Operator vertex of each input vertex (``-1`` where unreferenced)."""

    def source_pins(self, vertices=None, **kinds):
        """Turn a source specification into :class:`~heatcore.domains.sources.SourcePins`.

        Parameters
        ----------
        vertices : int or sequence of int, optional
            Source vertices (distance 0).
        **kinds
            The other kinds this domain lists in ``source_kinds``: ``points``
            (``(element_indices, barycentric)``: points inside elements),
            ``edges`` (``(k, 2)`` vertex pairs) and ``region`` (elements whose
            union is the source). Old names (``face_points``, ``tet_points``,
            ``faces``, ``boundary_faces``) still work, with a
            ``DeprecationWarning``.

        Raises
        ------
        InvalidSourceError
            No source, a kind the domain does not take, indices out of range,
            unreferenced vertices, or elements that cannot be sources.

        Examples
        --------
        >>> import numpy as np
        >>> from heatcore.domains import TriangleMesh
        >>> mesh = TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0)
        >>> mesh.source_pins(region=[0]).vertices.tolist()
        [0, 1, 2]
        """
        return build_source_pins(self, vertices, **kinds)

    @abstractmethod
    def _pin_vertices(self, vertices, pins):
        """Add source ``vertices`` (input indices) to ``pins``, a :class:`~heatcore.domains.sources.PinBuilder`."""

    def _pin_points(self, points, pins):
        """Add points inside elements, ``(element_indices, barycentric)``, to ``pins``."""
        raise NotImplementedError  # reached only for a kind listed in source_kinds

    def _pin_edges(self, edges, pins):
        """Add edges, ``(k, 2)`` vertex pairs, to ``pins``."""
        raise NotImplementedError

    def _pin_region(self, region, pins):
        """Add a region (elements whose union is the source) to ``pins``."""
        raise NotImplementedError

    def eikonal_triangles(self):
        """Triangles and their edge lengths for the ``accuracy="high"`` pass, on the operator vertices.

        Returns
        -------
        (faces, lengths) : two lists of arrays
            ``faces[i]`` is ``(m_i, 3)`` operator vertex indices and
            ``lengths[i]`` the ``(m_i, 3)`` lengths of the sides opposite
            each corner, in the operators' units.

        Raises
        ------
        NotImplementedError
            The domain has no triangles to sweep (``supports_high_accuracy`` is False).

        Examples
        --------
        >>> import numpy as np
        >>> from heatcore.domains import TriangleMesh
        >>> faces, lengths = TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0).eikonal_triangles()
        >>> faces[0].shape, lengths[0].shape
        ((1, 3), (1, 3))
        """
        raise NotImplementedError(f"{type(self).__name__} has no triangles for the accuracy='high' pass")


class MeshDomain(Domain):
    """Base of the mesh domains: input ``vertices`` plus a ``vertex_map`` to operator vertices.

    Examples
    --------
    >>> import numpy as np
    >>> from heatcore.domains import TriangleMesh
    >>> TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0).output_vertices.tolist()
    [0, 1, 2]
    """

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

    def _pin_vertices(self, vertices, pins):
        """Source vertices: distance 0 and unit heat at each."""
        v = self._referenced(index_list(vertices, self.n_input_vertices, "vertex"))
        pins.add(v)
