"""Sources as the heat solver sees them: pinned vertex values plus a heat impulse.

Every kind of source (vertices, points inside elements, regions made of edges
or faces) becomes a :class:`SourcePins`: the operator vertices whose distance
is known (0 for a source vertex, the straight-line distance inside a flat
element for a point in that element) and the right-hand side of the heat
step. Domains build it; :mod:`heatcore.heat` consumes it.
"""

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


def edge_list(edges, n_vertices):
    """Validate edges given as vertex pairs; returns a ``(k, 2)`` int64 array.

    Raises
    ------
    InvalidSourceError
        Not of shape ``(k, 2)``, or vertex indices that :func:`index_list` rejects.
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
    """Validate barycentric coordinates: shape ``(count, corners)``, finite, >= 0, summing to 1."""
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
