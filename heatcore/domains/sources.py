"""Sources as the heat solver sees them: pinned vertex values plus a heat impulse.

Every domain speaks one vocabulary (:data:`SOURCE_KINDS`): ``vertices``,
``points=(element_indices, barycentric)`` (points inside elements),
``edges`` (vertex pairs) and ``region`` (elements whose union is the source);
each domain takes the kinds it lists in ``source_kinds``. Every kind becomes
part of one :class:`SourcePins`, built by :func:`build_source_pins`: the
operator vertices whose distance is known (0 for a source vertex, the
straight-line distance inside a flat element for a point in that element) and
the right-hand side of the heat step. Domains supply one ``_pin_KIND`` method
per kind; :mod:`heatcore.heat` consumes the pins.

Examples
--------
>>> import numpy as np
>>> from heatcore.domains import TriangleMesh
>>> mesh = TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0)
>>> pins = build_source_pins(mesh, [0], points=([0], [[0.0, 0.5, 0.5]]))
>>> pins.vertices.tolist(), pins.values.round(3).tolist()
([0, 1, 2], [0.0, 0.707, 0.707])
"""

import warnings
from dataclasses import dataclass

import numpy as np

from ..errors import InvalidSourceError


@dataclass
class SourcePins:
    """Known distances at some operator vertices, and where heat is injected.

    Attributes
    ----------
    vertices : (k,) int array, operator vertex indices (unique)
    values : (k,) float array, distance at each pinned vertex (>= 0)
    heat : (n,) float array, the heat step's right-hand side

    Examples
    --------
    >>> pins = SourcePins.combine(4, [2, 0, 2], [0.5, 0.0, 0.25], [2, 0], [1.0, 1.0])
    >>> pins.vertices.tolist(), pins.values.tolist(), pins.heat.tolist()
    ([0, 2], [0.0, 0.25], [1.0, 0.0, 1.0, 0.0])
    """

    vertices: np.ndarray
    values: np.ndarray
    heat: np.ndarray

    @classmethod
    def combine(cls, n, vertices, values, heat_vertices, heat_weights):
        """Merge possibly repeated pins (keeping the smallest value) and heat impulses."""
        vertices = np.asarray(vertices, dtype=np.int64)
        values = np.asarray(values, dtype=float)
        order = np.lexsort((values, vertices))
        vertices, values = vertices[order], values[order]
        first = np.r_[True, vertices[1:] != vertices[:-1]]
        heat = np.bincount(heat_vertices, weights=heat_weights, minlength=n).astype(float)
        return cls(vertices[first], values[first], heat)


#: The source vocabulary of every domain: keyword -> what it names.
SOURCE_KINDS = {
    "vertices": "vertex indices (distance 0)",
    "points": "points inside elements: (element indices, barycentric coordinates)",
    "edges": "edges as (k, 2) vertex pairs; the distance is to their union",
    "region": "elements whose union is the source (faces, polygons, or boundary triangles of a tet mesh)",
}

#: Old source keywords, kept for one release: they warn and mean the new name.
DEPRECATED_SOURCE_KEYWORDS = {
    "face_points": "points",
    "tet_points": "points",
    "faces": "region",
    "boundary_faces": "region",
}


def source_keywords(kinds, stacklevel=4):
    """Source keywords in the current vocabulary: old names renamed with a ``DeprecationWarning``.

    Parameters
    ----------
    kinds : dict
        Keyword arguments naming sources (``vertices`` excluded).
    stacklevel : int
        Where the warning points (the user's call).

    Returns
    -------
    dict
        The same sources under the names of :data:`SOURCE_KINDS`.

    Raises
    ------
    InvalidSourceError
        An unknown keyword, or a kind given under its old and its new name.

    Examples
    --------
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     source_keywords({"faces": [3]})
    {'region': [3]}
    >>> caught[0].category.__name__
    'DeprecationWarning'
    """
    renamed = {}
    for name, value in kinds.items():
        new = DEPRECATED_SOURCE_KEYWORDS.get(name, name)
        if new not in SOURCE_KINDS or new == "vertices":
            known = ", ".join(k for k in SOURCE_KINDS if k != "vertices")
            raise InvalidSourceError(f"unknown source keyword {name!r}: sources are vertices (positional), {known}")
        if new != name:
            warnings.warn(f"the source keyword {name!r} is deprecated; use {new}=", DeprecationWarning, stacklevel=stacklevel)
        if value is not None and renamed.get(new) is not None:
            raise InvalidSourceError(f"{new} given twice (as {new}= and under an old name)")
        if value is not None or new not in renamed:
            renamed[new] = value
    return renamed


class PinBuilder:
    """Collects pins and heat impulses from each source kind, then merges them into :class:`SourcePins`.

    Examples
    --------
    >>> pins = PinBuilder(4)
    >>> pins.add(np.array([2]))
    >>> pins.add(np.array([1, 3]), values=np.array([0.5, 0.5]), heat_vertices=(), heat_weights=())
    >>> built = pins.build("vertices")
    >>> built.vertices.tolist(), built.heat.tolist()
    ([1, 2, 3], [0.0, 0.0, 1.0, 0.0])
    """

    def __init__(self, n_vertices, heat_once=False):
        self.n_vertices = n_vertices
        self.heat_once = heat_once
        self._vertices, self._values, self._heat_vertices, self._heat_weights = [], [], [], []

    def add(self, vertices, values=None, heat_vertices=None, heat_weights=None):
        """Pin operator ``vertices`` to ``values`` (default 0) and inject heat (default 1 at each of them)."""
        vertices = np.asarray(vertices, dtype=np.int64)
        self._vertices.append(vertices)
        self._values.append(np.zeros(vertices.size) if values is None else np.asarray(values, dtype=float))
        if heat_vertices is None:
            heat_vertices, heat_weights = vertices, np.ones(vertices.size)
        self._heat_vertices.append(np.asarray(heat_vertices, dtype=np.int64))
        self._heat_weights.append(np.asarray(heat_weights, dtype=float))

    def build(self, kinds):
        """The merged :class:`SourcePins`; a typed error naming ``kinds`` when nothing was pinned."""
        if sum(v.size for v in self._vertices) == 0:
            listing = kinds if isinstance(kinds, str) else ", ".join(kinds)
            raise InvalidSourceError(f"no source given: pass {listing} (at least one)")
        vertices = np.concatenate(self._vertices)
        if self.heat_once:  # unit heat once per pinned vertex, however often it was named
            vertices = np.unique(vertices)
            ones = np.ones(vertices.size)
            return SourcePins.combine(self.n_vertices, vertices, np.zeros(vertices.size), vertices, ones)
        return SourcePins.combine(
            self.n_vertices,
            vertices,
            np.concatenate(self._values),
            np.concatenate(self._heat_vertices),
            np.concatenate(self._heat_weights),
        )


def build_source_pins(domain, vertices=None, **kinds):
    """The one builder of :class:`SourcePins`: every kind of source, on any domain.

    Parameters
    ----------
    domain : heatcore.domains.base.Domain
        Lists the kinds it takes in ``source_kinds`` and pins each with its
        ``_pin_KIND(value, builder)`` method.
    vertices : int or sequence of int, optional
        Source vertices.
    **kinds
        ``points``, ``edges``, ``region`` (or their deprecated old names, see
        :data:`DEPRECATED_SOURCE_KEYWORDS`).

    Returns
    -------
    SourcePins

    Raises
    ------
    InvalidSourceError
        No source, a kind the domain does not take, or what the domain's
        ``_pin_KIND`` rejects.

    Examples
    --------
    >>> import numpy as np
    >>> from heatcore.domains import PointCloud
    >>> build_source_pins(PointCloud(np.random.default_rng(0).random((200, 3))), [5]).values.tolist()
    [0.0]
    """
    kinds = {"vertices": vertices, **source_keywords(kinds)}
    given = [k for k, v in kinds.items() if v is not None]
    refused = [k for k in given if k not in domain.source_kinds]
    if refused:
        raise InvalidSourceError(
            f"a {domain.domain_name} takes only {', '.join(domain.source_kinds)} as sources, not {', '.join(refused)}"
        )
    builder = PinBuilder(domain.n_vertices, heat_once=domain.unit_heat_once)
    pin = {"vertices": domain._pin_vertices, "points": domain._pin_points, "edges": domain._pin_edges,
           "region": domain._pin_region}
    for kind in domain.source_kinds:
        if kinds.get(kind) is not None:
            pin[kind](kinds[kind], builder)
    return builder.build(domain.source_kinds)


def source_vertices(n_vertices, elements, vertices=None, *, points=None, edges=None, region=None):
    """The input vertices that sources name or touch: the vertices, the edges' ends, the elements' corners.

    A domain built for one query keeps only the connected parts that hold
    them (``only_parts_of`` of :class:`~heatcore.domains.TriangleMesh`): each
    part is solved as if alone, so the others would only cost time.

    Parameters
    ----------
    n_vertices : int
    elements : (m, k) int array
        The elements (faces) that ``points`` and ``region`` index.
    vertices, points, edges, region
        As :meth:`~heatcore.domains.base.Domain.source_pins` takes them
        (barycentric coordinates are not read).

    Returns
    -------
    (j,) int64 array, input vertex indices (unique)

    Raises
    ------
    InvalidSourceError
        Indices that :func:`index_list` or :func:`edge_list` rejects, or a
        ``points`` that is not a pair.

    Examples
    --------
    >>> F = np.array([[0, 1, 2], [2, 3, 4]])
    >>> source_vertices(6, F, [5], edges=[[0, 1]], region=[1]).tolist()
    [0, 1, 2, 3, 4, 5]
    """
    found = [np.zeros(0, dtype=np.int64)]
    if vertices is not None:
        found.append(index_list(vertices, n_vertices, "vertex"))
    if edges is not None:
        found.append(edge_list(edges, n_vertices).ravel())
    if region is not None:
        found.append(elements[index_list(region, len(elements), "face")].ravel())
    if points is not None:
        try:
            element_indices, _ = points
        except (TypeError, ValueError):
            raise InvalidSourceError("points must be a pair (face indices, barycentric coordinates)") from None
        found.append(elements[index_list(element_indices, len(elements), "face")].ravel())
    return np.unique(np.concatenate(found))


def edge_list(edges, n_vertices):
    """Validate edges given as vertex pairs; returns a ``(k, 2)`` int64 array.

    Raises
    ------
    InvalidSourceError
        Not of shape ``(k, 2)``, or vertex indices that :func:`index_list` rejects.

    Examples
    --------
    >>> edge_list([[0, 1], [1, 2]], 3).tolist()
    [[0, 1], [1, 2]]
    >>> edge_list([0, 1], 3)
    Traceback (most recent call last):
    ...
    heatcore.errors.InvalidSourceError: edges must have shape (k, 2), got (2,)
    """
    try:
        e = np.asarray(edges)
    except (TypeError, ValueError) as exc:  # ragged nesting
        raise InvalidSourceError(f"edges must be vertex pairs of shape (k, 2): {exc}") from None
    if e.size and (e.ndim != 2 or e.shape[1] != 2):
        raise InvalidSourceError(f"edges must have shape (k, 2), got {e.shape}")
    return index_list(e.reshape(-1), n_vertices, "vertex").reshape(-1, 2)


def index_list(indices, upper, what):
    """Validate a list of indices into ``range(upper)``; returns an int64 array.

    Raises
    ------
    InvalidSourceError
        Nested or ragged lists, non-integer, negative or out-of-range entries.

    Examples
    --------
    >>> index_list([3, 7], 10, "vertex").tolist()
    [3, 7]
    >>> index_list([[3], [7]], 10, "vertex")
    Traceback (most recent call last):
    heatcore.errors.InvalidSourceError: vertex indices must be a flat list of integers, got shape (2, 1)
    """
    try:
        arr = np.asarray(indices)
    except (TypeError, ValueError) as exc:  # ragged nesting
        raise InvalidSourceError(f"{what} indices must be a flat list of integers: {exc}") from None
    if arr.ndim > 1:
        raise InvalidSourceError(f"{what} indices must be a flat list of integers, got shape {arr.shape}")
    arr = np.atleast_1d(arr)
    if arr.dtype == object:  # Python integers beyond 64 bits, or not numbers at all
        if not all(isinstance(i, (int, np.integer)) and not isinstance(i, bool) for i in arr):
            raise InvalidSourceError(f"{what} indices must be integers")
    elif arr.size and not np.issubdtype(arr.dtype, np.integer):
        if not np.issubdtype(arr.dtype, np.floating) or np.any(~np.isfinite(arr)) or np.any(arr != np.round(arr)):
            raise InvalidSourceError(f"{what} indices must be integers, got {arr.dtype}")
    bad = np.array([i < 0 or i >= upper for i in arr], dtype=bool) if arr.dtype == object else (arr < 0) | (arr >= upper)
    if bad.any():  # checked before any cast, so the message shows the value given
        raise InvalidSourceError(
            f"{what} index {int(arr[bad][0])} is out of range: valid {what} indices are 0..{upper - 1}"
        )
    return arr.astype(np.int64)


def barycentric_array(bary, count, corners):
    """Validate barycentric coordinates: shape ``(count, corners)``, finite, >= 0, summing to 1.

    Returns
    -------
    (count, corners) float array
        The coordinates, rounding below zero clipped and rows renormalized.

    Raises
    ------
    InvalidSourceError
        Wrong shape, not finite, negative, or rows not summing to 1.

    Examples
    --------
    >>> barycentric_array([[0.2, 0.3, 0.5]], 1, 3).tolist()
    [[0.2, 0.3, 0.5]]
    >>> barycentric_array([[0.5, 0.6, 0.0]], 1, 3)
    Traceback (most recent call last):
    ...
    heatcore.errors.InvalidSourceError: barycentric coordinates of point 0 are [0.5, 0.6, 0.0]: they must be >= 0 and sum to 1
    """
    try:
        b = np.asarray(bary, dtype=float)
        b = b.reshape(-1, corners) if b.size else np.zeros((0, corners))
    except (TypeError, ValueError) as exc:
        raise InvalidSourceError(f"barycentric coordinates must be numbers, {corners} per point: {exc}") from None
    if b.shape[0] != count:
        raise InvalidSourceError(f"got {count} element indices but {b.shape[0]} barycentric coordinate rows")
    if not np.isfinite(b).all():
        raise InvalidSourceError("barycentric coordinates must be finite")
    if (b < -1e-9).any() or np.any(np.abs(b.sum(axis=1) - 1.0) > 1e-6):
        row = int(np.flatnonzero((b < -1e-9).any(axis=1) | (np.abs(b.sum(axis=1) - 1.0) > 1e-6))[0])
        raise InvalidSourceError(
            f"barycentric coordinates of point {row} are {b[row].tolist()}: they must be >= 0 and sum to 1"
        )
    return np.clip(b, 0.0, None) / np.clip(b, 0.0, None).sum(axis=1, keepdims=True)
