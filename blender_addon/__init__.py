"""Heat Geodesics: a Blender add-on/extension computing geodesic distance by the heat method.

Select vertices, press *Geodesic Distance* in View3D > Sidebar > Geodesic (or
run ``bpy.ops.mesh.heat_geodesic_distance()``), and the mesh gets a FLOAT
point attribute with the distance and an active color attribute showing it.
All numerics live in heatcore; this package only moves data between Blender
and heatcore.

Modules: ``adapters`` (bpy <-> arrays), ``cache`` (prefactored solvers),
``api`` (:func:`compute_geodesic_distance` for scripts), ``stages`` (a run's
stages: prepare, build, finish), ``outputs`` (what a run writes),
``background`` (the solver build in a worker thread), ``display`` (what
shows while it runs), ``properties``,
``operator``, ``panel`` (the sidebar panel and its *Advanced* sub-panel),
``isoline_operator`` (the *Isoline Curves* operator), ``path_operator`` and ``path_api``
(the *Geodesic Path* operator and :func:`geodesic_path`), ``uvmap`` (:func:`geodesic_uv_map`,
the *Geodesic UV Map* for scripts) and ``uv_operator`` (its operator), ``signed`` (:func:`signed_distance_from_edges`,
*Signed Distance from Edges* for scripts) and ``signed_operator`` (its operator), ``straighten``
(:func:`straighten_edges`) and ``straighten_operator`` (*Straighten Edges*), ``menus`` (entries in the Edit Mode, Object Mode and Weight Paint menus; F3
finds them), ``shape`` (which shape is measured), ``undo`` (active color
across undo), ``material`` (the isoline material), ``legend`` (its
legend sub-panel), and the interactive tool: ``probe`` (:class:`GeodesicProbe`,
sources at surface points, the field live), ``probe_surface`` (ray casting
the displayed mesh), ``overlay`` (what it draws), ``curves`` (its path and isolines as curve objects) and
``probe_tool`` (its modal operator and toolbar tools), ``probe_session`` (their event logic); ``tooltips`` (the options' tooltips for Blender users),
``targets`` (the objects a click measures), ``elements`` (selected faces and edges as sources),
``select_operator`` (*Select › Within Geodesic Distance*), ``redo`` (the operator's redo panel) and ``presets``
(its presets).

Examples
--------
>>> import bpy                                                   # doctest: +SKIP
>>> bpy.ops.mesh.heat_geodesic_distance(isolines=8)              # doctest: +SKIP
>>> from bl_ext.user_default.heat_geodesics import compute_geodesic_distance  # doctest: +SKIP
>>> compute_geodesic_distance(bpy.context.object, sources=[0]).max_distance   # doctest: +SKIP
>>> from bl_ext.user_default.heat_geodesics import GeodesicProbe              # doctest: +SKIP
>>> GeodesicProbe(bpy.context.object).move_to(0, (0.2, 0.3, 0.5))             # doctest: +SKIP
>>> from bl_ext.user_default.heat_geodesics import geodesic_uv_map            # doctest: +SKIP
>>> geodesic_uv_map(bpy.context.object, 0, unit=0.5).name                     # doctest: +SKIP
'geodesic_uv'
"""

import bpy

from . import (
    isoline_operator,
    menus,
    operator,
    panel,
    path_operator,
    presets,
    probe_tool,
    properties,
    select_operator,
    signed_operator,
    straighten_operator,
    undo,
    uv_operator,
)
from .adapters import AddonError
from .api import GeodesicResult, PathResult, compute_geodesic_distance, geodesic_path
from .background import BackgroundBuild
from .cache import SOLVERS
from .overlay import Overlay
from .probe import GeodesicProbe
from .signed import SignedResult, signed_distance_from_edges
from .straighten import StraightenResult, straighten_edges
from .uvmap import UVMapResult, geodesic_uv_map

__all__ = ["compute_geodesic_distance", "GeodesicResult", "GeodesicProbe", "geodesic_path", "PathResult",
           "geodesic_uv_map", "UVMapResult", "signed_distance_from_edges", "SignedResult", "straighten_edges", "StraightenResult",
           "AddonError",
           "register", "unregister"]


def register():
    """Register the settings, the operators, the toolbar tools, the sidebar panel and the menu entries."""
    properties.register()
    bpy.utils.register_class(operator.MESH_OT_heat_geodesic_distance)
    probe_tool.register()
    bpy.utils.register_class(isoline_operator.MESH_OT_heat_geodesic_isoline_curves)
    bpy.utils.register_class(uv_operator.MESH_OT_heat_geodesic_uv_map)
    bpy.utils.register_class(path_operator.MESH_OT_heat_geodesic_path)
    bpy.utils.register_class(select_operator.MESH_OT_heat_geodesic_select_within)
    bpy.utils.register_class(signed_operator.MESH_OT_heat_signed_distance)
    bpy.utils.register_class(straighten_operator.MESH_OT_heat_straighten_edges)
    panel.register()
    undo.register()
    menus.register()
    presets.register()


def unregister():
    """Unregister everything :func:`register` added and drop cached solvers."""
    menus.unregister()
    undo.unregister()
    panel.unregister()
    probe_tool.unregister()
    bpy.utils.unregister_class(select_operator.MESH_OT_heat_geodesic_select_within)
    bpy.utils.unregister_class(uv_operator.MESH_OT_heat_geodesic_uv_map)
    bpy.utils.unregister_class(straighten_operator.MESH_OT_heat_straighten_edges)
    bpy.utils.unregister_class(signed_operator.MESH_OT_heat_signed_distance)
    bpy.utils.unregister_class(path_operator.MESH_OT_heat_geodesic_path)
    bpy.utils.unregister_class(isoline_operator.MESH_OT_heat_geodesic_isoline_curves)
    bpy.utils.unregister_class(operator.MESH_OT_heat_geodesic_distance)
    properties.unregister()
    BackgroundBuild.cancel_running()  # a build still running stops at its next stage; nothing is kept
    for overlay in list(Overlay.live):  # a button's preview still drawn: its run ends with the add-on
        overlay.remove()
    SOLVERS.clear()
