"""Script API: geodesic distance on a Blender mesh object in one call.

The operator is a thin wrapper around :func:`compute_geodesic_distance`, so
scripts and the button do exactly the same thing.

Examples
--------
>>> from bl_ext.user_default.heat_geodesics import compute_geodesic_distance  # doctest: +SKIP
>>> result = compute_geodesic_distance(bpy.context.object, isolines=10)       # doctest: +SKIP
>>> result.max_distance, result.seconds                                       # doctest: +SKIP
"""

import importlib
import time
import warnings
from dataclasses import dataclass

import numpy as np

from . import adapters
from ._heatcore import colormap as colormaps
from ._heatcore import heatcore
from .adapters import AddonError
from .cache import SOLVERS
from .material import show_isoline_material
from .shape import evaluated_copy, measured_positions, nearest_vertices
from .undo import remember_active_color

#: ``heatcore.options``: every option's name, range, default and help (the bundled copy's).
options = importlib.import_module(heatcore.__name__ + ".options")

DEFAULT_ATTRIBUTE = "geodesic_distance"
DEFAULT_COLOR_ATTRIBUTE = "geodesic_distance_color"

#: Options that shape the domain (``heatcore.TriangleMesh``), with their defaults;
#: every other keyword goes to ``heatcore.HeatSolver``.
MESH_OPTIONS = options.defaults("mesh")


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


def _no_progress(fraction, message):
    pass


def resolve_sources(obj, sources=None, vertex_group=None, F=None, notes=None):
    """Source vertex indices: given ones, a vertex group's members, or the selection.

    Vertices no face uses (loose vertices) are dropped when other sources
    remain, and a note is appended to ``notes``; so is a note when a whole
    mesh selected in Object Mode (as after adding a primitive) makes every
    vertex a source.

    Raises
    ------
    AddonError
        No source vertex, only loose ones, or indices outside the mesh.
    """
    n = len(obj.data.vertices)
    if sources is not None:
        src = np.unique(np.asarray(sources, dtype=np.int64).ravel())
        what = "the given source list"
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


def _check_isoline_options(attribute, spacing, width):
    """The isoline material reads the distance attribute: it must be written; spacing >= 0, width > 0."""
    if attribute is None:
        raise AddonError("isoline_material=True draws the distance attribute: give an attribute name, not None")
    if not (np.isfinite(spacing) and spacing >= 0):
        raise AddonError(f"isoline_spacing must be 0 (from the isoline count) or a positive distance, got {spacing}")
    if not (np.isfinite(width) and width > 0):
        raise AddonError(f"isoline_width must be a positive number of pixels, got {width}")


def _renamed(solver_options):
    """``time_factor=`` (the add-on's old name of ``m``) as ``m=``, with a DeprecationWarning."""
    if "time_factor" not in solver_options:
        return dict(solver_options)
    solver_options = dict(solver_options)
    value = solver_options.pop("time_factor")
    if "m" in solver_options:
        raise AddonError("give m= only: time_factor= is its deprecated name")
    warnings.warn("time_factor= is deprecated; use m= (heatcore's name of the heat time factor)",
                  DeprecationWarning, stacklevel=3)
    return {**solver_options, "m": value}


def compute_geodesic_distance(
    obj,
    sources=None,
    *,
    vertex_group=None,
    attribute=DEFAULT_ATTRIBUTE,
    color_attribute=DEFAULT_COLOR_ATTRIBUTE,
    colormap="viridis",
    isolines=0,
    normalize=False,
    weight_group=None,
    space="WORLD",
    shape="EVALUATED",
    new_object=False,
    isoline_material=False,
    isoline_spacing=0.0,
    isoline_width=1.5,
    progress=None,
    **solver_options,
):
    """Geodesic distance from source vertices of a mesh object, written back as attributes.

    Works in Object Mode and Edit Mode (the Edit Mode selection and geometry
    are synced first; the object is returned to its mode). Only the named
    outputs are created or overwritten; nothing else on the mesh changes.

    Parameters
    ----------
    obj : bpy.types.Object
        A mesh object. Distances are measured on the shape on screen (see
        ``space`` and ``shape``) and written to the mesh's own vertices.
    sources : sequence of int, optional
        Source vertex indices. Default: the vertex group ``vertex_group`` if
        given, else the selected vertices.
    vertex_group : str, optional
        Use the members of this vertex group (weight > 0) as sources.
    attribute : str or None
        FLOAT attribute on the POINT domain that receives the distance
        (``-1`` at vertices no source reaches). None: not written.
    color_attribute : str or None
        FLOAT_COLOR POINT attribute that receives the colors; it becomes the
        active and render color. None: not written.
    colormap : str
        A colormap of ``heatcore.viz.colormap.COLORMAPS`` (viridis, magma, ...).
    isolines : int
        Number of isolines (0 for none): dark stripes in the vertex colors,
        and the isoline material's lines (spacing: largest distance / isolines).
    normalize : bool
        Divide the distance attribute by the largest distance (values in [0, 1]).
    weight_group : str, optional
        Also write the normalized distance (0 at the sources, 1 farthest) as
        weights of this vertex group, for modifiers.
    space : {"WORLD", "LOCAL"}
        "WORLD": in scene units, with the object's scale, rotation and
        parents applied; "LOCAL": in the object's own coordinates.
    shape : {"EVALUATED", "BASIS"}
        "EVALUATED": shape keys mixed as shown and deform modifiers applied
        (modifiers that change the vertices, such as Subdivision or Mirror,
        are left out, with a warning naming them); "BASIS": the mesh data as
        stored. ``space="LOCAL", shape="BASIS"`` measures the mesh data alone.
    new_object : bool
        Measure the whole evaluated mesh (every modifier applied, Subdivision
        and Mirror included) on a new object ``"<name> Geodesic"`` (reused on
        re-runs) and write the outputs there; ``obj`` is not modified. Its
        sources are the new mesh's vertices nearest to the source vertices as
        displayed. Needs ``shape="EVALUATED"``.
    isoline_material : bool
        Also show the distance per pixel: a generated material (colormap
        colors and isolines of even width in screen pixels, drawn from the
        interpolated ``attribute``, so independent of the mesh density) set
        by a Geometry Nodes modifier "Geodesic Isolines" (added, or updated
        on re-runs). The mesh's materials and material indices are not
        modified; disable or remove the modifier to restore the look.
    isoline_spacing : float
        Distance between the material's isolines, in the units of the
        distance (``space``); 0: the largest distance / ``isolines``.
    isoline_width : float
        Width of the material's isolines in screen pixels, at any zoom (a
        line is 0.7 to 1 times it wide, by its direction on screen).
    progress : callable, optional
        ``progress(fraction, message)`` called between stages.
    **solver_options
        ``robust``, ``refine`` and ``weld`` go to :class:`heatcore.TriangleMesh`;
        all others (``m``, ``boundary``, ``accuracy``, ``backend``, ...) to
        :class:`heatcore.HeatSolver`. Options declared in ``heatcore.options``
        are checked there first. ``time_factor`` is a deprecated name of
        ``m`` (DeprecationWarning).

    Returns
    -------
    GeodesicResult

    Raises
    ------
    AddonError
        Not a mesh, no vertices, no sources, or an output name taken by
        another kind of attribute. Nothing is modified.
    heatcore.HeatcoreError
        Invalid options or geometry (for example a source on a loose vertex).
        Nothing is modified.
    """
    start = time.perf_counter()
    progress = progress or _no_progress
    if obj is None or obj.type != "MESH":
        raise AddonError(f"{getattr(obj, 'name', obj)!r} is not a mesh object")
    mesh = obj.data
    try:
        colormap = options.check("colormap", colormap)
    except heatcore.InvalidOptionError as exc:
        raise AddonError(str(exc)) from None
    isolines = options.check("isolines", isolines)
    solver_options = options.check_all(_renamed(solver_options))
    for name, data_type in ((attribute, "FLOAT"), (color_attribute, "FLOAT_COLOR")):
        if name is not None:
            adapters.check_attribute_free(mesh, name, "POINT", data_type)
    if isoline_material:
        _check_isoline_options(attribute, isoline_spacing, isoline_width)

    progress(0.05, "reading mesh")
    if obj.mode == "EDIT":
        obj.update_from_editmode()
    if len(mesh.vertices) == 0:
        raise AddonError(f"mesh {mesh.name!r} has no vertices")
    notes = []
    _, F = adapters.mesh_arrays(mesh)
    src = resolve_sources(obj, sources, vertex_group, F, notes)
    if new_object:
        if shape != "EVALUATED":
            raise AddonError("new_object=True measures the evaluated mesh: it needs shape='EVALUATED'")
        cage, _ = measured_positions(obj, "LOCAL", "EVALUATED")
        obj = evaluated_copy(obj)
        mesh, shape = obj.data, "BASIS"
        src = np.unique(nearest_vertices(obj, cage[src]))
        _, F = adapters.mesh_arrays(mesh)
    V, skipped = measured_positions(obj, space, shape)
    if skipped:
        notes.append(f"{obj.name}: distance measured without the modifiers that change its vertices "
                     f"({', '.join(skipped)}), on the deformed cage of its own vertices")
    for note in notes:
        warnings.warn(note, stacklevel=2)

    mesh_options = {k: solver_options.pop(k, default) for k, default in MESH_OPTIONS.items()}
    if not F.shape[0]:  # a point cloud takes refine only
        mesh_options = {"refine": mesh_options["refine"]}
    solver_seconds = 0.0

    def build():
        nonlocal solver_seconds
        progress(0.1, f"building the heat solver for {len(V):,} vertices")
        t0 = time.perf_counter()
        if F.shape[0]:
            domain = heatcore.TriangleMesh(V, F, **mesh_options)
        else:  # vertices only: a point cloud
            domain = heatcore.PointCloud(V, **mesh_options)
        solver = heatcore.HeatSolver(domain, **solver_options)
        solver_seconds = time.perf_counter() - t0
        return solver

    solver, cached = SOLVERS.get(mesh.name_full if new_object else mesh.session_uid, V, F, {**mesh_options, **solver_options}, build)
    progress(0.8, "solving for the distance")
    d = solver.distance(src)
    finite = np.isfinite(d)
    dmax = float(d[finite].max()) if finite.any() else 0.0
    scale = 1.0 / dmax if (normalize and dmax > 0) else 1.0

    progress(0.9, "writing attributes")
    with adapters.object_mode(obj):
        if attribute is not None:
            adapters.write_float_attribute(mesh, attribute, np.where(finite, d * scale, adapters.UNREACHABLE_VALUE))
        if color_attribute is not None:
            remember_active_color(mesh, color_attribute)
            rgb = colormaps.colorize(d, colormap=colormap, isolines=int(isolines))
            adapters.write_color_attribute(mesh, color_attribute, rgb)
        if weight_group:
            weights = np.where(finite, d / dmax if dmax > 0 else 0.0, np.nan)
            adapters.write_vertex_group(obj, weight_group, np.clip(weights, 0.0, 1.0))
        mesh.update()
    if isoline_material:
        spacing = isoline_spacing or (dmax / isolines if isolines else 0.0)
        show_isoline_material(obj, attribute, colormap=colormap, max_distance=dmax, spacing=spacing,
                              attribute_scale=1.0 / scale, line_width=isoline_width, space=space)
    progress(1.0, "done")
    return GeodesicResult(
        distance=d,
        sources=src,
        max_distance=dmax,
        n_vertices=len(V),
        seconds=time.perf_counter() - start,
        solver_seconds=solver_seconds,
        cached=cached,
        skipped_modifiers=skipped,
        warnings=notes,
        object=obj,
    )
