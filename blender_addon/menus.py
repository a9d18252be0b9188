"""Menu entries of the geodesic distance operator, so that it can be found where mesh tools are.

Edit Mode: the right-click context menu, the header's *Vertex* menu and
*Mesh › Weights* (the *Select* menu also holds *Within Geodesic Distance*, first); Object Mode: the *Object* menu and the right-click
context menu (mesh objects); Weight Paint: the *Weights* menu. The *Weights*
entries run the operator with the vertex-group output on; the others have the
interactive *Geodesic Probe* (:mod:`.probe_tool`) just above it; the Edit Mode
context menu and the two Object Mode menus also hold *Isoline Curves* after it, and the Edit Mode
context menu and *Vertex* menu end with *Geodesic Path* (:data:`PATH_MENUS`). The Edit Mode
*UV* menu (U) ends with the *Geodesic UV Map*, after Blender's own projections (:data:`UV_ENTRIES`). Blender's menu
search (F3) finds every entry, by its label, in the mode where its menu is
shown. :data:`ENTRIES` lists them; :func:`register` appends one draw function
per menu (never twice) and :func:`unregister` removes them all.
"""

import bpy

from .isoline_operator import MESH_OT_heat_geodesic_isoline_curves
from .operator import MESH_OT_heat_geodesic_distance
from .path_operator import MESH_OT_heat_geodesic_path
from .probe_tool import MESH_OT_heat_geodesic_probe
from .select_operator import MESH_OT_heat_geodesic_select_within
from .signed_operator import MESH_OT_heat_signed_distance
from .straighten_operator import MESH_OT_heat_straighten_edges
from .uv_operator import MESH_OT_heat_geodesic_uv_map

OPERATOR = MESH_OT_heat_geodesic_distance.bl_idname
PROBE = MESH_OT_heat_geodesic_probe.bl_idname
ICON = "DRIVER_DISTANCE"
PROBE_ICON = "CURSOR"
#: The *Isoline Curves* operator, drawn after the distance entry in :data:`CURVE_MENUS`.
CURVES_OPERATOR = MESH_OT_heat_geodesic_isoline_curves.bl_idname
CURVES_ICON = "OUTLINER_OB_CURVE"
CURVE_MENUS = ("VIEW3D_MT_edit_mesh_context_menu", "VIEW3D_MT_object", "VIEW3D_MT_object_context_menu")
#: The *Geodesic Path* operator (two selected vertices), drawn last in :data:`PATH_MENUS`.
PATH_OPERATOR = MESH_OT_heat_geodesic_path.bl_idname
PATH_ICON = "CURVE_PATH"
PATH_MENUS = ("VIEW3D_MT_edit_mesh_context_menu", "VIEW3D_MT_edit_mesh_vertices")
#: The *Geodesic UV Map* operator, at the end of the Edit Mode *UV* menu (U), after Blender's own projections
#: (:data:`UV_ENTRIES`).
UV_OPERATOR = MESH_OT_heat_geodesic_uv_map.bl_idname
UV_ICON = "UV"
#: *Within Geodesic Distance* (grow the selection), first of our entries in the Edit Mode *Select* menu.
SELECT_OPERATOR = MESH_OT_heat_geodesic_select_within.bl_idname
SELECT_MENU = "VIEW3D_MT_select_edit_mesh"
#: *Signed Distance from Edges*, at the end of the Edit Mode *Edge* menu and the context menu (:data:`SIGNED_ENTRIES`).
SIGNED_OPERATOR = MESH_OT_heat_signed_distance.bl_idname
SIGNED_ICON = "MOD_MASK"
#: *Straighten Edges*, in the Edit Mode *Edge* menu after *Signed Distance from Edges*.
STRAIGHTEN_OPERATOR = MESH_OT_heat_straighten_edges.bl_idname
STRAIGHTEN_ICON = "IPO_LINEAR"
#: Marker attribute of our draw functions (finds entries left by an earlier copy of the module).
MARK = "_heat_geodesic_entry"


def _entry(menu, text, weights=False, mesh_only=False, curves=False):
    """A draw function adding the operator's entry to ``menu`` (a separator, the probe unless ``weights``,
    the entry; with ``curves``, then the *Isoline Curves* entry; in :data:`PATH_MENUS`, then *Geodesic Path*)."""
    path = menu in PATH_MENUS

    def draw(self, context):
        if mesh_only:
            obj = context.active_object
            if obj is None or obj.type != "MESH":
                return
        layout = self.layout
        layout.separator()
        # Invoke: options not given by the entry come from the panel (as from the button).
        layout.operator_context = "INVOKE_REGION_WIN"
        if menu == SELECT_MENU:
            layout.operator(SELECT_OPERATOR, text="Within Geodesic Distance", icon=ICON)
        if not weights:
            layout.operator(PROBE, text="Geodesic Probe", icon=PROBE_ICON)
        props = layout.operator(OPERATOR, text=text, icon=ICON)
        if weights:
            props.write_weights = True
        if curves:
            layout.operator(CURVES_OPERATOR, text="Isoline Curves", icon=CURVES_ICON)
        if path:
            layout.operator(PATH_OPERATOR, text="Geodesic Path", icon=PATH_ICON)

    draw.__name__ = draw.__qualname__ = f"draw_heat_geodesic_{menu}"
    setattr(draw, MARK, menu)
    return draw


#: (menu class name, draw function): where the operator appears.
ENTRIES = (
    ("VIEW3D_MT_edit_mesh_context_menu", _entry("VIEW3D_MT_edit_mesh_context_menu", "Geodesic Distance", curves=True)),
    ("VIEW3D_MT_edit_mesh_vertices", _entry("VIEW3D_MT_edit_mesh_vertices", "Geodesic Distance")),
    ("VIEW3D_MT_select_edit_mesh", _entry("VIEW3D_MT_select_edit_mesh", "Geodesic Distance")),
    ("VIEW3D_MT_edit_mesh_weights", _entry("VIEW3D_MT_edit_mesh_weights", "Geodesic Distance Weights", weights=True)),
    ("VIEW3D_MT_object", _entry("VIEW3D_MT_object", "Geodesic Distance", mesh_only=True, curves=True)),
    ("VIEW3D_MT_object_context_menu",
     _entry("VIEW3D_MT_object_context_menu", "Geodesic Distance", mesh_only=True, curves=True)),
    ("VIEW3D_MT_paint_weight", _entry("VIEW3D_MT_paint_weight", "Geodesic Distance Weights", weights=True)),
)




def _single_entry(menu, operator, text, icon, kind):
    """A draw function adding one operator's entry (invoked: the panel's options) to ``menu``."""

    def draw(self, context):
        self.layout.separator()
        self.layout.operator_context = "INVOKE_REGION_WIN"
        self.layout.operator(operator, text=text, icon=icon)

    draw.__name__ = draw.__qualname__ = f"draw_heat_{kind}_{menu}"
    setattr(draw, MARK, menu)
    return draw


#: Menus that hold only the *Geodesic UV Map* (invoked: the panel's options, the view's up): the Edit Mode
#: *UV* menu (U), beside Smart UV Project and Project from View.
UV_ENTRIES = (("VIEW3D_MT_uv_map", _single_entry("VIEW3D_MT_uv_map", UV_OPERATOR, "Geodesic UV Map", UV_ICON,
                                                 "geodesic_uv")),)
#: Menus with *Signed Distance from Edges* and *Straighten Edges*: the Edit Mode *Edge* menu (Ctrl E).
SIGNED_ENTRIES = (
    ("VIEW3D_MT_edit_mesh_edges", _single_entry("VIEW3D_MT_edit_mesh_edges", SIGNED_OPERATOR,
                                                "Signed Distance from Edges", SIGNED_ICON, "signed")),
    ("VIEW3D_MT_edit_mesh_edges", _single_entry("VIEW3D_MT_edit_mesh_edges", STRAIGHTEN_OPERATOR,
                                                "Straighten Edges", STRAIGHTEN_ICON, "straighten")),
)


#: Every (menu, draw function) this add-on adds, in order (a menu may get several).
ALL_ENTRIES = ENTRIES + UV_ENTRIES + SIGNED_ENTRIES


def ours(menu):
    """The draw functions of this add-on in ``bpy.types.<menu>`` (none when unregistered).

    Examples
    --------
    >>> ours("VIEW3D_MT_paint_weight")  # doctest: +SKIP
    [<function draw_heat_geodesic_VIEW3D_MT_paint_weight ...>]
    """
    funcs = getattr(getattr(bpy.types, menu).draw, "_draw_funcs", None) or []
    return [f for f in funcs if getattr(f, MARK, None) == menu]


def register():
    """Append the entries; entries already there (an earlier copy of this module) are replaced.

    Examples
    --------
    >>> register()  # doctest: +SKIP
    >>> len(ours("VIEW3D_MT_object"))  # doctest: +SKIP
    1
    """
    unregister()  # entries of an earlier copy of this module
    for menu, draw in ALL_ENTRIES:
        getattr(bpy.types, menu).append(draw)


def unregister():
    """Remove every entry :func:`register` added.

    Examples
    --------
    >>> unregister()  # doctest: +SKIP
    >>> ours("VIEW3D_MT_object")  # doctest: +SKIP
    []
    """
    for menu in dict.fromkeys(menu for menu, _ in reversed(ALL_ENTRIES)):
        cls = getattr(bpy.types, menu)
        for old in ours(menu):
            cls.remove(old)
