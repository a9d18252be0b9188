"""Script API of geodesic paths: the shortest path between two vertices, or through waypoints, as a curve object.

:func:`geodesic_path` measures on the shape the user sees (the same
:func:`~.stages.prepare_run` as the distance, so the cached solver is reused),
calls ``HeatSolver.geodesic_path`` and writes the curve object
``"<name> Geodesic Path"`` (:func:`~.curves.write_curves`: one poly spline,
world coordinates, reused on re-runs, the probe's path curve too). The ends
are given, or read from Edit Mode: two selected vertices, the active one the
source; or three and more, shift-clicked one by one, visited in the order
they were selected (``closed``: back to the first). ``select_edges`` also
selects the mesh edges along the path (:func:`heatcore.paths.edge_chain`: the
shortest chain of edges among the faces each leg crosses).

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
        The end vertices (for a closed path, both the first waypoint).
    waypoints : list of int
        The vertices the path passes through, in order (the two ends for a plain path).
    leg_lengths : (w - 1,) float array
        The length of each leg between consecutive waypoints, in the units of ``space``.
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
    waypoints: list
    leg_lengths: np.ndarray
    edges: np.ndarray
    seconds: float
    cached: bool
    warnings: list


def selected_ends(obj):
    """The vertices a path from the Edit Mode selection visits: ``[source, target]``, or the waypoints in order.

    Two selected vertices: the active one (selected last) is the source.
    Three or more: each must have been clicked (Blender's selection history
    holds what was clicked, not what was box-selected), and they are visited in
    the order they were clicked.

    Raises
    ------
    AddonError
        Not in Edit Mode; fewer than two selected vertices; two without the
        active one among them; more than two not all clicked one by one.

    Examples
    --------
    >>> selected_ends(bpy.context.edit_object)   # doctest: +SKIP
    [12, 40]
    """
    if obj.mode != "EDIT":
        raise AddonError(f"Geodesic Path reads the two ends from Edit Mode and {obj.name!r} is in {obj.mode.title()} "
                         "Mode: Tab into Edit Mode, select the target, then Shift-click the source (the active vertex)")
    obj.update_from_editmode()
    selected = selected_vertices(obj.data)
    if len(selected) < 2:
        raise AddonError(f"select two vertices of {obj.name!r} (the active one is the source), or Shift-click "
                         f"three or more waypoints in order: {len(selected):,} selected")
    bm = bmesh.from_edit_mesh(obj.data)
    bm.verts.index_update()  # the indices of the synced mesh
    history = [e.index for e in bm.select_history if isinstance(e, bmesh.types.BMVert)]
    if len(selected) > 2:
        if sorted(set(history)) != sorted(selected.tolist()):
            raise AddonError(f"{len(selected):,} vertices of {obj.name!r} are selected but not all one by one: "
                             "Shift-click the waypoints in the order the path visits them (a box or loop "
                             "selection has no order)")
        return history
    active = history[-1] if history else None
    if active is None or active not in selected:
        raise AddonError(f"no active vertex among the two selected vertices of {obj.name!r}: Shift-click the source "
                         "last so that it is the active one (the path runs from it to the other)")
    return [int(active), int(selected[selected != active][0])]


def edge_chain_along(obj, V, path, source, target):
    """Mesh edges along one leg ``path``: the shortest chain among the vertices of the polygons it crosses."""
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


def select_mesh_edges(obj, edge_ids):
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


def geodesic_path(obj, source=None, target=None, *, waypoints=None, closed=False, select_edges=False, space="WORLD",
                  shape="EVALUATED", progress=None, **solver_options):
    """The geodesic path from vertex ``source`` to vertex ``target`` (or through ``waypoints``), as a curve object.

    Parameters
    ----------
    obj : bpy.types.Object
        A mesh object with faces.
    source, target : int, optional
        Vertex indices. Default (both None, no waypoints): from Edit Mode,
        two selected vertices (the active one the source), or three and more
        clicked one by one, in that order (:func:`selected_ends`).
    waypoints : sequence of int, optional
        The vertices to pass through, in order (instead of ``source`` and ``target``).
    closed : bool
        Return from the last waypoint to the first: a closed loop.
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
    if waypoints is not None and source is not None:
        raise AddonError("give the waypoints, or the source and the target, not both")
    if waypoints is None and source is None:
        waypoints = selected_ends(obj)  # synced with Edit Mode
    else:
        waypoints = [source, target] if waypoints is None else list(waypoints)
        if obj.mode == "EDIT":
            obj.update_from_editmode()
    waypoints = [int(v) for v in waypoints]
    if len(waypoints) < 2:
        raise AddonError(f"a path needs two vertices or more, got {len(waypoints)}")
    if not len(obj.data.polygons):
        raise AddonError(f"Geodesic Path runs on faces and mesh {obj.data.name!r} has none")
    run = path_run(obj, space, shape, progress, solver_options)
    try:
        if len(waypoints) == 2 and not closed:
            path = run.placement.path(run.solver.geodesic_path(*waypoints))
        else:
            path = run.placement.path(run.solver.geodesic_path(points=waypoints, closed=closed))
    except heatcore.InvalidSourceError as exc:  # a bad index, a loose vertex, another part
        raise AddonError(f"{obj.name}: {exc}") from None
    edge_ids = np.zeros(0, dtype=np.int64)
    if select_edges:
        edge_ids = _leg_edges(obj, run, waypoints, closed)
    points = world_points(obj, run, path.points)
    curve = write_curves(obj, "Path", [points])
    if select_edges:
        select_mesh_edges(obj, edge_ids)
    return PathResult(curve, float(path.length), points, path, waypoints[0], waypoints[0] if closed else waypoints[-1],
                      waypoints, np.asarray(path.leg_lengths, dtype=np.float64), edge_ids, time.perf_counter() - start,
                      run.cached, list(run.notes))


def path_run(obj, space, shape, progress, solver_options):
    """The prepared run of a path on ``obj`` (the shape as measured, loop triangles), its solver built and cached."""
    run = prepare_run(obj, sources_later=True, space=space, shape=shape, progress=progress,
                      attribute=None, color_attribute=None, **solver_options)
    for note in run.notes:
        warnings.warn(note, stacklevel=3)
    if run.solver is None:
        build_solver(run, progress)
        SOLVERS.store(run.cache_id, run.key, run.solver)
    return run


def world_points(obj, run, points):
    """Points measured by ``run`` in world coordinates (Space Local: moved by the object's matrix)."""
    points = np.asarray(points, dtype=np.float64)
    if run.space == "LOCAL":
        M = np.array(obj.matrix_world, dtype=np.float64)
        points = points @ M[:3, :3].T + M[:3, 3]
    return points


def _leg_edges(obj, run, waypoints, closed):
    """The mesh edges along each leg (`edge_chain_along` of the leg's own path), in order."""
    stops = waypoints + waypoints[:1] if closed else waypoints
    chains = [edge_chain_along(obj, run.V, run.placement.path(run.solver.geodesic_path(a, b)), a, b)[1]
              for a, b in zip(stops[:-1], stops[1:])]
    return np.concatenate(chains) if chains else np.zeros(0, dtype=np.int64)
