"""The three stages of a run, for the script API (one after the other) and the button (build in the background).

1. :func:`prepare_run` (main thread): check the options, read the measured
   shape and the sources from Blender, look the solver up in the cache;
2. :func:`build_solver` (any thread): heatcore only, no ``bpy``; reports
   heatcore's build stages and may be cancelled between them;
3. :func:`finish_run` (main thread): keep the new solver in the cache, query
   the distance, write the outputs. After a background build,
   :func:`check_unchanged` first makes sure the object still exists and has
   the shape the solver was built on.

:func:`~.api.compute_geodesic_distance` runs 1, 2, 3 in a row; the operator
runs 2 in a worker thread (:mod:`.background`) when the cache misses.

Examples
--------
>>> run = prepare_run(obj, isolines=10)               # doctest: +SKIP
>>> if run.solver is None:                            # doctest: +SKIP
...     build_solver(run, progress)                   # doctest: +SKIP
>>> result = finish_run(run)                          # doctest: +SKIP
"""

import importlib
import time
import warnings
from dataclasses import dataclass

import bpy
import numpy as np

from . import adapters
from ._heatcore import heatcore
from .adapters import AddonError
from .cache import IDENTITY, SOLVERS, Placement, geometry_key, placed, same_key
from .elements import domain_sources, selected_elements
from .outputs import OUTPUT_NAMES, check_outputs, write_outputs
from .polygons import (
    coincident_vertices,
    key_options,
    polygon_arrays,
    polygon_domain,
    use_polygons,
)
from .shape import (
    COPY_MARKER,
    evaluated_copy,
    measured_frame,
    nearest_vertices,
    object_positions,
)

#: ``heatcore.options``: every option's name, range, default and help (the bundled copy's).
options = importlib.import_module(heatcore.__name__ + ".options")
Progress = importlib.import_module(heatcore.__name__ + ".progress").Progress
_settings = importlib.import_module(heatcore.__name__ + ".settings")
#: ``heatcore.settings.Settings``: one run's options, checked once (``Settings.of("blender", ...)``).
Settings = _settings.Settings
#: The options each front end offers (``FRONT_END_OPTIONS["blender"]``: the add-on's properties and keywords).
FRONT_END_OPTIONS = _settings.FRONT_END_OPTIONS
#: A run that reaches fewer than this share of the vertices, where at least this share of them share their
#: position with another (a mesh imported as triangle soup), says that merging them would join the pieces.
MERGE_HINT = (0.1, 0.25)

#: The part of a run's progress (0..1) that the solver build covers (the domain's share of it is heatcore's).
BUILD_RANGE = (0.1, 0.8)
DOMAIN_SHARE = importlib.import_module(heatcore.__name__ + ".progress").DOMAIN_SHARE


@dataclass
class GeodesicResult:
    """What one run computed.

    Attributes
    ----------
    distance : (n,) float array
        Distance per vertex in object units (``inf`` where unreachable).
    sources : (k,) int array
        The source vertices.
    max_distance : float
        Largest finite distance.
    n_vertices : int
    seconds : float
        Wall time of the whole run.
    solver_seconds : float
        Time spent building the solver (0 when it came from the cache).
    cached : bool
        Whether the prefactored solver was reused.
    skipped_modifiers : list of str
        Modifiers left out because they change the vertices (``shape="EVALUATED"``):
        the distance is measured on the deformed cage of the mesh's own vertices.
    warnings : list of str
        What the user should know about this run (also issued as ``UserWarning``).
    object : bpy.types.Object
        The object written to: the one given, or its evaluated copy (``new_object=True``).
    """

    distance: np.ndarray
    sources: np.ndarray
    max_distance: float
    n_vertices: int
    seconds: float
    solver_seconds: float
    cached: bool
    skipped_modifiers: list
    warnings: list
    object: object = None


@dataclass
class PreparedRun:
    """One run as read from Blender by :func:`prepare_run`: arrays and its settings.

    Building its solver needs no ``bpy`` (:func:`build_solver`). ``object_uid``
    and ``mesh_uid`` (``session_uid``) find the object again after a
    background build, or tell that it was deleted; ``key`` is the cache key of
    the geometry and options, ``cache_id`` the cache's entry; ``solver`` comes
    from the cache (``cached``) or from :func:`build_solver`; ``outputs`` are
    the keywords of :func:`~.outputs.write_outputs`; ``F`` the triangles,
    read only when the solver is to be built (None when it came from the
    cache), and ``polygons`` the faces as ``(offsets, indices)`` when the
    mesh is measured as polygons (:mod:`.polygons`); ``notes`` the warnings
    for the user; ``start`` is the ``time.perf_counter()`` of the click. With
    ``new_object``, ``V`` and ``F`` are the evaluated mesh's (every modifier
    applied) and ``sources`` the positions of the source vertices as
    displayed: the copy is made, and the sources mapped onto it, only when
    the result is written (:func:`finish_run`), so that a cancelled run makes
    nothing. ``settings`` is the run's one ``heatcore.settings.Settings``
    (``Settings.of("blender", intent="interactive", ...)``: the solver is cached),
    whose mesh part builds the domain and solver part the solver;
    ``points_only`` says that the mesh has no faces (a point cloud).
    ``V`` are the measured positions (World space: placed by the object's
    world matrix), ``key`` holds the object's own and the matrix (the
    *frame*: :func:`~.cache.geometry_key`), so that a cached solver built
    before the object moved is found; ``placement`` maps the solver's
    coordinates and lengths to the run's (:class:`~.cache.Placement`: the
    identity, but for a cached solver built at another place or uniform scale).
    """

    object_name: str
    object_uid: int
    mesh_uid: int
    V: np.ndarray
    F: object
    sources: np.ndarray
    skipped_modifiers: list
    space: str
    shape: str
    settings: object
    outputs: dict
    key: tuple
    cache_id: object
    start: float
    notes: list
    new_object: bool = False
    polygons: object = None
    as_polygons: bool = False
    points_only: bool = False
    solver: object = None
    cached: bool = False
    solver_seconds: float = 0.0
    placement: object = IDENTITY
    kinds: dict = None
    triangle_faces: object = None


def resolve_sources(obj, sources=None, vertex_group=None, F=None, notes=None):
    """Source vertex indices: given ones, a vertex group's members, or the selection.

    Vertices no face uses (loose vertices) are dropped when other sources
    remain, and a note is appended to ``notes``; so is a note when a whole
    mesh selected in Object Mode (as after adding a primitive) makes every
    vertex a source.

    Raises
    ------
    AddonError
        No source vertex, only loose ones, indices outside the mesh, or an empty group name.
    """
    n = len(obj.data.vertices)
    if sources is not None:
        src = np.unique(np.asarray(sources, dtype=np.int64).ravel())
        what = "the given source list"
    elif vertex_group == "":
        raise AddonError(f"no source vertex group chosen for {obj.name!r}: pick one in Sources > Group, "
                         "or set Sources to Selected Vertices")
    elif vertex_group:
        src = adapters.vertex_group_members(obj, vertex_group)
        what = f"vertex group {vertex_group!r}"
    else:
        src = adapters.selected_vertices(obj.data)
        what = "the selection"
    if src.size == 0:
        hint = (
            "select one or more vertices in Edit Mode"
            if sources is None and not vertex_group
            else "give at least one vertex"
        )
        raise AddonError(f"no source vertices: {what} of {obj.name!r} is empty; {hint}")
    try:
        src = options.check_source_vertices(src, n)
    except heatcore.InvalidSourceError as exc:
        raise AddonError(str(exc)) from None
    notes = [] if notes is None else notes
    if F is not None and F.size:
        loose = np.bincount(F.ravel(), minlength=n)[src] == 0
        if loose.all():
            raise AddonError(f"no source vertices: {what} of {obj.name!r} holds only vertices no face uses "
                             f"({_listed(src)}); select vertices of the surface")
        if loose.any():
            notes.append(f"{loose.sum():,} of the sources are loose vertices (no face uses them: "
                         f"{_listed(src[loose])}); measured from the other {(~loose).sum():,}")
            src = src[~loose]
    if sources is None and not vertex_group and obj.mode == "OBJECT" and src.size == n > 1:
        notes.append(f"all {n:,} vertices of {obj.name!r} are selected (as after adding a primitive), so every "
                     "vertex is a source and every distance is 0; select the sources in Edit Mode")
    return src


def _listed(indices, shown=5):
    text = ", ".join(str(i) for i in indices[:shown])
    return text + (f" and {len(indices) - shown:,} more" if len(indices) > shown else "")


def _renamed(solver_options):
    """``time_factor=`` (the add-on's old name of ``m``) as ``m=``, with a DeprecationWarning."""
    if "time_factor" not in solver_options:
        return dict(solver_options)
    solver_options = dict(solver_options)
    value = solver_options.pop("time_factor")
    if "m" in solver_options:
        raise AddonError("give m= only: time_factor= is its deprecated name")
    warnings.warn("time_factor= is deprecated; use m= (heatcore's name of the heat time factor)",
                  DeprecationWarning, stacklevel=4)
    return {**solver_options, "m": value}


def read_geometry(obj, space, shape, new_object=False, synced=False):
    """Positions in object coordinates (``shape``), what fixes the triangles, skipped modifiers, and the frame
    of ``space`` (:func:`~.shape.measured_frame`: the measured positions are ``placed(V, frame)``), Edit Mode
    synced first.

    The second value is a tuple of arrays that, with the positions, fixes
    the triangles (the cache key): the mesh's face corners, triangle-to-face
    map and own positions (:func:`~.adapters.topology`; a few milliseconds,
    where copying the triangles out takes 0.15 s at 500k vertices), or with
    ``new_object`` the triangles themselves and the faces as ``(offsets,
    indices)`` (:func:`read_triangles` gives the triangles in both cases). ``new_object``: the whole evaluated mesh (every
    modifier applied) as :func:`~.shape.evaluated_copy` will hold it (placed as ``obj``), read
    without making data. ``synced``: the caller has just synced Edit Mode (each sync is a BMesh conversion,
    56 ms at 504k vertices).
    """
    if obj.mode == "EDIT" and not synced:
        obj.update_from_editmode()
    frame = measured_frame(obj, space)
    if not new_object:
        V, skipped = object_positions(obj, shape)
        return V, (*adapters.topology(obj.data), adapters.vertex_positions(obj.data)), skipped, frame
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    try:
        mesh = evaluated.to_mesh()
        V, F = adapters.mesh_arrays(mesh)
        offsets, indices = polygon_arrays(mesh)  # a Subdivision's quads are measured as polygons
    finally:
        evaluated.to_mesh_clear()
    return V, (F, offsets, indices), [], frame


def run_key(V, topology, frame, settings, as_polygons, points_only, copy=False):
    """The cache key of a run's geometry (:func:`read_geometry`'s) and settings: a uniform scale of the frame
    keeps it unless an option is a length (a weld tolerance).

    Examples
    --------
    >>> V, topology, _, frame = read_geometry(obj, "WORLD", "EVALUATED")              # doctest: +SKIP
    >>> same_key(run.key, run_key(V, topology, frame, run.settings, False, False))      # doctest: +SKIP
    True
    """
    options = key_options(settings, as_polygons, points_only)
    return geometry_key(V, topology, options, copy=copy, frame=frame, rescale=not settings.mesh.weld)


def current_key(obj, run):
    """The cache key of ``obj``'s geometry as ``run`` measures it now, to compare with ``run.key``
    (:func:`~.cache.same_key`), and the placement of ``run``'s solver in it."""
    V, topology, _, frame = read_geometry(obj, run.space, run.shape, run.new_object)
    key = run_key(V, topology, frame, run.settings, run.as_polygons, run.points_only)
    return key, Placement.between(run.key[2], frame)


def read_triangles(obj, topology, new_object=False):
    """The triangles of :func:`read_geometry`'s geometry (read from ``obj`` unless ``topology`` holds them)."""
    return topology[0] if new_object else adapters.mesh_arrays(obj.data)[1]


def prepare_run(obj, sources=None, *, vertex_group=None, space="WORLD", shape="EVALUATED", new_object=False,
                progress=None, sources_later=False, polygons="AUTO", selected="VERTICES", **run_options):
    """Stage 1 (main thread): check everything, read the mesh and the sources, look up the cached solver.

    Takes the arguments of :func:`~.api.compute_geodesic_distance`: the output
    options (``OUTPUT_NAMES``) and the solver options go in ``run_options``.
    Nothing is modified, except that a stale cached solver of this mesh
    (other geometry or options) is dropped. The warnings for the user are
    in ``notes`` (the caller issues them). ``sources_later=True`` reads no
    sources (``run.sources`` is empty): the caller places them afterwards
    (the probe's points on faces, :mod:`.probe`) and measures loop
    triangles. ``polygons``: :mod:`.polygons` (``"AUTO"``: a mesh with
    n-gons is measured as polygons). ``selected="FACES"`` or ``"EDGES"``: the
    selected faces (a region) or edges are the sources (:mod:`.elements`;
    ``run.sources`` holds their vertices, ``run.kinds`` the elements).

    Returns
    -------
    PreparedRun
        With ``solver`` set when the cache had it.
    """
    start = time.perf_counter()
    progress = Progress(progress)
    if obj is None or obj.type != "MESH":
        raise AddonError(f"{getattr(obj, 'name', obj)!r} is not a mesh object")
    mesh = obj.data
    outputs = check_outputs(obj, source_group=vertex_group if sources is None else None,
                            **{k: run_options.pop(k) for k in OUTPUT_NAMES if k in run_options})
    # Blender's defaults (weld off); kept for the next clicks, but the first answer is waited for
    settings = Settings.of("blender", intent="interactive", **_renamed(run_options))

    progress(0.05, "reading mesh")
    if obj.mode == "EDIT":
        obj.update_from_editmode()
    if len(mesh.vertices) == 0:
        raise AddonError(f"mesh {mesh.name!r} has no vertices")
    notes = []
    corners, triangle_faces = adapters.topology(mesh)  # every vertex a face uses (loose sources are dropped)
    kinds = None
    if sources_later:
        src = np.zeros(0, dtype=np.int64)
    elif selected != "VERTICES" and sources is None and vertex_group is None:
        if new_object:
            raise AddonError("selected faces or edges as sources measure the object itself: turn Apply All "
                             "Modifiers (New Object) off, or use Selected Vertices")
        src, kinds = selected_elements(obj, selected, notes)
    else:
        src = resolve_sources(obj, sources, vertex_group, corners, notes)
    if new_object:
        if shape != "EVALUATED":
            raise AddonError("new_object=True measures the evaluated mesh: it needs shape='EVALUATED'")
        cage, _ = object_positions(obj, "EVALUATED")
        src = cage[src]  # mapped onto the copy's vertices when it is made
    V, topology, skipped, frame = read_geometry(obj, space, shape, new_object, synced=True)
    if skipped:
        notes.append(f"{obj.name}: distance measured without the modifiers that change its vertices "
                     f"({', '.join(skipped)}), on the deformed cage of its own vertices")

    as_polygons = use_polygons(polygons, mesh, settings, points_later=sources_later,
                               offsets=topology[1] if new_object else None)
    points_only = not topology[0].size  # no face corners (no triangles): a point cloud, which takes refine only
    key = run_key(V, topology, frame, settings, as_polygons, points_only)
    run = PreparedRun(
        object_name=obj.name, object_uid=obj.session_uid, mesh_uid=mesh.session_uid, V=placed(V, frame),
        F=None, sources=src, skipped_modifiers=skipped, space=space, shape=shape, settings=settings,
        points_only=points_only, outputs=outputs, key=key, start=start, notes=notes, new_object=new_object,
        cache_id=(COPY_MARKER, obj.session_uid) if new_object else ("polygons", mesh.session_uid) if as_polygons
        else mesh.session_uid, as_polygons=as_polygons,  # a mesh's polygon and triangle solvers: side by side
        kinds=kinds, triangle_faces=triangle_faces,
    )
    entry = SOLVERS.entry(run.cache_id, key)  # built on this shape, maybe elsewhere or at another uniform scale
    if entry is not None and not covers(entry[1].domain, src, sources_later or new_object):
        entry = None  # built for the parts other sources were on
    run.cached = entry is not None
    if run.cached:  # run.key: the solver's own, in the frame it was built in
        run.key, run.solver = entry
        run.placement = Placement.between(run.key[2], frame)
    else:
        SOLVERS.discard(run.cache_id)  # free the stale solver before building
        # Polygons need them only where merging may measure them as triangles instead (polygon_domain, weld set)
        if new_object or not as_polygons or settings.mesh.weld is not None:
            run.F = read_triangles(obj, topology, new_object)
        run.polygons = (topology[1:] if new_object else polygon_arrays(mesh, topology[:2])) if as_polygons else None
        run.key = run_key(V, topology, frame, settings, as_polygons, points_only, copy=True)  # kept with the solver
    return run


def covers(domain, sources, every_part):
    """Whether a cached solver's ``domain`` holds the ``sources`` (input vertex indices), or every part.

    A click builds only the connected parts its sources are on (the others
    wait for a click of their own): runs whose sources come later (the probe,
    paths) or are not indices (``new_object``) need every part.
    """
    if every_part:
        return getattr(domain, "parts_left_out", 0) == 0
    return bool((domain.output_vertices[sources] >= 0).all())


def build_solver(run, progress=None):
    """Stage 2 (any thread): build the heat solver of a :func:`prepare_run` with heatcore alone (no ``bpy``).

    ``progress(fraction, message)`` gets heatcore's build stages mapped onto
    ``BUILD_RANGE``; when it raises (a cancel), the exception propagates and
    ``run.solver`` stays None. The cache is not touched (:func:`finish_run` fills it).
    What the user should know about the polygons (measured as triangles) is appended to ``run.notes``.
    """
    report = Progress(progress).part(*BUILD_RANGE)
    report(0.0, f"building the heat solver for {len(run.V):,} vertices")
    t0 = time.perf_counter()
    mesh = run.settings.mesh
    # the parts the sources are on, alone (each part is solved as if alone); the others wait for their click
    only = run.sources if run.sources.size and not run.new_object else None
    domain = None if run.polygons is None else polygon_domain(run.V, run.polygons, mesh, run.notes, only,
                                                              report.part(0.0, DOMAIN_SHARE))
    if domain is None and run.F.shape[0]:
        domain = heatcore.TriangleMesh(run.V, run.F, mesh, progress=report.part(0.0, DOMAIN_SHARE), only_parts_of=only)
    elif domain is None:  # vertices only: a point cloud (of the mesh options, it takes refine)
        domain = heatcore.PointCloud(run.V, refine=mesh.refine, progress=report.part(0.0, DOMAIN_SHARE))
    solver = heatcore.HeatSolver(domain, run.settings.solver, progress=report.part(DOMAIN_SHARE, 1.0))
    run.solver_seconds = time.perf_counter() - t0
    run.solver = solver
    return solver


def find_object(run):
    """The run's object, found again by ``session_uid``; None when it was deleted or its mesh replaced."""
    obj = bpy.data.objects.get(run.object_name)
    if obj is None or obj.session_uid != run.object_uid:
        obj = next((o for o in bpy.data.objects if o.session_uid == run.object_uid), None)
    if obj is None or obj.type != "MESH" or obj.data.session_uid != run.mesh_uid:
        return None
    return obj


def check_unchanged(run):
    """The run's object, once checked to exist still and to measure the shape the solver was built on.

    After a background build, during which the user could go on working: a
    move of the object meanwhile is allowed (``run.placement`` follows it).

    Raises
    ------
    AddonError
        The object was deleted (or its mesh replaced), its measured shape or
        its triangles changed, or an output name was taken meanwhile.
    """
    obj = find_object(run)
    if obj is None:
        raise AddonError(f"{run.object_name!r} was deleted while its solver was being built; nothing was written")
    key, placement = current_key(obj, run)
    if not same_key(run.key, key):
        raise AddonError(
            f"{obj.name!r} changed while its solver was being built (its shape or its vertices); "
            "nothing was written: run it again"
        )
    check_outputs(obj, **run.outputs)
    run.placement = placement
    return obj


def finish_run(run, progress=None, obj=None):
    """Stage 3 (main thread): keep a newly built solver in the cache, query the distance, write the outputs.

    ``obj`` defaults to the run's object (:func:`find_object`). With
    ``new_object``, the outputs go to its evaluated copy, made (or updated) here.

    Returns
    -------
    GeodesicResult
    """
    progress = Progress(progress)
    obj = obj or find_object(run)
    if obj is None:
        raise AddonError(f"{run.object_name!r} was deleted; nothing was written")
    if not run.cached:
        SOLVERS.store(run.cache_id, run.key, run.solver)
    sources = run.sources
    if run.new_object:
        obj = evaluated_copy(obj)
        sources = np.unique(nearest_vertices(obj, run.sources))
    progress(0.8, "solving for the distance")
    if run.kinds:  # selected faces or edges: the distance to their union
        d = run.placement.distance(run.solver.distance(**domain_sources(run.solver.domain, run.kinds,
                                                                        run.triangle_faces)))
    else:
        d = run.placement.distance(run.solver.distance(sources))
    hint = None if run.points_only else merge_hint(run.V, d, run.settings.mesh.weld)
    if hint:
        run.notes.append(hint)
    progress(0.9, "writing attributes")
    dmax = write_outputs(obj, d, run.space, **run.outputs)
    progress(1.0, "done")
    return GeodesicResult(
        distance=d,
        sources=sources,
        max_distance=dmax,
        n_vertices=len(run.V),
        seconds=time.perf_counter() - run.start,
        solver_seconds=run.solver_seconds,
        cached=run.cached,
        skipped_modifiers=run.skipped_modifiers,
        warnings=run.notes,
        object=obj,
    )


def merge_hint(V, d, weld):
    """A note naming *Merge Coincident Vertices* where the distance reached almost nothing of a soup; else None.

    Merging off (``weld=None``), the pieces of a mesh imported as triangle
    soup (an STL file: every triangle its own three vertices) are islands of
    their own, and a source reaches only its own. The note is given where the
    distance reaches fewer than ``MERGE_HINT[0]`` of the vertices and at least
    ``MERGE_HINT[1]`` of them share their position with another; a mesh merely
    in pieces that touch (Suzanne's eyes) gets none.

    Examples
    --------
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]] * 20, float)
    >>> merge_hint(V, np.r_[0.0, 1.0, 1.0, np.full(57, np.inf)], None)[:34]
    'the distance reaches 3 of 60 verti'
    >>> merge_hint(V, np.r_[0.0, 1.0, 1.0, np.full(57, np.inf)], 0.0) is None
    True
    """
    if weld is not None:  # merging on
        return None
    reached = int(np.isfinite(d).sum())
    if reached >= MERGE_HINT[0] * len(V):
        return None
    shared = coincident_vertices(V)
    if shared < MERGE_HINT[1] * len(V):
        return None
    return (f"the distance reaches {reached:,} of {len(V):,} vertices: the mesh is in pieces that touch "
            f"({shared:,} vertices share their position with another, as in a mesh imported as triangle soup, "
            "such as STL); turn on Advanced > Merge Coincident Vertices (weld=0.0 in scripts) to join them")
