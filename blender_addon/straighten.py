"""Script API of *Straighten Edges*: a selected edge path or loop shortened to a geodesic, as a curve object.

The selected edges become chains and loops (:func:`heatcore.edge_curves`);
each chain is shortened with its ends kept (``HeatSolver.straighten_path``),
each loop to the closed geodesic of its class (``HeatSolver.straighten_loop``:
around a cylinder, its waist). They are measured on the shape the user sees
(the same :func:`~.stages.prepare_run` as *Geodesic Path*, so the cached solver
is reused) and written as the curve object ``"<name> Geodesic Straightened"``
(one poly spline each, cyclic for loops). ``select_edges`` replaces the edge
selection of each chain or loop by the mesh edges nearest to its geodesic.

Examples
--------
>>> from bl_ext.user_default.heat_geodesics import straighten_edges   # doctest: +SKIP
>>> result = straighten_edges(bpy.context.object)                     # doctest: +SKIP
>>> result.lengths, result.before                                     # doctest: +SKIP
([1.571], [1.802])
"""

import time
from dataclasses import dataclass
from types import SimpleNamespace

import numpy as np

from ._heatcore import heatcore
from .adapters import AddonError
from .curves import write_curves
from .path_api import edge_chain_along, path_run, select_mesh_edges, world_points
from .signed import selected_edges


@dataclass
class StraightenResult:
    """What :func:`straighten_edges` made.

    Attributes
    ----------
    curve : bpy.types.Object
        The curve object ``"<name> Geodesic Straightened"``.
    paths : list of heatcore.GeodesicPath
        The straightened chains and loops, in the measured coordinates.
    lengths, before : list of float
        Each one's length after and before (the selected edges), in the units of ``space``.
    closed : list of bool
        Which are loops.
    edges : (j,) int array
        The mesh edges selected along the chains (``select_edges``); empty otherwise.
    seconds : float
    cached : bool
    warnings : list of str
    """

    curve: object
    paths: list
    lengths: list
    before: list
    closed: list
    edges: np.ndarray
    seconds: float
    cached: bool
    warnings: list


def straighten_edges(obj, edges=None, *, select_edges=False, space="WORLD", shape="EVALUATED", progress=None,
                     **solver_options):
    """Straighten the selected edge chains and loops of a mesh object into geodesics, written as a curve object.

    Parameters
    ----------
    obj : bpy.types.Object
        A mesh object with faces.
    edges : (k, 2) array_like of int, optional
        The edges (vertex pairs). Default: the selected edges (Edit Mode is synced first).
    select_edges : bool
        Select, instead of each straightened chain's or loop's edges, the shortest chain of mesh edges among
        the faces its geodesic crosses (a loop: along each half).
    space, shape, progress, **solver_options
        As for :func:`~.path_api.geodesic_path`.

    Returns
    -------
    StraightenResult

    Raises
    ------
    AddonError
        Not a mesh with faces, no edge selected, an edge that is not the mesh's. Nothing is modified.
    """
    start = time.perf_counter()
    if obj is None or obj.type != "MESH":
        raise AddonError(f"Straighten Edges needs a mesh object; {getattr(obj, 'name', obj)!r} is not one")
    if obj.mode == "EDIT":
        obj.update_from_editmode()
    if not len(obj.data.polygons):
        raise AddonError(f"Straighten Edges runs on faces and mesh {obj.data.name!r} has none")
    pairs = selected_edges(obj.data) if edges is None else np.asarray(edges, dtype=np.int64).reshape(-1, 2)
    if len(pairs) == 0:
        raise AddonError(f"no edge selected on {obj.name!r}: select an edge path or loop in Edit Mode")
    run = path_run(obj, space, shape, progress, solver_options)
    chains = heatcore.edge_curves(run.solver.domain.faces, pairs)
    paths, before, closed = [], [], []
    try:
        for chain in chains:
            loop = len(chain) > 2 and chain[0] == chain[-1]
            found = run.solver.straighten_loop(chain) if loop else run.solver.straighten_path(chain)
            paths.append(run.placement.path(found))
            before.append(float(np.linalg.norm(np.diff(run.V[chain], axis=0), axis=1).sum()))  # the run's units
            closed.append(loop)
    except heatcore.HeatcoreError as exc:
        raise AddonError(f"{obj.name}: {exc}") from None
    points = [world_points(obj, run, p.points) for p in paths]
    curve = write_curves(obj, "Straightened", points, closed=closed)
    edge_ids = np.zeros(0, dtype=np.int64)
    if select_edges:
        edge_ids = _reselect(obj, run, chains, paths, closed)
    return StraightenResult(curve, paths, [float(p.length) for p in paths], before, closed, edge_ids,
                            time.perf_counter() - start, run.cached, list(run.notes))


def _reselect(obj, run, chains, paths, closed):
    """Each chain's edges deselected and the edges along its geodesic selected (a loop: along both its halves)."""
    E = np.empty(2 * len(obj.data.edges), dtype=np.int64)
    obj.data.edges.foreach_get("vertices", E)
    E = np.sort(E.reshape(-1, 2), axis=1)
    along, drop = [], set()
    for chain, path, loop in zip(chains, paths, closed):
        edges = _loop_edges(obj, run, path) if loop else edge_chain_along(obj, run.V, path, int(chain[0]),
                                                                          int(chain[-1]))[1]
        if edges.size:  # a loop whose halves no chain of edges follows keeps its selection
            along.append(edges)
            drop |= {tuple(sorted(e)) for e in zip(chain[:-1].tolist(), chain[1:].tolist())}
    deselect = np.array([tuple(e) in drop for e in E.tolist()], dtype=bool)
    new = np.concatenate(along) if along else np.zeros(0, dtype=np.int64)
    _set_edge_selection(obj, deselect, new)
    return new


def _loop_edges(obj, run, path):
    """Mesh edges along a closed geodesic: a chain along each half, between the vertices nearest its start and its
    middle (empty where either half has none)."""
    faces = np.asarray(path.faces)
    half = len(faces) // 2
    if half == 0:
        return np.zeros(0, dtype=np.int64)
    points = np.asarray(path.points)
    ends = [int(np.argmin(np.linalg.norm(run.V - points[i], axis=1))) for i in (0, len(points) // 2)]
    first = edge_chain_along(obj, run.V, SimpleNamespace(faces=faces[:half]), ends[0], ends[1])[1]
    second = edge_chain_along(obj, run.V, SimpleNamespace(faces=faces[half:]), ends[1], ends[0])[1]
    if not (first.size and second.size):
        return np.zeros(0, dtype=np.int64)
    return np.concatenate([first, second])


def _set_edge_selection(obj, deselect, select_ids):
    """Deselect the edges marked in ``deselect``, then select ``select_ids``."""
    import bmesh

    if obj.mode == "EDIT":
        bm = bmesh.from_edit_mesh(obj.data)
        bm.edges.ensure_lookup_table()
        for i in np.flatnonzero(deselect).tolist():
            bm.edges[i].select_set(False)
        bmesh.update_edit_mesh(obj.data, loop_triangles=False, destructive=False)
    else:
        select = np.zeros(len(obj.data.edges), dtype=bool)
        obj.data.edges.foreach_get("select", select)
        select[deselect] = False
        obj.data.edges.foreach_set("select", select)
    select_mesh_edges(obj, select_ids)
