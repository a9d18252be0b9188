"""Script API: geodesic distance on a Blender mesh object in one call.

The operator is a thin wrapper around the same stages (:mod:`.stages`), so
scripts and the button do exactly the same thing; the button builds the
solver in a background thread, a script waits for it.

Examples
--------
>>> from bl_ext.user_default.heat_geodesics import compute_geodesic_distance  # doctest: +SKIP
>>> result = compute_geodesic_distance(bpy.context.object, isolines=10)       # doctest: +SKIP
>>> result.max_distance, result.seconds                                       # doctest: +SKIP
>>> from bl_ext.user_default.heat_geodesics import geodesic_path              # doctest: +SKIP
>>> geodesic_path(bpy.context.object, 0, 40).length                           # doctest: +SKIP
"""

import warnings

from .outputs import DEFAULT_ATTRIBUTE, DEFAULT_COLOR_ATTRIBUTE, DEFAULT_WEIGHT_GROUP
from .path_api import PathResult, geodesic_path
from .stages import (
    FRONT_END_OPTIONS,
    GeodesicResult,
    build_solver,
    finish_run,
    options,
    prepare_run,
    resolve_sources,
)

__all__ = [
    "DEFAULT_ATTRIBUTE",
    "DEFAULT_COLOR_ATTRIBUTE",
    "DEFAULT_WEIGHT_GROUP",
    "FRONT_END_OPTIONS",
    "GeodesicResult",
    "PathResult",
    "compute_geodesic_distance",
    "geodesic_path",
    "options",
    "resolve_sources",
]


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
    weight_radius=None,
    weight_falloff="LINEAR",
    weight_invert=False,
    space="WORLD",
    shape="EVALUATED",
    new_object=False,
    isoline_material=False,
    isoline_spacing=0.0,
    isoline_width=1.5,
    isoline_style="SHADED",
    polygons="AUTO",
    selected="VERTICES",
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
        and the isoline material's lines (spacing: largest distance / (isolines + 1)).
    normalize : bool
        Divide the distance attribute by the largest distance (values in [0, 1]).
    weight_group : str, optional
        Also write weights for modifiers to this vertex group (the panel's
        default name: ``"geodesic_weight"``): 1 at the sources falling to 0
        at ``weight_radius`` (:func:`heatcore.weights.distance_weights`).
        Every vertex is a member; vertices no source reaches get 0. The group
        becomes the active one; one made by an earlier run is replaced. Its
        name must differ from every attribute of the mesh and from
        ``attribute`` and ``color_attribute`` (attributes and vertex groups
        share one set of names), and from ``vertex_group``.
    weight_radius : float, optional
        Geodesic distance at which the weight reaches 0, in the units of
        ``space``. None: the largest distance.
    weight_falloff : {"LINEAR", "SMOOTH", "SHARP", "ROOT"}
        The weight's curve (Blender's falloff types, as in the
        VertexWeightProximity modifier): linear, smoothstep, squared, square root.
    weight_invert : bool
        Invert the falloff: weight 0 at the sources rising to 1 at the radius
        (unreachable vertices stay 0).
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
        distance (``space``); 0: the largest distance / (``isolines`` + 1).
    isoline_width : float
        Width of the material's isolines in screen pixels, at any zoom (a
        line is 0.7 to 1 times it wide, by its direction on screen).
    isoline_style : {"SHADED", "FLAT"}
        How the isoline material is lit: "SHADED", by the scene (Principled
        BSDF, the colors also glowing faintly); "FLAT", not at all (Emission:
        the colormap's colors exactly, in any light). The operator's
        *Isoline Material* is on by default; this function draws it only when
        ``isoline_material=True`` (a script gets only the outputs it asks for).
    polygons : {"AUTO", "TRIANGULATE"}
        ``"AUTO"``: a mesh with quads or n-gons is measured as polygons
        (:class:`heatcore.PolygonMesh`: each face on heatcore's own
        triangulation of it; see :mod:`.polygons` for where the loop
        triangles are used instead);
        ``"TRIANGULATE"``: always its loop triangles.
    selected : {"VERTICES", "EDGES", "FACES"}
        Without ``sources`` or ``vertex_group``: the selected vertices, or
        the selected edges (the distance to them, 0 along them: heatcore's
        ``edges=``) or faces (the distance to that region, 0 inside it:
        heatcore's ``region=``) are the sources. Edges and faces need
        ``new_object=False``.
    progress : callable, optional
        ``progress(fraction, message)`` at each stage: reading the mesh, each
        stage of the solver build (heatcore's, see ``heatcore.progress``),
        solving, writing. It may raise to abort: nothing is written then.
    **solver_options
        ``robust``, ``refine`` and ``weld`` go to :class:`heatcore.TriangleMesh`
        (``refine`` only to a ``PolygonMesh``). ``weld``: None by default, unlike
        heatcore's own default: the mesh is measured as it is connected in
        Blender (islands that touch at a vertex, as Suzanne's eyes, stay
        apart); ``weld=0.0`` merges vertices at exactly the same position (the
        panel's *Merge Coincident Vertices*, for meshes imported as triangle
        soup; a mesh with quads that has vertices to merge is then measured
        as its triangles), a tolerance those closer than it;
        all others (``m``, ``boundary``, ``accuracy``, ``backend``) to
        :class:`heatcore.HeatSolver`. They make the run's one
        ``heatcore.settings.Settings`` (``Settings.of("blender", ...)``: each
        value checked once, Blender's defaults for the others; an option the
        Blender front end does not offer, ``FRONT_END_OPTIONS["blender"]``, is
        an ``InvalidOptionError``). ``time_factor`` is a deprecated name of
        ``m`` (DeprecationWarning).

    Returns
    -------
    GeodesicResult

    Raises
    ------
    AddonError
        Not a mesh, no vertices, no sources, or an output name that collides
        (taken by another kind of attribute; a weight group named like an
        attribute; an attribute named like a vertex group). Nothing is modified.
    heatcore.HeatcoreError
        Invalid options or geometry (for example a source on a loose vertex).
        Nothing is modified.
    """
    run = prepare_run(
        obj, sources, vertex_group=vertex_group, space=space, shape=shape, new_object=new_object, progress=progress,
        attribute=attribute, color_attribute=color_attribute, colormap=colormap, isolines=isolines,
        normalize=normalize, weight_group=weight_group, weight_radius=weight_radius,
        weight_falloff=weight_falloff, weight_invert=weight_invert, isoline_material=isoline_material,
        isoline_spacing=isoline_spacing, isoline_width=isoline_width,
        isoline_style=isoline_style, polygons=polygons, selected=selected, **solver_options,
    )
    for note in run.notes:
        warnings.warn(note, stacklevel=2)
    known = len(run.notes)
    if run.solver is None:
        build_solver(run, progress)
        for note in run.notes[known:]:  # from the build: polygons measured as triangles
            warnings.warn(note, stacklevel=2)
        known = len(run.notes)
    result = finish_run(run, progress, obj)
    for note in run.notes[known:]:  # from the query: a soup that merging would join
        warnings.warn(note, stacklevel=2)
    return result
