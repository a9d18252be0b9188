"""Quads and n-gons measured as polygons: which meshes get ``heatcore.PolygonMesh``, and its arrays.

Blender meshes are mostly quads. heatcore's ``PolygonMesh`` measures each
face on heatcore's own triangulation of it (Delaunay in the face's plane,
concave faces and 180-degree corners included, docs/polygon.md): on a quad
grid 1.10% from the exact distance where the loop triangles, whose diagonals
all run one way, give 1.22%; on a quad sphere 1.71% against 1.53% (its
quads are not flat: the two diagonal choices make different surfaces). So a
distance run (``polygons="AUTO"``, the default) builds a ``PolygonMesh`` for
a mesh that has a face of four or more corners, from Blender's faces as they
are, and a ``TriangleMesh`` of the loop triangles otherwise, or where only
triangles serve:

- ``accuracy="high"``: the eikonal pass runs on triangle meshes;
- points on faces (the probe) and geodesic paths: they live on loop triangles;
- ``robust=False`` (plain cotan operators) and ``weld``, ``TriangleMesh``
  options: a weld tolerance, or with *Merge Coincident Vertices* on
  (``weld=0``) vertices at exactly the same position (found when the solver
  is built: :func:`polygon_domain`). By default nothing is merged
  (``weld=None``: the mesh as connected in Blender), so coincident vertices
  keep the polygons;
- ``polygons="TRIANGULATE"``: the loop triangles, as before.

A polygon whose sides cross (a bowtie) is measured as its fan triangles,
with a note to the user (``split_crossing=True``).

Examples
--------
>>> use_polygons("AUTO", bpy.data.meshes["Cube"], Settings.of("blender", accuracy="high"))  # doctest: +SKIP
False
"""

import importlib

import numpy as np

from . import adapters
from ._heatcore import heatcore
from .adapters import AddonError

#: heatcore's welding (``heatcore.domains.weld``), for :func:`coincident_vertices`.
WELD = importlib.import_module(heatcore.__name__ + ".domains.weld")

#: The choices of ``polygons=``: faces kept as polygons where the mesh has n-gons, or loop triangles always.
POLYGON_CHOICES = ("AUTO", "TRIANGULATE")


def check_polygons(value):
    """``value`` if it is one of ``POLYGON_CHOICES``; else an :class:`~.adapters.AddonError`.

    Examples
    --------
    >>> check_polygons("AUTO")
    'AUTO'
    """
    if value not in POLYGON_CHOICES:
        raise AddonError(f"polygons must be one of {', '.join(POLYGON_CHOICES)}, got {value!r}")
    return value


def has_ngons(mesh):
    """Whether ``mesh`` has a face of four or more corners (its loops outnumber three per face).

    Examples
    --------
    >>> has_ngons(bpy.data.meshes["Cube"])  # doctest: +SKIP
    True
    """
    return len(mesh.loops) > 3 * len(mesh.polygons)


def use_polygons(choice, mesh, settings, *, points_later=False, offsets=None):
    """Whether a run measures ``mesh`` as polygons (``heatcore.PolygonMesh``); see the module docstring.

    Parameters
    ----------
    choice : {"AUTO", "TRIANGULATE"}
    mesh : bpy.types.Mesh
    settings : heatcore.settings.Settings
        The run's settings (``accuracy``; ``robust``, ``weld``).
    points_later : bool
        Sources placed on faces later (the probe, paths).
    offsets : int array, optional
        With ``new_object``: the face offsets of the evaluated mesh that is
        measured (a Subdivision makes quads of triangles), instead of ``mesh``.

    Examples
    --------
    >>> use_polygons("AUTO", bpy.data.meshes["Cube"], Settings.of("blender"))  # doctest: +SKIP
    True
    """
    if check_polygons(choice) == "TRIANGULATE" or points_later:
        return False
    if settings.solver.accuracy == "high" or settings.mesh.weld or not settings.mesh.robust:
        return False  # the eikonal pass, a weld tolerance, plain cotan operators: triangle options
    return has_ngons(mesh) if offsets is None else bool(np.diff(offsets).max(initial=0) > 3)


def key_options(settings, as_polygons, points_only=False):
    """The options part of a run's cache key: every mesh and solver option, and ``polygons=True`` for a polygon run.

    :func:`~.stages.prepare_run` keys the solver with it and
    :func:`~.stages.check_unchanged` compares with it after a background
    build: both must use this. A point cloud (``points_only``) is keyed by
    the one mesh option it takes, ``refine``.

    Examples
    --------
    >>> key_options(Settings.of("blender", refine=0), True)  # doctest: +SKIP
    {'robust': True, 'refine': 0, 'weld': None, 'm': 1.0, 'boundary': 'robin', 'accuracy': 'smooth', 'backend': 'auto', 'polygons': True}
    """
    mesh = {"refine": settings.mesh.refine} if points_only else settings.mesh.keywords()
    return {**mesh, **settings.solver.keywords(), **({"polygons": True} if as_polygons else {})}


def polygon_domain(V, polygons, mesh, notes=None, only_parts_of=None, progress=None):
    """``heatcore.PolygonMesh`` of the faces, or None where merging (``weld=0``) has vertices to merge (exact duplicates).

    Polygons whose sides cross (a bowtie) are measured as their fan
    triangles. Either case appends a note for the user to ``notes``: the
    build may run in a worker thread, where a warning would reach no one.

    Parameters
    ----------
    V : (n, 3) float array
    polygons : (offsets, indices)
    mesh : heatcore.settings.MeshSettings
        The run's mesh options: ``weld`` decides, ``refine`` goes to the PolygonMesh
        (which takes no other).
    notes : list of str, optional
    only_parts_of : (k,) int array, optional
        The sources: only the connected parts they are on are built (``heatcore.PolygonMesh``).
    progress : callable, optional
        The build's stages (``heatcore.progress``).

    Examples
    --------
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)
    >>> mesh = Settings.of("blender", refine=0, weld=0.0).mesh
    >>> type(polygon_domain(V, (np.array([0, 4]), np.arange(4)), mesh)).__name__  # doctest: +SKIP
    'PolygonMesh'
    >>> polygon_domain(V[[0, 1, 2, 2]], (np.array([0, 4]), np.arange(4)), mesh) is None  # doctest: +SKIP
    True
    """
    notes = [] if notes is None else notes
    if mesh.weld is not None:
        merged = coincident_vertices(V)
        if merged:
            notes.append(f"measured as triangles, not polygons: {merged:,} vertices share their position with "
                         "another and are welded (Merge Coincident Vertices; polygons are not merged)")
            return None
    try:
        return heatcore.PolygonMesh(V, polygons, refine=mesh.refine, only_parts_of=only_parts_of, progress=progress)
    except heatcore.InvalidMeshError as exc:  # checked before any refinement: a cheap first try
        if "cross themselves" not in str(exc):
            raise
        notes.append(str(exc).split("; polygon ")[0].replace("polygon(s)", "face(s)")
                     + ": measured as their fan triangles (fix them in Edit Mode to measure them as polygons)")
    return heatcore.PolygonMesh(V, polygons, refine=mesh.refine, split_crossing=True, only_parts_of=only_parts_of,
                                progress=progress)


def coincident_vertices(V):
    """How many vertices share their exact position with another of ``V`` (n, 3): welding would merge them.

    heatcore's own check (``weld_map``: a hash of the rows first, so a mesh
    with none sorts nothing; 504k vertices: 0.05 s, where ``np.unique`` of
    the rows took 0.26 s).

    Examples
    --------
    >>> coincident_vertices(np.array([[0, 0, 0], [1, 0, 0], [0, 0, 0]], float))
    1
    """
    return WELD.weld_map(V, 0.0)[1]


def polygon_arrays(mesh, topology=None):
    """Blender's faces as ``(offsets, indices)``: face ``i`` is ``indices[offsets[i]:offsets[i + 1]]``.

    From :func:`~.adapters.topology` (plain copies of the mesh's layers; pass
    ``topology`` where it was read already): the face corners' vertices are
    stored face after face, and a face of ``k`` corners has ``k - 2`` loop
    triangles, which give the offsets (51k quads: 0.5 ms, where reading
    ``loop_start``, ``loop_total`` and the loops' ``vertex_index`` element by
    element took 14 ms).

    Examples
    --------
    >>> offsets, indices = polygon_arrays(bpy.data.meshes["Cube"])  # doctest: +SKIP
    >>> np.diff(offsets).tolist()  # doctest: +SKIP
    [4, 4, 4, 4, 4, 4]
    """
    corner_verts, triangle_faces = adapters.topology(mesh) if topology is None else topology
    offsets = np.zeros(int(triangle_faces.max(initial=-1)) + 2, dtype=np.int64)
    np.cumsum(np.bincount(triangle_faces) + 2, out=offsets[1:])
    return offsets, corner_verts.astype(np.int64)
