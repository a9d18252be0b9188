"""The distance fields a solver keeps for geodesic paths: :class:`PathField` and the solver's :class:`PathFieldCache`.

A path's first step is a distance from its source (and from its target):
one query of the solver, refined by the eikonal pass. Paths from one source
to many targets reuse it: the solver holds a :class:`PathFieldCache` of the
:data:`FIELDS_KEPT` fields used last, as its public attribute
``path_fields`` (made by :meth:`PathFieldCache.of` on the solver's first
path where the solver has not made it itself). The fields depend on the
solver (its ``m`` and ``accuracy``), so they live with the solver, not in
the domain's cache; the mesh they descend on does (:class:`~heatcore.paths.surface.PathMesh`).

Examples
--------
>>> import heatcore as hc
>>> solver = hc.HeatSolver(hc.TriangleMesh(*hc.io.load_demo_mesh()))
>>> _ = solver.geodesic_path(0, 1453)
>>> len(PathFieldCache.of(solver)), PathFieldCache.of(solver) is solver.path_fields
(2, True)
"""

from ..high_accuracy import high_accuracy_distance
from .surface import PathMesh
from .trace import DescentField

#: Distance fields a solver keeps for paths (the source's and the last target's).
FIELDS_KEPT = 2


class PathFieldCache:
    """The distance fields one solver keeps for paths, the ``kept`` used last (the most recent last).

    Parameters
    ----------
    kept : int, default :data:`FIELDS_KEPT`
        How many fields it keeps; the least recently used goes first.

    Examples
    --------
    >>> cache = PathFieldCache(kept=2)
    >>> [cache.get_or_build(key, lambda: key.upper()) for key in ("a", "b", "a", "c")]
    ['A', 'B', 'A', 'C']
    >>> "b" in cache, "a" in cache, len(cache)  # "b" was used least recently
    (False, True, 2)
    >>> cache.clear(); len(cache)
    0
    """

    def __init__(self, kept=FIELDS_KEPT):
        self.kept = kept
        self._fields = {}

    @classmethod
    def of(cls, solver):
        """``solver.path_fields``, made and set here where the solver has none yet (or holds None).

        Examples
        --------
        >>> import heatcore as hc
        >>> solver = hc.HeatSolver(hc.TriangleMesh(*hc.io.load_demo_mesh()))
        >>> PathFieldCache.of(solver) is PathFieldCache.of(solver)
        True
        """
        fields = getattr(solver, "path_fields", None)
        if fields is None:
            fields = solver.path_fields = cls()
        return fields

    def get_or_build(self, key, build):
        """The field kept under ``key`` (now the most recently used), or ``build()``'s, kept in place of the oldest.

        Parameters
        ----------
        key : hashable
            What identifies the field's source (:meth:`~heatcore.paths.surface.SurfacePoint.key`).
        build : callable
            Called with no argument, only when ``key`` is not kept.

        Examples
        --------
        >>> PathFieldCache().get_or_build(("v", 0), lambda: "a field")
        'a field'
        """
        if key in self._fields:
            self._fields[key] = self._fields.pop(key)  # the most recently used last
            return self._fields[key]
        field = build()
        while self._fields and len(self._fields) >= self.kept:
            self._fields.pop(next(iter(self._fields)))
        self._fields[key] = field
        return field

    def clear(self):
        """Drop every field."""
        self._fields.clear()

    def __contains__(self, key):
        return key in self._fields

    def __len__(self):
        return len(self._fields)


class PathField:
    """The distance from one point and its descent data, kept in the solver's :class:`PathFieldCache`.

    Paths from one source to many targets query the source once.

    Examples
    --------
    >>> import heatcore as hc
    >>> solver = hc.HeatSolver(hc.TriangleMesh(*hc.io.load_demo_mesh()))
    >>> field = PathField.of(solver, PathMesh.of(solver.domain).vertex_point(0))
    >>> field is PathField.of(solver, PathMesh.of(solver.domain).vertex_point(0))
    True
    """

    def __init__(self, descent, key):
        self.descent, self.key = descent, key

    @classmethod
    def of(cls, solver, source):
        """The field of ``source`` (a :class:`~heatcore.paths.surface.SurfacePoint`) on ``solver``: a kept one,
        or one query."""
        return PathFieldCache.of(solver).get_or_build(source.key(), lambda: cls.query(solver, source))

    @classmethod
    def query(cls, solver, source):
        """The field of ``source`` computed anew: the solver's distance, refined by the eikonal pass.

        Examples
        --------
        >>> import heatcore as hc
        >>> solver = hc.HeatSolver(hc.TriangleMesh(*hc.io.load_demo_mesh()))
        >>> PathField.query(solver, PathMesh.of(solver.domain).vertex_point(0)).key
        ('v', 0)
        """
        mesh = PathMesh.of(solver.domain)
        if source.vertex >= 0:
            pins = solver.domain.source_pins([int(mesh.input_vertex[source.vertex])])
        else:
            face = int(mesh.face_ids[source.face])
            pins = solver.domain.source_pins(points=([face], [mesh.bary_in(source.face, source)]))
        if solver.accuracy == "high":
            phi = solver.distance_from_pins(pins)
        else:  # the eikonal pass all the same: a better route for little more time
            phi = high_accuracy_distance(solver.domain, pins, lambda: solver.distance_from_pins(pins))
        phi = phi[: mesh.positions.shape[0]]
        return cls(DescentField(mesh, phi), source.key())
