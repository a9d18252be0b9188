"""Command-line outputs: names checked before any work, every file written atomically.

An output is first written to a hidden temporary file in its own folder
(same suffix, so that writers choosing the format by extension still do),
then moved over the target with :func:`os.replace`: a crash, a Ctrl-C or a
failing writer never leaves a half-written file, and an existing file is
replaced whole or not at all. Output names are checked before the mesh is
read: a known extension, a ``.png`` picture, no name given twice, not a
folder, and no output that is one of the command's inputs (unless
``overwrite``). One rule for output folders, in every command: a missing
folder is created when the file is written (as ``mkdir -p`` would); a file
standing where a folder must be is refused before any work.

Errors: :class:`UsageError` (exit status 2) for a command line that
contradicts itself, :class:`CliError` (exit status 1) for the file system.

Examples
--------
>>> import tempfile, pathlib, numpy as np
>>> folder = tempfile.TemporaryDirectory()
>>> path = pathlib.Path(folder.name) / "d.npy"
>>> with atomic_output(path) as tmp:
...     np.save(tmp, np.arange(3.0))
>>> np.load(path).tolist(), sorted(p.name for p in path.parent.iterdir())
([0.0, 1.0, 2.0], ['d.npy'])
>>> folder.cleanup()
"""

import contextlib
import os
import secrets
from pathlib import Path

import numpy as np

from ..errors import HeatcoreError
from ..io.curves import CURVE_READERS

OUTPUT_SUFFIXES = (".ply", ".npy", ".csv", ".vtu", ".vtk", ".msh")
VOLUME_OUTPUT_SUFFIXES = (".vtu", ".vtk", ".msh")
#: Isolines in the PNG when ``--isolines`` is not given.
PNG_ISOLINES = 12


class CliError(HeatcoreError):
    """A command-line input is unusable (sources file, output folder, ...): exit status 1.

    Examples
    --------
    >>> error = CliError("cannot read sources file s.txt")
    >>> isinstance(error, HeatcoreError), error.exit_status
    (True, 1)
    """

    exit_status = 1


class UsageError(CliError):
    """The command line contradicts itself (output names, option values): exit status 2.

    Examples
    --------
    >>> error = UsageError("output d.npy is given twice")
    >>> isinstance(error, CliError), error.exit_status
    (True, 2)
    """

    exit_status = 2


@contextlib.contextmanager
def atomic_output(path):
    """Yield a temporary path beside ``path``; on success move it over ``path``, else remove it.

    Parameters
    ----------
    path : str or path-like
        The file to write. Its folder is created when missing.

    Yields
    ------
    pathlib.Path
        ``.<name>.tmp-<random><suffix>`` in the same folder (same file
        system, so the final :func:`os.replace` is atomic).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> folder = tempfile.TemporaryDirectory()
    >>> path = pathlib.Path(folder.name) / "note.txt"
    >>> _ = path.write_text("old")
    >>> try:
    ...     with atomic_output(path) as tmp:
    ...         _ = tmp.write_text("half")
    ...         raise RuntimeError("writer failed")
    ... except RuntimeError:
    ...     pass
    >>> path.read_text(), len(list(path.parent.iterdir()))
    ('old', 1)
    >>> folder.cleanup()
    """
    path = Path(path)
    tmp = path.with_name(f".{path.stem}.tmp-{secrets.token_hex(4)}{path.suffix}")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        yield tmp
        with open(tmp, "rb+") as f:  # on disk before the rename makes it visible
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException as exc:
        with contextlib.suppress(OSError):
            tmp.unlink()
        if isinstance(exc, OSError):  # about the output, not the temporary file the user never named
            raise CliError(f"cannot write {path}: {exc.strerror or exc}") from exc
        raise


def same_file(a, b):
    """Whether paths ``a`` and ``b`` name the same existing file (False when either does not exist).

    Examples
    --------
    >>> import tempfile
    >>> tmp = tempfile.TemporaryDirectory()
    >>> a = Path(tmp.name) / "a.ply"
    >>> _ = a.write_text("ply")
    >>> same_file(a, Path(tmp.name) / "." / "a.ply"), same_file(a, Path(tmp.name) / "b.ply")
    (True, False)
    >>> tmp.cleanup()
    """
    try:
        return os.path.samefile(a, b)
    except OSError:  # one of them does not exist (yet): not the same file
        return False


def check_output_paths(outputs, png=None, inputs=(), overwrite=False, curves=None):
    """Refuse unusable output names before any work.

    Parameters
    ----------
    outputs : list of path-like
        Data outputs (``-o``); the suffix picks the format.
    png : path-like, optional
        The picture (``--png``).
    inputs : list of path-like
        Files the command reads (mesh, sources files).
    overwrite : bool
        Allow an output to replace an input.
    curves : path-like, optional
        The isoline curves (``--isolines-out``), an ``.obj`` file.

    Raises
    ------
    UsageError
        Unknown extension, a picture not named ``.png``, curves not named ``.obj``, a name given twice,
        an output that is an input (without ``overwrite``).
    CliError
        An output that is a folder, or whose folder cannot be created.

    Examples
    --------
    >>> check_output_paths(["d.npy"], png="d.png")
    >>> check_output_paths(["d.txt"])
    Traceback (most recent call last):
    ...
    heatcore.apps.outputs.UsageError: output d.txt: unknown extension '.txt'; use one of .ply, .npy, .csv, .vtu, .vtk, .msh
    """
    outputs = [Path(p) for p in outputs]
    for out in outputs:
        if out.suffix.lower() not in OUTPUT_SUFFIXES:
            raise UsageError(f"output {out}: unknown extension {out.suffix!r}; use one of {', '.join(OUTPUT_SUFFIXES)}")
    if png is not None:
        png = Path(png)
        if png.suffix.lower() != ".png":
            raise UsageError(f"--png {png}: the picture is a PNG file; give a name ending in .png")
        outputs.append(png)
    if curves is not None:
        curves = Path(curves)
        if curves.suffix.lower() not in CURVE_READERS:
            raise UsageError(f"--isolines-out {curves}: the curves are polylines; give a name ending in "
                             f"{', '.join(CURVE_READERS)}")
        outputs.append(curves)
    for i, out in enumerate(outputs):
        if any(out == other or same_file(out, other) for other in outputs[:i]):
            raise UsageError(f"output {out} is given twice")
        for source in inputs:
            if not overwrite and same_file(out, source):
                raise UsageError(f"output {out} is an input of this command; "
                                 "write elsewhere, or pass --overwrite to replace it")
        check_writable(out)


def check_writable(out):
    """Refuse an output that is a folder, or whose folder cannot be created (a file stands on its way).

    Parameters
    ----------
    out : path-like

    Raises
    ------
    CliError

    Examples
    --------
    >>> import tempfile
    >>> tmp = tempfile.TemporaryDirectory()
    >>> note = Path(tmp.name) / "note.txt"
    >>> _ = note.write_text("")
    >>> check_writable(Path(tmp.name) / "new" / "d.npy")  # a missing folder: created when written
    >>> check_writable(note / "d.npy")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    heatcore.apps.outputs.CliError: cannot write .../note.txt/d.npy: .../note.txt is a file, not a folder
    >>> tmp.cleanup()
    """
    out = Path(out)
    if out.is_dir():
        raise CliError(f"cannot write {out}: it is a folder")
    folder = out.parent
    while not folder.exists() and folder != folder.parent:
        folder = folder.parent
    if folder.exists() and not folder.is_dir():
        raise CliError(f"cannot write {out}: {folder} is a file, not a folder")


def check_outputs_fit(outputs, png, kind, curves=None):
    """Refuse outputs that cannot hold this kind of domain, before the precompute.

    Parameters
    ----------
    outputs : list of path-like
        Data outputs (``-o``).
    png : path-like or None
        The picture (``--png``).
    kind : str
        The domain's kind (:attr:`heatcore.io.domain.DomainFile.kind`):
        ``"triangle"``, ``"polygon"``, ``"tet"`` or ``"points"``.
    curves : path-like, optional
        The isoline curves (``--isolines-out``).

    Raises
    ------
    CliError
        A volume format for a surface, a ``.ply`` for a tetrahedral mesh, or a
        picture or isoline curves of a point cloud.

    Examples
    --------
    >>> check_outputs_fit(["d.ply", "d.npy"], "d.png", "triangle")
    >>> check_outputs_fit(["d.vtu"], None, "triangle")
    Traceback (most recent call last):
    ...
    heatcore.apps.outputs.CliError: output d.vtu: .vtu/.vtk/.msh outputs are for tetrahedral meshes; use .ply, .npy or .csv
    """
    for out in outputs:
        suffix = Path(out).suffix.lower()
        if suffix in VOLUME_OUTPUT_SUFFIXES and kind != "tet":
            raise CliError(f"output {out}: .vtu/.vtk/.msh outputs are for tetrahedral meshes; use .ply, .npy or .csv")
        if kind == "tet" and suffix == ".ply":
            raise CliError(f"output {out}: a tetrahedral mesh is written as .vtu, .vtk or .msh (or .npy/.csv)")
    if kind == "points" and png is not None:
        raise CliError("--png draws surfaces; a point cloud has none (write .ply, .npy or .csv)")
    if kind == "points" and curves is not None:
        raise CliError("--isolines-out draws curves on surfaces; a point cloud has none (write .ply, .npy or .csv)")


def write_output(path, V, F, d, sources, colormap, isolines):
    """Write distances by extension, atomically: .ply (quality + colors + selection), .npy, .csv,
    or .vtu/.vtk/.msh (``F`` the tets; a point-data field ``distance``).

    Parameters
    ----------
    path : path-like
        The output; its suffix picks the format (:data:`OUTPUT_SUFFIXES`).
    V : (n, 3) array
        Vertex positions.
    F : (m, 3) or (m, 4) int array
        Triangles (``.ply``) or tetrahedra (``.vtu``, ``.vtk``, ``.msh``);
        unused by ``.npy`` and ``.csv``.
    d : (n,) array
        The distances (``inf`` where unreachable).
    sources : array of int
        Source vertices: the saved selection of a ``.ply``.
    colormap : str
        Vertex colours of a ``.ply`` (:mod:`heatcore.viz.colormap`).
    isolines : int or None
        Dark isoline stripes in the colours of a ``.ply`` (None: none).

    Raises
    ------
    UsageError
        An unknown extension.

    Examples
    --------
    >>> import tempfile
    >>> tmp = tempfile.TemporaryDirectory()
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    >>> d = np.array([0.0, 1.0, 1.0])
    >>> write_output(Path(tmp.name) / "d.csv", V, [[0, 1, 2]], d, [0], "viridis", None)
    >>> print((Path(tmp.name) / "d.csv").read_text())
    index,distance
    0,0
    1,1
    2,1
    <BLANKLINE>
    >>> write_output(Path(tmp.name) / "d.ply", V, [[0, 1, 2]], d, [0], "viridis", 4)
    >>> sorted(p.name for p in Path(tmp.name).iterdir())
    ['d.csv', 'd.ply']
    >>> tmp.cleanup()
    """
    from ..viz.colormap import colorize, to_uint8

    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in OUTPUT_SUFFIXES:
        raise UsageError(f"output {path}: unknown extension {path.suffix!r}; use one of {', '.join(OUTPUT_SUFFIXES)}")
    with atomic_output(path) as tmp:
        if suffix == ".ply":
            from ..io.mesh import write_ply

            write_ply(tmp, V, F, d, to_uint8(colorize(d, colormap, isolines=isolines or 0)), selection=sources)
        elif suffix in VOLUME_OUTPUT_SUFFIXES:
            from ..io.tet import write_tet_distance

            write_tet_distance(tmp, V, F, d)
        elif suffix == ".npy":
            np.save(tmp, d)
        else:
            table = np.column_stack([np.arange(len(d)), d])
            np.savetxt(tmp, table, fmt=["%d", "%.17g"], delimiter=",", header="index,distance", comments="")


def render_png(path, V, F, d, sources, colormap, isolines, title=None, view=None, signed=False):
    """Draw the distance field into a PNG file, atomically (:func:`heatcore.viz.render.render_distance`).

    Parameters
    ----------
    path : path-like
        The picture.
    V, F : arrays
        Vertex positions (n, 3) and triangles (m, 3).
    d : (n,) array
        The distances.
    sources : array of int
        Source vertices, marked in the picture.
    colormap : str
        A heatcore colormap (:mod:`heatcore.viz.colormap`).
    isolines : int or None
        Isolines drawn (None: :data:`PNG_ISOLINES`).
    title : str, optional
    view : dict, optional
        Camera keywords of :func:`~heatcore.viz.render.render_distance`
        (``elevation``, ``azimuth``, ``up``).
    signed : bool, default False
        A signed field: the diverging colors and the zero set (``colormap`` unused).

    Examples
    --------
    >>> import tempfile
    >>> tmp = tempfile.TemporaryDirectory()
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    >>> F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    >>> png = Path(tmp.name) / "d.png"
    >>> render_png(png, V, F, np.array([0.0, 1.0, 1.0, 1.0]), [0], "viridis", 4, title="tetrahedron")
    >>> png.read_bytes()[:4]
    b'\\x89PNG'
    >>> tmp.cleanup()
    """
    from ..viz.render import render_distance

    with atomic_output(path) as tmp:
        render_distance(
            tmp, V, F, d, sources=sources, colormap=colormap,
            isolines=PNG_ISOLINES if isolines is None else isolines, title=title, signed=signed, **(view or {}),
        )


def write_isolines(path, V, F, d, count):
    """Write ``count`` isoline curves of the distances as polylines (``.obj``, ``.vtk``, ``.ply``), atomically.

    The levels are ``max * j / (count + 1)``, ``j = 1..count``
    (:func:`heatcore.contours.isoline_levels`); curves of the surface
    triangles ``F`` (:func:`heatcore.isolines`), written by
    :func:`heatcore.io.curves.write_curves` (the OBJ with a comment naming
    each curve's level).

    Returns
    -------
    list of Isoline
        The curves written.

    Examples
    --------
    >>> import tempfile
    >>> tmp = tempfile.TemporaryDirectory()
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    >>> curves = write_isolines(Path(tmp.name) / "c.obj", V, [[0, 1, 2]], np.array([0.0, 1.0, 1.0]), 1)
    >>> print((Path(tmp.name) / "c.obj").read_text().strip())
    # heatcore isolines: 1 levels of the distance at max*j/2, j = 1..1 (max 1)
    # isoline 0: level 0.5, 2 points, open
    v 0 0.5 0
    v 0.5 0 0
    l 1 2
    >>> tmp.cleanup()
    """
    from ..contours import isolines
    from ..io.curves import write_curves

    curves = isolines(V, F, d, count)
    finite = np.isfinite(d)
    vmax = float(d[finite].max()) if finite.any() else float("nan")
    header = f"heatcore isolines: {count} levels of the distance at max*j/{count + 1}, j = 1..{count} (max {vmax:.17g})"
    labels = [f"isoline {j}: level {c.level:.17g}, {len(c.points)} points, {'closed' if c.closed else 'open'}"
              for j, c in enumerate(curves)]
    with atomic_output(path) as tmp:
        write_curves(tmp, curves, header=header, labels=labels)
    return curves
