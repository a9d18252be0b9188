"""Script API of *Signed Distance from Edges*: the selected edges as curves, the signed heat method's field written back.

The selected edges (closed loops, open chains, several pieces) become the
curves of :class:`heatcore.SignedHeatSolver`, each oriented by the winding of
the faces (:func:`heatcore.edge_curves`): a loop that splits its part of the
mesh in two has its side of smaller area on its left, so that side is
positive. Where faces are selected, the curves are the border of the
selection instead (:func:`heatcore.region_boundary_curves`, the mesh's own
boundary left out), with the selected faces inside (positive). The
field is written as a FLOAT point attribute, a color attribute with a
diverging map (blue outside, red inside) and, if asked, a vertex group of
weights (inside 1, outside 0, with a soft edge ``weight_band`` wide). Nothing
else on the mesh changes; parts no curve reaches get 0 (and gray).

Examples
--------
>>> from bl_ext.user_default.heat_geodesics import signed_distance_from_edges    # doctest: +SKIP
>>> result = signed_distance_from_edges(bpy.context.object, weight_group="inside")  # doctest: +SKIP
>>> result.curves, round(result.max_distance, 3)                                   # doctest: +SKIP
(1, 0.412)
"""

import time
from dataclasses import dataclass

import numpy as np

from . import adapters
from ._heatcore import colormap as colormaps
from ._heatcore import heatcore
from .outputs import weights
from .adapters import AddonError
from .cache import SOLVERS, placed
from .polygons import key_options
from .shape import measured_frame, object_positions
from .stages import FRONT_END_OPTIONS, Settings

#: The options of the signed heat method (no ``accuracy``: its own distance is the sharper one).
SIGNED_OPTIONS = FRONT_END_OPTIONS["signed heat"]
DEFAULT_SIGNED_ATTRIBUTE = "signed_distance"
DEFAULT_SIGNED_COLOR = "signed_distance_color"


@dataclass
class SignedResult:
    """What one *Signed Distance from Edges* run wrote.

    Attributes
    ----------
    distance : (n,) float array
        The signed distance of each vertex (``inf`` in parts no curve reaches).
    curves : int
        Curves the selected edges made (loops and chains).
    min_distance, max_distance : float
        Over the reached vertices (negative: outside).
    unreached : int
        Vertices of parts no curve reaches (written 0, colored gray).
    seconds : float
    cached : bool
        Whether the prefactored solver was reused.
    """

    distance: np.ndarray
    curves: int
    min_distance: float
    max_distance: float
    unreached: int
    seconds: float
    cached: bool


def selected_edges(mesh):
    """The selected edges of ``mesh`` as ``(k, 2)`` vertex pairs (sync Edit Mode first).

    Examples
    --------
    >>> selected_edges(bpy.context.object.data)   # doctest: +SKIP
    array([[0, 1], [1, 5]])
    """
    with adapters.stored(mesh) as data:
        pairs = np.empty(2 * len(data.edges), dtype=np.int64)
        data.edges.foreach_get("vertices", pairs)
        select = np.zeros(len(data.edges), dtype=bool)
        data.edges.foreach_get("select", select)
    return pairs.reshape(-1, 2)[select]


def selected_triangles(mesh, triangle_faces):
    """Indices of the loop triangles of the selected faces (``triangle_faces``: each triangle's face)."""
    with adapters.stored(mesh) as data:
        select = np.zeros(len(data.polygons), dtype=bool)
        data.polygons.foreach_get("select", select)
    return np.flatnonzero(select[triangle_faces])


def _curves(obj, F, triangle_faces, edges, V):
    """The curves of a run: the ``edges`` given, else the selected faces' border, else the selected edges."""
    region = selected_triangles(obj.data, triangle_faces) if edges is None else np.zeros(0, dtype=np.int64)
    if region.size:
        curves = heatcore.region_boundary_curves(F, region, mesh_boundary=False)
        if not curves:
            raise AddonError(f"the selected faces of {obj.name!r} have no border inside the mesh (they cover whole "
                             "parts): select fewer faces, or only the edges of the curve")
        return curves
    edges = selected_edges(obj.data) if edges is None else np.asarray(edges, dtype=np.int64).reshape(-1, 2)
    if len(edges) == 0:
        raise AddonError(f"no edge selected on {obj.name!r}: select the edges of the curve (a loop, or chains) in "
                         "Edit Mode, or the faces inside it")
    return heatcore.edge_curves(F, edges, positions=V)


def signed_distance_from_edges(obj, edges=None, *, attribute=DEFAULT_SIGNED_ATTRIBUTE,
                               color_attribute=DEFAULT_SIGNED_COLOR, weight_group=None, weight_band=0.0, isolines=0,
                               space="WORLD", shape="EVALUATED", **solver_options):
    """Signed geodesic distance to the selected edges of a mesh object, written to its attributes.

    Parameters
    ----------
    obj : bpy.types.Object
        A mesh object (Object or Edit Mode).
    edges : (k, 2) array_like of int, optional
        The curve's edges as vertex pairs. Default: the border of the
        selected faces (inside positive), or without selected faces the
        selected edges.
    attribute : str or None
        The FLOAT point attribute that receives the field (None: not written).
    color_attribute : str or None
        The color attribute (blue to red, made active); None: not written.
    weight_group : str, optional
        A vertex group of weights: 1 inside, 0 outside.
    weight_band : float
        Width of the soft edge of the weights across the curve (0: a hard mask).
    isolines : int
        Dark stripes at 0 and this many levels on each side, in the colors.
    space, shape
        Which shape is measured, as in :func:`compute_geodesic_distance`.
    **solver_options
        ``m``, ``boundary``, ``backend``, ``robust``, ``refine``, ``weld``
        (:data:`SIGNED_OPTIONS`); ``weld`` is off by default (the mesh as
        connected in Blender).

    Returns
    -------
    SignedResult

    Raises
    ------
    AddonError
        Not a mesh, no edge, an output name taken, a bad option. Nothing is modified.
    heatcore.HeatcoreError
        A bad mesh or option. Nothing is modified.
    """
    start = time.perf_counter()
    if obj is None or getattr(obj, "type", None) != "MESH":
        raise AddonError(f"{getattr(obj, 'name', obj)!r} is not a mesh object")
    unknown = sorted(set(solver_options) - set(SIGNED_OPTIONS))
    if unknown:
        raise AddonError(f"Signed Distance takes the options {', '.join(SIGNED_OPTIONS)}; not {', '.join(unknown)}")
    if not (np.isfinite(weight_band) and weight_band >= 0):
        raise AddonError(f"the weight band must be a width >= 0, got {weight_band}")
    settings = Settings.of("signed heat", intent="interactive", **{"weld": None, **solver_options})
    adapters.check_output_names(obj, attribute, color_attribute, weight_group or None)
    if obj.mode == "EDIT":
        obj.update_from_editmode()
    corner_verts, triangle_faces = adapters.topology(obj.data)
    F = adapters.mesh_arrays(obj.data)[1]
    frame = measured_frame(obj, space)
    local, _ = object_positions(obj, shape)
    V = placed(local, frame)
    curves = _curves(obj, F, triangle_faces, edges, V)

    def build():
        return heatcore.SignedHeatSolver(heatcore.TriangleMesh(V, F, settings.mesh), settings.solver)

    solver, cached = SOLVERS.get(("signed", obj.data.session_uid), V, (corner_verts, triangle_faces),
                                 key_options(settings, False), build)
    d = solver.distance([[int(v) for v in c] for c in curves])
    finite = np.isfinite(d)
    with adapters.writing(obj):
        if attribute is not None:
            adapters.write_float_attribute(obj.data, attribute, np.where(finite, d, 0.0))
        if color_attribute is not None:
            adapters.write_color_attribute(obj.data, color_attribute, colormaps.colorize_signed(d, isolines=isolines))
        if weight_group:
            adapters.write_vertex_group(obj, weight_group, weights.signed_weights(d, weight_band))
    return SignedResult(distance=d, curves=len(curves), min_distance=float(d[finite].min()) if finite.any() else 0.0,
                        max_distance=float(d[finite].max()) if finite.any() else 0.0,
                        unreached=int((~finite).sum()), seconds=time.perf_counter() - start, cached=cached)
