"""The batch runner: geodesic distances for many mesh files, locally or on a Dask cluster.

One task per mesh file: read it, build the :class:`~heatcore.HeatSolver` once
(the factorizations), then solve every source of the mesh against that solver
in blocks of rows, and write the result. Tasks run on a local process pool
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

Examples
--------
>>> import tempfile
>>> from heatcore.io import demo_mesh_path
>>> out = tempfile.mkdtemp()
>>> rows = run_batch([demo_mesh_path()], out, "0,17", workers=0, progress=False)
>>> rows[0]["status"], load_distances(output_path(out, demo_mesh_path())).shape
('ok', (2, 2930))
"""

import logging
import os
import sys
import time
from pathlib import Path

import numpy as np

from ...errors import InvalidSourceError
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
from .runners import error_message, run_dask, run_pool

log = logging.getLogger("heatcore.apps.batch")

_BYTES_PER_VALUE = 8  # float64 distances


# --------------------------------------------------------------------------- one mesh


def block_rows(n_vertices, max_memory_mb):
    """Rows of ``n_vertices`` float64 distances that fit in ``max_memory_mb`` (at least 1).

    Raises
    ------
    BatchError
        Not even one row fits.
    """
    bound = max_memory_mb * 1024 * 1024
    rows = int(bound // (_BYTES_PER_VALUE * n_vertices))
    if rows < 1:
        raise BatchError(f"--max-memory {max_memory_mb:g} MB is below one distance row of this mesh "
                         f"({n_vertices} vertices = {n_vertices * _BYTES_PER_VALUE / 2**20:.3g} MB)")
    return rows


def _source_rows(solver, spec, sources, n, rows_done):
    """Yield one distance row per source; ``rows_done`` (a set of row numbers) are not computed (None)."""
    for i, s in enumerate(sources):
        yield None if i in rows_done else solver.distance([int(s)])


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
    """
    import logging
    import warnings

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
    key = result_key(task.path, spec, task.kind, task.mesh_options, task.solver_options)
    mesh = read_mesh_file(task.path, task.kind)
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
    solver = HeatSolver(mesh.domain(**task.mesh_options), **task.solver_options)

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
        for d in _source_rows(solver, spec, sources, n, writer.rows_done()):
            writer.add(d)
    writer.finish(sources, spec)
    return {"vertices": n, "sources": int(sources.size)}


# --------------------------------------------------------------------------- the batch


class _Progress:
    """``batch: 12/40 meshes (1 error, 3 skipped) 30% 0:42 elapsed, ETA 1:38`` on one stderr line."""

    def __init__(self, total, enabled=True, stream=None):
        self.total, self.enabled, self.stream = total, enabled, stream or sys.stderr
        self.done = self.errors = self.skipped = 0
        self.start = time.perf_counter()
        self.computed = 0

    def update(self, row):
        self.done += 1
        self.errors += row["status"] == "error"
        self.skipped += row["status"] == "skipped"
        self.computed += row["status"] != "skipped"
        self.show()

    def show(self, end=""):
        if not self.enabled:
            return
        elapsed = time.perf_counter() - self.start
        left = self.total - self.done
        eta = "--:--" if self.computed == 0 else _clock(elapsed / self.computed * left)
        notes = ", ".join(s for s in (f"{self.errors} error{'s' * (self.errors != 1)}" if self.errors else "",
                                      f"{self.skipped} skipped" if self.skipped else "") if s)
        pct = 100 * self.done // max(self.total, 1)
        bar = "#" * (20 * self.done // max(self.total, 1))
        self.stream.write(f"\rbatch: [{bar:<20}] {self.done}/{self.total} meshes{f' ({notes})' if notes else ''} "
                          f"{pct}% {_clock(elapsed)} elapsed, ETA {eta}{end}")
        self.stream.flush()

    def close(self):
        self.show(end="\n")


def _clock(seconds):
    seconds = int(round(seconds))
    h, rest = divmod(seconds, 3600)
    return f"{h}:{rest // 60:02d}:{rest % 60:02d}" if h else f"{rest // 60}:{rest % 60:02d}"


def run_batch(inputs, output_dir, sources=None, *, sources_suffix=None, union=False, scheduler=None,
              workers=None, max_memory_mb=DEFAULT_MAX_MEMORY_MB, kind="auto", mesh_options=None,
              solver_options=None, progress=True, resume_only=False):
    """Geodesic distances for every mesh file of ``inputs``; returns the summary rows.

    Parameters
    ----------
    inputs : path-like or list of path-like
        Folders (their mesh files), glob patterns or files.
    output_dir : path-like
        Created if missing. Holds one ``NAME.npz`` per mesh and ``summary.csv``.
    sources : str or SourceSpec, optional
        ``"0,17"``, ``"all"`` or ``"farthest:K"`` (see :func:`parse_sources`).
    sources_suffix : str, optional
        Per-mesh sources files instead (``".sources.txt"``).
    union : bool, default False
        One row per mesh: distance to the union of its sources.
    scheduler : str or distributed.Client, optional
        Address of a running ``dask.distributed`` scheduler (or a client): run
        there, one task per mesh. Default: a local process pool.
    workers : int, optional
        Processes of the local pool (default: all cores); 0 runs in this process.
    max_memory_mb : float, default 1024
        Bound on the distance rows a task holds at once; results with more rows
        are written in blocks of that size. Each concurrent task has its own bound.
    kind : str, default "auto"
        How to read files (see :func:`heatcore.io.domain.read_domain`).
    mesh_options, solver_options : dict, optional
        Keywords of the domain (``robust``, ``refine``) and of
        :class:`~heatcore.HeatSolver` (``m``, ``boundary``, ``accuracy``).
    progress : bool, default True
        Progress line with counts and ETA on stderr.
    resume_only : bool, default False
        Only resume: raise :class:`BatchError` (before any work) when an
        existing result in ``output_dir`` was computed from another mesh file,
        other sources or other options, instead of recomputing it.

    Returns
    -------
    list of dict
        The rows of ``summary.csv`` in input order. A result is reused
        (``skipped``) only when its key (:func:`~heatcore.apps.batch.storage.result_key`)
        equals this run's.

    Raises
    ------
    BatchError
        Bad inputs or options; with ``resume_only``, results that do not match.
    KeyboardInterrupt
        Re-raised after Ctrl-C, once queued work is cancelled, the pool's
        workers are stopped and ``summary.csv`` lists what is on disk (meshes
        not finished have status ``interrupted``).
    """
    spec = sources if isinstance(sources, SourceSpec) else parse_sources(sources, suffix=sources_suffix, union=union)
    if not (isinstance(max_memory_mb, (int, float)) and np.isfinite(max_memory_mb) and max_memory_mb > 0):
        raise BatchError(f"max memory must be a positive number of MB, got {max_memory_mb!r}")
    if workers is not None and (not isinstance(workers, int) or workers < 0):
        raise BatchError(f"workers must be a non-negative integer, got {workers!r}")
    paths = find_inputs(inputs)
    output_dir = Path(output_dir)
    try:
        output_dir.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise BatchError(f"cannot create output folder {output_dir}: {exc.strerror or exc}") from exc
    clean_temporaries(output_dir)  # partial files of a killed run
    mesh_options, solver_options = dict(mesh_options or {}), dict(solver_options or {})
    keys = {}

    def key_of(path):  # None when the file cannot be read (its task says why)
        if path not in keys:
            try:
                keys[path] = result_key(path, spec, kind, mesh_options, solver_options)
            except OSError:
                keys[path] = None
        return keys[path]

    rows, todo, stale = {}, [], []
    for p in paths:
        out = output_path(output_dir, p)
        if out.is_file():
            match, reason, info = check_result(out, key_of(p) or "")
            if match:
                rows[p] = _result_row(p, info, "skipped")
                continue
            stale.append((p, out, reason))
        todo.append(MeshTask(str(p), str(output_dir), spec, float(max_memory_mb), kind, mesh_options, solver_options))
    if stale:
        listed = "; ".join(f"{out.name}: {reason}" for _, out, reason in stale[:5])
        listed += f"; and {len(stale) - 5} more" if len(stale) > 5 else ""
        if resume_only:
            raise BatchError(f"resume only: {len(stale)} existing result(s) in {output_dir} were not computed from "
                             f"these inputs ({listed}); run without --resume-only to recompute them, or write to "
                             f"another folder")
        log.warning("recomputing %d result(s) made from other inputs (%s)", len(stale), listed)
        for p, out, _ in stale:  # a stale result must not look finished if this run stops early
            discard_result(out, key_digest(key_of(p)) if key_of(p) else None)

    bar = _Progress(len(paths), progress)
    for row in rows.values():
        bar.update(row)
    results = None
    try:
        if scheduler is not None:
            results = run_dask(todo, scheduler, process_mesh)
        elif workers == 0 or len(todo) <= 1 and workers is None:
            results = ((t, process_mesh(t)) for t in todo)
        else:
            results = run_pool(todo, workers or os.cpu_count() or 1, process_mesh)
        for task, row in results:
            rows[Path(task.path)] = row
            bar.update(row)
    finally:
        if results is not None:
            results.close()  # early (Ctrl-C): cancels queued tasks and stops the pool's workers now
        for task in todo:  # a result written but not yet reported is on disk: list it
            p, out = Path(task.path), output_path(output_dir, task.path)
            if p not in rows:
                match, _, info = check_result(out, key_of(p) or "") if out.is_file() else (False, "", {})
                rows[p] = _result_row(p, info, "ok") if match else _result_row(p, {}, "interrupted")
        clean_temporaries(output_dir)
        bar.close()
        ordered = [rows[p] for p in paths if p in rows]
        write_summary(output_dir / SUMMARY_NAME, ordered)
    return ordered


def _result_row(path, info, status):
    error = "the batch stopped before this mesh was finished" if status == "interrupted" else ""
    return {"file": str(path), "vertices": info.get("vertices", ""), "sources": info.get("sources", ""),
            "seconds": "0.000" if status == "skipped" else "", "status": status, "error": error}
