"""Columns kept per vertex for the queries that come back to the same vertices.

A point source dragged across neighbouring faces (the Blender add-on's probe)
pins the same corners again. The solves that depend on one vertex only (its
unit response in the Poisson step, the forward half of that response) are
kept in a :class:`ColumnCache`: the most recently used vertices' columns,
within a memory bound.

Examples
--------
>>> import numpy as np
>>> cache = ColumnCache(3, megabytes=0, min_columns=2)
>>> solved = []
>>> def unit_columns(vertices):
...     solved.append(vertices.tolist())
...     return np.eye(3)[:, vertices]
>>> cache.columns(np.array([0, 1]), unit_columns)[:, 1].tolist()
[0.0, 1.0, 0.0]
>>> _ = cache.columns(np.array([1, 2]), unit_columns)  # vertex 1 is kept: only 2 is solved
>>> solved, sorted(cache)
([[0, 1], [2]], [1, 2])
"""

from collections import OrderedDict

import numpy as np

#: The memory (MB) and the number of columns a cache holds, by default: the
#: most recently used columns, at most ``MAX_CACHED_COLUMNS`` and
#: ``COLUMN_CACHE_MB`` megabytes of them (but at least ``MIN_CACHED_COLUMNS``).
COLUMN_CACHE_MB = 64
MIN_CACHED_COLUMNS = 4
MAX_CACHED_COLUMNS = 64


class ColumnCache(OrderedDict):
    """Vertex -> its column (``(rows,)`` array), least recently used first, within a memory bound.

    Parameters
    ----------
    rows : int
        Length of each column.
    megabytes, min_columns, max_columns : float, int, int, optional
        The bound: at most ``max_columns`` columns and ``megabytes`` of them,
        but at least ``min_columns``. Defaults: the module's constants, read
        at each call (so that they can be changed at run time).

    Examples
    --------
    >>> ColumnCache(2**20, megabytes=64).keep
    8
    """

    def __init__(self, rows, megabytes=None, min_columns=None, max_columns=None):
        super().__init__()
        self.rows = rows
        self._bound = (megabytes, min_columns, max_columns)

    @property
    def keep(self):
        """How many columns are kept."""
        megabytes, low, high = (
            default if value is None else value
            for value, default in zip(self._bound, (COLUMN_CACHE_MB, MIN_CACHED_COLUMNS, MAX_CACHED_COLUMNS))
        )
        return max(low, min(high, int(megabytes * 2**20) // (8 * self.rows)))

    def columns(self, vertices, compute):
        """The columns of ``vertices`` as an ``(rows, k)`` array (columns contiguous); ``compute(missing)`` solves the others.

        ``compute`` takes an int array of vertices and returns their columns
        ``(rows, len(missing))``; they are kept, and the least recently used
        dropped beyond the bound. More vertices than the cache keeps are
        computed and not kept.
        """
        vertices = np.asarray(vertices, dtype=np.int64)
        keep = self.keep
        if vertices.size > keep:
            return compute(vertices)
        order = vertices.tolist()
        missing = [v for v in dict.fromkeys(order) if v not in self]
        if missing:
            solved = compute(np.asarray(missing, dtype=np.int64))
            for j, v in enumerate(missing):
                self[v] = np.ascontiguousarray(solved[:, j])
        Z = np.empty((self.rows, len(order)), order="F")
        for j, v in enumerate(order):
            Z[:, j] = self[v]
            self.move_to_end(v)
        while len(self) > keep:
            self.popitem(last=False)
        return Z
