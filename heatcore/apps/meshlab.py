"""PyMeshLab front end: a MeshLab-style filter from a vertex selection to geodesic distance.

MeshLab has no Python plugin API, so the front end is a function that acts like
a filter on a :class:`pymeshlab.MeshSet`'s current mesh
(:func:`geodesic_distance_from_selection`), and a command (:func:`main`) that
MeshLab users run on files they export from MeshLab and open again there:

    python scripts/heatcore_meshlab.py scan.ply -o scan_distance.ply
    python scripts/heatcore_meshlab.py scan.obj --sources 0 17 -o out.ply
    python scripts/heatcore_meshlab.py scan.obj --select "(y > 0.9)" -o out.ply

The filter reads the selection as sources, writes the distance as vertex
quality (what MeshLab's colour and selection tools use) and as a custom vertex
scalar attribute, colours the vertices, and returns statistics. No numerics
live here: the distance comes from :class:`heatcore.HeatSolver`.

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
import os
import re
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from ..domains.triangle import TriangleMesh
from ..errors import (
    HeatcoreError,
    InvalidMeshError,
    InvalidOptionError,
    InvalidSourceError,
)
from ..heat import HeatSolver
from ..viz import colormap as _colormap

#: Name of the custom per-vertex scalar attribute that receives the distance.
DEFAULT_ATTRIBUTE = "heat_distance"

#: Quality given to vertices that no source reaches. Distances are >= 0, so
#: MeshLab's ``compute_selection_by_condition_per_vertex(condselect="q < 0")``
#: selects exactly these vertices; MeshLab's tools cannot handle ``inf``.
DEFAULT_UNREACHABLE = -1.0

#: MeshLab's own colour ramps (``compute_color_from_scalar_per_vertex``), by our name.
MESHLAB_COLORMAPS = {
    "meshlab-rgb": "RGB",
    "meshlab-viridis": "Viridis",
    "meshlab-plasma": "Plasma",
    "meshlab-cividis": "Cividis",
    "meshlab-turbo": "Turbo",
    "meshlab-rdpu": "RdPu",
}

#: Every accepted ``colormap``: heatcore's tables, MeshLab's ramps, or "none" (colours untouched).
COLORMAP_CHOICES = tuple(sorted(_colormap.COLORMAPS)) + tuple(MESHLAB_COLORMAPS) + ("none",)

# Names MeshLab's expression parser defines per vertex; an attribute may not shadow them.
_RESERVED_NAMES = {
    "x", "y", "z", "nx", "ny", "nz", "r", "g", "b", "a", "q", "vi", "rad", "vtu", "vtv", "ti",
    "x0", "y0", "z0", "nx0", "ny0", "nz0", "r0", "g0", "b0", "a0", "q0", "vsel", "fsel",
}  # fmt: skip
_IDENTIFIER = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
_COLOR_ATTRIBUTES = ("heatcore_red", "heatcore_green", "heatcore_blue")


def geodesic_distance_from_selection(
    ms,
    *,
    m=1.0,
    boundary="robin",
    robust=True,
    refine="auto",
    weld=0.0,
    colormap="viridis",
    isolines=0,
    attribute=DEFAULT_ATTRIBUTE,
    unreachable=DEFAULT_UNREACHABLE,
    solver=None,
    **solver_options,
):
    """Geodesic distance from the selection of a MeshSet's current mesh, MeshLab-filter style.

    Sources are the selected vertices; where no vertex is selected, the
    selected faces (the distance is then to their union). The distance is
    written as vertex quality and as the custom vertex scalar attribute
    ``attribute``, and the vertices are coloured. The selection is left as it
    is. On any error the mesh is left unchanged.

    Parameters
    ----------
    ms : pymeshlab.MeshSet
        Its current mesh is the input; triangles are used as pymeshlab stores
        them (polygons are triangulated).
    m : float, default 1.0
        Heat time factor, ``t = m h^2``; larger gives a smoother distance.
    boundary : {"robin", "neumann", "dirichlet"}, default "robin"
        Boundary condition of the heat step on meshes with holes.
    robust : bool, default True
        Intrinsic Delaunay operators (accurate on badly shaped triangles);
        ``False`` gives plain cotan, as MeshLab's own heat filter uses.
    refine : "auto" or int, default "auto"
        Midpoint subdivision levels before solving (see :class:`heatcore.TriangleMesh`).
    weld : float or None, default 0.0
        Merge vertices closer than this (0: at the same position; None:
        never), see :class:`heatcore.TriangleMesh`.
    colormap : str, default "viridis"
        One of heatcore's colormaps (``viridis``, ``magma``, ``inferno``,
        ``plasma``, ``cividis``), one of MeshLab's ramps (``meshlab-rgb``,
        ``meshlab-viridis``, ``meshlab-plasma``, ``meshlab-cividis``,
        ``meshlab-turbo``, ``meshlab-rdpu``), or ``"none"`` to leave colours alone.
    isolines : int, default 0
        Dark isoline stripes (heatcore colormaps only).
    attribute : str, default "heat_distance"
        Custom vertex scalar attribute that receives the distance; usable by
        name in MeshLab expressions (``condselect="heat_distance < 0.1"``).
    unreachable : float, default -1.0
        Quality and attribute value of vertices no source reaches (another
        connected component, unreferenced vertices). MeshLab's tools do not
        handle ``inf``; the statistics count these vertices.
    solver : HeatSolver, optional
        A solver from an earlier call's statistics (``stats["solver"]``) on
        the same mesh: skips the precomputation.
    **solver_options
        Further keyword arguments of :class:`heatcore.HeatSolver`, passed
        through unchanged (for example ``accuracy="high"``).

    Returns
    -------
    dict
        ``sources`` (int), ``source_kind`` ("vertices" or "faces"),
        ``vertices``, ``faces``, ``polygons`` (faces of more than 3 sides in
        the input), ``reached``, ``unreachable`` (vertex counts), ``min``,
        ``max``, ``mean`` (of the finite distances), ``attribute``,
        ``colormap``, ``seconds`` (``setup``, ``distance``, ``write``,
        ``total``), ``distance`` ((n,) array with ``inf`` where unreachable)
        and ``solver`` (pass it back to skip the setup next time).

    Raises
    ------
    InvalidSourceError
        Nothing is selected.
    InvalidOptionError
        An option is out of range, or ``solver`` belongs to another mesh.
    InvalidMeshError
        The current mesh has no faces.
    """
    start = time.perf_counter()
    _check_options(colormap, isolines, attribute, unreachable)
    mesh = _current_mesh(ms)
    V = np.asarray(mesh.vertex_matrix(), dtype=np.float64)
    F = np.asarray(mesh.face_matrix(), dtype=np.int64)
    if F.shape[0] == 0:
        raise InvalidMeshError("the current mesh has no faces: the heat method needs a triangle or polygon mesh")
    kind, sources = _selected_sources(mesh)

    if solver is None:
        domain = TriangleMesh(V, F, robust=robust, refine=refine, weld=weld)
        solver = HeatSolver(domain, m=m, boundary=boundary, **solver_options)
    else:
        _check_solver(solver, V, F)
    setup = time.perf_counter()
    if kind == "vertices":
        d = solver.distance(sources)
    else:
        d = solver.distance(faces=sources)
    query = time.perf_counter()

    finite = np.isfinite(d)
    values = np.where(finite, d, float(unreachable))
    _write_vertex_attribute(ms, mesh, attribute, values)
    ms.compute_scalar_by_function_per_vertex(q=attribute)
    vmax = float(d[finite].max()) if finite.any() else 0.0
    _write_colors(ms, mesh, d, colormap, isolines, vmax)
    done = time.perf_counter()

    return {
        "sources": len(sources),
        "source_kind": kind,
        "vertices": int(V.shape[0]),
        "faces": int(F.shape[0]),
        "polygons": _polygon_count(mesh),
        "reached": int(finite.sum()),
        "unreachable": int((~finite).sum()),
        "min": float(d[finite].min()) if finite.any() else float("nan"),
        "max": vmax if finite.any() else float("nan"),
        "mean": float(d[finite].mean()) if finite.any() else float("nan"),
        "attribute": attribute,
        "colormap": colormap,
        "seconds": {
            "setup": setup - start,
            "distance": query - setup,
            "write": done - query,
            "total": done - start,
        },
        "distance": d,
        "solver": solver,
    }


def _check_options(colormap, isolines, attribute, unreachable):
    if colormap not in COLORMAP_CHOICES:
        raise InvalidOptionError(f"unknown colormap {colormap!r}; choose one of {', '.join(COLORMAP_CHOICES)}")
    if not (isinstance(isolines, (int, np.integer)) and not isinstance(isolines, bool) and isolines >= 0):
        raise InvalidOptionError(f"isolines must be a non-negative integer, got {isolines!r}")
    if isolines and colormap not in _colormap.COLORMAPS:
        raise InvalidOptionError(f"isolines need one of heatcore's colormaps {sorted(_colormap.COLORMAPS)}")
    if not (isinstance(attribute, str) and _IDENTIFIER.match(attribute)) or attribute in _RESERVED_NAMES:
        raise InvalidOptionError(
            f"attribute name {attribute!r} must be an identifier (letters, digits, _) "
            f"and not one of MeshLab's per-vertex variables {sorted(_RESERVED_NAMES)}"
        )
    if attribute in _COLOR_ATTRIBUTES:
        raise InvalidOptionError(f"attribute name {attribute!r} is used for the colours; choose another")
    if not (isinstance(unreachable, (int, float, np.integer, np.floating)) and np.isfinite(unreachable)):
        raise InvalidOptionError(f"unreachable must be a finite number (MeshLab cannot use inf), got {unreachable!r}")


def _current_mesh(ms):
    try:
        mesh = ms.current_mesh()
    except Exception as exc:  # pymeshlab raises its own exception type for an empty MeshSet
        raise InvalidMeshError(f"the MeshSet has no current mesh: load one first ({exc})") from exc
    if not mesh.is_compact():  # deleted elements linger until compaction; arrays need a compact mesh
        mesh.compact()
    return mesh


def _selected_sources(mesh):
    """("vertices", indices) of the selected vertices, else ("faces", indices) of selected faces."""
    vertices = np.flatnonzero(mesh.vertex_selection_array())
    if vertices.size:
        return "vertices", vertices
    faces = np.flatnonzero(mesh.face_selection_array())
    if faces.size:
        return "faces", faces
    raise InvalidSourceError(
        "no source: the mesh has no selected vertices or faces. Select the source vertices "
        "(in MeshLab, save as PLY with the 'Flags' box checked to keep the selection), "
        "or pass sources explicitly (--sources indices, or --select a MeshLab condition)"
    )


def _check_solver(solver, V, F):
    domain = getattr(solver, "domain", None)
    same = (
        domain is not None
        and getattr(domain, "vertices", np.empty((0, 3))).shape == V.shape
        and getattr(domain, "faces", np.empty((0, 3))).shape == F.shape
        and np.array_equal(domain.vertices, V)
        and np.array_equal(domain.faces, F)
    )
    if not same:
        raise InvalidOptionError(
            "the solver passed in was built for another mesh (vertices or faces differ): "
            "call without solver= to build one for this mesh"
        )


def _polygon_count(mesh):
    """Faces of more than three sides in the input (pymeshlab keeps them as faux-edge triangle fans).

    Polygons are triangulated for now; once heatcore has a polygon domain,
    polygon input goes through it instead.
    """
    try:
        polys = mesh.polygonal_face_list()
    except Exception:  # a build of pymeshlab without polygon support: count none
        return 0
    return int(sum(1 for p in polys if len(p) > 3))


def _attribute_exists(mesh, name):
    try:
        mesh.vertex_custom_scalar_attribute_array(name)
    except Exception:  # pymeshlab raises PyMeshLabException for a missing attribute
        return False
    return True


def _write_vertex_attribute(ms, mesh, name, values):
    """Set the custom vertex scalar attribute ``name`` to ``values`` (adding or overwriting it).

    pymeshlab can add an attribute but neither remove nor overwrite one from
    numpy; an existing one is overwritten through MeshLab's expression filter,
    from a fresh scratch attribute (which stays: MeshLab cannot delete
    attributes; custom attributes are not saved to files).
    """
    values = np.ascontiguousarray(values, dtype=np.float64)
    if not _attribute_exists(mesh, name):
        mesh.add_vertex_custom_scalar_attribute(values, name)
        return
    k = 1
    while _attribute_exists(mesh, f"{name}_scratch{k}"):
        k += 1
    scratch = f"{name}_scratch{k}"
    mesh.add_vertex_custom_scalar_attribute(values, scratch)
    ms.compute_new_custom_scalar_attribute_per_vertex(name=name, expr=scratch)


def _write_colors(ms, mesh, d, colormap, isolines, vmax):
    if colormap == "none":
        return
    if colormap in MESHLAB_COLORMAPS:
        # MeshLab's own ramp over the quality range [0, vmax]; unreachable vertices clamp to 0's colour.
        ms.compute_color_from_scalar_per_vertex(
            minval=0.0, maxval=vmax if vmax > 0 else 1.0, colormap=MESHLAB_COLORMAPS[colormap]
        )
        return
    rgb = _colormap.to_uint8(_colormap.colorize(d, colormap=colormap, isolines=isolines))
    for name, channel in zip(_COLOR_ATTRIBUTES, rgb.T):
        _write_vertex_attribute(ms, mesh, name, channel.astype(np.float64))
    x, y, z = _COLOR_ATTRIBUTES
    ms.compute_color_by_function_per_vertex(x=x, y=y, z=z, a="255")


# --------------------------------------------------------------------------- command line

#: Solver options on the command line: (flag, argparse keywords). Each entry is
#: passed to the filter as the keyword ``dest``; adding a solver option is one line here.
SOLVER_ARGUMENTS = (
    ("--m", dict(dest="m", type=float, default=1.0, help="heat time factor, t = m h^2 (default 1; larger: smoother)")),
    (
        "--boundary",
        dict(dest="boundary", choices=("robin", "neumann", "dirichlet"), default="robin",
             help="boundary condition on meshes with holes (default robin)"),
    ),
    (
        "--accuracy",
        dict(dest="accuracy", choices=("smooth", "high"), default="smooth",
             help="smooth: the heat method; high: plus an ordered eikonal pass (more accurate, slower)"),
    ),
    (
        "--no-robust",
        dict(dest="robust", action="store_false",
             help="plain cotan operators instead of intrinsic Delaunay (less accurate on bad triangles)"),
    ),
    (
        "--refine",
        dict(dest="refine", default="auto",
             help="midpoint subdivision levels before solving: 'auto' or 0..8 (default auto)"),
    ),
)  # fmt: skip


def _refine_value(text):
    if text == "auto":
        return "auto"
    try:
        return int(text)
    except ValueError:
        raise InvalidOptionError(f"--refine must be 'auto' or an integer 0..8, got {text!r}") from None


def build_parser(prog=None):
    """The argument parser of :func:`main` (also used by ``heatcore meshlab``)."""
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
    """Add this command's arguments to an argparse parser (for a ``heatcore meshlab`` subcommand)."""
    parser.add_argument("input", help="mesh file (PLY, OBJ, OFF, STL, ... anything pymeshlab reads)")
    parser.add_argument("-o", "--output", help="output PLY (default: INPUT stem + '_distance.ply')")
    src = parser.add_mutually_exclusive_group()
    src.add_argument(
        "--sources", type=int, nargs="+", metavar="VERTEX",
        help="source vertex indices (replace the file's selection)",
    )  # fmt: skip
    src.add_argument(
        "--select", metavar="CONDITION",
        help="MeshLab per-vertex condition selecting the sources, e.g. \"(y > 0.9)\" or \"vi == 0\"",
    )  # fmt: skip
    for flag, kwargs in SOLVER_ARGUMENTS:
        parser.add_argument(flag, **kwargs)
    parser.add_argument(
        "--colormap", choices=COLORMAP_CHOICES, default="viridis",
        help="vertex colours: heatcore's colormaps, MeshLab's ramps (meshlab-*), or none (default viridis)",
    )  # fmt: skip
    parser.add_argument("--isolines", type=int, default=0, help="isoline stripes in the colours (default 0)")
    parser.add_argument(
        "--unreachable", type=float, default=DEFAULT_UNREACHABLE,
        help="quality of vertices no source reaches (default -1)",
    )  # fmt: skip
    parser.add_argument("--ascii", action="store_true", help="write an ASCII PLY (default binary)")
    parser.add_argument("--json", action="store_true", help="print the statistics as JSON")
    return parser


def run(args):
    """Run the command for parsed arguments; returns the statistics (raises heatcore errors)."""
    try:
        import pymeshlab
    except ImportError as exc:
        raise HeatcoreError("this command needs pymeshlab: pip install pymeshlab") from exc

    path = Path(args.input)
    if not path.is_file():
        raise InvalidMeshError(f"input file {path} does not exist")
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
    mesh = _current_mesh(ms)
    if args.sources is not None:
        _select_vertices(ms, mesh, args.sources)
    elif args.select is not None:
        problem = check_condition(args.select)
        if problem:
            raise InvalidSourceError(f"MeshLab cannot evaluate --select {args.select!r}: {problem}")
        ms.compute_selection_by_condition_per_vertex(condselect=args.select)
        if not mesh.vertex_selection_array().any():
            raise InvalidSourceError(f"--select {args.select!r} selects no vertex")

    refine = _refine_value(args.refine)
    options = {kw["dest"]: getattr(args, kw["dest"]) for _, kw in SOLVER_ARGUMENTS}
    options["refine"] = refine
    stats = geodesic_distance_from_selection(
        ms, colormap=args.colormap, isolines=args.isolines, unreachable=args.unreachable, **options
    )
    _save_ply(ms, output, binary=not args.ascii)
    stats["output"] = str(output)
    return stats


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
    idx = np.asarray(indices, dtype=np.int64)
    bad = idx[(idx < 0) | (idx >= n)]
    if bad.size:
        raise InvalidSourceError(f"source vertex {int(bad[0])} is out of range: the mesh has {n} vertices (0..{n - 1})")
    flags = np.zeros(n)
    flags[idx] = 1.0
    _write_vertex_attribute(ms, mesh, "heatcore_sources", flags)
    ms.set_selection_none(allfaces=True, allverts=True)
    ms.compute_selection_by_condition_per_vertex(condselect="heatcore_sources > 0.5")


def _save_ply(ms, output, binary=True):
    """Write the current mesh as PLY with quality, colours and selection; no partial file on failure."""
    output.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(suffix=".ply", prefix=".heatcore-", dir=output.parent)
    os.close(fd)
    try:
        ms.save_current_mesh(
            tmp,
            binary=binary,
            save_vertex_quality=True,
            save_vertex_color=True,
            save_vertex_flag=True,
            save_face_flag=True,
        )
        os.replace(tmp, output)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)


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
    ``main(["mesh.ply", "-o", "mesh_distance.ply"])`` returns 0 after writing the PLY.
    """
    parser = build_parser(prog)
    args = parser.parse_args(argv)
    try:
        stats = run(args)
    except HeatcoreError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    print(format_report(stats, as_json=args.json))
    return 0


def format_report(stats, as_json=False):
    """The command's printed report: a summary, or the statistics as JSON."""
    if as_json:
        return json.dumps({k: v for k, v in stats.items() if k not in ("distance", "solver")}, indent=2)
    return _summary(stats)
