"""The ``heatcore`` command's arguments: option groups generated from :mod:`heatcore.options`.

Each subcommand offers the options of its front end's row of
:data:`heatcore.settings.FRONT_END_OPTIONS` (``"cli"`` for ``distance``,
``demo`` and ``path``, ``"batch"``, ``"vector heat"`` for ``logmap``); their
flags, types, ranges, defaults and help texts all come from
:mod:`heatcore.options`, so a new option is one more declaration there and one
more name in that table. A run turns what was parsed into one
:class:`~heatcore.settings.Settings` (:func:`settings_of`), which the command
hands over as it is.

Examples
--------
>>> p = OneLineErrorParser(prog="demo")
>>> add_solver_options(p)
>>> s = settings_of(p.parse_args(["--m", "2", "--no-weld"]), intent="one query")
>>> s.solver.m, s.solver.intent, s.mesh.weld, sorted(s.mesh.given)
(2.0, 'one query', None, ['weld'])
"""

import argparse
from pathlib import Path

import numpy as np

from .. import options
from ..io.curves import curve_formats_help
from ..io.mesh import short
from ..settings import FRONT_END_OPTIONS, Settings
from .inputs import SOURCE_FLAGS, SourcesAction, parse_non_negative_int, parse_positive_float


class OneLineErrorParser(argparse.ArgumentParser):
    """Usage errors as one line (``heatcore distance: error: ...``), exit status 2.

    Examples
    --------
    >>> p = OneLineErrorParser(prog="demo")
    >>> try:
    ...     p.parse_args(["--nope"])
    ... except SystemExit as stop:
    ...     stop.code
    2
    """

    def __init__(self, *args, formatter_class=None, **kwargs):
        super().__init__(*args, formatter_class=formatter_class or _HelpFormatter, **kwargs)

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {short(message, 400)} (see '{self.prog} --help')\n")


def solver_option_names(front_end="cli"):
    """The mesh and solver options ``front_end`` offers (:data:`~heatcore.settings.FRONT_END_OPTIONS`), in its order.

    Examples
    --------
    >>> solver_option_names("cli")
    ('m', 'boundary', 'accuracy', 'backend', 'robust', 'refine', 'weld')
    """
    return tuple(name for name in FRONT_END_OPTIONS[front_end] if options.OPTIONS[name].target in ("mesh", "solver"))


def add_solver_options(parser, front_end="cli"):
    """Add the mesh and solver options of ``front_end``: ``--m``, ``--boundary``, ``--accuracy``, ``--backend``, ...

    One argument group, "solver options", of :func:`solver_option_names`;
    each option's flag, type, range, default and help come from
    :mod:`heatcore.options`.

    Parameters
    ----------
    parser : argparse.ArgumentParser
    front_end : str, default "cli"
        Whose options and defaults (``"vector heat"``: ``heatcore logmap``'s).

    Examples
    --------
    >>> p = OneLineErrorParser(prog="demo")
    >>> add_solver_options(p)
    >>> args = p.parse_args(["--m", "4", "--refine", "0"])
    >>> args.m, args.refine, args.boundary
    (4.0, 0, 'robin')
    """
    group = parser.add_argument_group("solver options")
    for name in solver_option_names(front_end):
        options.add_argument(group, name, front_end=front_end)


def settings_of(args, front_end="cli", intent="reuse"):
    """The run's one :class:`~heatcore.settings.Settings`, from parsed arguments.

    Every option of ``front_end`` (:data:`~heatcore.settings.FRONT_END_OPTIONS`)
    that the parser has goes in where it differs from the front end's
    default: those count as given (``settings.mesh.given``), so a domain
    refuses an option it does not take only when the user set it
    (:meth:`heatcore.io.domain.DomainFile.domain`). The values were checked
    by argparse (:meth:`heatcore.options.Option.parse`); :meth:`Settings.of`
    checks each once more, as it checks every front end's.

    Parameters
    ----------
    args : argparse.Namespace
    front_end : str, default "cli"
    intent : {"reuse", "one query"}, default "reuse"
        What the solver is built for (:data:`heatcore.settings.INTENTS`).

    Examples
    --------
    >>> p = OneLineErrorParser(prog="demo")
    >>> add_solver_options(p)
    >>> s = settings_of(p.parse_args(["--accuracy", "high", "--refine", "0"]))
    >>> s.mesh.refine, s.solver.accuracy, s.solver.intent, sorted(s.mesh.given)
    (0, 'high', 'reuse', ['refine'])
    """
    unset = object()
    values = {name: getattr(args, name, unset) for name in FRONT_END_OPTIONS[front_end]}
    given = {name: value for name, value in values.items()
             if value is not unset and value != options.OPTIONS[name].default_for(front_end)}
    return Settings.of(front_end, intent=intent, **given)


def add_output_options(parser, png_help=None, view_default=None, colormap=True):
    """Add ``--colormap``, ``--isolines``, ``--view`` and (given ``png_help``) ``--png``.

    Parameters
    ----------
    parser : argparse.ArgumentParser
    png_help : str, optional
        Help text of ``--png``; without it there is no ``--png``.
    view_default : str, optional
        What the picture's camera is without ``--view`` (for the help text); ``--view`` is added
        when there is a picture: with ``png_help`` or ``view_default``.
    colormap : bool, default True
        Offer ``--colormap`` (False: the command has colors of its own, as ``heatcore signed``).

    Examples
    --------
    >>> p = OneLineErrorParser(prog="demo")
    >>> add_output_options(p, png_help="a picture")
    >>> args = p.parse_args(["--colormap", "magma", "--png", "d.png", "--view=-40,20"])
    >>> args.colormap, args.isolines, args.png.name, args.view
    ('magma', None, 'd.png', {'azimuth': -40.0, 'elevation': 20.0})
    """
    picture = bool(png_help or view_default)
    group = parser.add_argument_group("picture and colors" if picture else "colors")
    if colormap:
        options.add_argument(group, "colormap", picture=picture)
    options.add_argument(group, "isolines", picture=picture)
    if png_help:
        group.add_argument("--png", type=Path, default=None, metavar="PATH", help=png_help)
    if png_help or view_default:
        group.add_argument("--view", type=_view, default=None, metavar="AZIMUTH,ELEVATION",
                           help="camera of the picture in degrees: azimuth about the up axis (y), elevation "
                                f"above the horizon, -90..90 (default: {view_default or '30,15'}; a negative "
                                "azimuth as --view=-40,15)")


def _view(text):
    """``AZIMUTH,ELEVATION`` in degrees to camera keywords; :class:`argparse.ArgumentTypeError` when bad.

    Examples
    --------
    >>> _view("150, 15")
    {'azimuth': 150.0, 'elevation': 15.0}
    >>> _view("10,95")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: elevation must be between -90 and 90 degrees, got 95
    """
    parts = text.split(",")
    try:
        azimuth, elevation = (float(part) for part in parts)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected AZIMUTH,ELEVATION in degrees (e.g. 30,15), got {text!r}") from None
    if not (np.isfinite(azimuth) and np.isfinite(elevation)):
        raise argparse.ArgumentTypeError(f"the view's angles must be finite numbers, got {text!r}")
    if abs(elevation) > 90:
        raise argparse.ArgumentTypeError(f"elevation must be between -90 and 90 degrees, got {elevation:g}")
    return {"azimuth": azimuth, "elevation": elevation}


#: How every subcommand's sources are written (the help texts say it).
SOURCES_SYNTAX = "-s 0 17, -s 0,17 and -s 0 -s 17 mean the same (also --source, --sources)"


def is_source_keyword(word):
    """Whether a source word names a whole specification (``heatcore batch``'s ``all``, ``farthest:K``).

    Examples
    --------
    >>> is_source_keyword("all"), is_source_keyword("Farthest:8"), is_source_keyword("17")
    (True, True, False)
    """
    return word.lower() == "all" or word.lower().startswith("farthest:")


def source_text(sources):
    """``batch``'s parsed sources as the text :func:`heatcore.apps.batch.parse_sources` reads (None stays None).

    Examples
    --------
    >>> source_text([0, 17]), source_text("farthest:8"), source_text(None)
    ('0,17', 'farthest:8', None)
    """
    if sources is None or isinstance(sources, str):
        return sources
    return ",".join(map(str, sources))


def add_common_options(parser):
    """Add the options every subcommand has: ``-q/--quiet``.

    Examples
    --------
    >>> p = OneLineErrorParser(prog="demo")
    >>> add_common_options(p)
    >>> p.parse_args(["-q"]).quiet, p.parse_args([]).quiet
    (True, False)
    """
    parser.add_argument("-q", "--quiet", action="store_true", help="no progress or timing lines on stderr")


def distance_arguments(p):
    """Add the arguments of ``heatcore distance``: the mesh, sources, outputs, picture, solver options.

    Examples
    --------
    >>> p = OneLineErrorParser(prog="heatcore distance")
    >>> distance_arguments(p)
    >>> args = p.parse_args(["spot.obj", "-s", "0", "-s", "17", "-o", "d.npy"])
    >>> args.mesh.name, args.source, args.output, args.refine
    ('spot.obj', [0, 17], ['d.npy'], 'auto')
    >>> p.parse_args(["spot.obj", "-s", "0", "17"]).source == p.parse_args(["spot.obj", "--sources", "0,17"]).source
    True
    """
    p.add_argument("mesh", type=Path, metavar="MESH",
                   help="mesh file: PLY (keeps MeshLab's vertex selection), OBJ, OFF, STL, glTF, ...; "
                        "tetrahedral meshes (.msh, .vtu, .vtk, .mesh, .node/.ele); point clouds "
                        "(.xyz, or PLY/OBJ without faces)")
    options.add_argument(p, "domain")
    src = p.add_argument_group("sources (combined; default: the PLY's selected vertices)")
    src.add_argument(*SOURCE_FLAGS, dest="source", action=SourcesAction, metavar="INDEX",
                     help=f"source vertex indices (0-based): {SOURCES_SYNTAX}")
    src.add_argument("--sources-file", type=Path, action="append", metavar="FILE",
                     help="text file of 0-based vertex indices separated by whitespace or commas "
                          "('#' starts a comment); may be repeated")
    p.add_argument("-o", "--output", action="append", default=[], metavar="FILE",
                   help="output file, format by extension: .ply (quality + colors), .npy, .csv "
                        "(index,distance), or for tetrahedral meshes .vtu/.vtk/.msh (point-data field "
                        "'distance'); repeat for several. Outputs are written whole or not at all "
                        "(a temporary file, then renamed)")
    p.add_argument("--overwrite", action="store_true",
                   help="allow an output to replace an input file (the mesh or a sources file); "
                        "the input's other vertex properties are not kept")
    add_output_options(p, png_help="also write a PNG picture of the distance field (matplotlib); "
                                   "a name ending in .png",
                       view_default="facing the first source, from outside the surface at it (its marker in view)")
    p.add_argument("--isolines-out", action=PathAndCount, default=None,
                   help="also write N isoline curves of the distance as polylines, at max*j/(N+1) for j = 1..N "
                        "(the levels of the PNG's lines; N defaults to --isolines, else 12: the PNG's lines); "
                        "format by extension: " + curve_formats_help())
    add_solver_options(p)
    add_common_options(p)


class PathAndCount(argparse.Action):
    """``--isolines-out PATH [N]``: ``(Path, int or None)``, ``N`` at least ``minimum`` (a usage error otherwise).

    ``N`` left out is None: the command picks its default (the levels of its PNG).

    Examples
    --------
    >>> p = OneLineErrorParser(prog="demo")
    >>> _ = p.add_argument("--isolines-out", action=PathAndCount)
    >>> p.parse_args(["--isolines-out", "c.obj", "8"]).isolines_out
    (PosixPath('c.obj'), 8)
    >>> p.parse_args(["--isolines-out", "c.obj"]).isolines_out
    (PosixPath('c.obj'), None)
    >>> p.format_usage().strip()
    'usage: demo [-h] [--isolines-out PATH [N]]'
    """

    def __init__(self, option_strings, dest, minimum=1, **kwargs):
        super().__init__(option_strings, dest, nargs="+", metavar=("PATH", "N"), **kwargs)
        self.minimum = minimum

    def __call__(self, parser, namespace, values, option_string=None):
        if len(values) > 2:
            parser.error(f"argument {option_string}: expected PATH [N], got {len(values)} values")
        count = None
        if len(values) == 2:
            try:
                count = parse_non_negative_int(values[1])
            except argparse.ArgumentTypeError as exc:
                parser.error(f"argument {option_string}: N {exc}")
            if count < self.minimum:
                parser.error(f"argument {option_string}: N must be at least {self.minimum}, got {count}")
        setattr(namespace, self.dest, (Path(values[0]), count))


class _HelpFormatter(argparse.HelpFormatter):
    """argparse's, with a :class:`PathAndCount` option shown as ``PATH [N]`` (not ``PATH [N ...]``)."""

    def _format_args(self, action, default_metavar):
        if isinstance(action, PathAndCount):
            return "{} [{}]".format(*action.metavar)
        return super()._format_args(action, default_metavar)


def demo_arguments(p):
    """Add the arguments of ``heatcore demo``: the output folder, colours, solver options.

    Examples
    --------
    >>> p = OneLineErrorParser(prog="heatcore demo")
    >>> demo_arguments(p)
    >>> args = p.parse_args(["-d", "out", "--isolines", "8"])
    >>> args.output_dir, args.isolines, args.colormap
    ('out', 8, 'viridis')
    """
    p.add_argument("-d", "--output-dir", default=".", metavar="DIR",
                   help="folder for demo.ply and demo.png, created if missing (default: current folder)")
    add_output_options(p, view_default="150,15: spot's three-quarter front")
    add_solver_options(p)
    add_common_options(p)


def meshlab_arguments(p):
    """Add the arguments of ``heatcore meshlab``: those of the MeshLab script (:func:`heatcore.apps.meshlab.add_arguments`).

    The script's flags and this command's are the same, ``-q`` included.

    Examples
    --------
    >>> p = OneLineErrorParser(prog="heatcore meshlab")
    >>> meshlab_arguments(p)
    >>> args = p.parse_args(["scan.ply", "--sources", "0", "17"])
    >>> args.input, args.sources, args.unreachable
    ('scan.ply', [0, 17], -1.0)
    """
    from . import meshlab

    meshlab.add_arguments(p)


def batch_arguments(p):
    """Add the arguments of ``heatcore batch``: inputs, output folder, sources, execution, solver options.

    Examples
    --------
    >>> p = OneLineErrorParser(prog="heatcore batch")
    >>> batch_arguments(p)
    >>> args = p.parse_args(["meshes/", "-o", "out", "--sources", "farthest:8", "-j", "2"])
    >>> args.inputs, args.output_dir.name, args.sources, args.workers, args.max_memory
    (['meshes/'], 'out', 'farthest:8', 2, 1024.0)
    >>> p.parse_args(["meshes/", "-o", "out", "-s", "0", "17"]).sources
    [0, 17]
    """
    p.add_argument("inputs", nargs="+", metavar="INPUT",
                   help="folders (their mesh files), glob patterns (quote them) or mesh files")
    p.add_argument("-o", "--output-dir", type=Path, required=True, metavar="DIR",
                   help="folder for one NAME.npz per mesh and summary.csv (created if missing); a rerun "
                        "skips a mesh whose NAME.npz was computed from the same file bytes, sources and "
                        "options (so it resumes), and recomputes one made from other inputs")
    src = p.add_argument_group("sources (give one)")
    src.add_argument(*SOURCE_FLAGS, dest="sources", action=SourcesAction, keywords=is_source_keyword, metavar="SPEC",
                     help=f"vertex indices (one row per source; {SOURCES_SYNTAX}), 'all' (the full distance "
                          "matrix, in blocks) or 'farthest:K' (K farthest-point samples by heat distance, "
                          "starting at vertex 0)")
    src.add_argument("--sources-file-suffix", metavar="SUFFIX",
                     help="per-mesh sources files: with '.sources.txt', bunny.obj reads bunny.sources.txt "
                          "next to it (indices separated by whitespace or commas, '#' comments)")
    src.add_argument("--union", action="store_true",
                     help="one row per mesh: the distance to the union of the sources")
    run = p.add_argument_group("execution")
    run.add_argument("--scheduler", metavar="ADDRESS",
                     help="run on this dask.distributed scheduler (e.g. tcp://10.0.0.5:8786), one task per "
                          "mesh; the files must be on a file system the workers share (needs heatcore[batch])")
    run.add_argument("-j", "--workers", type=parse_non_negative_int, default=None, metavar="N",
                     help="local processes (default: all cores; 0: in this process)")
    run.add_argument("--max-memory", type=parse_positive_float, default=1024.0, metavar="MB",
                     help="distance rows a task holds at once, in MB; larger results are written as "
                          "per-block .npy files in NAME.blocks/ (default: %(default)s)")
    run.add_argument("--resume-only", action="store_true",
                     help="only resume an earlier run: stop with an error, before any work, if a result in "
                          "the output folder was computed from another mesh file, other sources or options")
    options.add_argument(p, "domain")
    add_solver_options(p, front_end="batch")
    add_common_options(p)


def logmap_arguments(p):
    """Add the arguments of ``heatcore logmap``: the mesh, one source, a reference direction, outputs, solver options.

    Examples
    --------
    >>> p = OneLineErrorParser(prog="heatcore logmap")
    >>> logmap_arguments(p)
    >>> args = p.parse_args(["spot.obj", "-s", "970", "--reference", "0", "1", "0", "-o", "uv.ply"])
    >>> args.source, args.reference, args.output, args.accuracy
    (970, [0.0, 1.0, 0.0], ['uv.ply'], 'high')
    """
    p.add_argument("mesh", type=Path, metavar="MESH", help="triangle mesh file (PLY, OBJ, OFF, STL, glTF, ...)")
    p.add_argument(*SOURCE_FLAGS, dest="source", action=SourcesAction, single=True, required=True, metavar="INDEX",
                   help="the source vertex (0-based): the origin of the coordinates; one only")
    p.add_argument("--reference", type=float, nargs=3, default=None, metavar=("X", "Y", "Z"),
                   help="a direction at the source (3D, projected on its tangent plane) that becomes the +u "
                        "axis; default: the source's tangent basis (heatcore.VectorHeatSolver.tangent_basis)")
    p.add_argument("-o", "--output", action="append", default=[], metavar="FILE",
                   help="output file, format by extension: .ply (the coordinates as vertex texture "
                        "coordinates, s/t and texture_u/texture_v; the distance as quality and colors), "
                        ".npy ((n, 2) float64) or .csv (index,u,v); unreachable vertices get inf (0 in a PLY's "
                        "texture coordinates); repeat for several")
    p.add_argument("--overwrite", action="store_true", help="allow an output to replace the mesh file")
    add_output_options(p)
    add_solver_options(p, front_end="vector heat")
    add_common_options(p)
