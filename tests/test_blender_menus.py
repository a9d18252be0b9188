"""Findable and documented: menu entries, the Advanced sub-panel, the options table and the licenses.

With the real ``bpy`` (Blender 5.0 headless). Blender's own menus are drawn
into a recording stub layout (a headless ``bpy`` has no window to draw in):
the menu's own ``draw`` and every appended draw function run as in the UI,
and the recorded ``operator(...)`` calls and property sets are checked. The
options table of docs/blender.md is checked against the properties, the panel
as drawn and the signature of ``compute_geodesic_distance``; the bundled
wheels against scripts/build_blender_extension.py.
"""

import importlib.util
import inspect
import re
import sys
import traceback
from pathlib import Path

import blender_required  # noqa: F401 (first: without bpy, the module is skipped)
import bpy
import numpy as np
import pytest
from test_blender import addon, attribute, empty_scene, ico_sphere, select_only  # noqa: F401 (fixtures)

import heatcore as hc
from heatcore.options import OPTIONS

REPO = Path(__file__).resolve().parents[1]
DOCS = REPO / "docs" / "blender.md"
OPERATOR = "mesh.heat_geodesic_distance"


# ---------------------------------------------------------------- a recording layout


class Props:
    """Operator properties returned by ``layout.operator``: records what a menu sets."""

    def __init__(self):
        self.__dict__["values"] = {}

    def __setattr__(self, name, value):
        self.values[name] = value

    def __getattr__(self, name):  # nested groups (props.MESH_OT_rip.use_fill = ...)
        return Props()


class Layout:
    """Stands in for ``bpy.types.UILayout``; every call is appended to a shared log."""

    def __init__(self, log, heading=None):
        self.__dict__.update(log=log, heading=heading, operator_context="EXEC_DEFAULT")

    def __setattr__(self, name, value):
        self.__dict__[name] = value

    def operator(self, idname, **kw):
        props = Props()
        self.log.append(("operator", idname, kw, self.operator_context, props))
        return props

    def prop(self, data, name, **kw):
        self.log.append(("prop", name, kw, self.heading))

    def prop_search(self, data, name, *args, **kw):
        self.log.append(("prop", name, kw, self.heading))

    def column(self, heading=None, **kw):
        return Layout(self.log, heading)

    def __getattr__(self, name):  # label, box, row, separator, menu, template_...: recorded, nested
        def call(*args, **kw):
            self.log.append((name, args, kw))
            return Layout(self.log, self.heading)

        return call


def draw(cls, context=None):
    """Run ``cls.draw`` (a menu or panel class, with its appended functions) into a :class:`Layout`.

    Blender's menu drawing prints and swallows exceptions of draw functions; here they fail the test.
    """
    log = []

    class Self:
        layout = Layout(log)

        def __getattr__(self, name):
            return getattr(cls, name)

    errors = []
    original = traceback.print_exc
    traceback.print_exc = lambda *a, **k: errors.append(traceback.format_exc())
    try:
        cls.draw(Self(), context or bpy.context)
    finally:
        traceback.print_exc = original
    assert not errors, f"{cls.__name__} raised while drawing:\n{errors[0]}"
    return log


def operators(log, idname=OPERATOR):
    return [entry for entry in log if entry[0] == "operator" and entry[1] == idname]


def mode(obj, name):
    with bpy.context.temp_override(active_object=obj, object=obj):
        bpy.ops.object.mode_set(mode=name)


# ---------------------------------------------------------------- menus

WEIGHT_MENUS = {"VIEW3D_MT_paint_weight", "VIEW3D_MT_edit_mesh_weights"}
CURVE_MENUS = {"VIEW3D_MT_edit_mesh_context_menu", "VIEW3D_MT_object", "VIEW3D_MT_object_context_menu"}
#: A built-in operator each menu draws (its own draw ran, ours came after).
BUILT_IN = {
    "VIEW3D_MT_edit_mesh_context_menu": "mesh.extrude_vertices_move",
    "VIEW3D_MT_edit_mesh_vertices": "mesh.vert_connect_path",
    "VIEW3D_MT_select_edit_mesh": "mesh.select_axis",
    "VIEW3D_MT_edit_mesh_weights": "object.vertex_group_normalize",
    "VIEW3D_MT_object": "object.join",
    "VIEW3D_MT_object_context_menu": "object.delete",
    "VIEW3D_MT_paint_weight": "paint.weight_gradient",
}


def test_the_entries_are_in_menus_of_this_blender(addon):
    menus = [menu for menu, _ in addon.menus.ENTRIES]
    assert set(menus) == set(BUILT_IN)
    assert all(hasattr(bpy.types, menu) and issubclass(getattr(bpy.types, menu), bpy.types.Menu) for menu in menus)


@pytest.mark.parametrize("menu", sorted(BUILT_IN))
def test_each_menu_draws_our_entry_last_with_invoke(addon, menu):
    obj = ico_sphere(subdivisions=1)
    if menu.startswith(("VIEW3D_MT_edit_mesh", "VIEW3D_MT_select_edit")):
        mode(obj, "EDIT")
    try:
        log = draw(getattr(bpy.types, menu))
    finally:
        mode(obj, "OBJECT")
    assert operators(log, BUILT_IN[menu]), f"{menu}'s own entries were not drawn"
    ours = operators(log)
    assert len(ours) == 1, ours
    _, _, kw, context, props = ours[0]
    curves = operators(log, "mesh.heat_geodesic_isoline_curves")
    paths = operators(log, "mesh.heat_geodesic_path")
    last = [e for e in log if e[0] == "operator"][-1 - len(curves) - len(paths):]
    assert last[0] is ours[0]
    # Isoline Curves follows the distance entry in the Edit Mode context menu and the Object Mode menus.
    assert len(curves) == (menu in CURVE_MENUS)
    if curves:
        assert last[1] is curves[0] and curves[0][2]["text"] == "Isoline Curves" and curves[0][3] == "INVOKE_REGION_WIN"
    # Geodesic Path ends the Edit Mode context menu and Vertex menu (two selected vertices).
    assert len(paths) == (menu in addon.menus.PATH_MENUS)
    if paths:
        assert last[-1] is paths[0] and paths[0][2]["text"] == "Geodesic Path" and paths[0][3] == "INVOKE_REGION_WIN"
    # Invoked, so options not set by the entry come from the panel (Blender's Object menu ends in EXEC).
    assert context == "INVOKE_REGION_WIN"
    assert kw["icon"] == "DRIVER_DISTANCE"
    if menu in WEIGHT_MENUS:
        assert kw["text"] == "Geodesic Distance Weights"
        assert props.values == {"write_weights": True}
    else:
        assert kw["text"] == "Geodesic Distance"
        assert props.values == {}


@pytest.mark.parametrize("menu", ["VIEW3D_MT_object", "VIEW3D_MT_object_context_menu"])
def test_object_menus_show_the_entry_for_meshes_only(addon, menu):
    bpy.ops.object.empty_add()
    log = draw(getattr(bpy.types, menu))
    assert not operators(log) and not operators(log, "mesh.heat_geodesic_isoline_curves")
    ico_sphere(subdivisions=1)
    log = draw(getattr(bpy.types, menu))
    assert len(operators(log)) == 1 and len(operators(log, "mesh.heat_geodesic_isoline_curves")) == 1


def test_register_twice_or_a_reloaded_copy_adds_no_duplicate_and_unregister_removes_all(addon):
    menus = [menu for menu, _ in addon.menus.ENTRIES]

    def counts():
        return {m: len(addon.menus.ours(m)) for m in menus}

    assert counts() == dict.fromkeys(menus, 1)
    addon.menus.register()
    assert counts() == dict.fromkeys(menus, 1)
    # What an earlier copy of the module (a reload without unregister) leaves behind is replaced.
    stale = addon.menus._entry("VIEW3D_MT_object", "stale")
    bpy.types.VIEW3D_MT_object.append(stale)
    addon.menus.register()
    assert counts() == dict.fromkeys(menus, 1)
    assert stale not in bpy.types.VIEW3D_MT_object.draw._draw_funcs

    addon.unregister()
    try:
        assert counts() == dict.fromkeys(menus, 0)
        for menu in menus:
            funcs = getattr(bpy.types, menu).draw._draw_funcs
            assert not [f for f in funcs if "heat_geodesic" in f.__name__], menu
        assert not hasattr(bpy.types, "VIEW3D_PT_heat_geodesic_advanced")
    finally:
        addon.register()
    assert counts() == dict.fromkeys(menus, 1)


def test_weight_paint_entry_writes_the_weights(addon):
    """The Weights menu's entry, invoked as the menu does, in Weight Paint mode: weights = 1 - distance / max."""
    obj = ico_sphere(subdivisions=3)
    V = np.array([v.co for v in obj.data.vertices])
    pole = int(np.argmax(V[:, 2]))
    select_only(obj, [pole])
    mode(obj, "WEIGHT_PAINT")
    (_, _, _, context, props), = operators(draw(bpy.types.VIEW3D_MT_paint_weight))
    settings = bpy.context.scene.heat_geodesic
    assert not settings.write_weights  # the panel's setting is off: the entry turns it on
    with bpy.context.temp_override(active_object=obj, object=obj):
        assert bpy.ops.mesh.heat_geodesic_distance(context, **props.values) == {"FINISHED"}
    assert obj.mode == "WEIGHT_PAINT"
    mode(obj, "OBJECT")
    group = obj.vertex_groups[settings.weight_group]
    weights = np.array([group.weight(i) for i in range(len(V))])
    d = attribute(obj.data, settings.attribute)
    np.testing.assert_allclose(weights, 1.0 - d / d.max(), atol=1e-6)  # 1 at the source, 0 farthest
    assert weights[pole] == 1.0 and weights.min() == pytest.approx(0.0)


# ---------------------------------------------------------------- panels


def drawn_properties(addon):
    """{property: (panel label, panel)} of everything the two panels draw, with every optional row shown."""
    settings = bpy.context.scene.heat_geodesic
    settings.source, settings.write_weights = "VERTEX_GROUP", True
    try:
        out = {}
        for cls, where in ((addon.panel.VIEW3D_PT_heat_geodesic, ""), (addon.panel.VIEW3D_PT_heat_geodesic_advanced,
                                                                        "Advanced › ")):
            for entry in draw(cls):
                if entry[0] == "prop":
                    name, kw = entry[1], entry[2]
                    label = kw.get("text") or addon.properties.GeodesicOptions.__annotations__[name].keywords["name"]
                    assert name not in out, f"{name} drawn twice"
                    out[name] = where + label
        return out
    finally:
        settings.source, settings.write_weights = "SELECTED", False


def test_advanced_subpanel_is_closed_and_holds_the_solver_jargon(addon):
    advanced = addon.panel.VIEW3D_PT_heat_geodesic_advanced
    assert bpy.types.VIEW3D_PT_heat_geodesic_advanced.bl_parent_id == "VIEW3D_PT_heat_geodesic"
    assert advanced.bl_options == {"DEFAULT_CLOSED"}
    assert advanced.bl_category == "Geodesic" and advanced.bl_region_type == "UI"
    labels = drawn_properties(addon)
    assert {n for n, label in labels.items() if label.startswith("Advanced")} == {"boundary", "robust", "backend", "polygons",
                                                                                "refine", "weld"}
    assert not labels["m"].startswith("Advanced") and not labels["accuracy"].startswith("Advanced")
    # Every option of the operator is in one of the two panels.
    assert set(labels) == set(addon.properties.GeodesicOptions.__annotations__)


def test_backend_is_passed_to_the_solver(addon):
    obj = ico_sphere(subdivisions=3)
    select_only(obj, [0])
    with bpy.context.temp_override(active_object=obj, object=obj):
        assert bpy.ops.mesh.heat_geodesic_distance(backend="auto") == {"FINISHED"}
        assert bpy.ops.mesh.heat_geodesic_distance(backend="superlu") == {"FINISHED"}
    stats = bpy.context.window_manager.heat_geodesic_stats
    assert not stats.cached  # another backend is another solver
    (_, solver), = [e for k, e in addon.SOLVERS._entries.items() if k == obj.data.session_uid]
    # kept for the next clicks, but factored as for one query (the first click is waited for)
    assert solver.settings.backend == "superlu" and solver.settings.intent == "interactive"
    d = attribute(obj.data, "geodesic_distance")
    V = np.array([v.co for v in obj.data.vertices])
    obj.data.calc_loop_triangles()
    F = np.array([t.vertices[:] for t in obj.data.loop_triangles])
    expected = hc.HeatSolver(hc.TriangleMesh(V, F), backend="superlu").distance([0])
    np.testing.assert_allclose(d, expected, rtol=1e-5, atol=1e-6)


# ---------------------------------------------------------------- docs/blender.md


def options_table():
    """Rows of the options table of docs/blender.md as dicts keyed by the header."""
    lines = DOCS.read_text().splitlines()
    header = "| Panel | Property | Script keyword | Default | Script default | Meaning |"
    start = lines.index(header)
    keys = [c.strip() for c in header.strip("|").split("|")]
    rows = []
    for line in lines[start + 2:]:
        if not line.startswith("|"):
            break
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        assert len(cells) == len(keys), f"docs/blender.md options table: {line!r}"
        rows.append(dict(zip(keys, cells)))
    return rows


def code(cell):
    m = re.fullmatch(r"`([^`]*)`", cell)
    return m.group(1) if m else None


def panel_default(prop):
    """How the table writes a property's default (as the panel shows it)."""
    default = prop.keywords.get("default")
    if prop.function is bpy.props.EnumProperty:
        return {item[0]: item[1] for item in prop.keywords["items"]}[default]
    if prop.function is bpy.props.BoolProperty:
        return "on" if default else "off"
    if prop.function is bpy.props.StringProperty:
        return f"`{default}`" if default else "empty"
    return str(default)


def script_default(value):
    return "`" + repr(value).replace("'", '"') + "`"


def test_docs_state_every_option_with_its_label_and_defaults(addon):
    rows = options_table()
    annotations = addon.properties.GeodesicOptions.__annotations__
    signature = inspect.signature(addon.compute_geodesic_distance)
    keywords = {n: p.default for n, p in signature.parameters.items() if n != "obj" and p.kind != p.VAR_KEYWORD}
    keywords.update({n: o.default_for("blender") for n, o in OPTIONS.items() if o.target in ("mesh", "solver")})  # **solver_options
    labels = drawn_properties(addon)

    documented_props = [code(r["Property"]) for r in rows if r["Property"] != "—"]
    documented_keywords = [code(r["Script keyword"]) for r in rows if r["Script keyword"] != "—"]
    assert sorted(documented_props) == sorted(annotations), "every operator property once, and no other"
    assert sorted(documented_keywords) == sorted(keywords), "every keyword of compute_geodesic_distance once"
    for row in rows:
        prop, keyword = code(row["Property"]), code(row["Script keyword"])
        if prop:
            assert row["Panel"] == labels[prop], row
            assert row["Default"] == panel_default(annotations[prop]), row
        else:
            assert row["Panel"] == row["Default"] == "—", row
        if keyword:
            assert row["Script default"] == script_default(keywords[keyword]), row
        else:
            assert row["Script default"] == "—", row
        assert row["Meaning"], row


def test_docs_name_where_the_entries_are(addon):
    text = DOCS.read_text()
    for where in ("Vertex", "Object", "Weights", "F3", "Advanced"):
        assert where in text, where
    assert "mesh without faces" not in text  # point clouds work


# ---------------------------------------------------------------- licenses


def build_script():
    spec = importlib.util.spec_from_file_location("build_blender_extension", REPO / "scripts" / "build_blender_extension.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules.setdefault(spec.name, module)
    spec.loader.exec_module(module)
    return module


def test_manifest_and_docs_name_every_bundled_wheel_and_its_license():
    build = build_script()
    pins = [req.split("==") for req in build.REQUIREMENTS + [r for group in build.OPTIONAL_REQUIREMENTS for r in group]]
    assert sorted(name for name, _ in pins) == sorted(build.WHEEL_LICENSES)
    manifest = (REPO / "blender_addon" / "blender_manifest.toml").read_text()
    docs = DOCS.read_text()
    for name, version in pins:
        license_ = build.WHEEL_LICENSES[name]
        assert re.search(rf"^#\s+{re.escape(name)} {re.escape(version)}: {re.escape(license_)}\b", manifest, re.MULTILINE), name
        assert f"| {name} | {version} | {license_} |" in docs, name
    assert 'license = ["SPDX:GPL-3.0-or-later"]' in manifest  # cvxopt is GPL-3.0-or-later: so is the whole
    assert build.WHEEL_LICENSES["cvxopt"] == "GPL-3.0-or-later"


def test_the_licenses_are_those_of_the_installed_packages():
    """Where a bundled package is installed here, its metadata states the license the table gives."""
    import importlib.metadata as md

    build = build_script()
    checked = 0
    for name, license_ in build.WHEEL_LICENSES.items():
        try:
            meta = md.metadata(name)
        except md.PackageNotFoundError:
            continue
        stated = " ".join(filter(None, [meta.get("License-Expression"), meta.get("License"),
                                        *(meta.get_all("Classifier") or [])]))
        words = {"BSD-3-Clause": "BSD", "Apache-2.0": "Apache", "GPL-3.0-or-later": "either version 3",
                 "MIT AND Apache-2.0": "MIT AND Apache-2.0", "PSF-2.0": "PSF-2.0"}[license_]
        assert words in stated, f"{name}: {stated[:200]!r}"
        checked += 1
    assert checked >= 1


def test_panel_has_the_distance_and_isoline_curves_buttons(addon):
    log = draw(addon.panel.VIEW3D_PT_heat_geodesic)
    assert len(operators(log)) == 1
    (curves,) = operators(log, "mesh.heat_geodesic_isoline_curves")
    assert curves[2]["text"] == "Curves"
