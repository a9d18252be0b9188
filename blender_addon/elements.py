"""Selected faces (a region) and selected edges as sources, as heatcore takes them (``region=``, ``edges=``).

The distance is then to the union of the selected faces (0 inside them) or
of the selected edges (0 along them, not only at their corners), as
``HeatSolver.distance(region=...)`` and ``distance(edges=...)`` give it.
:func:`selected_elements` reads the selection; :func:`domain_sources` turns
it into the keywords of the domain that was built: a ``PolygonMesh`` takes
Blender's faces as they are, a ``TriangleMesh`` of the loop triangles the
triangles of the selected faces.

Examples
--------
>>> vertices, kinds = selected_elements(obj, "FACES")              # doctest: +SKIP
>>> solver.distance(**domain_sources(solver.domain, kinds, triangle_faces))  # doctest: +SKIP
"""

import numpy as np

from ._heatcore import heatcore
from .adapters import AddonError, stored

#: Which selected elements are the sources: ``selected=`` of the script API.
ELEMENTS = ("VERTICES", "EDGES", "FACES")


def _selected(collection, n):
    sel = np.zeros(n, dtype=bool)
    collection.foreach_get("select", sel)
    return np.flatnonzero(sel)


def selected_elements(obj, selected, notes=None):
    """The vertices of the selected edges or faces of ``obj`` (Edit Mode synced) and the sources as ``{kind: ...}``.

    Every edge or face selected in Object Mode (as after adding a primitive)
    makes every distance 0: a note says so in ``notes``.

    Returns
    -------
    vertices : (k,) int array
        The vertices they hold (the connected parts to build, the cache's check).
    kinds : dict
        ``{"edges": (e, 2) vertex pairs}`` or ``{"faces": face indices}``.

    Raises
    ------
    AddonError
        Nothing of that kind selected.
    """
    if selected not in ELEMENTS[1:]:
        raise AddonError(f"selected must be one of {', '.join(ELEMENTS)}, got {selected!r}")
    with stored(obj.data) as mesh:
        if selected == "EDGES":
            index = _selected(mesh.edges, len(mesh.edges))
            pairs = np.empty(2 * len(mesh.edges), dtype=np.int64)
            mesh.edges.foreach_get("vertices", pairs)
            elements = pairs.reshape(-1, 2)[index]
            vertices = np.unique(elements)
            kinds = {"edges": elements}
        else:
            index = _selected(mesh.polygons, len(mesh.polygons))
            vertices = np.unique(np.concatenate([list(mesh.polygons[i].vertices) for i in index] or [[]]))
            kinds = {"faces": index}
    what = "edges" if selected == "EDGES" else "faces"
    total = len(obj.data.edges) if selected == "EDGES" else len(obj.data.polygons)
    if notes is not None and obj.mode == "OBJECT" and index.size == total > 1:
        notes.append(f"all {total:,} {what} of {obj.name!r} are selected (as after adding a primitive), so every "
                     f"distance is 0; select the source {what} in Edit Mode")
    if index.size == 0:
        raise AddonError(f"no source {what}: no {what[:-1]} of {obj.name!r} is selected; select {what} in Edit Mode "
                         f"(or set Sources to Selected Vertices)")
    return vertices.astype(np.int64), kinds


def domain_sources(domain, kinds, triangle_faces):
    """Keywords of ``HeatSolver.distance`` for ``kinds`` on the ``domain`` built.

    Parameters
    ----------
    domain : heatcore domain
    kinds : dict
        From :func:`selected_elements`.
    triangle_faces : (m,) int array
        The face of each loop triangle (:func:`~.adapters.topology`).

    Examples
    --------
    >>> domain_sources(object(), {"faces": np.array([1])}, np.array([0, 1, 1, 2])) ["region"].tolist()
    [1, 2]
    """
    if "edges" in kinds:
        return {"edges": kinds["edges"]}
    if isinstance(domain, heatcore.PolygonMesh):
        return {"region": kinds["faces"]}
    return {"region": np.flatnonzero(np.isin(triangle_faces, kinds["faces"]))}
