"""Reading batch results back: the block layout, whether a result is complete and current, its rows.

A result is an index ``NAME.npz`` (sources, vertex count, key) holding its
distance rows (``distances``) or naming block files
``NAME.blocks/rows-START-STOP-DIGEST.npy`` (:func:`block_name`).
:func:`check_result` says whether a result is complete and was computed from
a given key; :func:`iter_blocks`, :func:`load_distances`, :func:`load_sources`
and :func:`load_key` read it. Writing is :mod:`heatcore.apps.batch.storage`.

Examples
--------
>>> import tempfile
>>> from heatcore.apps.batch.storage import write_index
>>> tmp = tempfile.TemporaryDirectory()
>>> out = Path(tmp.name) / "tri.npz"
>>> write_index(out, [0], 3, "0", "{}", distances=np.array([[0.0, 1.0, 1.0]]))
>>> check_result(out, "{}"), load_distances(out).tolist()
((True, '', {'vertices': 3, 'sources': 1}), [[0.0, 1.0, 1.0]])
>>> tmp.cleanup()
"""

from pathlib import Path

import numpy as np

from .keys import describe_difference


def block_name(start, stop, digest=None):
    """File name of the block holding rows ``start:stop`` of the result with key digest ``digest``.

    Examples
    --------
    >>> block_name(0, 16, "0123abcd"), block_name(16, 20)
    ('rows-000000000-000000016-0123abcd.npy', 'rows-000000016-000000020.npy')
    """
    return f"rows-{start:09d}-{stop:09d}" + (f"-{digest}" if digest else "") + ".npy"


def block_is_complete(path, rows, n):
    """Whether the block file ``path`` holds ``rows`` complete rows of ``n`` float64 distances.

    A block that cannot be read (missing, truncated, not ``.npy``) is not complete.

    Examples
    --------
    >>> import tempfile
    >>> tmp = tempfile.TemporaryDirectory()
    >>> block = Path(tmp.name) / block_name(0, 2)
    >>> np.save(block, np.zeros((2, 5)))
    >>> block_is_complete(block, 2, 5), block_is_complete(block, 3, 5), block_is_complete(block.with_suffix(".x"), 2, 5)
    (True, False, False)
    >>> tmp.cleanup()
    """
    try:
        block = np.load(path, mmap_mode="r")
    except (OSError, ValueError):
        return False
    return block.shape == (rows, n) and block.dtype == np.float64



def _block_paths(path, z):
    block_dir, starts = Path(path).parent / str(z["block_dir"]), z["block_starts"]
    digest = str(z["block_key"]) if "block_key" in z.files else None
    return [(int(a), int(b), block_dir / block_name(a, b, digest)) for a, b in zip(starts[:-1], starts[1:])]


def check_result(out, key):
    """Whether the result ``out`` is complete and was computed from ``key``.

    Returns
    -------
    (bool, str, dict)
        Match, the reason when not, and ``vertices`` / ``sources`` counts read
        from the index (empty when unreadable).

    Examples
    --------
    >>> check_result("no/such/result.npz", "{}")
    (False, 'no result', {})
    """
    out = Path(out)
    if not out.is_file():
        return False, "no result", {}
    try:
        with np.load(out) as z:
            info = {"vertices": int(z["n_vertices"]), "sources": int(z["sources"].size)}
            stored = str(z["key"]) if "key" in z.files else None
            blocks = [] if "distances" in z.files else _block_paths(out, z)
    except Exception as exc:  # noqa: BLE001 - any unreadable index is "not a result"
        return False, f"unreadable ({type(exc).__name__}: {exc})", {}
    if stored != key:
        return False, describe_difference(stored, key), info
    for a, b, path in blocks:
        if not block_is_complete(path, b - a, info["vertices"]):
            return False, f"block file {path.name} is missing or incomplete", info
    return True, "", info


def iter_blocks(path, mmap=True):
    """Yield ``(first_row, rows)`` blocks of a batch result, in order.

    Parameters
    ----------
    path : path-like
        A result index ``NAME.npz``.
    mmap : bool, default True
        Memory-map block files instead of reading them.

    Yields
    ------
    (int, (rows, n) array)
        The first row's number and the rows of one block (all rows at once
        when the index holds them).

    Examples
    --------
    >>> import tempfile
    >>> tmp = tempfile.TemporaryDirectory()
    >>> out = Path(tmp.name) / "tri.npz"
    >>> from heatcore.apps.batch.storage import write_index
    >>> write_index(out, [0, 1], 3, "0,1", "{}", distances=np.zeros((2, 3)))
    >>> [(start, rows.shape) for start, rows in iter_blocks(out)]
    [(0, (2, 3))]
    >>> tmp.cleanup()
    """
    path = Path(path)
    with np.load(path) as z:
        if "distances" in z.files:
            yield 0, z["distances"]
            return
        blocks = _block_paths(path, z)
    for a, _, block in blocks:
        yield a, np.load(block, mmap_mode="r" if mmap else None)


def load_distances(path):
    """All distance rows of a batch result as one ``(k, n)`` array (in memory: small results only).

    Examples
    --------
    >>> import tempfile
    >>> tmp = tempfile.TemporaryDirectory()
    >>> out = Path(tmp.name) / "tri.npz"
    >>> from heatcore.apps.batch.storage import write_index
    >>> write_index(out, [2], 3, "2", "{}", distances=np.array([[1.0, 1.0, 0.0]]))
    >>> load_distances(out)
    array([[1., 1., 0.]])
    >>> tmp.cleanup()
    """
    return np.concatenate([np.asarray(b) for _, b in iter_blocks(path, mmap=False)], axis=0)


def load_sources(path):
    """The source vertex of each row (or the union's sources) of a batch result.

    Examples
    --------
    >>> import tempfile
    >>> tmp = tempfile.TemporaryDirectory()
    >>> out = Path(tmp.name) / "tri.npz"
    >>> from heatcore.apps.batch.storage import write_index
    >>> write_index(out, [2, 0], 3, "2,0", "{}", distances=np.zeros((2, 3)))
    >>> load_sources(out)
    array([2, 0])
    >>> tmp.cleanup()
    """
    with np.load(path) as z:
        return z["sources"]


def load_key(path):
    """The key a result was computed from (JSON text; None for results of older versions).

    Examples
    --------
    >>> import tempfile
    >>> tmp = tempfile.TemporaryDirectory()
    >>> out = Path(tmp.name) / "tri.npz"
    >>> from heatcore.apps.batch.storage import write_index
    >>> write_index(out, [0], 3, "0", '{"format": 1}', distances=np.zeros((1, 3)))
    >>> load_key(out)
    '{"format": 1}'
    >>> tmp.cleanup()
    """
    with np.load(path) as z:
        return str(z["key"]) if "key" in z.files else None
