"""Input checking and cleanup with typed, actionable errors.

Examples
--------
>>> V, F = mesh_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
>>> F.dtype
dtype('int64')
"""

import warnings

import numpy as np

from ..errors import HeatcoreWarning, InvalidMeshError
from .parts import row_reduce


def vertex_array(V, name="V"):
    """Vertex positions as a finite ``(n, 3)`` float64 array (``(n, 2)`` is padded with z = 0).

    Parameters
    ----------
    V : (n, 3) or (n, 2) array_like of float
    name : str, default "V"
        The array's name in error messages.

    Returns
    -------
    (n, 3) float64 array

    Raises
    ------
    InvalidMeshError
        Not numeric, a wrong shape, no vertices, or NaN/inf coordinates.

    Examples
    --------
    >>> vertex_array([[0, 0], [1, 2]]).tolist()
    [[0.0, 0.0, 0.0], [1.0, 2.0, 0.0]]
    """
    try:
        V = np.array(V, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InvalidMeshError(f"{name} must be a numeric (n, 3) array: {exc}") from exc
    if V.ndim != 2 or V.shape[1] not in (2, 3):
        raise InvalidMeshError(f"{name} must have shape (n, 3) (or (n, 2)), got {V.shape}")
    if V.shape[0] == 0:
        raise InvalidMeshError(f"{name} is empty: the mesh has no vertices")
    if V.shape[1] == 2:
        V = np.column_stack([V, np.zeros(V.shape[0])])
    bad = ~row_reduce(np.logical_and, np.isfinite(V))
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise InvalidMeshError(
            f"{int(bad.sum())} vertices have NaN or infinite coordinates (first: vertex {i} = {V[i].tolist()})"
        )
    return V


def one_based_hint(indices, n_vertices):
    """``"; the indices look 1-based: ..."`` when they run from 1 to ``n_vertices``, else ``""``.

    Appended to an out-of-range message: a 1-based face list (as OBJ files
    store it) has no index 0 and reaches exactly the vertex count.

    Parameters
    ----------
    indices : array of int
        Every vertex index of the faces.
    n_vertices : int

    Returns
    -------
    str

    Examples
    --------
    >>> one_based_hint(np.array([1, 2, 3, 3, 4]), 4)
    '; the indices look 1-based (they run from 1 to 4): subtract 1, heatcore counts vertices from 0'
    >>> one_based_hint(np.array([0, 2, 5]), 4)
    ''
    """
    indices = np.asarray(indices)
    if indices.size and indices.min() == 1 and indices.max() == n_vertices:
        return (f"; the indices look 1-based (they run from 1 to {n_vertices}): subtract 1, "
                "heatcore counts vertices from 0")
    return ""


def index_array(A, n_vertices, columns, element="face", name="F"):
    """Element indices as an ``(m, columns)`` int64 array, each in ``[0, n_vertices)``.

    An index out of range is reported as given (a ``uint64`` ``2**64 - 1`` is
    not shown as ``-1``).

    Examples
    --------
    >>> index_array(np.array([[0, 1, 2**64 - 1]], dtype=np.uint64), 3, 3)
    Traceback (most recent call last):
    ...
    heatcore.errors.InvalidMeshError: face 0 references vertex 18446744073709551615 but the mesh has 3 vertices (valid indices are 0..2)
    """
    try:
        A = np.asarray(A)
    except ValueError as exc:  # ragged nested lists
        raise InvalidMeshError(f"{name} must be an integer array of shape (m, {columns}); got ragged rows") from exc
    if A.dtype == object:
        raise InvalidMeshError(f"{name} must be an integer array of shape (m, {columns}); got ragged rows")
    if A.ndim != 2 or A.shape[1] != columns:
        raise InvalidMeshError(f"{name} must have shape (m, {columns}), got {A.shape}")
    if A.shape[0] == 0:
        raise InvalidMeshError(f"{name} is empty: the mesh has no {element}s")
    if not np.issubdtype(A.dtype, np.integer):
        if not np.issubdtype(A.dtype, np.floating) or not np.all(np.isfinite(A)) or np.any(A != np.round(A)):
            raise InvalidMeshError(f"{name} must hold integer vertex indices, got dtype {A.dtype}")
    bad = (A < 0) | (A >= n_vertices)  # before the cast: uint64 and large floats would wrap around
    if bad.any():
        row, col = np.argwhere(bad)[0]
        raise InvalidMeshError(
            f"{element} {row} references vertex {int(A[row, col])} but the mesh has {n_vertices} vertices "
            f"(valid indices are 0..{n_vertices - 1}){one_based_hint(A, n_vertices)}"
        )
    return A.astype(np.int64)


def mesh_arrays(V, F):
    """Validate a triangle mesh.

    Parameters
    ----------
    V : (n, 3) array_like of float
    F : (m, 3) array_like of int

    Returns
    -------
    V : (n, 3) float64 array
    F : (m, 3) int64 array

    Raises
    ------
    InvalidMeshError
        Wrong shapes, non-finite coordinates, out-of-range or negative indices.

    Examples
    --------
    >>> V, F = mesh_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
    >>> V.dtype, F.dtype
    (dtype('float64'), dtype('int64'))
    """
    V = vertex_array(V)
    F = index_array(F, V.shape[0], 3)
    return V, F


def _sorted_rows(E):
    """``np.sort(E, axis=1)``; rows of three by a sorting network (3x faster than numpy's sort of each row)."""
    if E.ndim != 2 or E.shape[1] != 3:
        return np.sort(E, axis=1)
    a, b, c = E[:, 0], E[:, 1], E[:, 2]
    low, high = np.minimum(a, b), np.maximum(a, b)
    return np.column_stack([np.minimum(low, c), np.maximum(low, np.minimum(high, c)), np.maximum(high, c)])


def _may_have_duplicate_rows(S):
    """False when the rows of ``S`` are certainly distinct (one sort of one integer key per row)."""
    if S.shape[0] < 2:
        return False
    base = int(S.max()) + 1
    if base ** S.shape[1] >= 2**62:
        return True
    key = np.zeros(S.shape[0], dtype=np.int64)
    for column in S.T:
        key = key * base + column
    key.sort()
    return bool((key[1:] == key[:-1]).any())


def clean_elements(E, element="face", stacklevel=3):
    """Drop elements with repeated vertices and duplicates of another element.

    Both are harmless to drop: a repeated-vertex element has no area, and a
    duplicate adds nothing. A :class:`HeatcoreWarning` says how many went.

    Parameters
    ----------
    E : (m, k) int array
    element : str, default "face"
        What an element is called in the warning.
    stacklevel : int, default 3
        The warning's ``stacklevel`` (3: the caller of the function that calls this one).

    Returns
    -------
    kept : (m,) bool array

    Examples
    --------
    >>> import warnings
    >>> with warnings.catch_warnings():
    ...     warnings.simplefilter("ignore")
    ...     clean_elements(np.array([[0, 1, 2], [2, 1, 0], [0, 0, 1]])).tolist()
    [True, False, False]
    """
    S = _sorted_rows(E)
    repeated = np.zeros(E.shape[0], dtype=bool)
    for j in range(1, S.shape[1]):  # column by column: several times faster than .any(axis=1) on thin rows
        repeated |= S[:, j] == S[:, j - 1]
    unique = np.ones(E.shape[0], dtype=bool)
    if _may_have_duplicate_rows(S):
        order = np.lexsort(S.T[::-1])
        same_as_previous = np.r_[False, row_reduce(np.logical_and, S[order[1:]] == S[order[:-1]])]
        unique[order[same_as_previous]] = False
    kept = unique & ~repeated
    n_rep, n_dup = int(repeated.sum()), int((~unique & ~repeated).sum())
    if n_rep or n_dup:
        warnings.warn(
            f"ignored {n_rep} {element}s with repeated vertices and {n_dup} duplicate {element}s",
            HeatcoreWarning,
            stacklevel=stacklevel,
        )
    return kept
