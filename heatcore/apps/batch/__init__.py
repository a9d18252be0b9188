"""The batch runner: geodesic distances for many mesh files, locally or on a Dask cluster.

One task per mesh file: read it, build the :class:`~heatcore.HeatSolver` once
(the factorizations), then solve the sources of the mesh against that solver
in blocks of columns (:meth:`~heatcore.HeatSolver.distances`: one
multi-column solve per block, not one source at a time), and write the result. Tasks run on a local process pool
(all cores by default) or, with ``scheduler=ADDRESS``, on an existing
``dask.distributed`` cluster (``Client(address)``; the mesh files and the
output folder must be on a file system the workers share). The same function,
:func:`process_mesh`, runs in both cases, so the results are identical.

Sources per mesh (:func:`parse_sources`):

``"0,17"``
    these vertex indices, one distance row per source;
``"all"``
    every vertex: the full distance matrix, row ``i`` = distance from vertex ``i``;
``"farthest:K"``
    ``K`` farthest-point samples chosen with the heat distance itself: start
    at vertex 0, then repeatedly the vertex farthest from all sources so far;
``sources_suffix=".sources.txt"``
    the indices in a text file next to each mesh: ``bunny.obj`` reads
    ``bunny.sources.txt`` (whitespace/comma separated, ``#`` comments).

Output, per mesh ``NAME.EXT``, in the output folder:

``NAME.npz`` (compressed)
    ``sources`` (k,) int64, ``n_vertices``, ``spec``, ``key`` (what the result
    was computed from: :mod:`heatcore.apps.batch.keys`) and, when the ``k x n``
    rows fit in the memory bound, ``distances`` (k, n) float64 (``inf`` where
    unreachable). Otherwise the rows are in ``NAME.blocks/rows-START-STOP-DIGEST.npy``
    (one ``.npy`` per block, never all in memory, named by the key's digest)
    and the index holds ``block_dir``, ``block_starts`` and ``block_key``;
    :func:`iter_blocks` and :func:`load_distances` read either layout.
``summary.csv``
    ``file, vertices, sources, seconds, status, error`` with status ``ok``,
    ``error`` (the mesh could not be processed; the message says why),
    ``skipped`` (a result with this run's exact key existed: reruns resume) or
    ``interrupted`` (Ctrl-C came first).

A rerun reuses a result, or the finished blocks of an interrupted one, only
when its key equals the new one (same mesh bytes, sources and options);
other results are recomputed, or refused with ``resume_only=True``. Every
file is written under a temporary name and renamed when complete, and the
``.npz`` index is written last, so a file that looks finished is finished
(:mod:`heatcore.apps.batch.storage`). Ctrl-C stops the pool at once
(:mod:`heatcore.apps.batch.runners`).

The package, one concept per module; this module re-exports the public API:

:mod:`~heatcore.apps.batch.spec`
    what to compute: source specifications, inputs, tasks, output names;
:mod:`~heatcore.apps.batch.keys`
    what a result was computed from (its key);
:mod:`~heatcore.apps.batch.storage`
    atomic files, block files, temporary files, the index;
:mod:`~heatcore.apps.batch.results`
    reading results back: complete and current (:func:`check_result`), their rows;
:mod:`~heatcore.apps.batch.processes`
    whether a process still runs (POSIX, Windows), for temporary files and pool workers;
:mod:`~heatcore.apps.batch.task`
    one mesh: read, factor once, solve its sources in blocks, write;
:mod:`~heatcore.apps.batch.pool`
    the local process pool: a worker that dies fails only the mesh it held;
:mod:`~heatcore.apps.batch.runners`
    where tasks run: this process, a process pool, a Dask cluster;
:mod:`~heatcore.apps.batch.run`
    the batch: keys checked, tasks sent, progress, ``summary.csv``.

Examples
--------
>>> import tempfile
>>> from heatcore.io import demo_mesh_path
>>> tmp = tempfile.TemporaryDirectory()
>>> out = tmp.name
>>> rows = run_batch([demo_mesh_path()], out, "0,17", workers=0, progress=False)
>>> rows[0]["status"], load_distances(output_path(out, demo_mesh_path())).shape
('ok', (2, 2930))
>>> tmp.cleanup()
"""

from .keys import file_digest, key_options  # noqa: F401 - re-exported
from .run import run_batch  # noqa: F401 - re-exported
from .runners import error_message, run_dask, run_pool  # noqa: F401 - re-exported
from .spec import (  # noqa: F401 - re-exported
    DEFAULT_MAX_MEMORY_MB,
    MESH_SUFFIXES,
    BatchError,
    MeshTask,
    SourceSpec,
    find_inputs,
    output_path,
    parse_sources,
)
from .storage import (  # noqa: F401 - re-exported: the public reading API lives here too
    SUMMARY_FIELDS,
    SUMMARY_NAME,
    BlockWriter,
    check_result,
    clean_temporaries,
    discard_blocks,
    discard_result,
    iter_blocks,
    key_digest,
    load_distances,
    load_key,
    load_sources,
    result_key,
    sources_file_path,
    write_index,
    write_summary,
)
from .task import block_rows, farthest_point_sources, process_mesh, source_rows  # noqa: F401 - re-exported
