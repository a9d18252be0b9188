"""The ``heatcore`` command: geodesic distance on mesh files, and a demo.

Subcommands are registered in :data:`COMMANDS` with the :func:`command`
decorator (a function that adds the arguments, and one that runs them), so
a new subcommand is one more decorated pair; their arguments live in
:mod:`heatcore.apps.arguments`. Options are declared once, in
:mod:`heatcore.options` (flags, ranges, defaults, help); each subcommand
offers its front end's row of :data:`heatcore.settings.FRONT_END_OPTIONS`
and turns what was parsed into one :class:`~heatcore.settings.Settings`
(:func:`~heatcore.apps.arguments.settings_of`), whose mesh part builds the
domain and whose solver part the :class:`~heatcore.HeatSolver`.

Progress and timings go to stderr (``--quiet`` silences them); results and
the paths written go to stdout. Every error is one line on stderr. Exit
status 2: the command line itself is wrong, found before any file is read
(``heatcore distance: error: ...`` for an option value, such as a source
index no mesh can have; ``heatcore: error: ...`` for output names: an
unknown extension, a ``--png`` not named ``.png``, an output that is an
input without ``--overwrite``). Exit status 1: a file is (bad mesh, bad
sources file, a source beyond the mesh's vertices, an output that cannot be
written). A missing output folder is created, in every command.
Outputs are written atomically (:mod:`heatcore.apps.outputs`).

Examples
--------
>>> main(["--version"])  # doctest: +ELLIPSIS
heatcore ...
0
"""

import logging
import sys
import warnings
from collections.abc import Callable
from pathlib import Path
from typing import NamedTuple

import numpy as np

from ..errors import HeatcoreError, HeatcoreWarning, InvalidMeshError
from ..io.mesh import short
from ..viz.view import view_facing
from .arguments import (  # noqa: F401 (add_*_options, solver_option_names: part of this module's API)
    OneLineErrorParser,
    add_common_options,
    add_output_options,
    add_solver_options,
    batch_arguments,
    demo_arguments,
    distance_arguments,
    logmap_arguments,
    meshlab_arguments,
    settings_of,
    solver_option_names,
    source_text,
)
from .inputs import check_sources, command_line_sources, gather_sources, read_mesh_file
from .logmap import run_logmap
from .outputs import (  # noqa: F401 (check_outputs_fit, OUTPUT_SUFFIXES: part of this module's API)
    OUTPUT_SUFFIXES,
    PNG_ISOLINES,
    VOLUME_OUTPUT_SUFFIXES,
    CliError,
    UsageError,
    check_output_paths,
    check_outputs_fit,
    render_png,
    write_isolines,
    write_output,
)
from .path_command import PATH_DESCRIPTION, PATH_HELP, path_arguments, run_path
from .reporting import (
    StderrHandler,
    build_progress,
    distance_summary,
    format_seconds,
    show_warning,
    source_parts,
    timed_stage,
)
from .signed_command import (
    SIGNED_DESCRIPTION,
    SIGNED_HELP,
    run_signed,
    signed_arguments,
)
from .straighten_command import (
    STRAIGHTEN_DESCRIPTION,
    STRAIGHTEN_HELP,
    run_straighten,
    straighten_arguments,
)
from .trace_command import TRACE_DESCRIPTION, TRACE_HELP, run_trace, trace_arguments

log = logging.getLogger("heatcore.apps.cli")

#: Vertex near the tip of spot's nose (the snout's front, on the symmetry plane).
DEMO_SOURCE = 1453
#: Camera of the demo picture: spot faces -z with y up; a three-quarter front view.
DEMO_VIEW = {"elevation": 15.0, "azimuth": 150.0, "up": "y"}


# --------------------------------------------------------------------------- options


def build_solver(source, settings, only_parts_of=None):
    """Domain + HeatSolver from a :class:`~heatcore.io.domain.DomainFile` and the run's settings.

    The mesh part of ``settings`` builds the domain, its solver part (with
    its intent: ``"one query"`` for ``distance`` and ``demo``) the solver.
    ``only_parts_of`` (a one-off query's source vertices) leaves out the
    connected parts of a triangle mesh that no source is on.

    Examples
    --------
    >>> from heatcore.io import demo_mesh_path
    >>> args = build_parser().parse_args(["distance", "spot.obj", "-o", "d.npy", "--refine", "0"])
    >>> solver = build_solver(read_mesh_file(demo_mesh_path()), settings_of(args, intent="one query"))
    >>> solver.distance([0]).shape
    (2930,)
    """
    from .. import HeatSolver

    domain_progress, solver_progress = build_progress(*_work_ahead(source, settings, only_parts_of))
    with timed_stage("precompute"):
        domain = source.domain(settings.mesh, progress=domain_progress, only_parts_of=only_parts_of)
        welded = getattr(domain, "n_welded", 0)
        if welded:  # said when it happens: before the solver's lines
            log.info("welded %s coincident vertices: %s remain", f"{welded:,}", f"{len(source.vertices) - welded:,}")
        solver = HeatSolver(domain, settings.solver, progress=solver_progress)
    return solver


def _work_ahead(source, settings, only_parts_of):
    """The solver vertices and parts a build will have (what decides its progress lines), from the file's faces."""
    from ..domains.refine import work_ahead

    if source.kind != "triangle" or source.surface is None or not len(source.surface):
        return len(source.vertices), 1
    try:
        return work_ahead(source.surface, len(source.vertices), settings.mesh.refine, only_parts_of)
    except (ValueError, IndexError):  # an estimate never stops a run: the build says what is wrong
        return len(source.vertices), 1


# --------------------------------------------------------------------------- registry

class Command(NamedTuple):
    """A subcommand in :data:`COMMANDS`: its help, description, arguments and run functions.

    Examples
    --------
    >>> COMMANDS["distance"].run is run_distance, COMMANDS["distance"].arguments is distance_arguments
    (True, True)
    """

    help: str
    description: str
    arguments: Callable  # arguments(parser): adds the subcommand's options
    run: Callable  # run(args) -> exit status


#: Subcommands by name, in the order ``heatcore --help`` lists them.
COMMANDS = {}


def command(name, *, arguments, help, description=None):
    """Decorator registering ``run(args) -> int`` as subcommand ``name``.

    ``arguments(parser)`` adds the subcommand's options to its parser.

    Examples
    --------
    >>> @command("hello", arguments=add_common_options, help="say hello")
    ... def run_hello(args):
    ...     print("hello" if not args.quiet else "")
    ...     return 0
    >>> main(["hello"])
    hello
    0
    >>> del COMMANDS["hello"]
    """

    def register(run):
        COMMANDS[name] = Command(help, description or help, arguments, run)
        return run

    return register


# --------------------------------------------------------------------------- distance


@command(
    "distance",
    arguments=distance_arguments,
    help="geodesic distance from source vertices on a mesh file",
    description="Geodesic distance from source vertices to every vertex of a triangle (or polygon) "
    "mesh, by the heat method. Sources: --source and --sources-file; without them, the vertices "
    "selected in a PLY saved by MeshLab (vertex flags). Output by extension: .ply (distance as "
    "vertex quality, colormap as vertex colors, sources as the saved selection), .npy (float64 "
    "array) or .csv (index,distance); unreachable vertices get inf.",
)
def run_distance(args):
    """Run ``heatcore distance``: read the sources and the mesh, solve, write each output; returns 0.

    Examples
    --------
    >>> import tempfile
    >>> from heatcore.io import demo_mesh_path
    >>> tmp = tempfile.TemporaryDirectory()
    >>> out = Path(tmp.name) / "d.npy"
    >>> run_distance(build_parser().parse_args(["distance", str(demo_mesh_path()), "-s", "0", "-o", str(out)]))
    ... # doctest: +ELLIPSIS
    wrote .../d.npy
    0
    >>> float(np.load(out)[0]), np.load(out).shape
    (0.0, (2930,))
    >>> tmp.cleanup()
    """
    curves = args.isolines_out[0] if args.isolines_out else None
    if not args.output and args.png is None and curves is None:
        raise UsageError("nothing to write: give -o/--output FILE (.ply, .npy, .csv), --png PATH "
                         "and/or --isolines-out PATH [N]")
    check_output_paths(args.output, args.png, [args.mesh, *(args.sources_file or [])], args.overwrite, curves)
    settings = settings_of(args, intent="one query")  # one source set: the backend that factors fastest
    given = command_line_sources(args)
    with timed_stage("read mesh"):
        mesh = read_mesh_file(args.mesh, settings.domain)
    check_outputs_fit(args.output, args.png, mesh.kind, curves)
    log.info("%s: %d vertices", {"points": "point cloud", "tet": "tetrahedral mesh"}.get(mesh.kind, f"{mesh.kind} mesh"),
             len(mesh.vertices))
    sources, origin = gather_sources(args, mesh, given)
    check_sources(sources, len(mesh.vertices))
    log.info("sources: %d from %s", sources.size, origin)
    try:
        solver = build_solver(mesh, settings, only_parts_of=sources)  # one query: the sources' parts alone
    except InvalidMeshError as exc:  # the arrays read are checked here: say which file they came from
        raise InvalidMeshError(f"{args.mesh}: {exc}") from exc
    with timed_stage("query"):
        d = solver.distance(sources)
    log.info("%s", distance_summary(d, source_parts(solver, sources)))
    cells = mesh.cells if mesh.kind == "tet" else mesh.surface
    with timed_stage("write"):
        for out in args.output:
            faces = cells if Path(out).suffix.lower() in VOLUME_OUTPUT_SUFFIXES else mesh.surface
            write_output(out, mesh.vertices, faces if faces is not None else np.zeros((0, 3), int), d,
                         sources, args.colormap, args.isolines)
            print(f"wrote {out}")
    if args.png is not None:
        with timed_stage("render"):
            view = args.view if args.view is not None else view_facing(mesh.vertices, mesh.surface, int(sources[0]))
            render_png(args.png, mesh.vertices, mesh.surface, d, sources, args.colormap, args.isolines,
                       title=args.mesh.name, view=view)
        print(f"wrote {args.png}")
    if curves is not None:
        with timed_stage("isolines"):
            count = args.isolines_out[1] or args.isolines or PNG_ISOLINES  # N omitted: the PNG's lines
            written = write_isolines(curves, mesh.vertices, mesh.surface, d, count)
        print(f"wrote {curves}  ({len(written)} isoline curves)")
    return 0


# --------------------------------------------------------------------------- demo


@command(
    "demo",
    arguments=demo_arguments,
    help="distance from spot's nose on the bundled mesh: writes demo.ply and demo.png",
    description="Run the heat method on the bundled spot mesh (Keenan Crane, public domain) from a "
    f"vertex at the tip of the nose (vertex {DEMO_SOURCE}), and write demo.ply (distance as vertex "
    "quality and colors) and demo.png (a picture with isolines) into the output folder.",
)
def run_demo(args):
    """Run ``heatcore demo``: distance from spot's nose, written as demo.ply and demo.png; returns 0.

    Examples
    --------
    >>> import tempfile
    >>> tmp = tempfile.TemporaryDirectory()
    >>> run_demo(build_parser().parse_args(["demo", "-d", tmp.name, "--refine", "0"]))  # doctest: +ELLIPSIS
    wrote .../demo.ply  (distance as vertex quality and colors; open it in MeshLab)
    wrote .../demo.png
    spot: 2930 vertices, source vertex 1453; precompute ... ms, query ... ms, max distance ...
    0
    >>> tmp.cleanup()
    """
    from ..io.mesh import demo_mesh_path

    out_dir = Path(args.output_dir)
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise CliError(f"cannot create output folder {out_dir}: {exc.strerror or exc}") from exc
    with timed_stage("read mesh"):
        mesh = read_mesh_file(demo_mesh_path())
    log.info("mesh: spot, %d vertices, %d triangles", len(mesh.vertices), len(mesh.surface))
    sources = np.array([DEMO_SOURCE])
    solver = build_solver(mesh, settings_of(args, intent="one query"))
    with timed_stage("query"):
        d = solver.distance(sources)
    log.info("%s", distance_summary(d))
    ply, png = out_dir / "demo.ply", out_dir / "demo.png"
    with timed_stage("write"):
        write_output(ply, mesh.vertices, mesh.surface, d, sources, args.colormap, args.isolines)
    with timed_stage("render"):
        render_png(png, mesh.vertices, mesh.surface, d, sources, args.colormap, args.isolines,
                   title="geodesic distance from spot's nose (heat method)", view={**DEMO_VIEW, **(args.view or {})})
    t = timed_stage.timings
    print(f"wrote {ply}  (distance as vertex quality and colors; open it in MeshLab)")
    print(f"wrote {png}")
    print(f"spot: {len(mesh.vertices)} vertices, source vertex {DEMO_SOURCE}; "
          f"precompute {format_seconds(t['precompute'])}, query {format_seconds(t['query'])}, {distance_summary(d)}")
    return 0


@command(
    "meshlab",
    arguments=meshlab_arguments,
    help="MeshLab front end: distance from a mesh's selection, written as PLY quality and colors",
    description="Reads a mesh in any format pymeshlab reads, takes the sources from its saved "
    "selection (PLY vertex flags), --sources or --select, and writes a PLY with the distance as "
    "vertex quality, vertex colors and the selection kept, ready to open in MeshLab. Needs pymeshlab.",
)
def run_meshlab(args):
    """Run ``heatcore meshlab`` (:func:`heatcore.apps.meshlab.run`) and print its report; returns 0.

    Examples
    --------
    >>> import pytest, tempfile
    >>> _ = pytest.importorskip("pymeshlab")  # the test extra
    >>> from heatcore.io import demo_mesh_path
    >>> tmp = tempfile.TemporaryDirectory()
    >>> out = str(Path(tmp.name) / "spot.ply")
    >>> run_meshlab(build_parser().parse_args(["meshlab", str(demo_mesh_path()), "--sources", "0", "-o", out]))
    ... # doctest: +ELLIPSIS
    1 source vertices, 2930 vertices, 5856 faces
    distance: min 0, max ...
    time: setup ...
    wrote .../spot.ply (quality = distance, colours: viridis, selection kept)
    0
    >>> tmp.cleanup()
    """
    from . import meshlab

    try:
        stats = meshlab.run(args)
    except HeatcoreError as exc:  # every refusal is a usage or input problem (docs/meshlab.md): status 2
        exc.exit_status = meshlab.EXIT_INPUT_ERROR
        raise
    print(meshlab.format_report(stats, as_json=args.json))
    return 0


command("logmap", arguments=logmap_arguments,
        help="geodesic polar coordinates around a vertex (the log map): UVs in a PLY, or .npy/.csv",
        description="The logarithmic map from one vertex by the vector heat method: for every vertex, the "
        "distance r and the direction θ in which the geodesic leaves the source, as r (cos θ, sin θ) in mesh "
        "units (decal UVs). Output by extension: .ply (vertex texture coordinates, read as a UV map by "
        "Blender and as texture coordinates by MeshLab; the distance as quality and colors), .npy or .csv "
        "(index,u,v); unreachable vertices get inf.")(run_logmap)
command("path", arguments=path_arguments, help=PATH_HELP, description=PATH_DESCRIPTION)(run_path)
command("trace", arguments=trace_arguments, help=TRACE_HELP, description=TRACE_DESCRIPTION)(run_trace)
command("signed", arguments=signed_arguments, help=SIGNED_HELP, description=SIGNED_DESCRIPTION)(run_signed)
command("straighten", arguments=straighten_arguments, help=STRAIGHTEN_HELP,
        description=STRAIGHTEN_DESCRIPTION)(run_straighten)


# --------------------------------------------------------------------------- batch


@command(
    "batch",
    arguments=batch_arguments,
    help="distances for many mesh files (local processes or a Dask cluster): .npz per mesh + summary.csv",
    description="Geodesic distance for every mesh file of folders or glob patterns: each mesh is read and "
    "factored once, then all its sources are solved against it. Results: OUTPUT_DIR/NAME.npz "
    "(sources, distances one row per source; large results as per-block .npy files under the "
    "--max-memory bound) and summary.csv (file, vertices, sources, seconds, status, error). A bad mesh "
    "is reported with status 'error' and the batch goes on; existing outputs are skipped (resume). "
    "Runs on a local process pool, or on a dask.distributed cluster with --scheduler.",
)
def run_batch_command(args):
    """Run ``heatcore batch`` (:func:`heatcore.apps.batch.run_batch`); returns 0, or 1 if a mesh failed.

    Examples
    --------
    >>> import tempfile
    >>> from heatcore.io import demo_mesh_path
    >>> tmp = tempfile.TemporaryDirectory()
    >>> argv = ["batch", str(demo_mesh_path()), "-o", tmp.name, "--sources", "0,17", "-j", "0", "-q"]
    >>> run_batch_command(build_parser().parse_args(argv))  # doctest: +ELLIPSIS
    wrote .../summary.csv: 1 done, 0 skipped (already done), 0 failed
    0
    >>> tmp.cleanup()
    """
    from .batch import SUMMARY_NAME, parse_sources, run_batch

    spec = parse_sources(source_text(args.sources), suffix=args.sources_file_suffix, union=args.union)
    rows = run_batch(args.inputs, args.output_dir, spec, scheduler=args.scheduler, workers=args.workers,
                     max_memory_mb=args.max_memory, settings=settings_of(args, "batch"), progress=not args.quiet,
                     resume_only=args.resume_only)
    counts = {status: sum(r["status"] == status for r in rows) for status in ("ok", "skipped", "error")}
    for r in rows:
        if r["status"] == "error":
            log.warning("%s: %s", r["file"], r["error"])
    print(f"wrote {args.output_dir / SUMMARY_NAME}: {counts['ok']} done, {counts['skipped']} skipped "
          f"(already done), {counts['error']} failed")
    return 0 if counts["error"] == 0 else 1


# --------------------------------------------------------------------------- main


def build_parser():
    """The ``heatcore`` argument parser: one subparser per :data:`COMMANDS` entry, its ``run`` as default.

    Examples
    --------
    >>> args = build_parser().parse_args(["distance", "spot.obj", "-s", "3", "-o", "d.npy"])
    >>> args.command, args.run is run_distance, args.source
    ('distance', True, [3])
    """
    from .. import __version__

    parser = OneLineErrorParser(
        prog="heatcore",
        description="Geodesic distance on meshes by heat flow (Crane, Weischedel, Wardetzky 2013). "
        "Run 'heatcore COMMAND --help' for the options of a command.",
    )
    parser.add_argument("--version", action="version", version=f"heatcore {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name, cmd in COMMANDS.items():
        p = sub.add_parser(name, help=cmd.help, description=cmd.description)
        cmd.arguments(p)
        p.set_defaults(run=cmd.run)
    return parser


def main(argv=None):
    """Run the ``heatcore`` command; returns the exit status.

    Parameters
    ----------
    argv : list of str, optional
        Arguments without the program name (default: ``sys.argv[1:]``).

    Returns
    -------
    int
        0 done, 1 a file is bad (or a mesh of a batch failed), 2 a usage
        error, 130 interrupted; errors go to stderr as one line.

    Examples
    --------
    >>> import tempfile
    >>> from heatcore.io import demo_mesh_path
    >>> tmp = tempfile.TemporaryDirectory()
    >>> out = str(Path(tmp.name) / "d.csv")
    >>> main(["distance", str(demo_mesh_path()), "-s", "0", "-o", out, "-q"])  # doctest: +ELLIPSIS
    wrote .../d.csv
    0
    >>> main(["distance", str(demo_mesh_path()), "-s", "0", "-o", str(Path(tmp.name) / "d.txt")])
    2
    >>> tmp.cleanup()
    """
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help, --version, usage errors
        return exc.code if isinstance(exc.code, int) else 1

    root = logging.getLogger("heatcore")
    handler = StderrHandler()
    saved = root.level, root.propagate
    root.addHandler(handler)
    root.setLevel(logging.WARNING if args.quiet else logging.INFO)
    root.propagate = False
    timed_stage.timings = {}
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("always", HeatcoreWarning)
            warnings.showwarning = show_warning
            return args.run(args)
    except (HeatcoreError, OSError) as exc:
        message = str(exc)
        if isinstance(exc, OSError) and exc.filename is not None:
            message = f"{exc.filename}: {exc.strerror or exc}"
        sys.stderr.write(f"heatcore: error: {short(message, 600)}\n")
        return getattr(exc, "exit_status", 1)
    except KeyboardInterrupt:
        sys.stderr.write("heatcore: interrupted\n")
        return 130
    finally:
        root.removeHandler(handler)
        root.setLevel(saved[0])
        root.propagate = saved[1]


if __name__ == "__main__":
    sys.exit(main())
