"""Storage of batch results: atomic writes, temporary files, block files, the index.

Every result a batch writes carries the key of what it was computed from
(:func:`heatcore.apps.batch.keys.result_key`): the ``NAME.npz`` index stores it
(``key``), and each block file of ``NAME.blocks/`` has its digest in its name
(``rows-START-STOP-DIGEST.npy``). A rerun reuses a result, or a block, only when
its key equals the new key exactly (:func:`heatcore.apps.batch.results.check_result`).
Reading results back is :mod:`heatcore.apps.batch.results` (re-exported here).

Files are written under a temporary name ``.NAME.tmp-PID-HOST-RANDOM`` and
renamed when complete (:func:`save_atomic`); :func:`clean_temporaries` removes
the ones whose writer is gone (a killed run).

Examples
--------
>>> import tempfile
>>> from pathlib import Path
>>> tmp = tempfile.TemporaryDirectory()
>>> folder = Path(tmp.name)
>>> save_atomic(folder / "a.txt", lambda fh: fh.write(b"done"))
>>> sorted(p.name for p in folder.iterdir())
['a.txt']
>>> tmp.cleanup()
"""

import csv
import hashlib
import io
import os
import re
import socket
import time
import uuid
from pathlib import Path

import numpy as np

from .keys import (  # noqa: F401 - re-exported
    describe_difference,
    file_digest,
    key_digest,
    key_options,
    result_key,
    sources_file_path,
)
from .processes import pid_alive  # also re-exported: storage.pid_alive
from .results import (  # noqa: F401 - re-exported: reading results back
    block_is_complete,
    block_name,
    check_result,
    iter_blocks,
    load_distances,
    load_key,
    load_sources,
)

SUMMARY_NAME = "summary.csv"
SUMMARY_FIELDS = ("file", "vertices", "sources", "seconds", "status", "error")
#: Temporary files older than this (seconds) are removed whoever wrote them.
STALE_TEMPORARY_SECONDS = 24 * 3600
_HOST = hashlib.sha1(socket.gethostname().encode()).hexdigest()[:8]
# .NAME.tmp-PID-HOST-RANDOM (HOST absent in files of heatcore 0.1.0)
_TEMPORARY = re.compile(r"^\.(?P<name>.+)\.tmp-(?P<pid>\d+)-(?:(?P<host>[0-9a-f]{8})-)?(?P<rand>[0-9a-f]{8})$")


# --------------------------------------------------------------------------- atomic writes


def temporary_path(path):
    """The temporary name a file is written under before it is renamed to ``path``.

    Examples
    --------
    >>> is_temporary(temporary_path("out/spot.npz"))
    True
    """
    path = Path(path)
    return path.with_name(f".{path.name}.tmp-{os.getpid()}-{_HOST}-{uuid.uuid4().hex[:8]}")


def is_temporary(path):
    """Whether ``path`` is a temporary file name of :func:`temporary_path` (of any process).

    Examples
    --------
    >>> is_temporary("out/.spot.npz.tmp-123-abcdef12"), is_temporary("out/spot.npz")
    (True, False)
    """
    return _TEMPORARY.match(Path(path).name) is not None


def save_atomic(path, save):
    """Call ``save(file_object)`` on a temporary file next to ``path``, then rename it to ``path``.

    A reader never sees a partial ``path``; if ``save`` fails the temporary
    file is removed (a killed process leaves it: see :func:`clean_temporaries`).

    Examples
    --------
    >>> import tempfile
    >>> tmp = tempfile.TemporaryDirectory()
    >>> target = Path(tmp.name) / "x.bin"
    >>> save_atomic(target, lambda fh: fh.write(b"abc"))
    >>> target.read_bytes()
    b'abc'
    >>> tmp.cleanup()
    """
    tmp = temporary_path(path)
    try:
        with open(tmp, "wb") as fh:
            save(fh)
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()


def clean_temporaries(folder, max_age=STALE_TEMPORARY_SECONDS):
    """Remove temporary files of writers that are gone, in ``folder`` and its ``*.blocks`` folders.

    A temporary file is removed when its writer ran on this machine and no
    longer runs, or when it is older than ``max_age`` seconds (a writer on
    another machine of a Dask cluster). Files of live writers are left alone;
    readers ignore temporary files in any case.

    Returns
    -------
    list of Path
        The files removed.

    Examples
    --------
    >>> import subprocess, sys, tempfile
    >>> tmp = tempfile.TemporaryDirectory()
    >>> folder = Path(tmp.name)
    >>> dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
    ...                       capture_output=True, text=True).stdout.strip()
    >>> _ = (folder / f".a.npz.tmp-{dead}-abcdef12").write_bytes(b"partial")
    >>> _ = (folder / f".b.npz.tmp-{os.getpid()}-abcdef12").write_bytes(b"being written")
    >>> [p.name for p in clean_temporaries(folder)] == [f".a.npz.tmp-{dead}-abcdef12"]
    True
    >>> tmp.cleanup()
    """
    folder = Path(folder)
    if not folder.is_dir():
        return []
    candidates = list(folder.glob(".*.tmp-*"))
    for blocks in folder.glob("*.blocks"):
        candidates += blocks.glob(".*.tmp-*")
    removed = []
    now = time.time()
    for path in candidates:
        match = _TEMPORARY.match(path.name)
        if match is None:
            continue
        pid, host = int(match["pid"]), match["host"]
        try:
            old = now - path.stat().st_mtime > max_age
        except OSError:
            continue
        local = host is None or host == _HOST
        if old or (local and pid != os.getpid() and not pid_alive(pid)):
            try:
                path.unlink()
                removed.append(path)
            except OSError:
                pass
    return sorted(removed)


# --------------------------------------------------------------------------- blocks and index


def discard_blocks(block_dir, keep=()):
    """Remove the block files of ``block_dir`` not named in ``keep`` (and the folder once empty).

    Examples
    --------
    >>> import tempfile
    >>> tmp = tempfile.TemporaryDirectory()
    >>> blocks = Path(tmp.name) / "mesh.blocks"
    >>> blocks.mkdir()
    >>> for name in (block_name(0, 2, "aa"), block_name(0, 2, "bb")):
    ...     np.save(blocks / name, np.zeros((2, 3)))
    >>> discard_blocks(blocks, keep={block_name(0, 2, "aa")})
    >>> [p.name for p in blocks.iterdir()]
    ['rows-000000000-000000002-aa.npy']
    >>> discard_blocks(blocks)
    >>> blocks.exists()
    False
    >>> tmp.cleanup()
    """
    block_dir = Path(block_dir)
    if not block_dir.is_dir():
        return
    for stale in block_dir.glob("rows-*.npy"):
        if stale.name not in keep:
            stale.unlink(missing_ok=True)
    try:
        block_dir.rmdir()
    except OSError:
        pass  # not empty: blocks being kept, or a live writer's temporary file


class BlockWriter:
    """Collect distance rows; one in-memory array if they all fit, else one ``.npy`` per block.

    The block buffer holds at most ``rows_per_block`` rows (the memory bound).
    Block files are written atomically as they fill and are named by the
    result's key digest; with known sources a rerun with the same key reuses
    complete block files of the same layout (resume inside a mesh).

    Parameters
    ----------
    out : path-like
        The result index ``NAME.npz``; block files go to ``NAME.blocks/``.
    n : int
        Distances per row (the mesh's vertices).
    rows_per_block : int
        Rows held at once (:func:`heatcore.apps.batch.task.block_rows`).
    total : int or None
        Rows to come, when known (not for ``farthest:K``, which may stop early).
    key : str
        The result's key (:func:`heatcore.apps.batch.keys.result_key`).

    Examples
    --------
    Three rows, two per block: two block files, then the index.

    >>> import tempfile
    >>> tmp = tempfile.TemporaryDirectory()
    >>> out = Path(tmp.name) / "grid.npz"
    >>> writer = BlockWriter(out, 4, rows_per_block=2, total=3, key='{"demo": 1}')
    >>> for value in (0.0, 1.0, 2.0):
    ...     writer.add(np.full(4, value))
    >>> writer.finish([5, 6, 7], "5,6,7")
    >>> [(start, rows.shape) for start, rows in iter_blocks(out)]
    [(0, (2, 4)), (2, (1, 4))]
    >>> check_result(out, '{"demo": 1}')
    (True, '', {'vertices': 4, 'sources': 3})
    >>> tmp.cleanup()
    """

    def __init__(self, out, n, rows_per_block, total, key):
        self.out, self.n, self.rows_per_block, self.total = Path(out), n, rows_per_block, total
        self.key, self.digest = key, key_digest(key)
        self.single = total is not None and total <= rows_per_block
        self.block_dir = self.out.with_suffix(".blocks")
        self.buffer = np.empty((min(rows_per_block, total) if total else rows_per_block, n))
        self.filled = 0  # rows in the buffer
        self.start = 0  # row number of the buffer's first row
        self.starts = [0]

    def _path(self, start, stop):
        return self.block_dir / block_name(start, stop, self.digest)

    def rows_done(self):
        """Row numbers held by complete block files of this key and layout from an interrupted run."""
        if self.single or self.total is None or not self.block_dir.is_dir():
            return set()
        done = set()
        for start in range(0, self.total, self.rows_per_block):
            stop = min(start + self.rows_per_block, self.total)
            if block_is_complete(self._path(start, stop), stop - start, self.n):
                done.update(range(start, stop))
        return done

    def add(self, row):
        """Append one row (``None``: a row of a block file that is kept)."""
        if self.filled == 0 and not self.single:
            self.block_dir.mkdir(exist_ok=True)
        if row is not None:
            self.buffer[self.filled] = row
        self.filled += 1
        if not self.single and self.filled == self.rows_per_block:
            self._flush()

    def _flush(self):
        stop = self.start + self.filled
        name = self._path(self.start, stop)
        if not block_is_complete(name, self.filled, self.n):  # a complete block of this key is kept
            block = self.buffer[: self.filled]
            save_atomic(name, lambda fh: np.save(fh, block))
        self.start = stop
        self.starts.append(stop)
        self.filled = 0

    def finish(self, sources, spec):
        """Write the index (last), then remove block files of other keys or layouts."""
        if self.single:
            write_index(self.out, sources, self.n, spec, self.key, distances=self.buffer[: self.filled])
            discard_blocks(self.block_dir)
            return
        if self.filled:
            self._flush()
        write_index(self.out, sources, self.n, spec, self.key, block_dir=self.block_dir.name,
                    block_starts=np.asarray(self.starts, np.int64), block_key=np.str_(self.digest))
        discard_blocks(self.block_dir, {self._path(a, b).name for a, b in zip(self.starts[:-1], self.starts[1:])})


def write_index(out, sources, n, spec, key, **arrays):
    """Write the result index ``out`` (``.npz``) atomically, with its key.

    Parameters
    ----------
    out : path-like
        The index ``NAME.npz``.
    sources : sequence of int
        The source vertex of each row (or the union's sources).
    n : int
        Vertices of the mesh.
    spec : SourceSpec or str
        The source specification, stored as text.
    key : str
        What the result was computed from (:func:`heatcore.apps.batch.keys.result_key`).
    **arrays
        ``distances=`` (rows in the index) or ``block_dir=``, ``block_starts=``,
        ``block_key=`` (rows in block files).

    Examples
    --------
    >>> import tempfile
    >>> tmp = tempfile.TemporaryDirectory()
    >>> out = Path(tmp.name) / "tri.npz"
    >>> write_index(out, [0], 3, "0", "{}", distances=np.array([[0.0, 1.0, 1.0]]))
    >>> load_sources(out), load_distances(out)
    (array([0]), array([[0., 1., 1.]]))
    >>> tmp.cleanup()
    """
    from ... import __version__

    payload = {"sources": np.asarray(sources, np.int64), "n_vertices": np.int64(n), "spec": np.str_(str(spec)),
               "key": np.str_(key), "heatcore_version": np.str_(__version__)}
    payload.update(arrays)
    save_atomic(out, lambda fh: np.savez_compressed(fh, **payload))


def discard_result(out, keep_digest=None):
    """Remove a stale result: its index, and its block files except those of key digest ``keep_digest``.

    Examples
    --------
    >>> import tempfile
    >>> tmp = tempfile.TemporaryDirectory()
    >>> out = Path(tmp.name) / "tri.npz"
    >>> write_index(out, [0], 3, "0", "{}", distances=np.zeros((1, 3)))
    >>> discard_result(out)
    >>> out.exists()
    False
    >>> tmp.cleanup()
    """
    out = Path(out)
    out.unlink(missing_ok=True)
    block_dir = out.with_suffix(".blocks")
    if block_dir.is_dir():
        keep = {p.name for p in block_dir.glob(f"rows-*-{keep_digest}.npy")} if keep_digest else set()
        discard_blocks(block_dir, keep)


def write_summary(path, rows):
    """Write the summary rows as CSV (atomically).

    Examples
    --------
    >>> import tempfile
    >>> tmp = tempfile.TemporaryDirectory()
    >>> p = Path(tmp.name) / SUMMARY_NAME
    >>> write_summary(p, [{"file": "a.obj", "status": "ok"}])
    >>> p.read_text().splitlines()[1]
    'a.obj,,,,ok,'
    >>> tmp.cleanup()
    """
    text = io.StringIO()
    writer = csv.DictWriter(text, fieldnames=SUMMARY_FIELDS, lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    data = text.getvalue().encode()
    save_atomic(path, lambda fh: fh.write(data))
