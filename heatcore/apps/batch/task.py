"""One mesh of a batch: read it, factor once, solve its sources in blocks of columns, write the result.

:func:`process_mesh` is the task a runner (:mod:`heatcore.apps.batch.runners`)
runs per mesh file, in this process, in a pool worker or on a Dask worker. The
sources of a mesh are solved together with :meth:`heatcore.HeatSolver.distances`:
one multi-column heat solve, unit field and Poisson solve per block of
:meth:`~heatcore.HeatSolver.block_columns` sources (:func:`source_rows`), not
one source at a time. Only ``farthest:K`` goes source by source: each next
source is the farthest from the rows before it.

Examples
--------
>>> import heatcore as hc
>>> solver = hc.HeatSolver(hc.TriangleMesh(*hc.io.load_demo_mesh()))
>>> rows = list(source_rows(solver, [0, 17, 5], rows_done={1}))
>>> [None if r is None else r.shape for r in rows]
[(2930,), None, (2930,)]
"""

import logging
import os
import time
import warnings

import numpy as np

from ...errors import InvalidSourceError
from .keys import result_key, sources_file_path
from .runners import error_message
from .spec import BatchError, output_path
from .storage import BlockWriter, discard_blocks, write_index

_BYTES_PER_VALUE = 8  # float64 distances

def block_rows(n_vertices, max_memory_mb):
    """Rows of ``n_vertices`` float64 distances that fit in ``max_memory_mb`` (at least 1).

    Raises
    ------
    BatchError
        Not even one row fits.

    Examples
    --------
    >>> block_rows(1000, 1.0)  # 1 MB of rows of 1000 float64 distances
    131
    >>> block_rows(10**6, 1.0)
    Traceback (most recent call last):
    ...
    heatcore.apps.batch.spec.BatchError: --max-memory 1 MB is below one distance row of this mesh (1000000 vertices = 7.63 MB)
    """
    bound = max_memory_mb * 1024 * 1024
    rows = int(bound // (_BYTES_PER_VALUE * n_vertices))
    if rows < 1:
        raise BatchError(f"--max-memory {max_memory_mb:g} MB is below one distance row of this mesh "
                         f"({n_vertices} vertices = {n_vertices * _BYTES_PER_VALUE / 2**20:.3g} MB)")
    return rows


def source_rows(solver, sources, rows_done=(), columns=None):
    """Yield one distance row per source vertex, computed in blocks with :meth:`~heatcore.HeatSolver.distances`.

    Row ``i`` is ``solver.distance([sources[i]])`` (bit for bit on the
    ``qdldl`` and ``cholmod`` backends, within 1e-10 on the others).

    Parameters
    ----------
    solver : HeatSolver
    sources : sequence of int
        Source vertices, one row each.
    rows_done : set of int, optional
        Row numbers not to compute (a block file of an interrupted run holds
        them): ``None`` is yielded for them.
    columns : int, optional
        Sources per :meth:`~heatcore.HeatSolver.distances` call (default: its
        :meth:`~heatcore.HeatSolver.block_columns`, what its memory bound
        solves at once). At most ``columns`` rows are held besides the
        caller's.

    Yields
    ------
    (n,) float array or None

    Examples
    --------
    >>> import heatcore as hc
    >>> V = [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]]
    >>> F = [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]]
    >>> solver = hc.HeatSolver(hc.TriangleMesh(np.array(V, float), np.array(F), refine=3))  # octahedron
    >>> rows = list(source_rows(solver, [0, 1, 2], rows_done={1}, columns=2))
    >>> rows[1] is None, rows[0].round(2)
    (True, array([0.  , 2.5 , 1.41, 1.41, 1.41, 1.41]))
    >>> np.allclose(rows[2], solver.distance([2]), rtol=0, atol=1e-10)
    True
    """
    columns = columns or solver.block_columns()
    for start in range(0, len(sources), columns):
        rows = range(start, min(start + columns, len(sources)))
        todo = [i for i in rows if i not in rows_done]
        block = iter(solver.distances([int(sources[i]) for i in todo]) if todo else ())
        for i in rows:
            yield None if i in rows_done else next(block)


def farthest_point_sources(solver, k, n, candidates=None):
    """``k`` farthest-point samples by heat distance, with their distance rows.

    Starts at vertex 0 (the first candidate vertex), then adds the vertex whose
    distance to the nearest chosen source is largest (a vertex in a component
    no source reaches yet has distance ``inf`` and comes first).

    Parameters
    ----------
    solver : HeatSolver
    k : int
    n : int
        Number of input vertices.
    candidates : (n,) bool array, optional
        Vertices that may be chosen (default: all).

    Yields
    ------
    (int, (n,) float array)
        Each source and its distance row, in order.

    Raises
    ------
    InvalidSourceError
        Fewer than ``k`` distinct vertices can be chosen.

    Examples
    --------
    On an octahedron the farthest vertex from vertex 0 is its opposite, vertex 1:

    >>> import heatcore as hc
    >>> V = [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]]
    >>> F = [[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]]
    >>> solver = hc.HeatSolver(hc.TriangleMesh(np.array(V, float), np.array(F), refine=3))  # octahedron
    >>> [(source, row.round(2).tolist()) for source, row in farthest_point_sources(solver, 2, 6)]
    [(0, [0.0, 2.5, 1.41, 1.41, 1.41, 1.41]), (1, [2.5, 0.0, 1.41, 1.41, 1.41, 1.41])]
    """
    allowed = np.ones(n, bool) if candidates is None else np.asarray(candidates, bool)
    if allowed.sum() < k:
        raise InvalidSourceError(f"farthest:{k} asks for {k} sources but the mesh has {int(allowed.sum())} usable vertices")
    nearest = np.where(allowed, np.inf, -np.inf)
    source = int(np.flatnonzero(allowed)[0])
    for _ in range(k):
        row = solver.distance([source])
        yield source, row
        np.minimum(nearest, row, out=nearest)
        nearest[source] = -np.inf  # chosen: never again (also where its own row is not 0)
        source = int(np.argmax(nearest))
        if not nearest[source] > -np.inf:
            break


def process_mesh(task):
    """Run one mesh: read, factor once, solve all its sources in blocks, write atomically.

    Never raises for a bad mesh: the error goes into the returned row.

    Parameters
    ----------
    task : MeshTask

    Returns
    -------
    dict
        A summary row: file, vertices, sources, seconds, status ("ok" or
        "error"), error (message, empty when ok).

    Examples
    --------
    >>> import tempfile
    >>> from heatcore.io import demo_mesh_path
    >>> from heatcore.apps.batch import MeshTask, load_distances, parse_sources
    >>> tmp = tempfile.TemporaryDirectory()
    >>> row = process_mesh(MeshTask(str(demo_mesh_path()), tmp.name, parse_sources("0,17")))
    >>> row["status"], row["vertices"], row["sources"], load_distances(output_path(tmp.name, "spot.obj")).shape
    ('ok', 2930, 2, (2, 2930))
    >>> process_mesh(MeshTask(str(demo_mesh_path()), tmp.name, parse_sources("5000")))["error"]
    'source vertex 5000 is out of range: the mesh has 2930 vertices (0..2929)'
    >>> tmp.cleanup()
    """
    start = time.perf_counter()
    row = {"file": str(task.path), "vertices": "", "sources": "", "seconds": "", "status": "error", "error": ""}
    quiet = logging.getLogger("heatcore")
    level = quiet.level
    quiet.setLevel(logging.WARNING)  # per-mesh solver chatter would break the progress line
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # repaired-input warnings: one line each would flood stderr
            row.update(_process(task))
        row["status"] = "ok"
    except Exception as exc:  # noqa: BLE001 - a bad mesh must not stop the batch
        row["error"] = error_message(exc)
    finally:
        quiet.setLevel(level)
    row["seconds"] = f"{time.perf_counter() - start:.3f}"
    return row


def _process(task):
    from ...heat import HeatSolver
    from ..inputs import read_mesh_file, read_sources_file

    spec = task.spec
    out = output_path(task.output_dir, task.path)
    before = os.stat(task.path)
    settings = task.settings
    key = result_key(task.path, spec, settings)
    mesh = read_mesh_file(task.path, settings.domain)
    after = os.stat(task.path)
    if (before.st_size, before.st_mtime_ns) != (after.st_size, after.st_mtime_ns):
        raise BatchError(f"mesh file {task.path} changed while it was read: run the batch again")
    n = len(mesh.vertices)
    rows_per_block = block_rows(n, task.max_memory_mb)  # fail early, before the factorization
    if spec.mode == "indices":
        sources = np.asarray(spec.indices, dtype=np.int64)
    elif spec.mode == "file":
        sources = np.unique(np.asarray(read_sources_file(sources_file_path(task.path, spec.suffix)), np.int64))
    elif spec.mode == "all":
        sources = np.arange(n, dtype=np.int64)
    else:
        sources = None
    if sources is not None and sources.size:
        bad = sources[(sources < 0) | (sources >= n)]
        if bad.size:
            raise InvalidSourceError(f"source vertex {bad[0]} is out of range: the mesh has {n} vertices (0..{n - 1})")
    if spec.mode == "farthest" and spec.k > n:
        raise InvalidSourceError(f"farthest:{spec.k} asks for {spec.k} sources but the mesh has {n} vertices")
    solver = HeatSolver(mesh.domain(settings.mesh), settings.solver)

    if spec.union:
        distances = solver.distance(sources)[None, :]
        write_index(out, sources, n, spec, key, distances=distances)
        discard_blocks(out.with_suffix(".blocks"))  # blocks of an earlier key or layout
        return {"vertices": n, "sources": int(sources.size)}

    writer = BlockWriter(out, n, rows_per_block, spec.k if sources is None else sources.size, key)
    if spec.mode == "farthest":
        domain = solver.domain
        usable = np.asarray(domain.output_vertices) >= 0 if hasattr(domain, "output_vertices") else None
        chosen = []
        for s, d in farthest_point_sources(solver, spec.k, n, usable):
            chosen.append(s)
            writer.add(d)
        if len(chosen) < spec.k:
            raise InvalidSourceError(f"farthest:{spec.k}: only {len(chosen)} distinct vertices can be sources")
        sources = np.asarray(chosen, dtype=np.int64)
    else:
        for d in source_rows(solver, sources, writer.rows_done(), min(rows_per_block, solver.block_columns())):
            writer.add(d)
    writer.finish(sources, spec)
    return {"vertices": n, "sources": int(sources.size)}
