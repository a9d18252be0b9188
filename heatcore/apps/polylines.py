"""What the polyline commands (``heatcore path``, ``trace``, ``straighten``) share: arguments, checks, writers.

Each of them reads a mesh file, computes one polyline on its surface and
writes it to every ``-o`` file, by extension:

- ``.obj``: ``v`` lines and one ``l`` line per segment (MeshLab and PyMeshLab
  load the ``l`` elements as an edge mesh; Blender's OBJ importer makes them
  a mesh of edges, which Convert > Curve turns into a curve);
- ``.vtk``: legacy VTK line cells (meshio reads the segments; trimesh only the points);
- ``.ply``: ASCII PLY with ``vertex`` and ``edge`` elements (a ``Path3D`` in trimesh; meshio refuses it);
- ``.csv``: ``x,y,z`` rows, first point first.

The output names are checked before the mesh is read (:func:`check_outputs`);
the mesh is read and prepared as by the other commands (:func:`read_domain`).

Examples
--------
>>> from heatcore.apps.arguments import OneLineErrorParser
>>> p = OneLineErrorParser(prog="demo")
>>> add_polyline_arguments(p)
>>> args = p.parse_args(["spot.obj", "-o", "a.obj", "-o", "a.csv"])
>>> str(args.mesh), args.output, args.overwrite
('spot.obj', ['a.obj', 'a.csv'], False)
"""

from pathlib import Path

import numpy as np

from ..errors import InvalidMeshError
from ..io.curves import curve_formats_help, write_obj_curves, write_vtk_curves
from .arguments import settings_of
from .inputs import read_mesh_file
from .outputs import UsageError, atomic_output, check_writable, same_file
from .reporting import timed_stage

#: Output formats of the polyline commands.
PATH_SUFFIXES = (".obj", ".vtk", ".ply", ".csv")


def add_polyline_arguments(p):
    """Add the arguments every polyline command has: the mesh file, ``-o/--output``, ``--overwrite``.

    Examples
    --------
    >>> from heatcore.apps.arguments import OneLineErrorParser
    >>> p = OneLineErrorParser(prog="demo")
    >>> add_polyline_arguments(p)
    >>> p.parse_args(["m.ply"]).output
    []
    """
    p.add_argument("mesh", type=Path, metavar="MESH", help="triangle (or polygon) mesh file: OBJ, PLY, OFF, STL, ...")
    p.add_argument("-o", "--output", action="append", default=[], metavar="FILE",
                   help="polyline file, format by extension: " + curve_formats_help() + "; .csv (x,y,z); "
                        "repeat for several. Written whole or not at all")
    p.add_argument("--overwrite", action="store_true", help="allow an output to replace the mesh file")


def check_outputs(outputs, mesh, overwrite):
    """Refuse unusable output names before the mesh is read.

    Raises
    ------
    UsageError
        No output, an unknown extension, a name given twice, the mesh file itself (without ``overwrite``).
    CliError
        An output that is a folder, or whose folder cannot be created.

    Examples
    --------
    >>> check_outputs(["t.txt"], "m.obj", False)
    Traceback (most recent call last):
    ...
    heatcore.apps.outputs.UsageError: output t.txt: unknown extension '.txt'; use one of .obj, .vtk, .ply, .csv
    """
    if not outputs:
        raise UsageError(f"nothing to write: give -o/--output FILE ({', '.join(PATH_SUFFIXES)})")
    seen = []
    for out in map(Path, outputs):
        if out.suffix.lower() not in PATH_SUFFIXES:
            raise UsageError(f"output {out}: unknown extension {out.suffix!r}; use one of {', '.join(PATH_SUFFIXES)}")
        if any(out == other or same_file(out, other) for other in seen):
            raise UsageError(f"output {out} is given twice")
        if not overwrite and same_file(out, mesh):
            raise UsageError(f"output {out} is the mesh file; write elsewhere, or pass --overwrite to replace it")
        check_writable(out)
        seen.append(out)


def read_domain(args):
    """Read ``args.mesh`` and prepare its domain with the command line's mesh options: ``(domain, settings)``.

    Raises
    ------
    InvalidMeshError
        The mesh cannot be used (the message starts with the file name).

    Examples
    --------
    >>> import argparse
    >>> from heatcore.io import demo_mesh_path
    >>> domain, settings = read_domain(argparse.Namespace(mesh=demo_mesh_path(), refine=0))
    >>> type(domain).__name__
    'TriangleMesh'
    """
    with timed_stage("read mesh"):
        mesh = read_mesh_file(args.mesh)
    settings = settings_of(args)  # the command line's options (no domain kind, no colours)
    try:
        with timed_stage("prepare"):
            return mesh.domain(settings.mesh), settings
    except InvalidMeshError as exc:
        raise InvalidMeshError(f"{args.mesh}: {exc}") from exc


def write_outputs(outputs, points, header):
    """Write the polyline ``points`` to each file of ``outputs`` (:func:`write_path`), saying so on stdout.

    Examples
    --------
    >>> import tempfile, numpy as np
    >>> from pathlib import Path
    >>> tmp = tempfile.TemporaryDirectory()
    >>> write_outputs([str(Path(tmp.name) / "p.csv")], np.zeros((2, 3)), "two points")  # doctest: +ELLIPSIS
    wrote .../p.csv
    >>> tmp.cleanup()
    """
    with timed_stage("write"):
        for out in outputs:
            write_path(out, points, header=header)
            print(f"wrote {out}")


def write_path(target, points, header=None):
    """Write a polyline as ``.obj`` (``v`` + one ``l`` per segment), ``.vtk`` (line cells), ``.ply`` (vertex + edge) or ``.csv``.

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
    if suffix == ".vtk":  # meshio reads its segments (heatcore.io.curves.CURVE_READERS)
        with atomic_output(target) as tmp:
            write_vtk_curves(tmp, [(points, False)], header=header)
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


def count_points(path):
    """``"k points"`` or ``"1 point"`` for a polyline of ``k`` points.

    Examples
    --------
    >>> count_points([0]), count_points([0, 1, 2])
    ('1 point', '3 points')
    """
    return f"{len(path)} points" if len(path) > 1 else "1 point"
