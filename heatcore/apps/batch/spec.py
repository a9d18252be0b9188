"""What a batch runs: the source specification, the mesh files, one task per mesh.

Examples
--------
>>> parse_sources("farthest:8")
SourceSpec(mode='farthest', indices=(), k=8, suffix='', union=False)
>>> str(parse_sources("0, 17", union=True))
'0,17 (union)'
"""

import os
import re
from dataclasses import dataclass, field
from glob import glob
from pathlib import Path

from ...errors import HeatcoreError
from ...settings import Settings

#: Extensions a folder input picks up (what :func:`heatcore.io.domain.read_domain` reads).
MESH_SUFFIXES = (".ply", ".obj", ".off", ".stl", ".glb", ".gltf", ".msh", ".vtu", ".vtk", ".mesh", ".xyz")
DEFAULT_MAX_MEMORY_MB = 1024.0


class BatchError(HeatcoreError):
    """A batch cannot start: bad inputs, source specification or options.

    Examples
    --------
    >>> parse_sources("farthest:0")
    Traceback (most recent call last):
    ...
    heatcore.apps.batch.spec.BatchError: farthest:K needs K >= 1
    """


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

    Examples
    --------
    Usually made by :func:`parse_sources`; its text is what ``summary.csv`` and the result index record.

    >>> spec = SourceSpec("indices", indices=(0, 17), union=True)
    >>> str(spec), str(SourceSpec("farthest", k=8)), str(SourceSpec("file", suffix=".sources.txt"))
    ('0,17 (union)', 'farthest:8', 'file:.sources.txt')
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
    """Everything one worker needs for one mesh (picklable).

    Attributes
    ----------
    path : str
        The mesh file.
    output_dir : str
        Where ``NAME.npz`` goes (:func:`output_path`).
    spec : SourceSpec
    max_memory_mb : float
        Bound on the distance rows held at once, in MB.
    settings : Settings
        The run's settings (``Settings.of("batch", ...)``): how to read the
        file (``settings.domain``, see :func:`heatcore.io.domain.read_domain`),
        the domain's options (``settings.mesh``) and the solver's
        (``settings.solver``).

    Examples
    --------
    >>> import pickle
    >>> task = MeshTask("meshes/spot.obj", "out", parse_sources("0,17"), settings=Settings.of("batch", m=2.0))
    >>> pickle.loads(pickle.dumps(task)) == task, str(task.spec), task.settings.solver.m
    (True, '0,17', 2.0)
    """

    path: str
    output_dir: str
    spec: SourceSpec
    max_memory_mb: float = DEFAULT_MAX_MEMORY_MB
    settings: Settings = field(default_factory=lambda: Settings.of("batch"))


# --------------------------------------------------------------------------- paths


def find_inputs(inputs):
    """Mesh files from folders, glob patterns and file paths, sorted and unique.

    Folders contribute their files with a mesh extension (:data:`MESH_SUFFIXES`,
    not recursive); patterns are expanded with :func:`glob.glob` (``**``
    allowed).

    Returns
    -------
    list of pathlib.Path
        Absolute paths, in the order found (folders and matches sorted).

    Raises
    ------
    BatchError
        An input matches nothing, or two inputs would write the same output name.

    Examples
    --------
    >>> import tempfile
    >>> tmp = tempfile.TemporaryDirectory()
    >>> for name in ("b.ply", "a.obj", "notes.txt"):
    ...     _ = (Path(tmp.name) / name).write_text("")
    >>> [p.name for p in find_inputs(tmp.name)]
    ['a.obj', 'b.ply']
    >>> [p.name for p in find_inputs([str(Path(tmp.name) / "*.ply"), Path(tmp.name) / "a.obj"])]
    ['b.ply', 'a.obj']
    >>> find_inputs(Path(tmp.name) / "missing.obj")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    heatcore.apps.batch.spec.BatchError: input .../missing.obj: no such file or folder, and no file matches it as a pattern
    >>> tmp.cleanup()
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
    """The result index ``OUTPUT_DIR/NAME.npz`` of mesh ``NAME.EXT``.

    Examples
    --------
    >>> output_path("out", "meshes/bunny.obj").as_posix()
    'out/bunny.npz'
    """
    return Path(output_dir) / f"{Path(mesh_path).stem}.npz"
