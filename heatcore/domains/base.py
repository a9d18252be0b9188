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
  :meth:`Domain.eikonal_triangles` for the ``accuracy="high"`` pass,
  :meth:`Domain.two_step_vertices` for the heat method's two steps on refined parts;
- ``derived``: the one cache of what is derived from the domain
  (:class:`~heatcore.domains.derived.DerivedCache`: orderings, factors, the
  path mesh, eikonal corners, tangent frames), created on first use, so a
  subclass's constructor does nothing for it, and dropped with the domain.

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

import numpy as np
import scipy.sparse as sp

from ..errors import InvalidSourceError
from .derived import DerivedCache
from .parts import row_norms
from .sources import barycentric_array, build_source_pins, index_list


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
    def derived(self):
        """The :class:`~heatcore.domains.derived.DerivedCache` of this domain, created on first use.

        Examples
        --------
        >>> import numpy as np
        >>> from heatcore.domains import TriangleMesh
        >>> mesh = TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0)
        >>> mesh.derived is mesh.derived, len(mesh.derived)
        (True, 0)
        """
        cache = self.__dict__.get("_derived")
        if cache is None:
            cache = self.__dict__.setdefault("_derived", DerivedCache())  # one, even if two threads ask at once
        return cache

    @property
    def n_vertices(self):
        """Number of operator vertices: ``operators.n_vertices``, known without the operators where they are
        built on first use (:class:`~heatcore.domains.triangle.TriangleMesh`).

        Examples
        --------
        >>> import numpy as np
        >>> from heatcore.domains import TetMesh
        >>> TetMesh(np.r_[np.eye(3), [[0.0, 0.0, 0.0]]], [[0, 1, 2, 3]]).n_vertices
        4
        """
        return self.operators.n_vertices

    @property
    def vertex_unit_exponent(self):
        """Each operator vertex's length unit, as ``operators.unit_exponent`` (int array, or 0)."""
        return self.operators.unit_exponent

    @property
    def vertex_parts(self):
        """``(count, part of each operator vertex)`` where the domain knows them without its operators, else None
        (the solver finds them on the operators' elements)."""
        return None

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

    @property
    @abstractmethod
    def input_positions(self):
        """``(n_input_vertices, 3)`` positions of the vertices (or points) as given, in the input's units."""

    def straight_neighbours(self, vertices):
        """Input vertices joined to one of ``vertices`` by a straight segment that lies in the domain, and its length.

        The sides of its triangles, polygons or tets (and the diagonals of flat
        polygons): the distance between such a pair is exactly the segment's
        length. Nothing on a point cloud (its points are not joined by
        segments on the surface). Reads only the elements at ``vertices``:
        found in one pass over the elements (nothing kept: a one-off query
        pays no index), or, after :meth:`index_straight_neighbours`, looked up.

        Returns
        -------
        neighbours : int array, repeated where several of ``vertices`` reach one
        lengths : float array

        Examples
        --------
        >>> import numpy as np
        >>> from heatcore.domains import TriangleMesh
        >>> mesh = TriangleMesh(np.array([[0, 0, 0], [3, 0, 0], [0, 4, 0]], float), [[0, 1, 2]], refine=0)
        >>> near, lengths = mesh.straight_neighbours(np.array([0]))
        >>> sorted(zip(near.tolist(), lengths.tolist()))
        [(1, 3.0), (2, 4.0)]
        >>> mesh.index_straight_neighbours()
        >>> sorted(zip(*(x.tolist() for x in mesh.straight_neighbours(np.array([0])))))
        [(1, 3.0), (2, 4.0)]
        """
        mark = np.zeros(self.n_input_vertices, dtype=bool)
        mark[vertices] = True
        incidence = self.derived.get(("vertex elements", None))
        elements = None if incidence is None else _rows_of(incidence, np.flatnonzero(mark))
        a, b = self._element_sides(mark, elements)
        from_a, from_b = mark[a] & (a != b), mark[b] & (a != b)
        near, start = np.r_[b[from_a], a[from_b]], np.r_[a[from_a], b[from_b]]
        X = self.input_positions
        return near, row_norms(X[near] - X[start])

    def index_straight_neighbours(self):
        """Build, once, every vertex's elements, kept in :attr:`derived`: later lookups read the elements at their
        vertices only, not every element's corners (a counting sort of the corners: 504k polygons, 0.04 s)."""
        self.derived.get_or_build(("vertex elements", None), self._vertex_elements)

    def _vertex_elements(self):
        """``(indptr, elements)``: the kept elements of each input vertex, ascending, as a CSR matrix's rows."""
        element, vertex = self._element_corners()
        rows = sp.csr_matrix((element, (vertex, np.arange(vertex.size))), shape=(self.n_input_vertices, max(vertex.size, 1)))
        return rows.indptr.astype(np.int64), rows.data.astype(np.int64)

    def _element_corners(self):
        """The kept elements' corners: ``(element, vertex)`` index arrays, one entry per corner."""
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)

    def _element_sides(self, mark, elements=None):
        """Start and end (input vertex indices) of the sides of the kept elements with a ``mark``ed corner, in element
        order: ``elements`` where they are known (ascending), else found in one pass."""
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)

    def point_corners(self, points):
        """Input vertices of the elements that ``points=(element_indices, barycentric)`` sources lie in, ``(k, c)``.

        Examples
        --------
        >>> import numpy as np
        >>> from heatcore.domains import TriangleMesh
        >>> TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0).point_corners(([0], [[0.5, 0.5, 0.0]])).tolist()
        [[0, 1, 2]]
        """
        elements = self._point_elements()
        return elements[index_list(points[0], elements.shape[0], self.element_name)]

    def point_positions(self, points):
        """Positions of ``points=(element_indices, barycentric)`` sources, ``(k, 3)`` in the input's units.

        Examples
        --------
        >>> import numpy as np
        >>> from heatcore.domains import TriangleMesh
        >>> TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0).point_positions(([0], [[0.5, 0.5, 0.0]])).tolist()
        [[0.5, 0.5, 0.0]]
        """
        corners = self.point_corners(points)
        weights = barycentric_array(points[1], corners.shape[0], corners.shape[1])
        return np.einsum("kc,kcd->kd", weights, self.input_positions[corners])

    def _point_elements(self):
        """The input elements (vertex indices) that ``points`` sources name by index."""
        raise NotImplementedError  # reached only for a domain that lists "points" in source_kinds

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

    def two_step_vertices(self):
        """The operator vertices whose distance direction is read from two heat steps.

        ``log u_short - log u_long`` of :mod:`heatcore.steps.time_step` in
        place of the heat of one step. Surface domains read it on their
        refined parts, where one step's error repeats at every level (docs/polygon.md);
        tet meshes and point clouds never (a convex tet cube: 0.96% -> 1.9%).

        Returns
        -------
        None, True or (n,) bool array
            None: no vertex (one heat step); True: every vertex; else a mask of the operator vertices.

        Examples
        --------
        >>> from heatcore.domains import TetMesh
        >>> import numpy as np
        >>> TetMesh(np.r_[np.eye(3), [[0.0, 0.0, 0.0]]], [[0, 1, 2, 3]]).two_step_vertices() is None
        True
        """
        return None


class MeshDomain(Domain):
    """Base of the mesh domains: input ``vertices`` plus a ``vertex_map`` to operator vertices.

    Examples
    --------
    >>> import numpy as np
    >>> from heatcore.domains import TriangleMesh
    >>> TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0).output_vertices.tolist()
    [0, 1, 2]
    """

    #: ``(mask, why)`` pairs: input vertices of parts the domain left out (a mask over the input vertices)
    #: and why, as a source error says it ("lies on a part with no area").
    left_out = ()

    @property

    def n_input_vertices(self):
        """Number of vertices of the mesh as given."""
        return self.vertices.shape[0]

    @property
    def output_vertices(self):
        """Operator vertex of each input vertex (``-1`` where unreferenced)."""
        return self.vertex_map

    @property
    def input_positions(self):
        """The input vertices, ``(n, 3)``."""
        return self.vertices

    def _referenced(self, v):
        """Operator vertices of input vertices ``v``; a typed error for one no element uses."""
        mapped = self.vertex_map[v]
        if (mapped < 0).any():
            bad = int(v[mapped < 0][0])
            for left_out, why in self.left_out:
                if left_out[bad]:
                    raise InvalidSourceError(f"vertex {bad} {why}, so it cannot be a source")
            raise InvalidSourceError(f"vertex {bad} is not used by any {self.element_name}, so it cannot be a source")
        return mapped

    def _pin_vertices(self, vertices, pins):
        """Source vertices: distance 0 and unit heat at each."""
        v = self._referenced(index_list(vertices, self.n_input_vertices, "vertex"))
        pins.add(v)


def _rows_of(incidence, vertices):
    """The elements of ``vertices`` in ``incidence`` (:meth:`Domain._vertex_elements`), each once, ascending."""
    indptr, elements = incidence
    counts = indptr[vertices + 1] - indptr[vertices]
    pos = np.repeat(indptr[vertices] - np.r_[0, np.cumsum(counts)[:-1]], counts) + np.arange(counts.sum())
    return np.unique(elements[pos])
