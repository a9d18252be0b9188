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
    ``sources`` (k,) int64, ``n_vertices``, ``spec`` and, when the ``k x n``
    rows fit in the memory bound, ``distances`` (k, n) float64 (``inf`` where
    unreachable). Otherwise the rows are in ``NAME.blocks/rows-START-STOP.npy``
    (one ``.npy`` per block, never all in memory) and the index holds
    ``block_dir`` and ``block_starts``; :func:`iter_blocks` and
    :func:`load_distances` read either layout.
``summary.csv``
    ``file, vertices, sources, seconds, status, error`` with status ``ok``,
    ``error`` (the mesh could not be processed; the message says why) or
    ``skipped`` (its output already existed: reruns resume).

Every file is written under a temporary name and renamed when complete, and
the ``.npz`` index is written last, so a file that looks finished is finished.

Examples
--------
>>> import tempfile
>>> from heatcore.io import demo_mesh_path
>>> out = tempfile.mkdtemp()
>>> rows = run_batch([demo_mesh_path()], out, "0,17", workers=0, progress=False)
>>> rows[0]["status"], load_distances(output_path(out, demo_mesh_path())).shape
('ok', (2, 2930))
"""

import csv
import os
import re
import sys
import time
import traceback
import uuid
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass, field
from glob import glob
from pathlib import Path

import numpy as np

from .errors import HeatcoreError, InvalidOptionError, InvalidSourceError

#: Extensions a folder input picks up (what :func:`heatcore.domain_io.read_domain` reads).
MESH_SUFFIXES = (".ply", ".obj", ".off", ".stl", ".glb", ".gltf", ".msh", ".vtu", ".vtk", ".mesh", ".xyz")
SUMMARY_NAME = "summary.csv"
SUMMARY_FIELDS = ("file", "vertices", "sources", "seconds", "status", "error")
DEFAULT_MAX_MEMORY_MB = 1024.0
_BYTES_PER_VALUE = 8  # float64 distances


class BatchError(HeatcoreError):
    """A batch cannot start: bad inputs, source specification or options."""


# --------------------------------------------------------------------------- specification


@dataclass(frozen=True)
class SourceSpec:
    """Which sources to use on every mesh of a batch.

    Attributes
    ----------
    mode : {"indices", "all", "farthest", "file"}
    indices : tuple of int
        Vertex indices (mode "indices").
    k : int
        Number of samples (mode "farthest").
    suffix : str
        Sources file suffix replacing the mesh extension (mode "file").
    union : bool
        One distance row to the union of the sources instead of one row per source
        (modes "indices" and "file").
    """

    mode: str
    indices: tuple = ()
    k: int = 0
    suffix: str = ""
    union: bool = False

    def __str__(self):
        if self.mode == "indices":
            text = ",".join(map(str, self.indices))
        elif self.mode == "farthest":
            text = f"farthest:{self.k}"
        elif self.mode == "file":
            text = f"file:{self.suffix}"
        else:
            text = self.mode
        return text + (" (union)" if self.union else "")


def parse_sources(text=None, *, suffix=None, union=False):
    """Parse a source specification.

    Parameters
    ----------
    text : str, optional
        ``"0,17"`` (vertex indices), ``"all"`` or ``"farthest:K"``.
    suffix : str, optional
        Per-mesh sources file suffix (``".sources.txt"``): ``mesh.obj`` reads
        ``mesh.sources.txt``. Give either ``text`` or ``suffix``.
    union : bool, default False
        One row: the distance to the union of the sources.

    Returns
    -------
    SourceSpec

    Raises
    ------
    BatchError
        Unreadable specification, or both/neither of ``text`` and ``suffix``.

    Examples
    --------
    >>> parse_sources("farthest:8").k
    8
    >>> parse_sources("0, 17").indices
    (0, 17)
    """
    if (text is None) == (suffix is None):
        raise BatchError("give exactly one source specification: --sources (indices, 'all', 'farthest:K') "
                         "or --sources-file-suffix")
    if suffix is not None:
        if not suffix or "/" in suffix or os.sep in suffix:
            raise BatchError(f"sources file suffix must be a file name ending such as '.sources.txt', got {suffix!r}")
        return SourceSpec("file", suffix=suffix, union=union)
    text = text.strip()
    if text.lower() == "all":
        if union:
            raise BatchError("--union with 'all' would pin every vertex: use vertex indices or a sources file")
        return SourceSpec("all")
    match = re.fullmatch(r"farthest:(\d+)", text, flags=re.IGNORECASE)
    if match:
        k = int(match.group(1))
        if k < 1:
            raise BatchError("farthest:K needs K >= 1")
        if union:
            raise BatchError("--union does not apply to farthest:K")
        return SourceSpec("farthest", k=k)
    try:
        indices = tuple(int(tok) for tok in text.replace(",", " ").split())
    except ValueError:
        raise BatchError(f"cannot read sources {text!r}: give vertex indices ('0,17'), 'all' or 'farthest:K'") from None
    if not indices:
        raise BatchError("no sources given")
    if min(indices) < 0:
        raise BatchError(f"source vertex {min(indices)} is negative: vertex indices are 0-based")
    return SourceSpec("indices", indices=tuple(dict.fromkeys(indices)), union=union)


@dataclass(frozen=True)
class MeshTask:
    """Everything one worker needs for one mesh (picklable)."""

    path: str
    output_dir: str
    spec: SourceSpec
    max_memory_mb: float = DEFAULT_MAX_MEMORY_MB
    kind: str = "auto"
    mesh_options: dict = field(default_factory=dict)
    solver_options: dict = field(default_factory=dict)


# --------------------------------------------------------------------------- paths


def find_inputs(inputs):
    """Mesh files from folders, glob patterns and file paths, sorted and unique.

    Folders contribute their files with a mesh extension (:data:`MESH_SUFFIXES`,
    not recursive); patterns are expanded with :func:`glob.glob` (``**``
    allowed).

    Raises
    ------
    BatchError
        An input matches nothing, or two inputs would write the same output name.
    """
    if isinstance(inputs, (str, os.PathLike)):
        inputs = [inputs]
    found = []
    for item in inputs:
        path = Path(item)
        if path.is_dir():
            found += [p for p in sorted(path.iterdir()) if p.is_file() and p.suffix.lower() in MESH_SUFFIXES]
        elif path.is_file():
            found.append(path)
        else:
            matches = [Path(p) for p in sorted(glob(str(item), recursive=True)) if Path(p).is_file()]
            if not matches:
                raise BatchError(f"input {item}: no such file or folder, and no file matches it as a pattern")
            found += matches
    unique = list(dict.fromkeys(p.resolve() for p in found))
    if not unique:
        raise BatchError(f"no mesh files ({', '.join(MESH_SUFFIXES)}) in {', '.join(map(str, inputs))}")
    names = {}
    for p in unique:
        other = names.setdefault(p.stem, p)
        if other != p:
            raise BatchError(f"{other} and {p} would both write {p.stem}.npz: rename one or run them separately")
    return unique


def output_path(output_dir, mesh_path):
    """The result index ``OUTPUT_DIR/NAME.npz`` of mesh ``NAME.EXT``."""
    return Path(output_dir) / f"{Path(mesh_path).stem}.npz"


def sources_file_path(mesh_path, suffix):
    """The sources file of a mesh: ``bunny.obj`` with suffix ``.sources.txt`` gives ``bunny.sources.txt``."""
    mesh_path = Path(mesh_path)
    return mesh_path.with_name(mesh_path.stem + suffix)


def _temporary(path):
    path = Path(path)
    return path.with_name(f".{path.name}.tmp-{os.getpid()}-{uuid.uuid4().hex[:8]}")


def _save_atomic(path, save):
    """Call ``save(file_object)`` on a temporary file next to ``path``, then rename it to ``path``."""
    tmp = _temporary(path)
    try:
        with open(tmp, "wb") as fh:
            save(fh)
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()


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
        row["error"] = _message(exc)
    finally:
        quiet.setLevel(level)
    row["seconds"] = f"{time.perf_counter() - start:.3f}"
    return row


def _message(exc):
    if isinstance(exc, HeatcoreError):
        return str(exc)
    frame = traceback.extract_tb(exc.__traceback__)[-1] if exc.__traceback__ else None
    where = f" (at {Path(frame.filename).name}:{frame.lineno})" if frame else ""
    return f"{type(exc).__name__}: {exc}{where}"


def _process(task):
    from .cli import read_mesh_file, read_sources_file
    from .heat import HeatSolver

    spec = task.spec
    out = output_path(task.output_dir, task.path)
    mesh = read_mesh_file(task.path, task.kind)
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
        _write_index(out, sources, n, spec, distances=distances)
        return {"vertices": n, "sources": int(sources.size)}

    writer = _BlockWriter(out, n, rows_per_block, total=spec.k if sources is None else sources.size)
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


class _BlockWriter:
    """Collect distance rows; one in-memory array if they all fit, else one ``.npy`` per block.

    The block buffer holds at most ``rows_per_block`` rows (the memory bound).
    Block files are written atomically as they fill; with known sources a
    rerun reuses complete block files of the same layout (resume inside a mesh).
    """

    def __init__(self, out, n, rows_per_block, total):
        self.out, self.n, self.rows_per_block, self.total = Path(out), n, rows_per_block, total
        self.single = total is not None and total <= rows_per_block
        self.block_dir = self.out.with_suffix(".blocks")
        self.buffer = np.empty((min(rows_per_block, total) if total else rows_per_block, n))
        self.filled = 0  # rows in the buffer
        self.start = 0  # row number of the buffer's first row
        self.starts = [0]
        self.skip_block = False

    def _block_name(self, start, stop):
        return self.block_dir / f"rows-{start:09d}-{stop:09d}.npy"

    def _planned_stop(self, start):
        return start + self.rows_per_block if self.total is None else min(start + self.rows_per_block, self.total)

    def rows_done(self):
        """Row numbers held by complete block files of this layout from an earlier, interrupted run."""
        if self.single or self.total is None or not self.block_dir.is_dir():
            return set()
        done = set()
        for start in range(0, self.total, self.rows_per_block):
            stop = self._planned_stop(start)
            if self._block_name(start, stop).is_file():
                done.update(range(start, stop))
        return done

    def add(self, row):
        if self.filled == 0 and not self.single:
            self.block_dir.mkdir(exist_ok=True)
        if row is not None:
            self.buffer[self.filled] = row
        self.filled += 1
        if not self.single and self.filled == self.rows_per_block:
            self._flush()

    def _flush(self):
        stop = self.start + self.filled
        name = self._block_name(self.start, stop)
        if not name.is_file():  # a complete block file from an interrupted run is kept
            block = self.buffer[: self.filled]
            _save_atomic(name, lambda fh: np.save(fh, block))
        self.start = stop
        self.starts.append(stop)
        self.filled = 0

    def finish(self, sources, spec):
        if self.single:
            _write_index(self.out, sources, self.n, spec, distances=self.buffer[: self.filled])
            return
        if self.filled:
            self._flush()
        keep = {self._block_name(a, b).name for a, b in zip(self.starts[:-1], self.starts[1:])}
        for stale in self.block_dir.glob("rows-*.npy"):  # other layouts (another memory bound)
            if stale.name not in keep:
                stale.unlink()
        _write_index(self.out, sources, self.n, spec, block_dir=self.block_dir.name,
                     block_starts=np.asarray(self.starts, np.int64))


def _write_index(out, sources, n, spec, **arrays):
    payload = {"sources": np.asarray(sources, np.int64), "n_vertices": np.int64(n), "spec": np.str_(str(spec))}
    payload.update(arrays)
    _save_atomic(out, lambda fh: np.savez_compressed(fh, **payload))


# --------------------------------------------------------------------------- reading results


def iter_blocks(path, mmap=True):
    """Yield ``(first_row, rows)`` blocks of a batch result, in order.

    Parameters
    ----------
    path : path-like
        A result index ``NAME.npz``.
    mmap : bool, default True
        Memory-map block files instead of reading them.
    """
    path = Path(path)
    with np.load(path) as z:
        if "distances" in z.files:
            yield 0, z["distances"]
            return
        block_dir, starts = path.parent / str(z["block_dir"]), z["block_starts"]
    for a, b in zip(starts[:-1], starts[1:]):
        yield int(a), np.load(block_dir / f"rows-{a:09d}-{b:09d}.npy", mmap_mode="r" if mmap else None)


def load_distances(path):
    """All distance rows of a batch result as one ``(k, n)`` array (in memory: small results only)."""
    return np.concatenate([np.asarray(b) for _, b in iter_blocks(path, mmap=False)], axis=0)


def load_sources(path):
    """The source vertex of each row (or the union's sources) of a batch result."""
    with np.load(path) as z:
        return z["sources"]


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


def _skipped_row(path, out):
    row = {"file": str(path), "vertices": "", "sources": "", "seconds": "0.000", "status": "skipped", "error": ""}
    try:
        with np.load(out) as z:
            row["vertices"], row["sources"] = int(z["n_vertices"]), int(z["sources"].size)
    except Exception as exc:  # noqa: BLE001 - an unreadable old result is reported, not fatal
        row["error"] = f"existing output {out.name} is unreadable ({exc}); delete it to recompute"
    return row


def write_summary(path, rows):
    """Write the summary rows as CSV (atomically)."""
    import io

    text = io.StringIO()
    writer = csv.DictWriter(text, fieldnames=SUMMARY_FIELDS, lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    data = text.getvalue().encode()
    _save_atomic(path, lambda fh: fh.write(data))


def run_batch(inputs, output_dir, sources=None, *, sources_suffix=None, union=False, scheduler=None,
              workers=None, max_memory_mb=DEFAULT_MAX_MEMORY_MB, kind="auto", mesh_options=None,
              solver_options=None, progress=True):
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
        How to read files (see :func:`heatcore.domain_io.read_domain`).
    mesh_options, solver_options : dict, optional
        Keywords of the domain (``robust``, ``refine``) and of
        :class:`~heatcore.HeatSolver` (``m``, ``boundary``, ``accuracy``).
    progress : bool, default True
        Progress line with counts and ETA on stderr.

    Returns
    -------
    list of dict
        The rows of ``summary.csv`` in input order.
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

    rows = {}
    todo = []
    for p in paths:
        out = output_path(output_dir, p)
        if out.is_file():
            rows[p] = _skipped_row(p, out)
        else:
            todo.append(MeshTask(str(p), str(output_dir), spec, float(max_memory_mb), kind,
                                 dict(mesh_options or {}), dict(solver_options or {})))
    bar = _Progress(len(paths), progress)
    for row in rows.values():
        bar.update(row)
    try:
        if scheduler is not None:
            results = _run_dask(todo, scheduler)
        elif workers == 0 or len(todo) <= 1 and workers is None:
            results = ((t, process_mesh(t)) for t in todo)
        else:
            results = _run_pool(todo, workers or os.cpu_count() or 1)
        for task, row in results:
            rows[Path(task.path)] = row
            bar.update(row)
    finally:
        bar.close()
        ordered = [rows[p] for p in paths if p in rows]
        write_summary(output_dir / SUMMARY_NAME, ordered)
    return ordered


def _crash_row(task, exc):
    return {"file": task.path, "vertices": "", "sources": "", "seconds": "", "status": "error",
            "error": f"worker failed: {_message(exc)}"}


def _run_pool(tasks, workers):
    with ProcessPoolExecutor(max_workers=min(workers, max(len(tasks), 1))) as pool:
        futures = {pool.submit(process_mesh, t): t for t in tasks}
        for fut in as_completed(futures):
            task = futures[fut]
            try:
                yield task, fut.result()
            except Exception as exc:  # noqa: BLE001 - a crashed worker (e.g. killed) fails its mesh only
                yield task, _crash_row(task, exc)


def _run_dask(tasks, scheduler):
    try:
        from distributed import Client, as_completed as dask_completed
    except ImportError:
        raise InvalidOptionError(
            "--scheduler needs dask.distributed: pip install 'heatcore[batch]' (or 'dask[distributed]')"
        ) from None
    own = not isinstance(scheduler, Client)
    try:
        client = Client(scheduler, timeout="30s") if own else scheduler
    except (OSError, TimeoutError) as exc:
        raise BatchError(f"cannot connect to the Dask scheduler at {scheduler}: {exc}") from exc
    try:
        # One task per mesh: its factorization is built and used on the worker that runs it.
        futures = client.map(process_mesh, tasks, pure=False, key=[f"heatcore-batch-{Path(t.path).name}-{uuid.uuid4().hex[:8]}" for t in tasks])
        by_key = {f.key: t for f, t in zip(futures, tasks)}
        for fut in dask_completed(futures):
            task = by_key[fut.key]
            try:
                yield task, fut.result()
            except Exception as exc:  # noqa: BLE001 - a lost worker fails its mesh only
                yield task, _crash_row(task, exc)
            fut.release()
    finally:
        if own:
            client.close()
