"""Keys of batch results: what a result was computed from, so that a rerun never reuses a stale one.

A key (:func:`result_key`) is canonical JSON of the SHA-256 of the mesh file's
bytes, the sources (with the bytes of a per-mesh sources file), the domain
kind, every mesh and solver option of the run's
:class:`~heatcore.settings.Settings` (:func:`key_options`: each option holds its
value or its default, so a new option is keyed without a change here), the
heatcore version and the key format. Two runs share a result only when their
keys are equal.

Examples
--------
>>> from heatcore.apps.batch import parse_sources
>>> from heatcore.io import demo_mesh_path
>>> key = result_key(demo_mesh_path(), parse_sources("0,17"))
>>> sorted(json.loads(key))
['format', 'heatcore', 'kind', 'mesh_options', 'mesh_sha256', 'solver_options', 'sources']
"""

import hashlib
import json
import numbers
import os
from pathlib import Path

import numpy as np

#: Version of the key layout; a new one makes every older result stale.
KEY_FORMAT = 1


def file_digest(path, chunk=1 << 20):
    """SHA-256 (hex) of a file's bytes.

    Examples
    --------
    >>> import tempfile
    >>> tmp = tempfile.TemporaryDirectory()
    >>> p = Path(tmp.name) / "f"
    >>> _ = p.write_bytes(b"abc")
    >>> file_digest(p)[:16]
    'ba7816bf8f01cfea'
    >>> tmp.cleanup()
    """
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(chunk), b""):
            h.update(block)
    return h.hexdigest()


def sources_file_path(mesh_path, suffix):
    """The sources file of a mesh: ``bunny.obj`` with suffix ``.sources.txt`` gives ``bunny.sources.txt``.

    Examples
    --------
    >>> sources_file_path("meshes/bunny.obj", ".sources.txt").as_posix()
    'meshes/bunny.sources.txt'
    """
    mesh_path = Path(mesh_path)
    return mesh_path.with_name(mesh_path.stem + suffix)


def key_options(settings):
    """The ``(mesh_options, solver_options)`` a key holds: every option of the settings' mesh and solver parts.

    Key format 1 was first read from the signatures of
    ``DomainFile.domain`` and ``HeatSolver``, so both groups also name
    ``progress`` (null); it stays, so that the results written since keep
    their keys. The solver's intent is not keyed (a batch reuses its solver).

    Parameters
    ----------
    settings : Settings
        The run's settings (``Settings.of("batch", ...)``).

    Examples
    --------
    >>> from heatcore.settings import Settings
    >>> mesh, solver = key_options(Settings.of("batch", m=2))
    >>> solver["m"], mesh["robust"], mesh["progress"]
    (2.0, True, None)
    """
    return ({**settings.mesh.keywords(), "progress": None}, {**settings.solver.keywords(), "progress": None})


def _plain(value):
    """A JSON value that is the same for equal options given as int, float or numpy scalar."""
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, numbers.Real):
        return float(value)
    if value is None or isinstance(value, str):
        return value
    if isinstance(value, (os.PathLike,)):
        return os.fspath(value)
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in sorted(value.items(), key=lambda kv: str(kv[0]))}
    if isinstance(value, (list, tuple, np.ndarray)):
        return [_plain(v) for v in value]
    return repr(value)


def result_key(mesh_path, spec, settings=None):
    """The key of a batch result: what it was computed from, as canonical JSON.

    Parameters
    ----------
    mesh_path : path-like
        The mesh file; its bytes are hashed (SHA-256).
    spec : heatcore.apps.batch.SourceSpec
        The sources; a per-mesh sources file is hashed too.
    settings : Settings, optional
        The run's settings (default: ``Settings.of("batch")``): how the file is
        read (``settings.domain``) and every mesh and solver option
        (:func:`key_options`).

    Returns
    -------
    str

    Examples
    --------
    >>> from heatcore.apps.batch import parse_sources
    >>> from heatcore.io import demo_mesh_path
    >>> from heatcore.settings import Settings
    >>> a = result_key(demo_mesh_path(), parse_sources("0"))
    >>> a == result_key(demo_mesh_path(), parse_sources("0"), Settings.of("batch", m=1))
    True
    >>> a == result_key(demo_mesh_path(), parse_sources("5"))
    False
    """
    from ... import __version__
    from ...settings import Settings

    settings = Settings.of("batch") if settings is None else settings
    mesh_options, solver_options = key_options(settings)
    sources = {"mode": spec.mode, "union": bool(spec.union)}
    if spec.mode == "indices":
        sources["indices"] = [int(i) for i in spec.indices]
    elif spec.mode == "farthest":
        sources["k"] = int(spec.k)
    elif spec.mode == "file":
        sfile = sources_file_path(mesh_path, spec.suffix)
        sources["suffix"] = spec.suffix
        sources["sha256"] = file_digest(sfile) if sfile.is_file() else None
    key = {
        "format": KEY_FORMAT,
        "heatcore": __version__,
        "mesh_sha256": file_digest(mesh_path),
        "sources": sources,
        "kind": settings.domain,
        "mesh_options": _plain(mesh_options),
        "solver_options": _plain(solver_options),
    }
    return json.dumps(key, sort_keys=True, separators=(",", ":"))


def key_digest(key):
    """Short hex digest of a key (names the block files of a result).

    Examples
    --------
    >>> len(key_digest('{"a":1}'))
    16
    """
    return hashlib.sha256(key.encode()).hexdigest()[:16]


def describe_difference(old, new):
    """Why stored key ``old`` does not match ``new``, in words.

    Examples
    --------
    >>> describe_difference('{"sources":{"mode":"indices","indices":[0]}}',
    ...                     '{"sources":{"mode":"indices","indices":[5,9]}}')
    'sources 0 -> 5,9'
    """
    if old is None:
        return "written without a result key (an older heatcore)"
    try:
        a, b = json.loads(old), json.loads(new)
    except ValueError:
        return "its result key is unreadable"
    reasons = []
    if a.get("mesh_sha256") != b.get("mesh_sha256"):
        reasons.append("the mesh file changed")
    if a.get("sources") != b.get("sources"):
        x, y = _sources_text(a.get("sources")), _sources_text(b.get("sources"))
        reasons.append(f"sources {x} -> {y}" if x != y else "the sources file changed")
    for group in ("mesh_options", "solver_options"):
        x, y = a.get(group) or {}, b.get(group) or {}
        for name in sorted(set(x) | set(y)):
            if x.get(name, "unset") != y.get(name, "unset"):
                reasons.append(f"{name} {x.get(name, 'unset')} -> {y.get(name, 'unset')}")
    for field in ("kind", "heatcore", "format"):
        if a.get(field) != b.get(field):
            reasons.append(f"{field} {a.get(field)} -> {b.get(field)}")
    return ", ".join(reasons) or "other inputs"


def _sources_text(sources):
    sources = sources or {}
    mode = sources.get("mode")
    if mode == "indices":
        text = ",".join(map(str, sources.get("indices", [])))
    elif mode == "farthest":
        text = f"farthest:{sources.get('k')}"
    elif mode == "file":
        text = f"file *{sources.get('suffix')}"
    else:
        text = str(mode)
    return text + (" (union)" if sources.get("union") else "")
