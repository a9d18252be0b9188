"""The ``heatcore path`` command: the geodesic path between two points of a mesh file, as a polyline file.

``heatcore path MESH --from A --to B -o path.obj`` reads the mesh, builds the
solver (the usual solver options), computes :meth:`heatcore.HeatSolver.geodesic_path`
and writes the polyline; the length goes to stdout. ``A`` and ``B`` are vertex
indices (0-based) or surface points ``FACE:B0,B1,B2`` (a face index and three
barycentric coordinates). Outputs, by extension (``-o`` may be repeated):

- ``.obj``: ``v`` lines and one ``l`` line per segment (MeshLab and PyMeshLab
  load the ``l`` elements as an edge mesh, one edge per line; Blender's OBJ
  importer makes them a mesh of edges, which Convert > Curve turns into a curve);
- ``.ply``: ASCII PLY with ``vertex`` and ``edge`` elements;
- ``.csv``: ``x,y,z`` rows, source first.

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

import numpy as np

from ..errors import InvalidMeshError
from ..io.curves import write_obj_curves
from .arguments import add_common_options, add_solver_options, settings_of
from .inputs import parse_vertex_index, read_mesh_file
from .outputs import CliError, UsageError, atomic_output, same_file
from .reporting import timed_stage

log = logging.getLogger("heatcore.apps.cli")

#: Output formats of ``heatcore path``.
PATH_SUFFIXES = (".obj", ".ply", ".csv")

PATH_HELP = "the geodesic path between two points of a triangle mesh, as a polyline (.obj, .ply, .csv)"
PATH_DESCRIPTION = (
    "Shortest path on the surface of a triangle mesh between two points, each a vertex index (0-based) "
    "or a point inside a face, FACE:B0,B1,B2 (face index and barycentric coordinates). The heat "
    "distance from the first point picks the route, which is then straightened into an exact geodesic "
    "on the mesh's faces. Output by extension: .obj (v and l elements: an edge mesh in MeshLab, edges "
    "in Blender), .ply (vertex and edge elements), .csv (x,y,z). The length is printed."
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
    """Add the arguments of ``heatcore path``: the mesh, the two points, outputs, solver options.

    Examples
    --------
    >>> from heatcore.apps.arguments import OneLineErrorParser
    >>> p = OneLineErrorParser(prog="heatcore path")
    >>> path_arguments(p)
    >>> args = p.parse_args(["spot.obj", "--from", "0", "--to", "5:0.2,0.3,0.5", "-o", "p.obj"])
    >>> args.source, args.target, args.output
    (0, (5, [0.2, 0.3, 0.5]), ['p.obj'])
    """
    p.add_argument("mesh", type=Path, metavar="MESH", help="triangle (or polygon) mesh file: OBJ, PLY, OFF, STL, ...")
    p.add_argument("--from", dest="source", type=surface_point, required=True, metavar="POINT",
                   help="where the path starts: a vertex index, or FACE:B0,B1,B2 for a point inside a face")
    p.add_argument("--to", dest="target", type=surface_point, required=True, metavar="POINT",
                   help="where the path ends (as --from)")
    p.add_argument("-o", "--output", action="append", default=[], metavar="FILE",
                   help="polyline file, format by extension: .obj (v and l elements), .ply (vertex and edge "
                        "elements), .csv (x,y,z); repeat for several. Written whole or not at all")
    p.add_argument("--overwrite", action="store_true", help="allow an output to replace the mesh file")
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
    >>> tmp.cleanup()
    """
    _check_outputs(args.output, args.mesh, args.overwrite)
    with timed_stage("read mesh"):
        mesh = read_mesh_file(args.mesh)
    from ..heat import HeatSolver

    settings = settings_of(args)  # the command line's options (no domain kind, no colours)
    try:
        with timed_stage("precompute"):
            solver = HeatSolver(mesh.domain(settings.mesh), settings.solver)
    except InvalidMeshError as exc:
        raise InvalidMeshError(f"{args.mesh}: {exc}") from exc
    with timed_stage("path"):
        path = solver.geodesic_path(args.source, args.target)
    points = f"{len(path)} points" if len(path) > 1 else "1 point"
    print(f"length {path.length:.10g} ({points})")
    with timed_stage("write"):
        for out in args.output:
            write_path(out, path.points, header=f"heatcore geodesic path from {_spec(args.source)} to "
                                                f"{_spec(args.target)} on {Path(args.mesh).name}, length "
                                                f"{path.length:.17g}")
            print(f"wrote {out}")
    return 0


def write_path(target, points, header=None):
    """Write a polyline as ``.obj`` (``v`` + one ``l`` per segment), ``.ply`` (vertex + edge) or ``.csv``.

    The OBJ is written as the isoline curves are (:func:`~heatcore.io.curves.write_obj_curves`).

    Parameters
    ----------
    target : path-like
        The suffix picks the format; written atomically.
    points : (k, 3) float array
    header : str, optional
        A comment (OBJ and PLY).

    Examples
    --------
    >>> import tempfile, numpy as np
    >>> from pathlib import Path
    >>> tmp = tempfile.TemporaryDirectory()
    >>> write_path(Path(tmp.name) / "p.obj", np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0]], float))
    >>> print((Path(tmp.name) / "p.obj").read_text().strip())
    # path: 3 points
    v 0 0 0
    v 1 0 0
    v 1 1 0
    l 1 2
    l 2 3
    >>> tmp.cleanup()
    """
    target = Path(target)
    points = np.asarray(points, dtype=float).reshape(-1, 3)
    rows = [f"{x:.17g} {y:.17g} {z:.17g}" for x, y, z in points.tolist()]
    k = len(rows)
    suffix = target.suffix.lower()
    comment = [] if header is None else [" ".join(str(header).split())]
    if suffix == ".obj":  # as the isoline curves: heatcore.io.curves
        with atomic_output(target) as tmp:
            write_obj_curves(tmp, [(points, False)], header=header, labels=[f"path: {k} points"])
        return
    if suffix == ".ply":
        lines = ["ply", "format ascii 1.0"] + [f"comment {c}" for c in comment] + [
            f"element vertex {k}", "property double x", "property double y", "property double z",
            f"element edge {max(k - 1, 0)}", "property int vertex1", "property int vertex2", "end_header",
        ] + rows + [f"{i} {i + 1}" for i in range(k - 1)]
    elif suffix == ".csv":
        lines = ["x,y,z"] + [r.replace(" ", ",") for r in rows]
    else:
        raise UsageError(f"output {target}: unknown extension {target.suffix!r}; use one of {', '.join(PATH_SUFFIXES)}")
    with atomic_output(target) as tmp:
        tmp.write_text("\n".join(lines) + "\n")


def _check_outputs(outputs, mesh, overwrite):
    """Refuse unusable output names before the mesh is read."""
    if not outputs:
        raise UsageError("nothing to write: give -o/--output FILE (.obj, .ply, .csv)")
    seen = []
    for out in map(Path, outputs):
        if out.suffix.lower() not in PATH_SUFFIXES:
            raise UsageError(f"output {out}: unknown extension {out.suffix!r}; use one of {', '.join(PATH_SUFFIXES)}")
        if any(out == other or same_file(out, other) for other in seen):
            raise UsageError(f"output {out} is given twice")
        if not overwrite and same_file(out, mesh):
            raise UsageError(f"output {out} is the mesh file; write elsewhere, or pass --overwrite to replace it")
        if not out.parent.is_dir():
            raise CliError(f"cannot write {out}: folder {out.parent} does not exist")
        if out.is_dir():
            raise CliError(f"cannot write {out}: it is a folder")
        seen.append(out)


def _spec(point):
    """A point as given on the command line."""
    if isinstance(point, tuple):
        return f"face {point[0]} at ({', '.join(f'{b:g}' for b in point[1])})"
    return f"vertex {point}"
