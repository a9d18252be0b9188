"""The ``heatcore signed`` command: signed distance to curves drawn on a mesh, by the signed heat method.

``heatcore signed MESH --curve FILE [--curve FILE ...] -o out.ply`` reads the
mesh and the curves, runs :class:`heatcore.SignedHeatSolver` and writes the
signed field as ``heatcore distance`` writes a distance: ``.ply`` (the field as
vertex quality, a diverging colormap as vertex colors, the curves' vertices as
the saved selection), ``.npy`` or ``.csv``; ``--png`` draws it, and
``--isolines-out PATH [N]`` writes its zero set and ``N`` levels on each side as
OBJ polylines.

A curve file has one surface point per line, in order: a vertex index
(0-based), or ``FACE:B0,B1,B2`` for a point inside a face; blank lines and
lines starting with ``#`` are skipped; a closed curve repeats its first point
at the end. The curve's left (looking along the surface normal) is positive.

Exit status: 2 for a command line or curve file that is wrong before the mesh
is read, 1 for a bad mesh or a curve the mesh does not have.

Examples
--------
>>> import tempfile
>>> from pathlib import Path
>>> from heatcore.io import demo_mesh_path
>>> from heatcore.apps.cli import main
>>> tmp = tempfile.TemporaryDirectory()
>>> curve = Path(tmp.name) / "c.txt"
>>> _ = curve.write_text("# spot's first triangle, round\\n738\\n734\\n735\\n738\\n")
>>> main(["signed", str(demo_mesh_path()), "--curve", str(curve), "-o", str(Path(tmp.name) / "s.npy"), "-q"])
... # doctest: +ELLIPSIS
signed distance: min -..., max ..., 0 on 1 curve
wrote .../s.npy
0
>>> tmp.cleanup()
"""

import argparse
import logging
from pathlib import Path

import numpy as np

from ..errors import InvalidMeshError
from ..io.curves import curve_formats_help
from .arguments import (
    PathAndCount,
    add_common_options,
    add_output_options,
    add_solver_options,
    settings_of,
)
from .inputs import read_mesh_file
from .outputs import (
    UsageError,
    atomic_output,
    check_output_paths,
    check_outputs_fit,
    render_png,
    write_output,
)
from .path_command import surface_point
from .reporting import timed_stage

log = logging.getLogger("heatcore.apps.cli")

SIGNED_HELP = "signed distance to curves drawn on a mesh (the signed heat method): .ply, .npy, .csv, PNG"
SIGNED_DESCRIPTION = (
    "Signed geodesic distance to curves on the surface of a triangle or polygon mesh (or a point cloud), by "
    "the signed heat method (Feng and Crane 2024): positive on each curve's left, looking along the surface "
    "normal, negative on its right; broken, open or crossing curves give a smooth generalization. A curve "
    "file lists one surface point per line, in order: a vertex index, or FACE:B0,B1,B2 inside a face (not "
    "on polygon meshes and point clouds); a closed curve repeats its first point. Output by extension: .ply "
    "(the field as vertex quality, blue-to-red colors, the curves' vertices as the selection), .npy or .csv "
    "(index,value)."
)

#: Isolines on each side of the zero set in the PNG picture when --isolines is not given (none in PLY colors).
SIGNED_ISOLINES = 5


def read_curve_file(path):
    """The surface points of a curve file, in order (see the module); :class:`UsageError` when it is unusable.

    Examples
    --------
    >>> import tempfile
    >>> tmp = tempfile.TemporaryDirectory()
    >>> path = Path(tmp.name) / "c.txt"
    >>> _ = path.write_text("# a curve\\n4\\n\\n7:0.2,0.3,0.5\\n4\\n")
    >>> read_curve_file(path)
    [4, (7, [0.2, 0.3, 0.5]), 4]
    >>> _ = path.write_text("4\\nfour\\n")
    >>> read_curve_file(path)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    heatcore.apps.outputs.UsageError: .../c.txt line 2: ...
    >>> tmp.cleanup()
    """
    try:
        text = Path(path).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise UsageError(f"cannot read curve file {path}: {getattr(exc, 'strerror', None) or exc}") from exc
    points = []
    for number, line in enumerate(text.splitlines(), start=1):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        try:
            points.append(surface_point(line))
        except argparse.ArgumentTypeError as exc:
            raise UsageError(f"{path} line {number}: {exc}") from None
    if len(points) < 2:
        raise UsageError(f"curve file {path} has {len(points)} point{'s' * (len(points) != 1)}; a curve needs two")
    return points


def signed_arguments(p):
    """Add the arguments of ``heatcore signed``: the mesh, the curves, the options, the outputs.

    Examples
    --------
    >>> from heatcore.apps.arguments import OneLineErrorParser
    >>> p = OneLineErrorParser(prog="heatcore signed")
    >>> signed_arguments(p)
    >>> args = p.parse_args(["spot.obj", "--curve", "a.txt", "--curve", "b.txt", "-o", "s.ply"])
    >>> [c.name for c in args.curve], args.level_set, args.keep_normals, hasattr(args, "accuracy")
    (['a.txt', 'b.txt'], 'zero', False, False)
    """
    p.add_argument("mesh", type=Path, metavar="MESH", help="mesh file: OBJ, PLY, OFF, STL, ... (or a point cloud)")
    p.add_argument("--curve", type=Path, action="append", default=[], metavar="FILE",
                   help="a curve file (one surface point per line, in order); its left side is positive. Repeat "
                        "for several curves")
    p.add_argument("--unsigned-curve", type=Path, action="append", default=[], metavar="FILE",
                   help="a curve measured without a sign (positive on both sides)")
    p.add_argument("--level-set", choices=("zero", "multiple", "none"), default="zero",
                   help="how the curves fix the constant: all on the zero set (default), each on a level set of "
                        "its own, or none (their mean is 0)")
    p.add_argument("--keep-normals", action="store_true",
                   help="keep the diffused vectors normal to the curves on them (one more solve per curve point)")
    p.add_argument("-o", "--output", action="append", default=[], metavar="FILE",
                   help="output file, format by extension: .ply (value as vertex quality, blue-to-red colors), "
                        ".npy or .csv (index,value); repeat for several")
    add_output_options(p, png_help=f"draw the signed field into a PNG: blue to red, a line at 0 and at --isolines "
                                   f"levels on each side (default {SIGNED_ISOLINES})", colormap=False)
    p.add_argument("--isolines-out", action=PathAndCount, minimum=0, default=None,
                   help="write the zero set and N levels on each side as polylines (N defaults to --isolines, "
                        f"else {SIGNED_ISOLINES}: the PNG's lines): " + curve_formats_help())
    p.add_argument("--overwrite", action="store_true", help="allow an output to replace the mesh file")
    add_solver_options(p, front_end="signed heat")
    add_common_options(p)


def run_signed(args):
    """Run ``heatcore signed``: read the curves and the mesh, solve, write each output; returns 0.

    Examples
    --------
    >>> import tempfile
    >>> from heatcore.io import demo_mesh_path
    >>> from heatcore.apps.cli import build_parser
    >>> tmp = tempfile.TemporaryDirectory()
    >>> curve = Path(tmp.name) / "c.txt"
    >>> _ = curve.write_text("738\\n734\\n")  # an edge of spot
    >>> run_signed(build_parser().parse_args(["signed", str(demo_mesh_path()), "--curve", str(curve),
    ...                                       "-o", str(Path(tmp.name) / "s.csv")]))  # doctest: +ELLIPSIS
    signed distance: ...
    wrote .../s.csv
    0
    >>> tmp.cleanup()
    """
    from .. import SignedHeatSolver

    curves_out, count = _isolines_out(args)
    if not args.output and args.png is None and curves_out is None:
        raise UsageError("nothing to write: give -o/--output FILE (.ply, .npy, .csv), --png PATH "
                         "and/or --isolines-out PATH [N]")
    if not args.curve and not args.unsigned_curve:
        raise UsageError("no curve: give --curve FILE (signed) and/or --unsigned-curve FILE")
    inputs = [args.mesh, *args.curve, *args.unsigned_curve]
    check_output_paths(args.output, args.png, inputs, args.overwrite, curves_out)
    curves = [read_curve_file(c) for c in args.curve] + [read_curve_file(c) for c in args.unsigned_curve]
    signs = [True] * len(args.curve) + [False] * len(args.unsigned_curve)
    settings = settings_of(args, front_end="signed heat", intent="one query")
    with timed_stage("read mesh"):
        mesh = read_mesh_file(args.mesh, settings.domain)
    check_outputs_fit(args.output, args.png, mesh.kind, curves_out)
    try:
        with timed_stage("precompute"):
            solver = SignedHeatSolver(mesh.domain(settings.mesh), settings.solver)
    except InvalidMeshError as exc:
        raise InvalidMeshError(f"{args.mesh}: {exc}") from exc
    with timed_stage("query"):
        phi = solver.distance(curves, signs, level_set=args.level_set, keep_normals=args.keep_normals)
    finite = phi[np.isfinite(phi)]
    print(f"signed distance: min {finite.min():.6g}, max {finite.max():.6g}, 0 on {len(curves)} "
          f"curve{'s' * (len(curves) != 1)}" + (f"; {int((~np.isfinite(phi)).sum())} vertices unreached"
                                                 if finite.size < phi.size else ""))
    marked = np.unique([p for c in curves for p in c if isinstance(p, int)]).astype(np.int64)
    _write(args, mesh, phi, marked, curves_out, count)
    return 0


def _isolines_out(args):
    if args.isolines_out is None:
        return None, 0
    path, count = args.isolines_out
    if count is None:  # the PNG's lines
        count = SIGNED_ISOLINES if args.isolines is None else args.isolines
    return path, count


def _write(args, mesh, phi, marked, curves_out, count):
    """Each output of ``heatcore signed``: files, picture, isolines."""
    from ..contours import isolines, signed_levels
    from ..io.curves import write_curves
    from ..io.mesh import write_ply
    from ..viz.colormap import colorize_signed, to_uint8

    with timed_stage("write"):
        for out in args.output:
            if Path(out).suffix.lower() == ".ply":
                with atomic_output(Path(out)) as tmp:
                    write_ply(tmp, mesh.vertices, mesh.surface if mesh.surface is not None else np.zeros((0, 3), int),
                              phi, to_uint8(colorize_signed(phi, isolines=args.isolines or 0)), selection=marked)
            else:
                write_output(out, mesh.vertices, mesh.surface, phi, marked, "viridis", None)
            print(f"wrote {out}")
    if args.png is not None:
        with timed_stage("render"):
            render_png(args.png, mesh.vertices, mesh.surface, phi, [], "viridis",  # the zero line shows the curves
                       SIGNED_ISOLINES if args.isolines is None else args.isolines, title=args.mesh.name,
                       view=args.view, signed=True)
        print(f"wrote {args.png}")
    if curves_out is not None:
        with timed_stage("isolines"):
            levels = signed_levels(phi, count)
            curves = isolines(mesh.vertices, mesh.surface, phi, levels)
            labels = [f"isoline {j}: level {c.level:.17g}, {len(c.points)} points, {'closed' if c.closed else 'open'}"
                      for j, c in enumerate(curves)]
            header = f"heatcore signed: the zero set and {count} levels on each side of it"
            with atomic_output(curves_out) as tmp:
                write_curves(tmp, curves, header=header, labels=labels)
        print(f"wrote {curves_out}  ({len(curves)} isoline curves)")

