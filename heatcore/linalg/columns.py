"""Solving many right-hand sides so that every column is what it would be alone.

:func:`solve_columns` gives each column of an ``(n, k)`` right-hand side
exactly the result of a one-column solve, on every backend, as fast as one
wide call: backends differ in how a multi-column solve rounds and in which
fast paths they keep for one column.

Examples
--------
>>> import numpy as np, scipy.sparse as sp
>>> from heatcore.linalg import factor
>>> f = factor(sp.diags([2.0, 4.0, 8.0]).tocsr())
>>> np.round(solve_columns(f, np.ones((3, 5)))[:, 4], 12).tolist()
[0.5, 0.25, 0.125]
"""

import numpy as np

#: Multi-column solves go in calls of at most this many columns: CHOLMOD's
#: simplicial solve (the cholmod backend) takes 4 columns at a time through
#: another kernel than 1 to 3, with another rounding, so with at most 3 every
#: column is bit for bit its one-column solve (measured cost: within the noise
#: of one multi-column call; see docs/batch.md).
EXACT_SOLVE_COLUMNS = 3
#: Backends that solve one column at a time faster: the supernodal factor
#: solves a sparse right-hand side (a vertex's heat impulse) by a sparse
#: forward solve, for one column only (measured on nefertiti: blocks 10%
#: slower with 3 columns per call).
ONE_COLUMN_BACKENDS = ("supernodal",)


def solve_columns(factor, rhs):
    """``factor.solve(rhs)``, each column of an ``(n, k)`` ``rhs`` exactly as if solved alone.

    Parameters
    ----------
    factor : Factor
    rhs : (n,) or (n, k) float array

    Returns
    -------
    float array shaped like ``rhs`` (columns contiguous when ``k > 1``)

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> from heatcore.linalg import factor
    >>> f = factor(sp.diags([2.0, 4.0]).tocsr())
    >>> np.round(solve_columns(f, np.array([[2.0, 4.0], [4.0, 8.0]])), 12).tolist()
    [[1.0, 2.0], [1.0, 2.0]]
    """
    width = 1 if factor.backend in ONE_COLUMN_BACKENDS else EXACT_SOLVE_COLUMNS
    if rhs.ndim == 1 or 1 < rhs.shape[1] <= width:
        return factor.solve(rhs)
    out = np.empty(rhs.shape, order="F")
    for start in range(0, rhs.shape[1], width):
        if width == 1:
            out[:, start] = factor.solve(rhs[:, start])  # one dimension: what takes the sparse path
        else:
            out[:, start : start + width] = factor.solve(rhs[:, start : start + width])
    return out
