"""Script API of geodesic paths: the shortest path between two vertices as a curve object.

:func:`geodesic_path` measures on the shape the user sees (the same
:func:`~.stages.prepare_run` as the distance, so the cached solver is reused),
calls ``HeatSolver.geodesic_path`` and writes the curve object
``"<name> Geodesic Path"`` (:func:`~.curves.write_curves`: one poly spline,
world coordinates, reused on re-runs, the probe's path curve too). The two
ends are given, or read from Edit Mode: exactly two selected vertices, the
active one the source. ``select_edges`` also selects the mesh edges along
the path (:func:`heatcore.paths.edge_chain`: the shortest chain of edges
among the faces the path crosses).

Examples
--------
>>> from bl_ext.user_default.heat_geodesics import geodesic_path   # doctest: +SKIP
>>> result = geodesic_path(bpy.context.object)                      # doctest: +SKIP
>>> result.curve.name, round(result.length, 3)                      # doctest: +SKIP
('Suzanne Geodesic Path', 1.874)
"""

import importlib
import time
import warnings
from dataclasses import dataclass

import bmesh
import numpy as np

from ._heatcore import heatcore
from .adapters import AddonError, selected_vertices, topology
from .cache import SOLVERS
from .curves import write_curves
from .stages import build_solver, prepare_run

#: ``heatcore.paths`` (the bundled copy's): ``edge_chain``.
paths = importlib.import_module(heatcore.__name__ + ".paths")


@dataclass
class PathResult:
    """What :func:`geodesic_path` made.

    Attributes
    ----------
    curve : bpy.types.Object
        The curve object ``"<name> Geodesic Path"`` (one poly spline, world coordinates).
    length : float
        The path's length in the units of ``space`` (scene units for ``"WORLD"``).
    points : (k, 3) float array
        The spline's points in world coordinates, source first.
    path : heatcore.GeodesicPath
        heatcore's path in the measured coordinates (``faces`` are the mesh's loop triangles).
    source, target : int
        The end vertices.
    edges : (j,) int array
        The mesh edges selected (``select_edges``), in order from the source; empty otherwise.
    seconds : float
        Wall time of the call.
    cached : bool
        Whether the prefactored solver was reused.
    warnings : list of str
        What the user should know (modifiers left out of the measured shape).

    Examples
    --------
    >>> geodesic_path(obj, 0, 40).points[0]   # doctest: +SKIP
    array([0.   , 0.   , 1.   ])
    """

    curve: object
    length: float
    points: np.ndarray
    path: object
    source: int
    target: int
    edges: np.ndarray
    seconds: float
    cached: bool
    warnings: list


def selected_ends(obj):
    """The source (the active vertex) and the target (the other selected one) of ``obj`` in Edit Mode.

    Raises
    ------
    AddonError
        Not in Edit Mode, not exactly two selected vertices, or the active
        element is not one of them.

    Examples
    --------
    >>> selected_ends(bpy.context.edit_object)   # doctest: +SKIP
    (12, 40)
    """
    if obj.mode != "EDIT":
        raise AddonError(f"Geodesic Path reads the two ends from Edit Mode and {obj.name!r} is in {obj.mode.title()} "
                         "Mode: Tab into Edit Mode, select the target, then Shift-click the source (the active vertex)")
    obj.update_from_editmode()
    selected = selected_vertices(obj.data)
    if len(selected) != 2:
        raise AddonError(f"select exactly two vertices of {obj.name!r} (the active one is the source): "
                         f"{len(selected):,} are selected")
    bm = bmesh.from_edit_mesh(obj.data)
    active = bm.select_history.active
    if isinstance(active, bmesh.types.BMVert):
        bm.verts.index_update()  # the indices of the synced mesh
    if not isinstance(active, bmesh.types.BMVert) or active.index not in selected:
        raise AddonError(f"no active vertex among the two selected vertices of {obj.name!r}: Shift-click the source "
                         "last so that it is the active one (the path runs from it to the other)")
    return int(active.index), int(selected[selected != active.index][0])


def _edge_chain(obj, V, path, source, target):
    """Mesh edges along ``path``: the shortest chain among the vertices of the polygons it crosses."""
    mesh = obj.data
    corner_verts, triangle_faces = topology(mesh)
    totals = np.empty(len(mesh.polygons), dtype=np.int64)
    mesh.polygons.foreach_get("loop_total", totals)
    crossed = np.zeros(len(mesh.polygons), dtype=bool)
    crossed[triangle_faces[path.faces]] = True
    allowed = corner_verts[np.repeat(crossed, totals)]  # corners are stored polygon after polygon
    E = np.empty(2 * len(mesh.edges), dtype=np.int64)
    mesh.edges.foreach_get("vertices", E)
    return paths.edge_chain(V, E.reshape(-1, 2), allowed, source, target)


def _select_edges(obj, edge_ids):
    """Add the edges ``edge_ids`` (and their vertices) to the selection; the active element stays."""
    if obj.mode == "EDIT":
        bm = bmesh.from_edit_mesh(obj.data)
        bm.edges.ensure_lookup_table()
        for i in edge_ids:  # the chain's edges, not the mesh's
            bm.edges[int(i)].select_set(True)
        bmesh.update_edit_mesh(obj.data, loop_triangles=False, destructive=False)
        return
    mesh = obj.data
    for items, ids in ((mesh.edges, edge_ids), (mesh.vertices, None)):
        select = np.zeros(len(items), dtype=bool)
        items.foreach_get("select", select)
        if ids is None:
            E = np.empty(2 * len(mesh.edges), dtype=np.int64)
            mesh.edges.foreach_get("vertices", E)
            ids = E.reshape(-1, 2)[edge_ids].ravel()
        select[ids] = True
        items.foreach_set("select", select)
    mesh.update()


def geodesic_path(obj, source=None, target=None, *, select_edges=False, space="WORLD", shape="EVALUATED",
                  progress=None, **solver_options):
    """The geodesic path from vertex ``source`` to vertex ``target`` of a mesh object, written as a curve object.

    Parameters
    ----------
    obj : bpy.types.Object
        A mesh object with faces.
    source, target : int, optional
        Vertex indices. Default (both None): in Edit Mode, the two selected
        vertices, the active one (selected last) the source.
    select_edges : bool
        Also add to the selection the mesh edges along the path: the shortest
        chain of edges (by length) from the source to the target among the
        vertices of the faces the path crosses.
    space, shape : str
        Where the path is measured, as for :func:`~.api.compute_geodesic_distance`
        (default: world coordinates, the shape as displayed).
    progress : callable, optional
        ``progress(fraction, message)`` while the solver is built (when not cached).
    **solver_options
        As for :func:`~.api.compute_geodesic_distance` (``m``, ``accuracy``, ...);
        the same options reuse the same cached solver.

    Returns
    -------
    PathResult

    Raises
    ------
    AddonError
        Not a mesh with faces; no ends given and not exactly two selected
        vertices with the active one among them, or Object Mode; a bad index;
        a target in another part of the mesh (heatcore's message names both
        parts). Nothing is modified.

    Examples
    --------
    >>> result = geodesic_path(bpy.context.object, 0, 40, select_edges=True)   # doctest: +SKIP
    >>> result.curve.name, len(result.edges)                                  # doctest: +SKIP
    ('Icosphere Geodesic Path', 7)
    """
    start = time.perf_counter()
    if obj is None or obj.type != "MESH":
        raise AddonError(f"Geodesic Path needs a mesh object; {getattr(obj, 'name', obj)!r} is not one")
    if (source is None) != (target is None):
        raise AddonError("give both the source and the target vertex, or neither (then the Edit Mode selection)")
    if source is None:
        source, target = selected_ends(obj)
    elif obj.mode == "EDIT":
        obj.update_from_editmode()
    if not len(obj.data.polygons):
        raise AddonError(f"Geodesic Path runs on faces and mesh {obj.data.name!r} has none")
    run = prepare_run(obj, sources_later=True, space=space, shape=shape, progress=progress,
                      attribute=None, color_attribute=None, **solver_options)
    for note in run.notes:
        warnings.warn(note, stacklevel=2)
    if run.solver is None:
        build_solver(run, progress)
        SOLVERS.store(run.cache_id, run.key, run.solver)
    try:
        path = run.placement.path(run.solver.geodesic_path(int(source), int(target)))
    except heatcore.InvalidSourceError as exc:  # a bad index, a loose vertex, another part
        raise AddonError(f"{obj.name}: {exc}") from None
    edge_ids = np.zeros(0, dtype=np.int64)
    if select_edges:
        _, edge_ids = _edge_chain(obj, run.V, path, int(source), int(target))
    points = np.asarray(path.points, dtype=np.float64)
    if run.space == "LOCAL":
        M = np.array(obj.matrix_world, dtype=np.float64)
        points = points @ M[:3, :3].T + M[:3, 3]
    curve = write_curves(obj, "Path", [points])
    if select_edges:
        _select_edges(obj, edge_ids)
    return PathResult(curve, float(path.length), points, path, int(source), int(target), edge_ids,
                      time.perf_counter() - start, run.cached, list(run.notes))
