"""Geodesic Voronoi regions: the nearest of several sources at every vertex.

:func:`nearest_source` (offered as :meth:`heatcore.HeatSolver.nearest_source`) runs the sources through the batched
query :meth:`~heatcore.HeatSolver.distances` (a multi-column heat solve, unit
field and Poisson solve per block of columns, :mod:`heatcore.steps.blocks`)
and keeps only the running minimum, so the memory stays that of one block
however many sources there are.

Examples
--------
>>> import heatcore as hc
>>> solver = hc.HeatSolver(hc.TriangleMesh(*hc.io.load_demo_mesh()))
>>> labels = solver.nearest_source([0, 1453, [10, 20]])
>>> labels[[0, 1453, 10]].tolist()
[0, 1, 2]
"""

import numpy as np

from .errors import InvalidSourceError
from .steps.blocks import source_sequence


def nearest_source(solver, sources, *, return_distance=False, max_memory_mb=None):
    """The index (into ``sources``) of the nearest source at every vertex: geodesic Voronoi regions.

    The sources go through ``solver.distances`` in blocks of
    ``solver.block_columns()`` columns (one multi-column solve per block, not
    one query per source), each block's rows folded into a running
    minimum. A tie goes to the source listed first.

    Parameters
    ----------
    solver : HeatSolver
    sources : sequence
        The sources, each as in :meth:`~heatcore.HeatSolver.distances`: a vertex index, a
        sequence of vertex indices (one source made of several vertices),
        a mapping of :meth:`~heatcore.HeatSolver.distance`'s keywords (``{"points": ...}``,
        ``{"edges": ...}``, ``{"region": ...}``) or prepared
        :class:`~heatcore.domains.sources.SourcePins`.
    return_distance : bool, default False
        Also return the distance to the nearest source.
    max_memory_mb : float, optional
        Working memory of a block, as in :meth:`~heatcore.HeatSolver.distances`.

    Returns
    -------
    labels : (n,) int array
        ``n`` input vertices; -1 where no source can be reached.
    distance : (n,) float array
        Only with ``return_distance``: the distance to the nearest source (``inf``: unreachable).

    Raises
    ------
    InvalidSourceError
        No source, or a bad one (the error :meth:`~heatcore.HeatSolver.distance` raises for it).

    Examples
    --------
    >>> import numpy as np, heatcore as hc
    >>> V = np.array([[x, y, 0] for y in (0, 1) for x in range(4)], float)  # a strip of 3 squares
    >>> F = [[0, 1, 5], [0, 5, 4], [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6]]
    >>> solver = hc.HeatSolver(hc.TriangleMesh(V, F, refine=0))
    >>> nearest_source(solver, [0, 3]).tolist()   # the left half is nearer vertex 0, the right to 3
    [0, 0, 1, 1, 0, 0, 1, 1]
    """
    sources = source_sequence(sources)
    if not sources:
        raise InvalidSourceError("nearest_source needs at least one source")
    width = solver.block_columns(max_memory_mb)
    best = labels = None
    for start in range(0, len(sources), width):
        rows = solver.distances(sources[start : start + width], max_memory_mb=max_memory_mb)
        nearest = np.argmin(rows, axis=0)  # the first of equal distances
        value = rows[nearest, np.arange(rows.shape[1])]
        if best is None:
            best, labels = value, nearest + start
        else:
            closer = value < best  # strictly: a tie keeps the earlier block's source
            best[closer], labels[closer] = value[closer], nearest[closer] + start
    labels[~np.isfinite(best)] = -1
    return (labels, best) if return_distance else labels
