"""Command-line inputs: option values, sources and mesh files, checked before any work.

Option types raise :class:`argparse.ArgumentTypeError` (a one-line usage
error, exit status 2; the solver and colour options' types come from
:meth:`heatcore.options.Option.parse`); sources files and meshes raise
:class:`~heatcore.apps.outputs.CliError` or :class:`~heatcore.errors.InvalidMeshError`
(exit status 1). Sources given on the command line are read before the mesh,
so that a bad one costs nothing.

Examples
--------
>>> _vertex_index("17")
17
>>> _vertex_index("99999999999999999999")
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


def _positive_float(text):
    value = _parse(text, float, "a number")
    if not (np.isfinite(value) and value > 0):
        raise argparse.ArgumentTypeError(f"must be a positive number, got {text!r}")
    return value


def _vertex_index(text):
    value = _parse(text, int, "a vertex index")
    if value < 0:
        raise argparse.ArgumentTypeError(f"vertex indices are 0-based, got {text}")
    if value > MAX_INDEX:
        raise argparse.ArgumentTypeError(f"vertex index {text} is too large for any mesh (at most {MAX_INDEX})")
    return value


def _non_negative_int(text):
    value = _parse(text, int, "an integer")
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be >= 0, got {text!r}")
    return value


def read_sources_file(path):
    """Vertex indices from a text file: integers separated by whitespace or commas; ``#`` comments."""
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
    """
    try:
        check_source_vertices(sources, n_vertices)
    except InvalidSourceError as exc:
        raise CliError(str(exc)) from None


def command_line_sources(args):
    """Sources from --source and --sources-file (read before the mesh), or None."""
    sources = list(args.source or [])
    for path in args.sources_file or []:
        sources += read_sources_file(path)
    return np.unique(np.asarray(sources, dtype=np.int64)) if sources else None


def gather_sources(args, mesh, given=None):
    """Sources from the command line (``given``), else the mesh file's saved selection."""
    if given is not None:
        return given, "command line"
    selected = mesh.selected_vertices()
    if selected.size:
        return selected, f"the selection saved in {args.mesh.name}"
    raise CliError(
        "no sources: give --source INDEX or --sources-file FILE, "
        "or a PLY with selected vertices (MeshLab: save with the vertex flags)"
    )
