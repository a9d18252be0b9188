"""Blocks of sources for :meth:`~heatcore.HeatSolver.distances`: what a block is, and how wide one may be.

Many sources go through one multi-column query in blocks of columns that fit
a working-memory bound and stay in the processor's cache.

Examples
--------
>>> import heatcore as hc
>>> block_columns(hc.TriangleMesh(*hc.io.load_demo_mesh()).operators, 2930)
16
"""

from collections.abc import Iterable, Mapping

import numpy as np

from ..domains.sources import SourcePins
from ..errors import InvalidSourceError
from .unit_field import UNIT_FIELD_TILE_BYTES, tile_columns  # noqa: F401 (UNIT_FIELD_TILE_BYTES: named below)

#: Default bound (MB) on the working memory of :meth:`~heatcore.HeatSolver.distances`:
#: blocks of sources are solved in chunks of columns that fit.
QUERY_MEMORY_MB = 256
#: At most this many sources per chunk of :meth:`~heatcore.HeatSolver.distances`: the
#: time per source falls up to 8-32 columns and rises beyond, as the
#: per-column arrays leave the processor's cache (measured with 128 sources:
#: 1.4-1.6x a loop of queries at 8-32 columns on spot, nefertiti and a
#: 20k-vertex grid; 1.0-1.3x at 128).
MAX_BLOCK_COLUMNS = 16


def block_columns(ops, n_outputs, max_memory_mb=None):
    """Sources of one vertex each that :meth:`~heatcore.HeatSolver.distances` solves at once within ``max_memory_mb``.

    At most ``MAX_BLOCK_COLUMNS`` (16): wider blocks are no faster per
    source (their arrays leave the processor's cache).

    The working memory is about ``8 * (8 n + n_input)`` bytes per column
    (the heat impulse and the heat fields of both boundary conditions,
    ``-div X``, the Poisson solution, the output row) plus one tile of the
    unit field, ``8 * (dim + 5) * n_elements`` bytes per column of the tile
    (its columns: as many as fit in ``UNIT_FIELD_TILE_BYTES``, at least
    one). A source whose pinned vertices share a component adds ``8 n`` per
    pinned vertex while its column is pinned (its unit responses, as in
    :meth:`~heatcore.HeatSolver.distance`). Measured peak (tracemalloc, the output rows
    included) of a full block at the 256 MB default: 42% of it on spot,
    54% on nefertiti, 88% on a 20k-vertex grid with boundary (Robin).

    Parameters
    ----------
    ops : Operators
        The domain's operators.
    n_outputs : int
        Input vertices (the length of an output row).
    max_memory_mb : float, optional
        Default ``QUERY_MEMORY_MB``.

    Returns
    -------
    int
        At least 1.

    Examples
    --------
    >>> import heatcore as hc
    >>> mesh = hc.TriangleMesh(*hc.io.load_demo_mesh())
    >>> [block_columns(mesh.operators, 2930, mb) for mb in (None, 8, 1)]
    [16, 5, 1]
    """
    limit = (QUERY_MEMORY_MB if max_memory_mb is None else max_memory_mb) * 2**20
    tile = 8 * (ops.dim + 5) * ops.elements.shape[0] * tile_columns(ops)
    fit = int((limit - tile) // (8 * (8 * ops.n_vertices + n_outputs)))
    return max(1, min(fit, MAX_BLOCK_COLUMNS))


def source_sequence(sources_block):
    """The sources of a block as a list; a typed error for anything that is not a sequence of sources.

    Examples
    --------
    >>> source_sequence([0, [5, 9]])
    [0, [5, 9]]
    >>> source_sequence(7)
    Traceback (most recent call last):
    ...
    heatcore.errors.InvalidSourceError: sources_block must be a sequence of sources (one per row), got int; for one source use distance()
    """
    single = isinstance(sources_block, (str, bytes, Mapping, SourcePins)) or not isinstance(sources_block, Iterable)
    if single or isinstance(sources_block, np.ndarray) and sources_block.ndim == 0:
        raise InvalidSourceError(
            f"sources_block must be a sequence of sources (one per row), got {type(sources_block).__name__}; "
            "for one source use distance()"
        )
    return list(sources_block)
