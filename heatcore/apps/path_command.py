"""The ``heatcore path`` command: the geodesic path between two points of a mesh file, as a polyline file.

``heatcore path MESH --from A --to B -o path.obj`` reads the mesh, builds the
solver (the usual solver options), computes :meth:`heatcore.HeatSolver.geodesic_path`
and writes the polyline; the length goes to stdout. ``A`` and ``B`` are vertex
indices (0-based) or surface points ``FACE:B0,B1,B2`` (a face index and three
barycentric coordinates). ``--through A B C ...`` (instead of ``--from`` and
``--to``) gives one path through the waypoints, a geodesic from each to the
next, and ``--closed`` back to the first; each leg's length is printed too.
Outputs, by extension (``-o`` may be repeated): ``.obj``, ``.ply``, ``.csv``,
written as by every polyline command (:mod:`heatcore.apps.polylines`).

Exit status as for the other commands: 2 for a command line that is wrong
before any file is read (a point that is not an index or ``FACE:B0,B1,B2``,
an unknown extension), 1 for a bad mesh or points the mesh does not have (a
vertex index beyond it, a target in another part than the source), each
with a one-line message.

Examples
--------
>>> import tempfile
>>> from pathlib import Path
>>> from heatcore.io import demo_mesh_path
>>> from heatcore.apps.cli import main
>>> tmp = tempfile.TemporaryDirectory()
>>> out = str(Path(tmp.name) / "p.csv")
>>> main(["path", str(demo_mesh_path()), "--from", "0", "--to", "1453", "-o", out, "-q"])  # doctest: +ELLIPSIS
length 1.0865864... (50 points)
wrote .../p.csv
0
>>> tmp.cleanup()
"""

import argparse
import logging
from pathlib import Path

from ..errors import InvalidMeshError
from .arguments import add_common_options, add_solver_options
from .inputs import SourcesAction, parse_vertex_index
from .outputs import UsageError
from .polylines import (
    add_polyline_arguments,
    check_outputs,
    count_points,
    read_domain,
    write_outputs,
    write_path,  # noqa: F401 (kept importable from here)
)
from .reporting import timed_stage

log = logging.getLogger("heatcore.apps.cli")

PATH_HELP = "the geodesic path between two points of a triangle mesh, as a polyline (.obj, .vtk, .ply, .csv)"
PATH_DESCRIPTION = (
    "Shortest path on the surface of a triangle mesh between two points, each a vertex index (0-based) "
    "or a point inside a face, FACE:B0,B1,B2 (face index and barycentric coordinates), or through waypoints "
    "(--through, one geodesic per leg; --closed back to the first). The heat "
    "distance from the first point picks the route, which is then straightened into an exact geodesic "
    "on the mesh's faces. Output by extension: .obj (v and l elements: an edge mesh in MeshLab, edges "
    "in Blender), .vtk (VTK line cells), .ply (vertex and edge elements), .csv (x,y,z); which reader keeps "
    "the segments: see -o. The length is printed."
)


def surface_point(text):
    """Parse a command-line point: ``"17"`` (a vertex) or ``"12:0.2,0.3,0.5"`` (face 12, barycentric).

    Examples
    --------
    >>> surface_point("17"), surface_point("12:0.2,0.3,0.5")
    (17, (12, [0.2, 0.3, 0.5]))
    >>> surface_point("12:0.5,0.5")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: a point inside a face is FACE:B0,B1,B2 (three barycentric coordinates), got '12:0.5,0.5'
    """
    if ":" not in text:
        return parse_vertex_index(text)
    face, _, coordinates = text.partition(":")
    try:
        bary = [float(x) for x in coordinates.split(",")]
        index = int(face)
    except ValueError:
        bary, index = [], -1
    if len(bary) != 3 or index < 0:
        raise argparse.ArgumentTypeError(
            f"a point inside a face is FACE:B0,B1,B2 (three barycentric coordinates), got {text!r}")
    return index, bary


def path_arguments(p):
    """Add the arguments of ``heatcore path``: the mesh, the points (two, or waypoints), outputs, solver options.

    Examples
    --------
    >>> from heatcore.apps.arguments import OneLineErrorParser
    >>> p = OneLineErrorParser(prog="heatcore path")
    >>> path_arguments(p)
    >>> args = p.parse_args(["spot.obj", "--from", "0", "--to", "5:0.2,0.3,0.5", "-o", "p.obj"])
    >>> args.source, args.target, args.output
    (0, (5, [0.2, 0.3, 0.5]), ['p.obj'])
    >>> args = p.parse_args(["spot.obj", "--through", "0", "7", "9", "--closed", "-o", "p.obj"])
    >>> args.through, args.closed
    ([0, 7, 9], True)
    """
    add_polyline_arguments(p)
    p.add_argument("--from", dest="source", action=SourcesAction, parse=surface_point, single=True, what="start point",
                   metavar="POINT",
                   help="where the path starts: a vertex index, or FACE:B0,B1,B2 for a point inside a face")
    p.add_argument("--to", dest="target", action=SourcesAction, parse=surface_point, single=True, what="end point",
                   metavar="POINT",
                   help="where the path ends (as --from)")
    p.add_argument("--through", action=SourcesAction, parse=surface_point, metavar="POINT",
                   help="waypoints instead of --from and --to (two or more, as --from): one geodesic from each "
                        "to the next")
    p.add_argument("--closed", action="store_true", help="with --through: back to the first waypoint at the end")
    add_solver_options(p)
    add_common_options(p)


def run_path(args):
    """Run ``heatcore path``: read the mesh, find the path, write each output; returns 0.

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> from heatcore.io import demo_mesh_path
    >>> from heatcore.apps.cli import build_parser
    >>> tmp = tempfile.TemporaryDirectory()
    >>> out = Path(tmp.name) / "p.obj"
    >>> run_path(build_parser().parse_args(["path", str(demo_mesh_path()), "--from", "0", "--to", "0",
    ...                                     "-o", str(out)]))  # doctest: +ELLIPSIS
    length 0 (1 point)
    wrote .../p.obj
    0
    >>> run_path(build_parser().parse_args(["path", str(demo_mesh_path()), "--through", "0", "1453", "20",
    ...                                     "-o", str(out)]))  # doctest: +ELLIPSIS
    length ... (... points), legs ... ...
    wrote .../p.obj
    0
    >>> tmp.cleanup()
    """
    if args.through is not None:
        if args.source is not None or args.target is not None:
            raise UsageError("give either --from and --to, or --through")
        if len(args.through) < 2:
            raise UsageError(f"--through needs at least two points, got {len(args.through)}")
    elif args.source is None or args.target is None:
        raise UsageError("give --from POINT and --to POINT, or --through POINT POINT ...")
    elif args.closed:
        raise UsageError("--closed goes with --through")
    check_outputs(args.output, args.mesh, args.overwrite)
    domain, settings = read_domain(args)
    from ..heat import HeatSolver

    try:
        with timed_stage("precompute"):
            solver = HeatSolver(domain, settings.solver)
    except InvalidMeshError as exc:
        raise InvalidMeshError(f"{args.mesh}: {exc}") from exc
    with timed_stage("path"):
        if args.through is None:
            path = solver.geodesic_path(args.source, args.target)
            what = f"from {_spec(args.source)} to {_spec(args.target)}"
        else:
            path = solver.geodesic_path(points=args.through, closed=args.closed)
            what = f"{'closed, ' if args.closed else ''}through {', '.join(_spec(p) for p in args.through)}"
    legs = "" if args.through is None else ", legs " + " ".join(f"{x:.10g}" for x in path.leg_lengths)
    print(f"length {path.length:.10g} ({count_points(path)}){legs}")
    write_outputs(args.output, path.points,
                  f"heatcore geodesic path {what} on {Path(args.mesh).name}, length {path.length:.17g}")
    return 0


def _spec(point):
    """A point as given on the command line."""
    if isinstance(point, tuple):
        return f"face {point[0]} at ({', '.join(f'{b:g}' for b in point[1])})"
    return f"vertex {point}"
