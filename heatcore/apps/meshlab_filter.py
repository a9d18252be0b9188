"""The MeshLab-style filter: geodesic distance from a :class:`pymeshlab.MeshSet`'s selection.

:func:`geodesic_distance_from_selection` reads the selection of the current
mesh as sources, writes the distance as vertex quality and as a custom vertex
scalar attribute, colours the vertices, and returns statistics. Its options
become one :class:`heatcore.settings.Settings` of the ``"meshlab"`` front end
(checked once, with MeshLab's defaults; the options it offers are
``FRONT_END_OPTIONS["meshlab"]``), built for one query: "auto" stands for the
backend that factors fastest. :func:`distance_from_selection` takes those
settings as they are (the command builds them from its arguments). MeshLab's
own colour ramps are this front end's addition. No numerics live here: the
distance comes from :class:`heatcore.HeatSolver`.
The command line around it is :mod:`heatcore.apps.meshlab`.

pymeshlab is imported by the caller only (see DESIGN.md: ``bpy`` must be
imported before pymeshlab in a process).

Examples
--------
>>> sorted(MESHLAB_COLORMAPS)[:2], COLORMAP_CHOICES[-1]
(['meshlab-cividis', 'meshlab-plasma'], 'none')
"""


import re
import time

import numpy as np

from .. import options
from ..domains.sources import source_vertices
from ..domains.triangle import TriangleMesh
from ..errors import InvalidMeshError, InvalidOptionError, InvalidSourceError
from ..heat import HeatSolver
from ..settings import Settings
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

#: Choices this front end adds to :mod:`heatcore.options`' colormaps: MeshLab's ramps, or "none" (colours untouched).
EXTRA_COLORMAPS = (*MESHLAB_COLORMAPS, "none")
#: Every accepted ``colormap``.
COLORMAP_CHOICES = options.OPTIONS["colormap"].choices + EXTRA_COLORMAPS

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
    accuracy="auto",
    backend="auto",
    robust=True,
    refine="auto",
    weld=0.0,
    colormap="viridis",
    isolines=0,
    attribute=DEFAULT_ATTRIBUTE,
    unreachable=DEFAULT_UNREACHABLE,
    solver=None,
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
    accuracy : {"smooth", "high", "auto"}, default "auto"
        "high": an eikonal pass, about 5 times closer to exact (see :class:`heatcore.HeatSolver`);
        "auto": "high" on a mesh of 100,000 vertices or more where numba is installed (the filter
        answers one query), else "smooth".
    backend : {"auto", "supernodal", "qdldl", "cholmod", "superlu", "gpu"}, default "auto"
        Sparse factorization backend; "auto": the one that factors fastest
        (the filter answers one query; see :mod:`heatcore.linalg`).
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

    Examples
    --------
    An octahedron with its vertex 0 selected; the distance lands in the vertex quality:

    >>> import pytest
    >>> pymeshlab = pytest.importorskip("pymeshlab")  # the test extra
    >>> V = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], float)
    >>> F = np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]])
    >>> ms = pymeshlab.MeshSet()
    >>> ms.add_mesh(pymeshlab.Mesh(V, F.astype(np.int32)))
    >>> ms.compute_selection_by_condition_per_vertex(condselect="vi == 0")
    >>> stats = geodesic_distance_from_selection(ms, refine=3)
    >>> stats["source_kind"], stats["sources"], stats["reached"]
    ('vertices', 1, 6)
    >>> ms.current_mesh().vertex_scalar_array().round(2)
    array([0.  , 2.5 , 1.41, 1.41, 1.41, 1.41])

    Again with other colours, skipping the setup:

    >>> again = geodesic_distance_from_selection(ms, refine=3, colormap="meshlab-turbo", solver=stats["solver"])
    >>> again["solver"] is stats["solver"], np.array_equal(again["distance"], stats["distance"])
    (True, True)
    """
    settings = Settings.of("meshlab", intent="one query", m=m, boundary=boundary, accuracy=accuracy,
                           backend=backend, robust=robust, refine=refine, weld=weld, isolines=isolines)
    return distance_from_selection(ms, settings, colormap=colormap, attribute=attribute,
                                   unreachable=unreachable, solver=solver)


def distance_from_selection(ms, settings, *, colormap="viridis", attribute=DEFAULT_ATTRIBUTE,
                            unreachable=DEFAULT_UNREACHABLE, solver=None):
    """:func:`geodesic_distance_from_selection` with its options as one :class:`~heatcore.settings.Settings`.

    The mesh part builds the :class:`~heatcore.TriangleMesh`, the solver
    part the :class:`~heatcore.HeatSolver`, the output part gives the
    isolines; nothing is checked or defaulted again here. ``colormap``
    (which may be one of MeshLab's ramps, or "none"), ``attribute`` and
    ``unreachable`` are this front end's own, checked here.

    Parameters
    ----------
    ms : pymeshlab.MeshSet
    settings : Settings
        ``Settings.of("meshlab", intent="one query", ...)``.
    colormap, attribute, unreachable, solver
        As in :func:`geodesic_distance_from_selection`.

    Returns
    -------
    dict
        As :func:`geodesic_distance_from_selection`.

    Examples
    --------
    >>> import pytest
    >>> pymeshlab = pytest.importorskip("pymeshlab")  # the test extra
    >>> ms = pymeshlab.MeshSet()
    >>> ms.add_mesh(pymeshlab.Mesh(np.eye(3), np.array([[0, 1, 2]], np.int32)))
    >>> ms.compute_selection_by_condition_per_vertex(condselect="vi == 0")
    >>> stats = distance_from_selection(ms, Settings.of("meshlab", intent="one query", refine=0))
    >>> stats["reached"], stats["solver"].settings.intent
    (3, 'one query')
    """
    start = time.perf_counter()
    colormap = _check_options(colormap, settings.output.isolines, attribute, unreachable)
    mesh = current_mesh(ms)
    V = np.asarray(mesh.vertex_matrix(), dtype=np.float64)
    F = np.asarray(mesh.face_matrix(), dtype=np.int64)
    if F.shape[0] == 0:
        raise InvalidMeshError("the current mesh has no faces: the heat method needs a triangle or polygon mesh")
    kind, sources = _selected_sources(mesh)

    if solver is None:  # one query: only the parts the selection is on are built
        on = source_vertices(len(V), F, **{"vertices" if kind == "vertices" else "region": sources})
        solver = HeatSolver(TriangleMesh(V, F, settings.mesh, only_parts_of=on), settings.solver)
    else:
        _check_solver(solver, V, F)
    setup = time.perf_counter()
    if kind == "vertices":
        d = solver.distance(sources)
    else:
        d = solver.distance(region=sources)
    query = time.perf_counter()

    finite = np.isfinite(d)
    values = np.where(finite, d, float(unreachable))
    write_vertex_attribute(ms, mesh, attribute, values)
    ms.compute_scalar_by_function_per_vertex(q=attribute)
    vmax = float(d[finite].max()) if finite.any() else 0.0
    _write_colors(ms, mesh, d, colormap, settings.output.isolines, vmax)
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
    """The checked ``colormap`` (MeshLab's ramps too); the filter's own options (attribute, unreachable) checked.

    ``isolines`` (of the checked settings) only has to fit the colormap.
    """
    colormap = options.check("colormap", colormap, extra=EXTRA_COLORMAPS)
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
    return colormap


def current_mesh(ms):
    """The MeshSet's current mesh, compacted; :class:`~heatcore.errors.InvalidMeshError` when it has none.

    Examples
    --------
    >>> import pymeshlab  # doctest: +SKIP
    >>> current_mesh(pymeshlab.MeshSet())  # doctest: +SKIP
    Traceback (most recent call last):
    ...
    heatcore.errors.InvalidMeshError: the MeshSet has no current mesh: load one first (...)
    """
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


def write_vertex_attribute(ms, mesh, name, values):
    """Set the custom vertex scalar attribute ``name`` to ``values`` (adding or overwriting it).

    pymeshlab can add an attribute but neither remove nor overwrite one from
    numpy; an existing one is overwritten through MeshLab's expression filter,
    from a fresh scratch attribute (which stays: MeshLab cannot delete
    attributes; custom attributes are not saved to files).

    Examples
    --------
    >>> mesh = current_mesh(ms)  # doctest: +SKIP
    >>> write_vertex_attribute(ms, mesh, "geodesic", np.zeros(mesh.vertex_number()))  # doctest: +SKIP
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
        write_vertex_attribute(ms, mesh, name, channel.astype(np.float64))
    x, y, z = _COLOR_ATTRIBUTES
    ms.compute_color_by_function_per_vertex(x=x, y=y, z=z, a="255")
