"""The ``heatcore straighten`` command: an edge path or loop of a mesh file shortened to a geodesic.

``heatcore straighten MESH --path FILE -o path.obj`` reads the mesh and the
path (a text file, one vertex index per line, each joined to the next by an
edge of the mesh; blank lines and ``#`` comments ignored), shortens it with
:func:`heatcore.paths.drawn.straighten_on` (its ends and homotopy class kept,
to a locally shortest geodesic) or, with ``--loop``, with
:func:`heatcore.paths.drawn.straighten_loop_on` (a closed geodesic in the
loop's class), and writes the polyline as ``heatcore path`` does (``.obj``,
``.ply``, ``.csv``). The lengths before and after go to stdout. The mesh
options (``--weld``, ``--refine``, ...) are those of the other commands; no
solver is built.

Exit status as for ``heatcore path``: 2 for a command line that is wrong
before any file is read, 1 for a bad mesh or path file, or a path the mesh
does not have (two consecutive vertices that share no edge).

Examples
--------
>>> import tempfile
>>> from pathlib import Path
>>> from heatcore.io import demo_mesh_path
>>> from heatcore.apps.cli import main
>>> tmp = tempfile.TemporaryDirectory()
>>> edges = Path(tmp.name) / "edges.txt"
>>> _ = edges.write_text("764\\n0\\n767\\n")
>>> main(["straighten", str(demo_mesh_path()), "--path", str(edges), "-o", str(Path(tmp.name) / "s.csv"), "-q"])
... # doctest: +ELLIPSIS
length ... (edge path ..., 2 points)
wrote .../s.csv
0
>>> tmp.cleanup()
"""

import logging
from pathlib import Path

import numpy as np

from .arguments import add_common_options
from .outputs import CliError
from .polylines import (
    add_polyline_arguments,
    check_outputs,
    count_points,
    read_domain,
    write_outputs,
)
from .reporting import timed_stage
from .trace_command import add_mesh_options

log = logging.getLogger("heatcore.apps.cli")

STRAIGHTEN_HELP = "an edge path or loop shortened to a geodesic, as a polyline (.obj, .vtk, .ply, .csv)"
STRAIGHTEN_DESCRIPTION = (
    "Shorten a path along the edges of a triangle mesh (a text file, one vertex index per line, each joined "
    "to the next by an edge) to a locally shortest geodesic with the same ends, on the same side of every "
    "hole and handle; with --loop, a closed edge loop to a closed geodesic around the same holes and handles "
    "(around a cylinder: its circle). Output by extension: .obj (v and l elements), .vtk (VTK line "
    "cells), .ply (vertex and edge elements), .csv (x,y,z); which reader keeps the segments: see -o. The lengths before and after are printed."
)


def straighten_arguments(p):
    """Add the arguments of ``heatcore straighten``: the mesh, the path file, ``--loop``, outputs, mesh options.

    Examples
    --------
    >>> from heatcore.apps.arguments import OneLineErrorParser
    >>> p = OneLineErrorParser(prog="heatcore straighten")
    >>> straighten_arguments(p)
    >>> args = p.parse_args(["spot.obj", "--path", "edges.txt", "--loop", "-o", "s.obj"])
    >>> str(args.path), args.loop, args.output
    ('edges.txt', True, ['s.obj'])
    """
    add_polyline_arguments(p)
    p.add_argument("--path", type=Path, required=True, metavar="FILE",
                   help="text file of vertex indices (0-based), one per line, each joined to the next by an edge; "
                        "blank lines and # comments are ignored")
    p.add_argument("--loop", action="store_true",
                   help="the path is a closed loop (closed by the edge back to its first vertex if it is not): "
                        "shorten it to a closed geodesic, its start free")
    add_mesh_options(p)
    add_common_options(p)


def read_vertex_list(path):
    """The vertex indices of a path file: one integer per line; blank lines and ``#`` comments skipped.

    Raises
    ------
    CliError
        The file cannot be read, holds something else than one integer per line, or fewer than two.

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> tmp = tempfile.TemporaryDirectory()
    >>> f = Path(tmp.name) / "p.txt"
    >>> _ = f.write_text("# a path\\n3\\n 4 \\n\\n9  # the end\\n")
    >>> read_vertex_list(f).tolist()
    [3, 4, 9]
    >>> _ = f.write_text("3\\n4.5\\n")
    >>> read_vertex_list(f)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    heatcore.apps.outputs.CliError: .../p.txt line 2: a vertex index (an integer >= 0) per line, got '4.5'
    >>> tmp.cleanup()
    """
    try:
        text = Path(path).read_text()
    except (OSError, UnicodeDecodeError) as exc:
        raise CliError(f"cannot read path file {path}: {exc}") from None
    out = []
    for number, line in enumerate(text.splitlines(), start=1):
        entry = line.split("#", 1)[0].strip()
        if not entry:
            continue
        if not entry.isdigit():
            raise CliError(f"{path} line {number}: a vertex index (an integer >= 0) per line, got {entry!r}")
        out.append(int(entry))
    if len(out) < 2:
        raise CliError(f"{path}: a path needs at least two vertices, got {len(out)}")
    return np.array(out, dtype=np.int64)


def run_straighten(args):
    """Run ``heatcore straighten``: read the mesh and the path, straighten, write each output; returns 0.

    Examples
    --------
    >>> import tempfile
    >>> from pathlib import Path
    >>> from heatcore.io import demo_mesh_path
    >>> from heatcore.apps.cli import build_parser
    >>> tmp = tempfile.TemporaryDirectory()
    >>> edges = Path(tmp.name) / "edges.txt"
    >>> _ = edges.write_text("0\\n764\\n0\\n")
    >>> run_straighten(build_parser().parse_args(["straighten", str(demo_mesh_path()), "--path", str(edges),
    ...                                           "-o", str(Path(tmp.name) / "s.obj")]))  # doctest: +ELLIPSIS
    length 0 (edge path ..., 1 point)
    wrote .../s.obj
    0
    >>> tmp.cleanup()
    """
    check_outputs(args.output, args.mesh, args.overwrite)
    vertices = read_vertex_list(args.path)
    domain, _ = read_domain(args)
    from ..paths.drawn import straighten_loop_on, straighten_on

    with timed_stage("straighten"):
        path = (straighten_loop_on if args.loop else straighten_on)(domain, vertices)
    closed = np.r_[vertices, vertices[:1]] if args.loop and vertices[0] != vertices[-1] else vertices
    V = np.asarray(domain.vertices, dtype=float)
    before = float(np.linalg.norm(np.diff(V[closed], axis=0), axis=1).sum())
    print(f"length {path.length:.10g} (edge {'loop' if args.loop else 'path'} {before:.10g}, {count_points(path)})")
    what = "loop" if args.loop else "path"
    write_outputs(args.output, path.points, f"heatcore straightened {what} of {Path(args.path).name} on "
                                            f"{Path(args.mesh).name}, length {path.length:.17g}")
    return 0
