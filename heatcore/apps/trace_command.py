"""The ``heatcore trace`` command: the straightest geodesic from a point of a mesh file along a direction.

``heatcore trace MESH --from A --direction X Y Z --length L -o trace.obj``
reads the mesh, traces :func:`heatcore.paths.tracing.trace` (as
:meth:`heatcore.HeatSolver.trace`) and writes the polyline as ``heatcore path``
does (``.obj``, ``.ply``, ``.csv``); the length travelled, why the walk
stopped and where it ended go to stdout. ``A`` is a vertex index (0-based) or
``FACE:B0,B1,B2``; the direction is a 3D vector (projected on the tangent
plane at ``A``) or two coordinates in ``A``'s tangent basis (the vector heat
method's, as ``heatcore logmap`` uses it). The mesh options (``--weld``,
``--refine``, ...) are those of the other commands; no solver is built.

Exit status as for ``heatcore path``: 2 for a command line that is wrong
before any file is read, 1 for a bad mesh, start or direction.

Examples
--------
>>> import tempfile
>>> from pathlib import Path
>>> from heatcore.io import demo_mesh_path
>>> from heatcore.apps.cli import main
>>> tmp = tempfile.TemporaryDirectory()
>>> out = str(Path(tmp.name) / "t.csv")
>>> main(["trace", str(demo_mesh_path()), "--from", "0", "--direction", "0", "0", "1", "--length", "0.5",
...       "-o", out, "-q"])  # doctest: +ELLIPSIS
length 0.5 (stopped: length, ... points), end ...:...,...,...
wrote .../t.csv
0
>>> tmp.cleanup()
"""

import argparse
import logging
from pathlib import Path

from .. import options
from .arguments import add_common_options, solver_option_names
from .inputs import SourcesAction
from .outputs import UsageError
from .path_command import surface_point
from .polylines import (
    add_polyline_arguments,
    check_outputs,
    count_points,
    read_domain,
    write_outputs,
)
from .reporting import timed_stage

log = logging.getLogger("heatcore.apps.cli")

TRACE_HELP = "the straightest geodesic from a point along a direction, as a polyline (.obj, .vtk, .ply, .csv)"
TRACE_DESCRIPTION = (
    "Trace the straightest geodesic on the surface of a triangle mesh from a point (a vertex index, or "
    "FACE:B0,B1,B2 inside a face) along a direction (X Y Z, projected on the tangent plane; or X Y in the "
    "start vertex's tangent basis) for a length: straight across every face and edge, with half the angle "
    "on either side where it meets a vertex, stopping at the length or the boundary. Output by extension: "
    ".obj (v and l elements), .vtk (VTK line cells), .ply (vertex and edge elements), .csv (x,y,z); which "
    "reader keeps the segments: see -o. The length travelled, why it "
    "stopped and the end point (FACE:B0,B1,B2, a start for another trace) are printed."
)


def length_value(text):
    """Parse ``--length``: a finite number >= 0.

    Examples
    --------
    >>> length_value("2.5")
    2.5
    >>> length_value("-1")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: the length is a number >= 0, got '-1'
    """
    try:
        value = float(text)
    except ValueError:
        value = -1.0
    if not (value >= 0.0 and value < float("inf")):
        raise argparse.ArgumentTypeError(f"the length is a number >= 0, got {text!r}")
    return value


def trace_arguments(p):
    """Add the arguments of ``heatcore trace``: the mesh, the start, the direction, the length, outputs.

    Examples
    --------
    >>> from heatcore.apps.arguments import OneLineErrorParser
    >>> p = OneLineErrorParser(prog="heatcore trace")
    >>> trace_arguments(p)
    >>> args = p.parse_args(["spot.obj", "--from", "5:0.2,0.3,0.5", "--direction", "1", "0", "0",
    ...                      "--length", "2", "-o", "t.obj"])
    >>> args.start, args.direction, args.length
    ((5, [0.2, 0.3, 0.5]), [1.0, 0.0, 0.0], 2.0)
    """
    add_polyline_arguments(p)
    p.add_argument("--from", dest="start", action=SourcesAction, parse=surface_point, single=True, what="start point",
                   required=True, metavar="POINT",
                   help="where the trace starts: a vertex index, or FACE:B0,B1,B2 for a point inside a face")
    p.add_argument("--direction", type=float, nargs="+", required=True, metavar="X",
                   help="X Y Z: a 3D vector, projected on the tangent plane at the start; or X Y: coordinates in "
                        "the start vertex's tangent basis (the vector heat method's); its length does not matter")
    p.add_argument("--length", type=length_value, required=True, metavar="L",
                   help="how far to go, in mesh units (the trace stops earlier at the boundary)")
    add_mesh_options(p)
    add_common_options(p)


def add_mesh_options(parser):
    """Add the command line's mesh options (``--weld``, ``--refine``, ...): a trace builds no solver.

    Examples
    --------
    >>> from heatcore.apps.arguments import OneLineErrorParser
    >>> p = OneLineErrorParser(prog="demo")
    >>> add_mesh_options(p)
    >>> args = p.parse_args(["--refine", "0"])
    >>> args.refine, hasattr(args, "m")
    (0, False)
    """
    group = parser.add_argument_group("mesh options")
    for name in solver_option_names("cli"):
        if options.OPTIONS[name].target == "mesh":
            options.add_argument(group, name, front_end="cli")


def run_trace(args):
    """Run ``heatcore trace``: read the mesh, trace, write each output; returns 0.

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> from heatcore.io import demo_mesh_path
    >>> from heatcore.apps.cli import build_parser
    >>> tmp = tempfile.TemporaryDirectory()
    >>> out = Path(tmp.name) / "t.obj"
    >>> run_trace(build_parser().parse_args(["trace", str(demo_mesh_path()), "--from", "0", "--direction", "0",
    ...                                      "0", "1", "--length", "0", "-o", str(out)]))  # doctest: +ELLIPSIS
    length 0 (stopped: length, 1 point), end ...:...,...,...
    wrote .../t.obj
    0
    >>> tmp.cleanup()
    """
    if len(args.direction) not in (2, 3):
        raise UsageError(f"--direction takes 3 numbers (X Y Z) or 2 (X Y in the tangent basis), got "
                         f"{len(args.direction)}")
    check_outputs(args.output, args.mesh, args.overwrite)
    domain, _ = read_domain(args)
    from ..paths.tracing import trace

    with timed_stage("trace"):
        path = trace(domain, args.start, args.direction, args.length)
    face, bary = path.end
    print(f"length {path.length:.10g} (stopped: {path.stopped}, {count_points(path.points)}), end {face}:"
          f"{','.join(f'{b:.17g}' for b in bary)}")
    header = (f"heatcore trace from {args.start} along {' '.join(f'{x:g}' for x in args.direction)} on "
              f"{Path(args.mesh).name}, length {path.length:.17g} (stopped: {path.stopped})")
    write_outputs(args.output, path.points, header)
    return 0
