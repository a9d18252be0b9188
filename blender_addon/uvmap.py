"""Script API of the *Geodesic UV Map*: a UV map from the logarithmic map around a vertex or a surface point.

heatcore's :class:`~heatcore.VectorHeatSolver` gives every vertex its
geodesic polar coordinates around the source (distance, and the direction in
which the geodesic leaves the source), measured on the shape the user sees
(``space``, ``shape``: as for the distance). :func:`geodesic_uv_map` turns
them into UV coordinates (the source at ``(0.5, 0.5)``, one UV unit = ``unit``
scene units, the ``up`` direction at the source along +V) and writes them to
every face corner of each vertex, as a UV map of its own. Vertices no
geodesic reaches get :data:`UNREACHED_UV`. Nothing but that UV map (and which
UV map is active for editing) changes on the mesh.

Examples
--------
>>> from bl_ext.user_default.heat_geodesics import geodesic_uv_map        # doctest: +SKIP
>>> result = geodesic_uv_map(bpy.context.object, 120, unit=0.5, up=(0, 0, 1))   # doctest: +SKIP
>>> result.name, result.max_distance                                         # doctest: +SKIP
('geodesic_uv', 1.37)
"""

import time
from dataclasses import dataclass

import bmesh
import numpy as np

from . import adapters
from ._heatcore import heatcore
from .adapters import AddonError
from .cache import SOLVERS, geometry_key, placed
from .polygons import key_options
from .shape import measured_frame, object_positions
from .stages import FRONT_END_OPTIONS, Settings

#: The UV map's default name.
DEFAULT_UV_MAP = "geodesic_uv"
#: UV of the face corners of vertices that no geodesic from the source reaches (another loose part).
UNREACHED_UV = (0.0, 0.0)
#: Mesh custom property listing the UV maps this add-on made (only those are overwritten on a re-run).
MARKER = "heat_geodesic_uv_maps"
#: Longest UV map name Blender keeps, in bytes.
MAX_NAME = 63
#: The options the UV map takes (the domain's and the :class:`heatcore.VectorHeatSolver`'s), with its
#: front end's defaults (``weld`` off, ``accuracy`` high).
VECTOR_OPTIONS = FRONT_END_OPTIONS["blender uv map"]


def uv_settings(solver_options):
    """The UV map's one ``heatcore.settings.Settings`` of its options (its front end's defaults: weld off, accuracy high).

    Raises
    ------
    AddonError
        An option the UV map does not take (an output option of the distance).
    heatcore.InvalidOptionError
        A bad value.

    Examples
    --------
    >>> uv_settings({"m": 2}).solver.accuracy, uv_settings({"accuracy": "smooth"}).mesh.weld  # doctest: +SKIP
    ('high', None)
    """
    unknown = sorted(set(solver_options) - set(VECTOR_OPTIONS))
    if unknown:
        raise AddonError(f"the UV map takes the options {', '.join(VECTOR_OPTIONS)}; not {', '.join(unknown)}")
    return Settings.of("blender uv map", intent="interactive", **solver_options)


@dataclass
class UVMapResult:
    """What one *Geodesic UV Map* run wrote.

    Attributes
    ----------
    uv : (n, 2) float array
        The UV of each vertex (written to each of its face corners).
    name : str
        The UV map written.
    unit : float
        Scene units (of ``space``) per UV unit.
    max_distance : float
        Largest geodesic distance from the source to a reached vertex.
    unreached : int
        Vertices no geodesic reaches (UV :data:`UNREACHED_UV`).
    seconds : float
        Wall time of the run.
    cached : bool
        Whether the prefactored solver was reused.
    """

    uv: np.ndarray
    name: str
    unit: float
    max_distance: float
    unreached: int
    seconds: float
    cached: bool


def our_uv_maps(mesh):
    """Names of the UV maps of ``mesh`` that this add-on made (from its :data:`MARKER` property).

    Examples
    --------
    >>> our_uv_maps(bpy.context.object.data)   # doctest: +SKIP
    ['geodesic_uv']
    """
    return [n for n in str(mesh.get(MARKER, "")).split("\n") if n]


def check_uv_name(obj, name):
    """Refuse a UV map name that is empty, too long, reserved, or taken by anything but our own UV map.

    Raises
    ------
    AddonError
        With nothing modified.

    Examples
    --------
    >>> check_uv_name(bpy.context.object, "geodesic_uv")   # doctest: +SKIP
    """
    mesh = obj.data
    if not name:
        raise AddonError("the UV map name must not be empty")
    if len(name.encode()) > MAX_NAME:
        raise AddonError(f"UV map names are at most {MAX_NAME} bytes; {name!r} is longer")
    if name.startswith(".") or name in ("position", "id", "material_index"):
        raise AddonError(f"{name!r} is a name Blender reserves; choose another UV map name")
    if obj.vertex_groups.get(name) is not None:
        raise AddonError(f"{obj.name!r} has a vertex group {name!r}: choose another name for the UV map "
                         "(attributes and vertex groups share one set of names)")
    with adapters.stored(mesh) as data:
        existing = data.attributes.get(name)
        is_uv = data.uv_layers.get(name) is not None
        count = len(data.uv_layers)
    if existing is not None and not (is_uv and name in our_uv_maps(mesh)):
        what = "a UV map" if is_uv else f"an attribute ({existing.data_type} on {existing.domain})"
        raise AddonError(f"mesh {mesh.name!r} already has {what} named {name!r} that Geodesic UV Map did not "
                         "make; choose another name for the UV map (nothing was changed)")
    if existing is None and count >= 8:
        raise AddonError(f"mesh {mesh.name!r} has {count} UV maps, the most Blender allows; remove one or give the "
                         "name of a Geodesic UV Map to overwrite")


def active_vertex(obj):
    """The active vertex of ``obj`` in Edit Mode (the last one clicked), or None.

    Examples
    --------
    >>> active_vertex(bpy.context.edit_object)   # doctest: +SKIP
    412
    """
    if obj.mode != "EDIT":
        return None
    bm = bmesh.from_edit_mesh(obj.data)
    active = bm.select_history.active
    return active.index if isinstance(active, bmesh.types.BMVert) else None


def edge_direction(obj, vertex, V):
    """The direction from ``vertex`` along its selected edge (the first by index), else along its first edge.

    ``V`` are the measured positions. Raises :class:`AddonError` when the vertex has no edge.

    Examples
    --------
    >>> edge_direction(obj, 12, V)   # doctest: +SKIP
    array([0.1, 0. , 0. ])
    """
    with adapters.stored(obj.data) as data:
        edges = np.empty(2 * len(data.edges), dtype=np.int64)
        data.edges.foreach_get("vertices", edges)
        select = np.zeros(len(data.edges), dtype=bool)
        data.edges.foreach_get("select", select)
    edges = edges.reshape(-1, 2)
    at = np.flatnonzero((edges == vertex).any(axis=1))
    if at.size == 0:
        raise AddonError(f"vertex {vertex} of {obj.name!r} has no edge to take the up direction from")
    chosen = at[select[at]] if select[at].any() else at
    a, b = edges[chosen[0]]
    other = b if a == vertex else a
    return V[other] - V[vertex]


def _solver(obj, local, frame, topology, settings):
    """The mesh's cached :class:`heatcore.VectorHeatSolver` for this geometry (object coordinates ``local``
    placed by ``frame``) and these settings (built on a miss)."""
    given = key_options(settings, False)
    V = placed(local, frame)

    def build():
        # The distance's solver of this geometry, if cached, has the domain (and its scalar factorizations):
        # looked up with these settings, and with the same mesh options and the distance's default solver options;
        # only one built in this very frame (the log map's directions turn with the object).
        default_solver = Settings.of("blender", **{k: getattr(settings.mesh, k) for k in settings.mesh.given})
        keys = (given, key_options(default_solver, False))
        distance = next((found for found in (SOLVERS.lookup(obj.data.session_uid,
                                                            geometry_key(local, topology, o, False, frame), exact=True)
                                             for o in keys) if found is not None), None)
        if distance is not None:
            domain = distance.domain
        else:
            domain = heatcore.TriangleMesh(V, adapters.mesh_arrays(obj.data)[1], settings.mesh)
        return heatcore.VectorHeatSolver(domain, settings.solver)

    return SOLVERS.get(("uv map", obj.data.session_uid), V, topology, given, build)


def _to_space(obj, vector, space):
    """A world-space direction in the coordinates of ``space`` (tangent vectors map by the inverse matrix)."""
    vector = np.asarray(vector, dtype=np.float64).reshape(3)
    if space == "LOCAL":
        M = np.array(obj.matrix_world, dtype=np.float64)[:3, :3]
        vector = np.linalg.solve(M, vector)
    return vector


def log_map_uv(log_map, unit):
    """UV coordinates of log-map coordinates ``(x, y)`` (+x: the up direction): ``(0.5 - y, 0.5 + x) / unit``.

    +V is the up direction and +U its right (``up × normal``), so a texture
    reads unmirrored seen from outside. Rows that are not finite (unreached)
    get :data:`UNREACHED_UV`.

    Examples
    --------
    >>> log_map_uv(np.array([[1.0, 0.0], [0.0, 1.0], [np.inf, np.inf]]), 2.0).tolist()
    [[0.5, 1.0], [0.0, 0.5], [0.0, 0.0]]
    """
    log_map = np.asarray(log_map, dtype=np.float64)
    reached = np.isfinite(log_map).all(axis=1)
    uv = np.empty_like(log_map)
    uv[:] = UNREACHED_UV
    uv[reached, 0] = 0.5 - log_map[reached, 1] / unit
    uv[reached, 1] = 0.5 + log_map[reached, 0] / unit
    return uv


def write_uv_map(obj, name, uv):
    """Write the per-vertex ``uv`` to every face corner of each vertex of ``obj``'s UV map ``name`` (made if missing).

    The UV map becomes the active one (shown in the UV Editor); the render UV
    map is left as it was (Blender makes a mesh's first UV map the render one).

    Examples
    --------
    >>> write_uv_map(obj, "geodesic_uv", np.full((len(obj.data.vertices), 2), 0.5))   # doctest: +SKIP
    """
    mesh = obj.data
    with adapters.object_mode(obj):
        corners = np.empty(len(mesh.loops), dtype=np.int64)
        mesh.loops.foreach_get("vertex_index", corners)
        layer = mesh.uv_layers.get(name)
        if layer is None:
            layer = mesh.uv_layers.new(name=name, do_init=False)
            if layer is None:
                raise AddonError(f"Blender refused a new UV map on {mesh.name!r} (too many UV maps)")
        layer.uv.foreach_set("vector", uv[corners].astype(np.float32).ravel())
        mesh.uv_layers.active = layer
        if name not in our_uv_maps(mesh):
            mesh[MARKER] = "\n".join([*our_uv_maps(mesh), name])
        mesh.update()


def geodesic_uv_map(obj, vertex=None, *, point=None, name=DEFAULT_UV_MAP, unit=None, up=(0.0, 0.0, 1.0),
                    space="WORLD", shape="EVALUATED", **solver_options):
    """Write a UV map from the logarithmic map around a vertex (or a surface point) of a mesh object.

    Parameters
    ----------
    obj : bpy.types.Object
        A mesh object (Object or Edit Mode).
    vertex : int, optional
        The source vertex. Default: the active vertex in Edit Mode.
    point : (triangle, barycentric), optional
        Or a point on the surface: a loop triangle of the mesh and three
        barycentric weights, as :class:`GeodesicProbe` holds its points
        (``(vertex, None)``, a probe's point on a vertex, is that vertex):
        ``geodesic_uv_map(obj, point=probe.sources[-1])`` places the map at
        the probe's last point.
    name : str
        The UV map written. One this function made earlier is overwritten;
        any other attribute or UV map of that name is refused.
    unit : float, optional
        Scene units (of ``space``) per UV unit; None or 0: twice the largest
        distance, so the map fills the 0..1 square.
    up : (3,) array_like or "EDGE"
        The direction at the source that becomes +V: a world-space vector
        (its part along the surface normal is dropped), or ``"EDGE"``: along
        the vertex's selected edge (the first by index), else its first edge.
    space : {"WORLD", "LOCAL"}
    shape : {"EVALUATED", "BASIS"}
        Which shape is measured, as in :func:`compute_geodesic_distance`.
    **solver_options
        ``robust``, ``refine``, ``weld`` (the domain) and ``m``, ``boundary``,
        ``accuracy``, ``backend`` (:class:`heatcore.VectorHeatSolver`):
        :data:`VECTOR_OPTIONS`, made one ``Settings`` (:func:`uv_settings`:
        weld off, ``accuracy="high"``).

    Returns
    -------
    UVMapResult

    Raises
    ------
    AddonError
        Not a mesh, no source, a bad name, unit or up direction. Nothing is modified.
    heatcore.HeatcoreError
        A bad source (a vertex no face uses) or option. Nothing is modified.

    Examples
    --------
    >>> geodesic_uv_map(bpy.context.object, 0, unit=1.0, up="EDGE").unreached   # doctest: +SKIP
    0
    """
    start = time.perf_counter()
    if obj is None or getattr(obj, "type", None) != "MESH":
        raise AddonError(f"{getattr(obj, 'name', obj)!r} is not a mesh object")
    settings = uv_settings(solver_options)
    check_uv_name(obj, name)
    if unit is not None and not (np.isfinite(unit) and unit >= 0):
        raise AddonError(f"the UV unit must be a positive length (0: fit the map), got {unit}")
    if point is not None and vertex is None and point[1] is None:  # a probe's point on a vertex
        vertex, point = point[0], None
    if vertex is None and point is None:
        vertex = active_vertex(obj)
        if vertex is None:
            raise AddonError(f"no source: click a vertex of {obj.name!r} in Edit Mode (the active vertex), "
                             "or give vertex= or point=")
    if vertex is not None and point is not None:
        raise AddonError("give a vertex or a point, not both")
    if obj.mode == "EDIT":
        obj.update_from_editmode()
    frame = measured_frame(obj, space)
    local, _ = object_positions(obj, shape)
    V = placed(local, frame)
    if vertex is not None and not 0 <= int(vertex) < len(V):
        raise AddonError(f"vertex {vertex} is not a vertex of {obj.name!r} ({len(V):,} vertices)")
    if isinstance(up, str):
        if up != "EDGE":
            raise AddonError(f"up must be a 3D vector or 'EDGE', got {up!r}")
        if vertex is None:
            raise AddonError("up='EDGE' needs a vertex source (a point on a face has no edge of its own)")
        reference = edge_direction(obj, int(vertex), V)
    else:
        reference = _to_space(obj, up, space)
    if not np.all(np.isfinite(reference)) or not np.any(reference):
        raise AddonError(f"the up direction must be a nonzero vector, got {tuple(np.ravel(up))}")
    solver, cached = _solver(obj, local, frame, (*adapters.topology(obj.data), adapters.vertex_positions(obj.data)),
                             settings)
    try:
        if vertex is not None:
            log_map = solver.log_map(int(vertex), reference=reference)
        else:
            triangle, barycentric = point
            log_map = solver.log_map(points=([int(triangle)], [np.asarray(barycentric, dtype=np.float64)]),
                                     reference=reference)
    except heatcore.InvalidOptionError as exc:
        raise AddonError(f"the up direction has no part along the surface at the source ({exc}); "
                         "choose another") from None
    radius = np.hypot(log_map[:, 0], log_map[:, 1])
    reached = np.isfinite(radius)
    max_distance = float(radius[reached].max()) if reached.any() else 0.0
    unit = float(unit) if unit else (2.0 * max_distance or 1.0)
    uv = log_map_uv(log_map, unit)
    write_uv_map(obj, name, uv)
    return UVMapResult(uv=uv, name=name, unit=unit, max_distance=max_distance, unreached=int((~reached).sum()),
                       seconds=time.perf_counter() - start, cached=cached)
