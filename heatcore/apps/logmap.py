"""``heatcore logmap``: geodesic polar coordinates around a vertex (the log map), written as UVs.

The coordinates come from :class:`heatcore.VectorHeatSolver` (the vector heat
method, docs/vector-heat.md): for every vertex, ``r (cos θ, sin θ)`` with
``r`` the geodesic distance from the source and ``θ`` the direction in which
the geodesic leaves it, in mesh units. A PLY output holds them as vertex
texture coordinates (Blender's importer makes a UV map of them, MeshLab reads
them as per-vertex texture coordinates), with the distance as quality and
colors.

Examples
--------
>>> import tempfile
>>> from pathlib import Path
>>> from heatcore.apps.cli import main
>>> from heatcore.io import demo_mesh_path
>>> tmp = tempfile.TemporaryDirectory()
>>> out = Path(tmp.name) / "uv.npy"
>>> main(["logmap", str(demo_mesh_path()), "-s", "970", "-o", str(out), "--refine", "0", "-q"])
... # doctest: +ELLIPSIS
wrote .../uv.npy
0
>>> np.load(out).shape
(2930, 2)
>>> tmp.cleanup()
"""

import logging
from pathlib import Path

import numpy as np

from ..errors import InvalidMeshError
from .arguments import settings_of
from .inputs import check_sources, read_mesh_file
from .outputs import UsageError, atomic_output, check_output_paths
from .reporting import timed_stage

log = logging.getLogger("heatcore.apps.cli")

#: What ``heatcore logmap`` writes, by extension.
LOGMAP_SUFFIXES = (".ply", ".npy", ".csv")


def run_logmap(args):
    """Run ``heatcore logmap``: read the mesh, factor, compute the log map, write each output; returns 0.

    Examples
    --------
    >>> import tempfile
    >>> from heatcore.apps.cli import build_parser
    >>> from heatcore.io import demo_mesh_path
    >>> tmp = tempfile.TemporaryDirectory()
    >>> out = Path(tmp.name) / "uv.csv"
    >>> run_logmap(build_parser().parse_args(["logmap", str(demo_mesh_path()), "-s", "0", "-o", str(out)]))
    ... # doctest: +ELLIPSIS
    wrote .../uv.csv
    0
    >>> out.read_text().splitlines()[:2]
    ['index,u,v', '0,0,0']
    >>> tmp.cleanup()
    """
    from .. import VectorHeatSolver

    if not args.output:
        raise UsageError("nothing to write: give -o/--output FILE (.ply, .npy, .csv)")
    for out in map(Path, args.output):
        if out.suffix.lower() not in LOGMAP_SUFFIXES:
            raise UsageError(f"output {out}: unknown extension {out.suffix!r}; use one of {', '.join(LOGMAP_SUFFIXES)}")
    check_output_paths(args.output, None, [args.mesh], args.overwrite)
    with timed_stage("read mesh"):
        mesh = read_mesh_file(args.mesh, "triangle")
    log.info("triangle mesh: %d vertices", len(mesh.vertices))
    check_sources([args.source], len(mesh.vertices))
    settings = settings_of(args, "vector heat")  # the vector heat method's options and defaults
    try:
        with timed_stage("precompute"):
            solver = VectorHeatSolver(mesh.domain(settings.mesh), settings.solver)
    except InvalidMeshError as exc:  # the arrays read are checked here: say which file they came from
        raise InvalidMeshError(f"{args.mesh}: {exc}") from exc
    with timed_stage("query"):
        uv = solver.log_map(args.source, reference=args.reference)
    radius = np.hypot(uv[:, 0], uv[:, 1])
    reached = np.isfinite(radius)
    log.info("log map: %d of %d vertices reached, radius up to %.6g", reached.sum(), len(radius),
             radius[reached].max() if reached.any() else 0.0)
    with timed_stage("write"):
        for out in args.output:
            write_log_map(out, mesh.vertices, mesh.surface, uv, args.source, args.colormap, args.isolines)
            print(f"wrote {out}")
    return 0


def write_log_map(path, V, F, uv, source, colormap="viridis", isolines=None):
    """Write log-map coordinates by extension, atomically: .ply (texture coordinates), .npy or .csv.

    Parameters
    ----------
    path : path-like
    V : (n, 3) float array
    F : (m, 3) int array
    uv : (n, 2) float array
        The log map (``inf`` rows where unreachable: 0 in a PLY's texture
        coordinates, its quality keeps ``inf``).
    source : int
        The source vertex: the PLY's saved selection.
    colormap : str
    isolines : int or None
        Colors of the distance in a PLY (as ``heatcore distance``).

    Examples
    --------
    >>> import tempfile
    >>> tmp = tempfile.TemporaryDirectory()
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    >>> uv = np.array([[0.0, 0.0], [1.0, 0.0], [np.inf, np.inf]])
    >>> write_log_map(Path(tmp.name) / "uv.csv", V, [[0, 1, 2]], uv, 0)
    >>> print((Path(tmp.name) / "uv.csv").read_text())
    index,u,v
    0,0,0
    1,1,0
    2,inf,inf
    <BLANKLINE>
    >>> tmp.cleanup()
    """
    path = Path(path)
    suffix = path.suffix.lower()
    with atomic_output(path) as tmp:
        if suffix == ".ply":
            from ..io.mesh import write_ply
            from ..viz.colormap import colorize, to_uint8

            radius = np.hypot(uv[:, 0], uv[:, 1])
            colors = to_uint8(colorize(radius, colormap, isolines=isolines or 0))
            texcoords = np.where(np.isfinite(uv), uv, 0.0)
            write_ply(tmp, V, F, radius, colors, selection=[source], texcoords=texcoords)
        elif suffix == ".npy":
            np.save(tmp, uv)
        else:
            table = np.column_stack([np.arange(len(uv)), uv])
            np.savetxt(tmp, table, fmt=["%d", "%.17g", "%.17g"], delimiter=",", header="index,u,v", comments="")
