"""Command-line inputs: option values, sources and mesh files, checked before any work.

Option types raise :class:`argparse.ArgumentTypeError` (a one-line usage
error, exit status 2; the solver and colour options' types come from
:meth:`heatcore.options.Option.parse`); sources files and meshes raise
:class:`~heatcore.apps.outputs.CliError` or :class:`~heatcore.errors.InvalidMeshError`
(exit status 1). Sources given on the command line are read before the mesh,
so that a bad one costs nothing.

Examples
--------
>>> parse_vertex_index("17")
17
>>> parse_vertex_index("99999999999999999999")
Traceback (most recent call last):
...
argparse.ArgumentTypeError: vertex index 99999999999999999999 is too large for any mesh (at most 9223372036854775807)
"""

import argparse
import contextlib
from io import StringIO
from pathlib import Path

import numpy as np

from ..errors import InvalidSourceError
from ..io.mesh import short
from ..options import check_source_vertices
from .outputs import CliError

#: Largest vertex index a source may have (indices are int64).
MAX_INDEX = np.iinfo(np.int64).max


def _parse(text, kind, what):
    """``kind(text)``, or an argparse error saying the text is not ``what``."""
    try:
        return kind(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not {what}: {text!r}") from None


def parse_positive_float(text):
    """A finite number > 0 from an option value (an ``argparse`` type).

    Examples
    --------
    >>> parse_positive_float("2.5")
    2.5
    >>> parse_positive_float("0")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: must be a positive number, got '0'
    """
    value = _parse(text, float, "a number")
    if not (np.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"must be a positive number, got {text!r}")
    return value


def parse_vertex_index(text):
    """A 0-based vertex index from an option value (an ``argparse`` type): an integer in ``0..MAX_INDEX``.

    Examples
    --------
    >>> parse_vertex_index("0")
    0
    >>> parse_vertex_index("-1")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: vertex indices are 0-based, got -1
    """
    value = _parse(text, int, "a vertex index")
    if value < 0:
        raise argparse.ArgumentTypeError(f"vertex indices are 0-based, got {text}")
    if value > MAX_INDEX:
        raise argparse.ArgumentTypeError(f"vertex index {text} is too large for any mesh (at most {MAX_INDEX})")
    return value


#: The flags of a command's source option: every spelling means the same on every subcommand.
SOURCE_FLAGS = ("-s", "--source", "--sources")


def source_tokens(values):
    """Split command-line source words on commas: ``["0,17", "5"]`` -> ``["0", "17", "5"]``.

    A word holding ``:`` (a point inside a face, ``FACE:B0,B1,B2``) is kept whole.

    Examples
    --------
    >>> source_tokens(["0,17", " 5", "12:0.2,0.3,0.5", "3,"])
    ['0', '17', '5', '12:0.2,0.3,0.5', '3']
    """
    tokens = []
    for value in values:
        if ":" in value:
            tokens.append(value.strip())
        else:
            tokens += [token.strip() for token in value.split(",") if token.strip()]
    return tokens


class SourcesAction(argparse.Action):
    """One source syntax for every subcommand: ``-s 0 17``, ``-s 0,17`` and ``-s 0 -s 17`` mean the same.

    The words after the flag, split on commas (:func:`source_tokens`), are
    read by ``parse`` (default :func:`parse_vertex_index`) and appended to
    what earlier uses of the flag gave. With ``single=True`` the command
    takes one source (``what`` names it in messages): the value is that
    source, and a second one (in any spelling) is a usage error (exit
    status 2) that says so. ``keywords``
    are words that stand for a whole source specification (``batch``'s
    ``all``, ``farthest:K``): stored as the text, alone.

    Examples
    --------
    >>> p = argparse.ArgumentParser(prog="demo")
    >>> _ = p.add_argument(*SOURCE_FLAGS, dest="source", action=SourcesAction)
    >>> [p.parse_args(argv).source for argv in (["-s", "0", "17"], ["-s", "0,17"], ["-s", "0", "--source", "17"])]
    [[0, 17], [0, 17], [0, 17]]
    >>> q = argparse.ArgumentParser(prog="one")
    >>> _ = q.add_argument("-s", dest="source", action=SourcesAction, single=True)
    >>> q.parse_args(["-s", "5"]).source
    5
    """

    def __init__(self, option_strings, dest, nargs="+", parse=parse_vertex_index, single=False, keywords=None,
                 what="source", **kwargs):
        super().__init__(option_strings, dest, nargs=nargs, **kwargs)
        self.parse, self.single, self.keywords, self.what = parse, single, keywords, what

    def __call__(self, parser, namespace, values, option_string=None):
        flag = "/".join(self.option_strings)
        tokens = source_tokens(values)
        earlier = getattr(namespace, self.dest, None)
        if self.keywords is not None and any(self.keywords(token) for token in tokens):
            if len(tokens) > 1 or earlier is not None:
                parser.error(f"argument {flag}: {' '.join(tokens)!s} is a whole source specification: give it "
                             "alone, not with vertex indices")
            setattr(namespace, self.dest, tokens[0])
            return
        if isinstance(earlier, str):
            parser.error(f"argument {flag}: {earlier!r} is a whole source specification: give it alone")
        parsed = []
        for token in tokens:
            try:
                parsed.append(self.parse(token))
            except argparse.ArgumentTypeError as exc:
                hint = ("; the mesh file goes before the sources (or end them with --)"
                        if Path(token).suffix and not token[:1].isdigit() else "")
                parser.error(f"argument {flag}: {exc}{hint}")
        given = ([] if earlier is None else [earlier] if self.single else list(earlier)) + tokens
        if self.single and len(given) > 1:
            parser.error(f"argument {flag}: this command takes one {self.what}, got {len(given)} "
                         f"({', '.join(map(str, given))}); run it once per {self.what}")
        if self.single:
            setattr(namespace, self.dest, parsed[0] if parsed else earlier)
        else:
            setattr(namespace, self.dest, (earlier or []) + parsed)


def parse_non_negative_int(text):
    """An integer >= 0 from an option value (an ``argparse`` type).

    Examples
    --------
    >>> parse_non_negative_int("4")
    4
    >>> parse_non_negative_int("-2")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: must be >= 0, got '-2'
    """
    value = _parse(text, int, "an integer")
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be >= 0, got {text!r}")
    return value


def read_sources_file(path):
    """Vertex indices from a text file: integers separated by whitespace or commas; ``#`` comments.

    Parameters
    ----------
    path : path-like

    Returns
    -------
    list of int
        In file order, repeats kept.

    Raises
    ------
    CliError
        The file cannot be read, a token is not a vertex index (0-based, at
        most :data:`MAX_INDEX`), or it holds no index.

    Examples
    --------
    >>> import tempfile
    >>> tmp = tempfile.TemporaryDirectory()
    >>> path = Path(tmp.name) / "sources.txt"
    >>> _ = path.write_text("0, 17  # the nose\\n5\\n")
    >>> read_sources_file(path)
    [0, 17, 5]
    >>> _ = path.write_text("0 x\\n")
    >>> read_sources_file(path)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    heatcore.apps.outputs.CliError: .../sources.txt, line 1: 'x' is not a vertex index
    >>> tmp.cleanup()
    """
    path = Path(path)
    try:
        text = path.read_text()
    except OSError as exc:
        raise CliError(f"cannot read sources file {path}: {exc.strerror or exc}") from exc
    indices = []
    for lineno, line in enumerate(text.splitlines(), 1):
        for token in line.split("#", 1)[0].replace(",", " ").split():
            try:
                value = int(token)
            except ValueError:
                raise CliError(f"{path}, line {lineno}: {short(repr(token), 60)} is not a vertex index") from None
            if not 0 <= value <= MAX_INDEX:
                raise CliError(f"{path}, line {lineno}: {short(token, 60)} is not a vertex index "
                               f"(0-based, at most {MAX_INDEX})")
            indices.append(value)
    if not indices:
        raise CliError(f"sources file {path} holds no vertex indices")
    return indices


def read_mesh_file(path, kind="auto"):
    """:func:`heatcore.io.domain.read_domain`, with reader chatter and exits turned into one error.

    meshio prints to stdout/stderr and calls ``sys.exit`` on some malformed
    files; a command must not die that way.

    Parameters
    ----------
    path : path-like
    kind : str, default "auto"
        How to read the file (see :func:`heatcore.io.domain.read_domain`).

    Returns
    -------
    heatcore.io.domain.DomainFile

    Raises
    ------
    CliError
        The reader printed and exited.
    heatcore.errors.InvalidMeshError
        The file is not a mesh :func:`~heatcore.io.domain.read_domain` can use.

    Examples
    --------
    >>> from heatcore.io import demo_mesh_path
    >>> mesh = read_mesh_file(demo_mesh_path())
    >>> mesh.kind, len(mesh.vertices)
    ('triangle', 2930)
    """
    from ..io.domain import read_domain

    chatter = StringIO()
    try:
        with contextlib.redirect_stdout(chatter), contextlib.redirect_stderr(chatter):
            return read_domain(path, kind)
    except SystemExit:
        detail = " ".join(chatter.getvalue().split()) or "the reader gave up"
        raise CliError(f"cannot read mesh file {path}: {detail}") from None


def check_sources(sources, n_vertices):
    """Fail before the precomputation when a source index cannot be a vertex (exit status 1).

    The range check is :func:`heatcore.options.check_source_vertices`, shared by the front ends.

    Raises
    ------
    CliError
        A source is negative or not below ``n_vertices``.

    Examples
    --------
    >>> check_sources([0, 9], 10)
    >>> check_sources([12], 10)
    Traceback (most recent call last):
    ...
    heatcore.apps.outputs.CliError: source vertex 12 is out of range: the mesh has 10 vertices (0..9)
    """
    try:
        check_source_vertices(sources, n_vertices)
    except InvalidSourceError as exc:
        raise CliError(str(exc)) from None


def command_line_sources(args):
    """Sources from --source and --sources-file (read before the mesh), or None.

    Returns
    -------
    (k,) int64 array or None
        Sorted and unique; None when neither option is given.

    Examples
    --------
    >>> command_line_sources(argparse.Namespace(source=[17, 0, 17], sources_file=None))
    array([ 0, 17])
    >>> command_line_sources(argparse.Namespace(source=None, sources_file=None)) is None
    True
    """
    sources = list(args.source or [])
    for path in args.sources_file or []:
        sources += read_sources_file(path)
    return np.unique(np.asarray(sources, dtype=np.int64)) if sources else None


def gather_sources(args, mesh, given=None):
    """Sources from the command line (``given``), else the mesh file's saved selection.

    Parameters
    ----------
    args : argparse.Namespace
        Its ``mesh`` (the file's path) names the file in the returned origin.
    mesh : heatcore.io.domain.DomainFile
        The mesh read (:func:`read_mesh_file`).
    given : array, optional
        Sources from :func:`command_line_sources`.

    Returns
    -------
    (array, str)
        The sources and where they came from (for the progress line).

    Raises
    ------
    CliError
        No sources given and no selected vertex in the file.

    Examples
    --------
    A PLY saved with one vertex selected (MeshLab's vertex flags):

    >>> import tempfile
    >>> from heatcore.io import write_ply
    >>> tmp = tempfile.TemporaryDirectory()
    >>> path = Path(tmp.name) / "tri.ply"
    >>> write_ply(path, np.eye(3), [[0, 1, 2]], np.zeros(3), np.zeros((3, 3), np.uint8), selection=[1])
    >>> mesh = read_mesh_file(path)
    >>> gather_sources(argparse.Namespace(mesh=path), mesh)
    (array([1]), 'the selection saved in tri.ply')
    >>> gather_sources(argparse.Namespace(mesh=path), mesh, given=np.array([0, 2]))
    (array([0, 2]), 'command line')
    >>> tmp.cleanup()
    """
    if given is not None:
        return given, "command line"
    selected = mesh.selected_vertices()
    if selected.size:
        return selected, f"the selection saved in {args.mesh.name}"
    raise CliError(
        "no sources: give --source INDEX or --sources-file FILE, "
        "or a PLY with selected vertices (MeshLab: save with the vertex flags)"
    )
