"""Isoline curves and geodesic paths of a :class:`pymeshlab.MeshSet`'s current mesh as new edge-mesh layers.

:func:`isoline_curves_layer` reads the distance the filter
(:func:`heatcore.apps.meshlab_filter.geodesic_distance_from_selection`) wrote,
as vertex quality or a custom vertex scalar attribute, computes its isolines
with :func:`heatcore.isolines` and adds them to the MeshSet as one mesh of
vertices and edges (no faces): each isoline a chain of edges, closed ones
closed by an edge back to their first point. Negative values (the filter's
``unreachable = -1``) count as unreachable: the curves end there.

Examples
--------
>>> isoline_curves_layer.__name__
'isoline_curves_layer'
"""

import numpy as np

from ..contours import isoline_levels, isolines
from ..errors import InvalidOptionError


def _levels(d, levels, spacing):
    if spacing is not None:
        if not spacing > 0:
            raise InvalidOptionError(f"spacing must be positive, got {spacing!r}")
        finite = d[np.isfinite(d)]
        return spacing * np.arange(1, int(np.ceil(finite.max() / spacing))) if finite.size else np.zeros(0)
    if isinstance(levels, (int, np.integer)) and not isinstance(levels, bool):
        return isoline_levels(d, levels)
    return np.asarray(levels, dtype=float).ravel()


def edge_mesh_arrays(curves):
    """Vertices and edges of polylines: (k, 3) points and (e, 2) int32 edges, a closing edge per closed curve.

    Examples
    --------
    >>> import heatcore as hc
    >>> V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]]); F = np.array([[0, 1, 2]])
    >>> P, E = edge_mesh_arrays(hc.isolines(V, F, np.array([0.0, 1.0, 1.0]), [0.5]))
    >>> P.tolist(), E.tolist()
    ([[0.0, 0.5, 0.0], [0.5, 0.0, 0.0]], [[0, 1]])
    """
    points, edges, start = [np.zeros((0, 3))], [np.zeros((0, 2), dtype=np.int32)], 0
    for c in curves:
        k = len(c.points)
        idx = np.arange(start, start + k, dtype=np.int32)
        pairs = np.column_stack([idx[:-1], idx[1:]])
        if c.closed and k > 2:
            pairs = np.vstack([pairs, [[idx[-1], idx[0]]]])
        points.append(np.asarray(c.points, dtype=float))
        edges.append(pairs.astype(np.int32))
        start += k
    return np.vstack(points), np.vstack(edges)


def _add_edge_layer(ms, points, edges, name, set_as_current):
    """Add a mesh of vertices and edges to ``ms``; the current mesh stays current unless asked. Its id."""
    import pymeshlab  # the caller has imported it (after bpy, where both are used)

    current = ms.current_mesh().id()
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=points, edge_matrix=edges), mesh_name=name, set_as_current=True)
    new = ms.current_mesh_id()
    if not set_as_current:
        ms.set_current_mesh(current)
    return new


def isoline_curves_layer(ms, levels=8, spacing=None, attribute=None, name="isolines", set_as_current=False):
    """Add the isolines of the current mesh's distance to ``ms`` as a new edge-mesh layer.

    Parameters
    ----------
    ms : pymeshlab.MeshSet
        Its current mesh holds the distance (run the filter first).
    levels : int or sequence of float
        A number of evenly spaced levels (``max * j / (levels + 1)``) or the levels themselves.
    spacing : float, optional
        When given: a level at every multiple of it below the largest distance (``levels`` is ignored).
    attribute : str, optional
        Custom vertex scalar attribute to read; default the vertex quality.
    name : str
        Name of the new layer.
    set_as_current : bool
        Make the new layer current (default: the surface stays current).

    Returns
    -------
    dict
        ``id`` (the new layer's id), ``curves``, ``closed``, ``points``, ``edges``, ``levels``.

    Examples
    --------
    >>> import pytest
    >>> pymeshlab = pytest.importorskip("pymeshlab")  # the test extra
    >>> V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]); F = np.array([[0, 1, 2], [1, 3, 2]], np.int32)
    >>> ms = pymeshlab.MeshSet()
    >>> ms.add_mesh(pymeshlab.Mesh(V, F, v_scalar_array=V[:, 0] + V[:, 1]))
    >>> out = isoline_curves_layer(ms, levels=[1.0])
    >>> out["curves"], ms.mesh_number(), ms.mesh(out["id"]).edge_matrix().tolist()
    (1, 2, [[0, 1]])
    """
    mesh = ms.current_mesh()
    V, F = mesh.vertex_matrix(), mesh.face_matrix()
    if attribute is None:
        d = np.array(mesh.vertex_scalar_array(), dtype=float)
    else:
        d = np.array(mesh.vertex_custom_scalar_attribute_array(attribute), dtype=float)
    d[d < 0] = np.inf  # the filter's unreachable vertices
    curves = isolines(V, F, d, _levels(d, levels, spacing))
    P, E = edge_mesh_arrays(curves)
    new = _add_edge_layer(ms, P, E, name, set_as_current)
    return {"id": new, "curves": len(curves), "closed": sum(c.closed for c in curves),
            "points": len(P), "edges": len(E), "levels": sorted({c.level for c in curves})}


def geodesic_path_layer(ms, source=None, target=None, name="geodesic path", set_as_current=False, **solver_options):
    """Add the geodesic path between two vertices of the current mesh to ``ms`` as a new edge-mesh layer.

    Parameters
    ----------
    ms : pymeshlab.MeshSet
    source, target : int, optional
        Vertex indices of the current mesh. Default (both None): its two selected
        vertices, the lower index the source (MeshLab has no active vertex).
    name : str
        Name of the new layer: the path's points as vertices, a chain of edges.
    set_as_current : bool
        Make the new layer current (default: the surface stays current).
    **solver_options
        Mesh and solver options of the MeshLab front end (``refine``, ``m``,
        ``accuracy``, ``backend``, ...: ``FRONT_END_OPTIONS["meshlab"]``), made
        one :class:`~heatcore.settings.Settings` (MeshLab's defaults).

    Returns
    -------
    dict
        ``id`` (the new layer's id), ``length``, ``points``, ``source``, ``target``, ``path``
        (the :class:`~heatcore.GeodesicPath`).

    Raises
    ------
    InvalidSourceError
        Not exactly two selected vertices (without ``source`` and ``target``), or heatcore's own
        (an index out of range, a target in another part). The MeshSet is not changed.

    Examples
    --------
    >>> import pytest
    >>> pymeshlab = pytest.importorskip("pymeshlab")  # the test extra
    >>> V = np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]); F = np.array([[0, 1, 2], [1, 3, 2]], np.int32)
    >>> ms = pymeshlab.MeshSet()
    >>> ms.add_mesh(pymeshlab.Mesh(V, F))
    >>> out = geodesic_path_layer(ms, 0, 3, refine=0)
    >>> round(out["length"], 6), out["points"], ms.mesh(out["id"]).edge_matrix().tolist()
    (1.414214, 3, [[0, 1], [1, 2]])
    """
    from ..domains.triangle import TriangleMesh
    from ..errors import InvalidSourceError
    from ..heat import HeatSolver
    from ..settings import Settings

    settings = Settings.of("meshlab", **solver_options)
    mesh = ms.current_mesh()
    if (source is None) != (target is None):
        raise InvalidSourceError("give both the source and the target vertex, or neither (the two selected vertices)")
    if source is None:
        selected = np.flatnonzero(mesh.vertex_selection_array())
        if len(selected) != 2:
            raise InvalidSourceError(f"select exactly two vertices (the lower index is the source): {len(selected)} "
                                     "are selected")
        source, target = (int(i) for i in selected)
    solver = HeatSolver(TriangleMesh(mesh.vertex_matrix(), mesh.face_matrix(), settings.mesh), settings.solver)
    path = solver.geodesic_path(int(source), int(target))
    k = len(path.points)
    edges = np.column_stack([np.arange(k - 1), np.arange(1, k)]).astype(np.int32)
    new = _add_edge_layer(ms, path.points, edges, name, set_as_current)
    return {"id": new, "length": float(path.length), "points": k, "source": int(source), "target": int(target),
            "path": path}
