"""PyMeshLab front end: a MeshLab-style filter from a vertex selection to geodesic distance.

MeshLab has no Python plugin API, so the front end is a function that acts like
a filter on a :class:`pymeshlab.MeshSet`'s current mesh
(:func:`geodesic_distance_from_selection`), and a command (:func:`main`) that
MeshLab users run on files they export from MeshLab and open again there:

    python scripts/heatcore_meshlab.py scan.ply -o scan_distance.ply
    python scripts/heatcore_meshlab.py scan.obj --sources 0 17 -o out.ply
    python scripts/heatcore_meshlab.py scan.obj --select "(y > 0.9)" -o out.ply

The filter (:mod:`heatcore.apps.meshlab_filter`, re-exported here) reads the
selection as sources, writes the distance as vertex quality (what MeshLab's
colour and selection tools use) and as a custom vertex scalar attribute,
colours the vertices, and returns statistics. No numerics live here: the
distance comes from :class:`heatcore.HeatSolver`. The command offers the
options of ``FRONT_END_OPTIONS["meshlab"]`` (:mod:`heatcore.settings`), each
generated from its declaration in :mod:`heatcore.options`, and turns them into
one :class:`~heatcore.settings.Settings` built for one query (:func:`settings_of`).

pymeshlab is imported inside functions only (see DESIGN.md: ``bpy`` must be
imported before pymeshlab in a process).

Examples
--------
In a PyMeshLab script (not run as a doctest: it needs pymeshlab and a mesh file)::

    import pymeshlab
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh("spot.obj")
    ms.compute_selection_by_condition_per_vertex(condselect="vi == 0")
    stats = geodesic_distance_from_selection(ms, colormap="viridis", isolines=10)
    ms.current_mesh().vertex_scalar_array()  # the distance, as quality
"""

import argparse
import json
import logging
import sys
from pathlib import Path

import numpy as np

from .. import options
from ..errors import (
    HeatcoreError,
    InvalidMeshError,
    InvalidOptionError,
    InvalidSourceError,
)
from ..io.files import check_input_file
from ..settings import FRONT_END_OPTIONS, Settings
from .inputs import SOURCE_FLAGS, SourcesAction
from .meshlab_filter import (  # noqa: F401 - re-exported: the filter's public names
    COLORMAP_CHOICES,
    DEFAULT_ATTRIBUTE,
    DEFAULT_UNREACHABLE,
    EXTRA_COLORMAPS,
    MESHLAB_COLORMAPS,
    current_mesh,
    distance_from_selection,
    geodesic_distance_from_selection,
    write_vertex_attribute,
)
from .meshlab_signed import signed_from_arguments, signed_summary
from .outputs import atomic_output

#: Exit status of a usage or input problem (no selection, a missing file, ...), as docs/meshlab.md says:
#: the script and ``heatcore meshlab`` both.
EXIT_INPUT_ERROR = 2

#: Options of :mod:`heatcore.options` on this command line: those the MeshLab front end offers.
OPTION_NAMES = FRONT_END_OPTIONS["meshlab"]


def build_parser(prog=None):
    """The argument parser of :func:`main` (also used by ``heatcore meshlab``).

    Parameters
    ----------
    prog : str, optional
        The program name in usage and error lines.

    Examples
    --------
    >>> args = build_parser("heatcore_meshlab.py").parse_args(["scan.ply", "--select", "(y > 0.9)"])
    >>> args.select, args.output, args.colormap
    ('(y > 0.9)', None, 'viridis')
    """
    parser = argparse.ArgumentParser(
        prog=prog,
        description=(
            "Geodesic distance from a selection, for MeshLab: reads a mesh in any format pymeshlab "
            "reads, takes the sources from its saved selection (PLY vertex flags), from --sources or "
            "from --select, and writes a PLY with the distance as vertex quality, vertex colours and "
            "the selection kept, ready to open in MeshLab."
        ),
    )
    add_arguments(parser)
    return parser


def add_arguments(parser):
    """Add this command's arguments to an argparse parser (for a ``heatcore meshlab`` subcommand).

    The options of :data:`OPTION_NAMES` come from :mod:`heatcore.options`
    (MeshLab's ramps and ``none`` added to the colormaps).

    Returns
    -------
    argparse.ArgumentParser
        ``parser``.

    Examples
    --------
    >>> p = add_arguments(argparse.ArgumentParser(prog="meshlab"))
    >>> args = p.parse_args(["scan.obj", "--sources", "0", "17", "--colormap", "meshlab-turbo"])
    >>> args.sources, args.colormap, args.ascii
    ([0, 17], 'meshlab-turbo', False)
    >>> p.parse_args(["scan.obj", "-s", "0,17"]).sources
    [0, 17]
    """
    parser.add_argument("input", help="mesh file (PLY, OBJ, OFF, STL, ... anything pymeshlab reads)")
    parser.add_argument("-o", "--output", help="output PLY (default: INPUT stem + '_distance.ply')")
    src = parser.add_mutually_exclusive_group()
    src.add_argument(
        *SOURCE_FLAGS, dest="sources", action=SourcesAction, metavar="VERTEX",
        help="source vertex indices, 0-based (replace the file's selection): -s 0 17, -s 0,17 and -s 0 -s 17 "
             "mean the same (also --source, --sources)",
    )  # fmt: skip
    src.add_argument(
        "--select", metavar="CONDITION",
        help="MeshLab per-vertex condition selecting the sources, e.g. \"(y > 0.9)\" or \"vi == 0\"",
    )  # fmt: skip
    for name in OPTION_NAMES:
        if name == "colormap":
            options.add_argument(parser, name, front_end="meshlab", extra=EXTRA_COLORMAPS,
                                 note="also MeshLab's ramps (meshlab-*), or none (colours untouched)")
        else:
            options.add_argument(parser, name, front_end="meshlab")
    parser.add_argument(
        "--unreachable", type=float, default=DEFAULT_UNREACHABLE,
        help="quality of vertices no source reaches (default -1)",
    )  # fmt: skip
    parser.add_argument("--signed", action="store_true",
                        help="signed distance to the border of the selected faces instead (the file's saved face "
                             "selection, or --select-faces), positive inside, blue-to-red colours (docs/signed.md)")
    parser.add_argument("--select-faces", metavar="CONDITION",
                        help="with --signed: MeshLab per-face condition selecting the region, e.g. \"(x0 > 0)\"")
    parser.add_argument("--ascii", action="store_true", help="write an ASCII PLY (default binary)")
    parser.add_argument("--json", action="store_true", help="print the statistics as JSON")
    parser.add_argument("-q", "--quiet", action="store_true", help="no progress or timing lines on stderr")
    return parser


def run(args):
    """Run the command for parsed arguments; returns the statistics (raises heatcore errors).

    Loads the input with pymeshlab, selects the sources (``--sources``,
    ``--select``, or the file's saved selection), runs
    :func:`distance_from_selection` with the run's settings (:func:`settings_of`)
    and writes the PLY atomically.

    Returns
    -------
    dict
        The statistics of :func:`geodesic_distance_from_selection`, with ``output``.

    Raises
    ------
    heatcore.errors.HeatcoreError
        No pymeshlab; :class:`~heatcore.errors.InvalidMeshError` (unreadable
        input), :class:`~heatcore.errors.InvalidOptionError` (output not a new
        ``.ply``), :class:`~heatcore.errors.InvalidSourceError` (no source).

    Examples
    --------
    >>> import pytest, tempfile
    >>> _ = pytest.importorskip("pymeshlab")  # the test extra
    >>> from heatcore.io import demo_mesh_path
    >>> tmp = tempfile.TemporaryDirectory()
    >>> out = Path(tmp.name) / "spot.ply"
    >>> stats = run(build_parser().parse_args([str(demo_mesh_path()), "--sources", "0", "-o", str(out)]))
    >>> stats["sources"], stats["vertices"], stats["unreachable"], stats["output"] == str(out), out.is_file()
    (1, 2930, 0, True, True)
    >>> tmp.cleanup()
    """
    try:
        import pymeshlab
    except ImportError as exc:
        raise HeatcoreError("this command needs pymeshlab: pip install pymeshlab") from exc

    path = Path(args.input)
    if not path.exists():
        raise InvalidMeshError(f"input file {path} does not exist")
    check_input_file(path)  # a folder, FIFO, device, compressed or cut-short file: said as such
    output = Path(args.output) if args.output else path.with_name(path.stem + "_distance.ply")
    if output.suffix.lower() != ".ply":
        raise InvalidOptionError(f"output {output} must be a .ply file (MeshLab keeps quality and selection in PLY)")
    if output.resolve() == path.resolve():
        raise InvalidOptionError(f"output {output} would overwrite the input; choose another name")

    ms = pymeshlab.MeshSet()
    try:
        ms.load_new_mesh(str(path))
    except pymeshlab.PyMeshLabException as exc:
        raise InvalidMeshError(f"pymeshlab cannot read {path}: {exc}") from exc
    mesh = current_mesh(ms)
    if args.signed:
        stats = signed_from_arguments(ms, args)
        _save_ply(ms, output, binary=not args.ascii)
        stats["output"] = str(output)
        return stats
    if args.select_faces is not None:
        raise InvalidOptionError("--select-faces selects the region of --signed; sources are vertices: --select")
    if args.sources is not None:
        _select_vertices(ms, mesh, args.sources)
    elif args.select is not None:
        problem = check_condition(args.select)
        if problem:
            raise InvalidSourceError(f"MeshLab cannot evaluate --select {args.select!r}: {problem}")
        ms.compute_selection_by_condition_per_vertex(condselect=args.select)
        if not mesh.vertex_selection_array().any():
            raise InvalidSourceError(f"--select {args.select!r} selects no vertex")

    stats = distance_from_selection(ms, settings_of(args), colormap=args.colormap, unreachable=args.unreachable)
    _save_ply(ms, output, binary=not args.ascii)
    stats["output"] = str(output)
    return stats


def settings_of(args):
    """The run's :class:`~heatcore.settings.Settings` (MeshLab, one query) from parsed arguments.

    The colormap stays with the command (MeshLab's ramps are not heatcore's
    colormaps); every other option of :data:`OPTION_NAMES` goes in.

    Examples
    --------
    >>> s = settings_of(build_parser().parse_args(["scan.ply", "--m", "2", "--backend", "superlu"]))
    >>> s.solver.m, s.solver.backend, s.solver.intent, s.output.isolines
    (2.0, 'superlu', 'one query', 0)
    """
    values = {name: getattr(args, name) for name in OPTION_NAMES if name != "colormap"}
    return Settings.of("meshlab", intent="one query", **values)


_CHECK_CONDITION = """
import sys, numpy as np, pymeshlab
ms = pymeshlab.MeshSet()
ms.add_mesh(pymeshlab.Mesh(np.eye(3), np.array([[0, 1, 2]], dtype=np.int32)))
try:
    ms.compute_selection_by_condition_per_vertex(condselect=sys.argv[1])
except pymeshlab.PyMeshLabException as exc:
    print(str(exc).strip().splitlines()[-1])
"""


def check_condition(condition):
    """Why MeshLab cannot parse a per-vertex condition, or ``""`` when it can.

    The check runs in a child process: in pymeshlab 2025.7 a condition that
    fails to parse corrupts the process's memory (a later ``load_new_mesh``
    crashes with ``std::bad_alloc`` or a segmentation fault).

    Examples
    --------
    >>> import pytest
    >>> _ = pytest.importorskip("pymeshlab")  # the test extra
    >>> check_condition("vi == 0"), check_condition("vi === 1")  # doctest: +ELLIPSIS
    ('', '...Unexpected operator "=" found at position 5')
    """
    import subprocess

    try:
        done = subprocess.run(
            [sys.executable, "-c", _CHECK_CONDITION, condition], capture_output=True, text=True, timeout=120
        )
    except subprocess.TimeoutExpired:
        return "checking the condition timed out"
    if done.returncode != 0:
        return f"the check crashed ({done.stderr.strip().splitlines()[-1:] or done.returncode})"
    return done.stdout.strip()


def _select_vertices(ms, mesh, indices):
    """Make exactly ``indices`` the vertex selection (faces deselected)."""
    n = mesh.vertex_number()
    idx = options.check_source_vertices(indices, n)
    flags = np.zeros(n)
    flags[idx] = 1.0
    write_vertex_attribute(ms, mesh, "heatcore_sources", flags)
    ms.set_selection_none(allfaces=True, allverts=True)
    ms.compute_selection_by_condition_per_vertex(condselect="heatcore_sources > 0.5")


def _save_ply(ms, output, binary=True):
    """Write the current mesh as PLY with quality, colours and selection; no partial file on failure.

    Written as every heatcore writer writes (:func:`heatcore.apps.outputs.atomic_output`):
    a temporary file beside the output, created with the process's umask (0644 under
    the usual 022, not a private temporary file's 0600), renamed over the output.
    """
    with atomic_output(output) as tmp:
        ms.save_current_mesh(
            str(tmp),
            binary=binary,
            save_vertex_quality=True,
            save_vertex_color=True,
            save_vertex_flag=True,
            save_face_flag=True,
        )


def _summary(stats):
    s = stats["seconds"]
    lines = [
        f"{stats['sources']} source {stats['source_kind']}, {stats['vertices']} vertices, {stats['faces']} faces",
        f"distance: min {stats['min']:.6g}, max {stats['max']:.6g}, mean {stats['mean']:.6g}"
        + (f"; {stats['unreachable']} vertices unreachable" if stats["unreachable"] else ""),
        f"time: setup {s['setup']:.3f} s, distance {s['distance']:.3f} s, write {s['write']:.3f} s",
        f"wrote {stats['output']} (quality = distance, colours: {stats['colormap']}, selection kept)",
    ]
    return "\n".join(lines)


def main(argv=None, prog=None):
    """Command-line entry point; returns the exit status (0 success, 2 usage or input error).

    Examples
    --------
    >>> import pytest, tempfile
    >>> _ = pytest.importorskip("pymeshlab")  # the test extra
    >>> from heatcore.io import demo_mesh_path
    >>> tmp = tempfile.TemporaryDirectory()
    >>> out = str(Path(tmp.name) / "spot_distance.ply")
    >>> main([str(demo_mesh_path()), "--sources", "0", "-o", out, "--json"])  # doctest: +ELLIPSIS
    {
      "sources": 1,
      "source_kind": "vertices",
      "vertices": 2930,
    ...
    0
    >>> main([str(Path(tmp.name) / "missing.ply")])  # the error goes to stderr
    2
    >>> tmp.cleanup()
    """
    parser = build_parser(prog)
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help, usage errors (exit status 2)
        return exc.code if isinstance(exc.code, int) else 1
    logger = logging.getLogger("heatcore")
    saved = logger.level
    if args.quiet:
        logger.setLevel(logging.WARNING)
    try:
        stats = run(args)
    except HeatcoreError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_INPUT_ERROR
    finally:
        logger.setLevel(saved)
    print(format_report(stats, as_json=args.json))
    return 0


def format_report(stats, as_json=False):
    """The command's printed report: a summary, or the statistics as JSON.

    Parameters
    ----------
    stats : dict
        What :func:`run` returns (the distance array and the solver are left out of the JSON).
    as_json : bool, default False

    Examples
    --------
    >>> stats = {"sources": 1, "source_kind": "vertices", "vertices": 3, "faces": 1, "min": 0.0, "max": 1.0,
    ...          "mean": 0.6667, "unreachable": 0, "colormap": "viridis", "output": "tri_distance.ply",
    ...          "seconds": {"setup": 0.002, "distance": 0.0001, "write": 0.001}, "distance": np.zeros(3)}
    >>> print(format_report(stats))
    1 source vertices, 3 vertices, 1 faces
    distance: min 0, max 1, mean 0.6667
    time: setup 0.002 s, distance 0.000 s, write 0.001 s
    wrote tri_distance.ply (quality = distance, colours: viridis, selection kept)
    >>> json.loads(format_report(stats, as_json=True))["max"]
    1.0
    """
    if as_json:
        return json.dumps({k: v for k, v in stats.items() if k not in ("distance", "solver")}, indent=2)
    return signed_summary(stats) if "curves" in stats else _summary(stats)
