"""The batch: every mesh file of the inputs, skipped, computed or refused by its result key, on a runner.

:func:`run_batch` finds the mesh files, checks each existing result's key
(:mod:`heatcore.apps.batch.keys`: reused only when it equals this run's),
sends one task per mesh (:func:`heatcore.apps.batch.task.process_mesh`) to a
runner (:mod:`heatcore.apps.batch.runners`: this process, a local process
pool or a Dask cluster), shows progress on one stderr line and writes
``summary.csv`` (also after Ctrl-C, listing exactly what is on disk).
An example runs in :func:`run_batch`'s docstring.
"""

import logging
import os
import sys
import time
from pathlib import Path

import numpy as np

from ...errors import InvalidOptionError
from ...settings import Settings
from .keys import key_digest, result_key
from .runners import run_dask, run_pool
from .spec import (
    DEFAULT_MAX_MEMORY_MB,
    BatchError,
    MeshTask,
    SourceSpec,
    find_inputs,
    output_path,
    parse_sources,
)
from .storage import (
    SUMMARY_NAME,
    check_result,
    clean_temporaries,
    discard_result,
    write_summary,
)
from .task import process_mesh

log = logging.getLogger("heatcore.apps.batch")


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
    seconds = round(seconds)
    h, rest = divmod(seconds, 3600)
    return f"{h}:{rest // 60:02d}:{rest % 60:02d}" if h else f"{rest // 60}:{rest % 60:02d}"


def run_batch(inputs, output_dir, sources=None, *, sources_suffix=None, union=False, scheduler=None,
              workers=None, max_memory_mb=DEFAULT_MAX_MEMORY_MB, settings=None, kind="auto", mesh_options=None,
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
    settings : Settings, optional
        The run's settings, ``Settings.of("batch", ...)``: how to read files
        (``domain``), the domain's options and the solver's
        (:mod:`heatcore.settings`); every task takes them as they are.
    kind : str, default "auto"
        Without ``settings``: how to read files (see :func:`heatcore.io.domain.read_domain`).
    mesh_options, solver_options : dict, optional
        Without ``settings``: options of the domain (``robust``, ``refine``) and of
        :class:`~heatcore.HeatSolver` (``m``, ``boundary``, ``accuracy``,
        ``backend``), made one ``Settings.of("batch", ...)`` with ``kind``.
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
    InvalidOptionError
        A bad option value, or options given both in ``settings`` and as keywords.
    KeyboardInterrupt
        Re-raised after Ctrl-C, once queued work is cancelled, the pool's
        workers are stopped and ``summary.csv`` lists what is on disk (meshes
        not finished have status ``interrupted``).

    Examples
    --------
    Two sources on the bundled mesh, in this process; a rerun with the same
    inputs finds the result and skips it:

    >>> import tempfile
    >>> from heatcore.io import demo_mesh_path
    >>> from heatcore.apps.batch import load_distances
    >>> tmp = tempfile.TemporaryDirectory()
    >>> rows = run_batch([demo_mesh_path()], tmp.name, "0,17", workers=0, progress=False)
    >>> rows[0]["status"], rows[0]["sources"], load_distances(output_path(tmp.name, "spot.obj")).shape
    ('ok', 2, (2, 2930))
    >>> run_batch([demo_mesh_path()], tmp.name, "0,17", workers=0, progress=False)[0]["status"]
    'skipped'
    >>> sorted(p.name for p in Path(tmp.name).iterdir())
    ['spot.npz', 'summary.csv']
    >>> tmp.cleanup()
    """
    spec = sources if isinstance(sources, SourceSpec) else parse_sources(sources, suffix=sources_suffix, union=union)
    if not (isinstance(max_memory_mb, (int, float)) and np.isfinite(max_memory_mb) and max_memory_mb > 0):
        raise BatchError(f"max memory must be a positive number of MB, got {max_memory_mb!r}")
    if workers is not None and (not isinstance(workers, int) or workers < 0):
        raise BatchError(f"workers must be a non-negative integer, got {workers!r}")
    settings = _settings(settings, kind, mesh_options, solver_options)  # checked once, before any work
    paths = find_inputs(inputs)
    output_dir = Path(output_dir)
    try:
        output_dir.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise BatchError(f"cannot create output folder {output_dir}: {exc.strerror or exc}") from exc
    clean_temporaries(output_dir)  # partial files of a killed run
    keys = {}

    def key_of(path):  # None when the file cannot be read (its task says why)
        if path not in keys:
            try:
                keys[path] = result_key(path, spec, settings)
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
        todo.append(MeshTask(str(p), str(output_dir), spec, float(max_memory_mb), settings))
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


def _settings(settings, kind, mesh_options, solver_options):
    """The run's :class:`~heatcore.settings.Settings`: ``settings``, or one built of the option keywords."""
    keywords = {**(mesh_options or {}), **(solver_options or {}), **({"domain": kind} if kind != "auto" else {})}
    if settings is None:
        return Settings.of("batch", **keywords)
    if keywords:
        raise InvalidOptionError(f"give the options in settings or as keywords, not both ({', '.join(keywords)})")
    return settings


def _result_row(path, info, status):
    error = "the batch stopped before this mesh was finished" if status == "interrupted" else ""
    return {"file": str(path), "vertices": info.get("vertices", ""), "sources": info.get("sources", ""),
            "seconds": "0.000" if status == "skipped" else "", "status": status, "error": error}
