"""What an artist meets first (issue 37): tooltips, selection, one isoline count, units, the redo panel, sources.

With the real ``bpy`` (Blender 5.0 headless). Every registered property of
the add-on (operators, scene settings) is walked for its tooltip; runs on
several selected objects, faces and edges as sources are checked against
heatcore called on the same arrays.
"""

from pathlib import Path

import blender_required  # noqa: F401 (first: without bpy, the module is skipped)
import bpy
import numpy as np
import pytest
from test_blender import addon, attribute, empty_scene, ico_sphere, run, select_only  # noqa: F401 (fixtures)

import heatcore as hc

#: The add-on's operators (``bpy.ops.mesh.<name>``) that every test here knows of; the tooltip test walks them all.
OPERATORS = ("heat_geodesic_distance", "heat_geodesic_isoline_curves", "heat_geodesic_probe", "heat_geodesic_path",
             "heat_geodesic_uv_map", "heat_geodesic_select_within")
#: Properties every Blender property group has, with Blender's own tooltip.
BUILT_IN = {"rna_type", "name"}


def registered_properties():
    """(owner, property) of every property a user can meet: the operators' and the scene settings'."""
    ours = sorted({*OPERATORS, *(name for name in dir(bpy.ops.mesh) if name.startswith("heat_"))})
    owners = [(op, getattr(bpy.ops.mesh, op).get_rna_type()) for op in ours]
    owners.append(("scene.heat_geodesic", bpy.context.scene.heat_geodesic.bl_rna))
    return [(owner, prop) for owner, rna in owners for prop in rna.properties if prop.identifier not in BUILT_IN]


# ---------------------------------------------------------------- tooltips


def test_every_property_has_a_tooltip_for_a_blender_user(addon):
    foreign = addon.tooltips.FOREIGN_WORDS
    props = registered_properties()
    assert len(props) > 80
    for owner, prop in props:
        texts = [prop.description] + [item.description for item in getattr(prop, "enum_items", ())]
        where = f"{owner}.{prop.identifier}"
        assert prop.description.strip(), f"{where} has no tooltip"
        for text in texts:
            assert text[:1].isupper() or not text[:1].isalpha(), f"{where}: {text!r} starts lower-case"
            assert not any(word in text.lower() for word in foreign), f"{where}: {text!r} names another front end"


def test_accuracy_tooltip_states_the_cost_heatcore_measured_without_numba(addon):
    """The extension bundles no numba: High costs the vectorized pass's figure, declared once in heatcore."""
    slow = "-".join(f"{x:g}" for x in hc.options.HIGH_ACCURACY_COST["vectorized"])
    description = bpy.context.scene.heat_geodesic.bl_rna.properties["accuracy"].description
    assert f"{slow} times as long" in description, description


def test_spacing_tooltip_is_the_spacing_the_material_uses(addon):
    settings = bpy.context.scene.heat_geodesic
    assert "(Isolines + 1)" in settings.bl_rna.properties["isoline_spacing"].description
    obj = ico_sphere(3)
    select_only(obj, [0])
    result = addon.compute_geodesic_distance(obj, isolines=9, isoline_material=True)
    legend = addon.material.isoline_legend(obj)
    assert legend.spacing == pytest.approx(result.max_distance / 10, rel=1e-5)


# ---------------------------------------------------------------- selection


def _sphere_at(x, radius, name):
    obj = ico_sphere(3, radius)
    obj.location.x = x
    obj.name = name
    return obj


def test_every_selected_mesh_is_measured_on_its_own_and_the_others_named(addon, capfd):
    a, b = _sphere_at(0.0, 1.0, "A"), _sphere_at(4.0, 2.0, "B")
    select_only(a, [0])
    select_only(b, [5])
    bpy.ops.object.empty_add(location=(9, 0, 0))
    empty = bpy.context.active_object
    for obj in (a, b, empty):
        obj.select_set(True)
    with bpy.context.temp_override(active_object=a, object=a, selected_objects=[a, b, empty]):
        assert bpy.ops.mesh.heat_geodesic_distance(isolines=0) == {"FINISHED"}
    for obj, source in ((a, 0), (b, 5)):
        d = attribute(obj.data, "geodesic_distance")
        expected = addon.compute_geodesic_distance(obj, sources=[source], attribute=None, color_attribute=None)
        np.testing.assert_allclose(d, expected.distance, rtol=1e-5, atol=1e-6)
        assert d[source] == 0.0
    out = capfd.readouterr()
    assert "Skipped 'Empty' (not a mesh)" in out.out + out.err


def test_a_selected_object_without_sources_is_named_and_the_others_measured(addon, capfd):
    a, b = _sphere_at(0.0, 1.0, "A"), _sphere_at(4.0, 1.0, "B")
    select_only(a, [0])
    select_only(b, [])
    with bpy.context.temp_override(active_object=a, object=a, selected_objects=[a, b]):
        assert bpy.ops.mesh.heat_geodesic_distance() == {"FINISHED"}
    assert "geodesic_distance" in a.data.attributes and "geodesic_distance" not in b.data.attributes
    out = capfd.readouterr()
    assert "Skipped 'B' (no source vertices" in out.out + out.err


def test_hidden_objects_are_refused(addon):
    a, b = _sphere_at(0.0, 1.0, "A"), _sphere_at(4.0, 1.0, "B")
    select_only(a, [0])
    select_only(b, [0])
    b.hide_set(True)
    targets, skipped = addon.targets.target_objects(
        type("Context", (), {"active_object": a, "selected_objects": [a, b]})())
    assert targets == [a] and skipped == [("B", "hidden")]
    for op in ("heat_geodesic_distance", "heat_geodesic_path", "heat_geodesic_probe", "heat_geodesic_uv_map",
               "heat_geodesic_isoline_curves"):
        with bpy.context.temp_override(active_object=b, object=b, selected_objects=[b]):
            assert not getattr(bpy.ops.mesh, op).poll(), op


def test_vertex_group_sources_with_no_group_chosen_is_an_error(addon):
    obj = ico_sphere(2)
    select_only(obj, [0])
    with pytest.raises(RuntimeError, match="no source vertex group chosen"):
        run(obj, source="VERTEX_GROUP", vertex_group="")
    assert "geodesic_distance" not in obj.data.attributes
    with pytest.raises(addon.AddonError, match="no source vertex group chosen"):
        addon.compute_geodesic_distance(obj, vertex_group="")


# ---------------------------------------------------------------- consistency


def test_isoline_curves_count_is_the_panels_isolines(addon):
    settings = bpy.context.scene.heat_geodesic
    assert addon.isoline_operator.DEFAULT_COUNT == settings.bl_rna.properties["isolines"].default == 10
    count = bpy.ops.mesh.heat_geodesic_isoline_curves.get_rna_type().properties["count"]
    assert count.default == settings.bl_rna.properties["isolines"].default
    obj = ico_sphere(3)
    select_only(obj, [0])
    settings.isolines = 6
    try:
        run(obj, isolines=6)
        with bpy.context.temp_override(active_object=obj, object=obj):
            assert bpy.ops.mesh.heat_geodesic_isoline_curves("INVOKE_DEFAULT") == {"FINISHED"}
    finally:
        settings.isolines = 10
    curve = bpy.data.objects[f"{obj.name} Geodesic Isolines"]
    d = attribute(obj.data, "geodesic_distance")
    levels = addon.isoline_operator.curve_levels(d, 6, 0.0)
    np.testing.assert_allclose(levels, d.max() * np.arange(1, 7) / 7)  # the stripes' levels
    assert len(curve.data.splines) >= 6


def test_probe_and_isoline_curves_share_one_object(addon):
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=12, y_subdivisions=12, size=2.0)
    obj = bpy.context.active_object
    select_only(obj, [0])
    run(obj, isolines=4)
    with bpy.context.temp_override(active_object=obj, object=obj):
        bpy.ops.mesh.heat_geodesic_isoline_curves(count=4)
    probe = addon.GeodesicProbe(obj, isoline_curves=True, isolines=4)
    probe.move_to(0, (1.0, 0.0, 0.0))
    probe.confirm(push_undo=False)
    with bpy.context.temp_override(active_object=obj, object=obj):
        bpy.ops.mesh.heat_geodesic_isoline_curves(count=4)
    names = [o.name for o in bpy.data.objects if o.type == "CURVE"]
    assert names == [f"{obj.name} Geodesic Isolines"]


def test_the_probe_tool_has_an_icon_of_its_own(addon):
    for tool in (addon.probe_tool.VIEW3D_WT_heat_geodesic_probe_object,):
        assert tool.bl_icon != "ops.view3d.ruler"
        icon = Path(tool.bl_icon + ".dat")
        assert icon.is_file() and icon.parent.parent == Path(addon.__file__).parent
        data = icon.read_bytes()
        assert data[:4] == b"VCO\x00" and (len(data) - 8) % 18 == 0 and len(data) > 8
        assert bpy.app.icons.new_triangles_from_file(str(icon)) > 0


def test_shape_keys_object_mode_measures_the_mix_and_edit_mode_the_active_key(addon):
    obj = ico_sphere(3)
    obj.shape_key_add(name="Basis")
    tall = obj.shape_key_add(name="Tall")
    co = np.array([v.co for v in obj.data.vertices]) * [1.0, 1.0, 2.0]
    tall.data.foreach_set("co", co.astype(np.float32).ravel())
    tall.value = 0.5
    obj.active_shape_key_index = 1
    bpy.context.view_layer.update()
    pole = int(np.argmax(co[:, 2]))
    mix = addon.compute_geodesic_distance(obj, sources=[pole], attribute=None, color_attribute=None)
    with bpy.context.temp_override(active_object=obj, object=obj):
        bpy.ops.object.mode_set(mode="EDIT")
    try:
        key = addon.compute_geodesic_distance(obj, sources=[pole], attribute=None, color_attribute=None)
    finally:
        with bpy.context.temp_override(active_object=obj, object=obj):
            bpy.ops.object.mode_set(mode="OBJECT")
    # pole to pole: half an ellipse of half-height 1.5 (the mix) and 2 (the key at full)
    assert mix.max_distance == pytest.approx(3.97, rel=0.03)
    assert key.max_distance == pytest.approx(4.84, rel=0.03)
    docs = (Path(__file__).resolve().parents[1] / "docs" / "blender.md").read_text()
    assert "Object Mode measures the shape keys as mixed" in docs



# ---------------------------------------------------------------- units


@pytest.fixture
def imperial():
    units = bpy.context.scene.unit_settings
    before = units.system, units.scale_length
    units.system, units.scale_length = "IMPERIAL", 1.0
    yield units
    units.system, units.scale_length = before


def test_lengths_are_shown_in_scene_units(addon, imperial, capfd):
    settings = bpy.context.scene.heat_geodesic
    radius = settings.bl_rna.properties["weight_radius"]
    assert radius.subtype == "DISTANCE" and radius.unit == "LENGTH"  # Blender shows it in scene units
    obj = ico_sphere(3, radius=2.0)
    select_only(obj, [0])
    assert run(obj) == {"FINISHED"}
    stats = bpy.context.window_manager.heat_geodesic_stats
    shown = bpy.utils.units.to_string("IMPERIAL", "LENGTH", stats.max_distance, precision=4)
    assert shown != f"{stats.max_distance:.4g}" and ("'" in shown or '"' in shown)  # feet and inches
    out = capfd.readouterr()
    assert f"max {shown}," in out.out + out.err
    from test_blender_menus import draw

    labels = [entry[2].get("text") for entry in draw(addon.panel.VIEW3D_PT_heat_geodesic) if entry[0] == "label"]
    assert f"Max distance {shown}" in labels
    assert addon.legend.format_distance(1.5, "LOCAL", bpy.context.scene) == "1.5 (object units)"


# ---------------------------------------------------------------- redo panel


class Recorder:
    """Stands in for ``bpy.types.UILayout``: records the properties drawn, the labels, and the sections."""

    def __init__(self, log, section=""):
        self.log, self.section = log, section

    def prop(self, data, name, **kw):
        self.log.append((self.section, name))

    def column(self, **kw):
        return self

    def label(self, text=""):
        self.log.append((self.section, "label:" + text))

    def panel(self, idname, default_closed=False):
        return Recorder(self.log, "header"), Recorder(self.log, "advanced")


def test_redo_panel_draws_what_matters_without_path_edges(addon):
    op = bpy.ops.mesh.heat_geodesic_distance
    cls = addon.operator.MESH_OT_heat_geodesic_distance
    assert "PRESET" in cls.bl_options and callable(cls.draw)
    settings = bpy.context.scene.heat_geodesic  # the operator's properties, with every switch on
    settings.source, settings.write_weights, settings.isoline_material = "VERTEX_GROUP", True, True
    try:
        log = []
        addon.redo.draw_run_options(Recorder(log), settings)
    finally:
        settings.source, settings.write_weights = "SELECTED", False
    drawn = [name for _, name in log if not name.startswith("label:")]
    assert len(drawn) == len(set(drawn))
    every = {p.identifier for p in op.get_rna_type().properties} - {"rna_type"}
    assert set(drawn) == every - {"path_edges"}
    assert [name for section, name in log if section == "advanced"] == list(addon.redo.ADVANCED)
    log = []
    settings.isoline_material = False
    try:
        addon.redo.draw_run_options(Recorder(log), settings)  # switches off: their rows are not shown
    finally:
        settings.isoline_material = True  # the default
    drawn = {name for _, name in log}
    assert not drawn & {"vertex_group", "weight_radius", "weight_group", "isoline_spacing", "isoline_style",
                        "path_edges"}


def test_presets_set_the_outputs_of_common_uses(addon, tmp_path):
    import types

    paths = addon.presets.write_presets(tmp_path)
    assert [p.name for p in paths] == ["Mask.py", "Falloff_Weights.py", "Isolines.py"]
    paths[0].write_text("# the user's own\n")
    assert addon.presets.write_presets(tmp_path)[0].read_text() == "# the user's own\n"  # kept
    settings = bpy.context.scene.heat_geodesic
    stub = types.SimpleNamespace(context=types.SimpleNamespace(active_operator=settings))
    try:
        for path, expect in zip(paths[1:], ({"write_weights": True, "weight_falloff": "SMOOTH", "isolines": 0},
                                           {"isolines": 10, "isoline_material": True, "write_weights": False})):
            code = path.read_text().replace("import bpy\n", "")
            exec(compile(code, str(path), "exec"), {"bpy": stub})  # noqa: S102 - what the preset menu runs
            assert {name: getattr(settings, name) for name in expect} == expect
    finally:
        for name, value in addon.presets.OUTPUT_DEFAULTS.items():
            setattr(settings, name, value)
        settings.isolines = 10


# ---------------------------------------------------------------- sources: faces and edges


def _select_elements(obj, faces=(), edges=()):
    mesh = obj.data
    for collection, chosen in ((mesh.polygons, faces), (mesh.edges, edges), (mesh.vertices, ())):
        sel = np.zeros(len(collection), dtype=bool)
        collection.foreach_set("select", sel)
    for i in faces:
        mesh.polygons[i].select = True
    for i in edges:
        mesh.edges[i].select = True
    mesh.update()


def test_selected_faces_are_the_core_region_on_triangles_and_polygons(addon):
    import heatcore as hc

    tri = ico_sphere(3)  # triangles: a TriangleMesh of the loop triangles
    faces = [0, 1, 2, 7]
    _select_elements(tri, faces=faces)
    run(tri, source="FACES")
    d = attribute(tri.data, "geodesic_distance")
    V = np.array([v.co for v in tri.data.vertices])
    F = np.array([p.vertices[:] for p in tri.data.polygons])
    expected = hc.HeatSolver(hc.TriangleMesh(V, F, weld=None)).distance(region=faces)
    np.testing.assert_allclose(d, expected, rtol=1e-5, atol=1e-6)
    assert np.all(d[np.unique(F[faces])] == 0.0) and d.max() > 2.0

    bpy.ops.mesh.primitive_grid_add(x_subdivisions=9, y_subdivisions=9, size=2.0)
    quads = bpy.context.active_object  # quads: a PolygonMesh of Blender's faces
    faces = [10, 11, 19, 20]
    _select_elements(quads, faces=faces)
    result = addon.compute_geodesic_distance(quads, selected="FACES", attribute=None, color_attribute=None)
    V = np.array([v.co for v in quads.data.vertices])
    polygons = [list(p.vertices) for p in quads.data.polygons]
    expected = hc.HeatSolver(hc.PolygonMesh(V, polygons)).distance(region=faces)
    np.testing.assert_allclose(result.distance, expected, rtol=1e-5, atol=1e-6)


def test_selected_edges_are_the_core_edges(addon):
    import heatcore as hc

    obj = ico_sphere(3)
    edges = [0, 5, 9]
    _select_elements(obj, edges=edges)
    run(obj, source="EDGES")
    d = attribute(obj.data, "geodesic_distance")
    V = np.array([v.co for v in obj.data.vertices])
    F = np.array([p.vertices[:] for p in obj.data.polygons])
    E = np.array([obj.data.edges[i].vertices[:] for i in edges])
    expected = hc.HeatSolver(hc.TriangleMesh(V, F, weld=None)).distance(edges=E)
    np.testing.assert_allclose(d, expected, rtol=1e-5, atol=1e-6)
    vertex_only = addon.compute_geodesic_distance(obj, sources=np.unique(E), attribute=None, color_attribute=None)
    assert not np.allclose(d, vertex_only.distance)  # along the edges, not only at their ends


def test_every_face_selected_in_object_mode_is_named(addon):
    obj = ico_sphere(2)  # a new primitive: everything selected
    with pytest.warns(UserWarning, match="all 80 faces of 'Icosphere' are selected"):
        result = addon.compute_geodesic_distance(obj, selected="FACES")
    assert result.max_distance == 0.0


def test_no_selected_faces_is_an_error(addon):
    obj = ico_sphere(2)
    _select_elements(obj)
    with pytest.raises(RuntimeError, match="no source faces"):
        run(obj, source="FACES")
    with pytest.raises(addon.AddonError, match="no source edges"):
        addon.compute_geodesic_distance(obj, selected="EDGES")


def test_select_within_geodesic_distance_grows_the_selection(addon):
    obj = ico_sphere(3)
    V = np.array([v.co for v in obj.data.vertices])
    pole = int(np.argmax(V[:, 2]))
    _select_elements(obj)  # nothing selected (edges and faces included), then the pole
    select_only(obj, [pole])
    d = addon.compute_geodesic_distance(obj, sources=[pole], attribute=None, color_attribute=None).distance
    with bpy.context.temp_override(active_object=obj, object=obj):
        assert not bpy.ops.mesh.heat_geodesic_select_within.poll()  # Edit Mode only
        bpy.ops.object.mode_set(mode="EDIT")
        try:
            assert bpy.ops.mesh.heat_geodesic_select_within(distance=0.8) == {"FINISHED"}
        finally:
            bpy.ops.object.mode_set(mode="OBJECT")
    selected = np.array([v.select for v in obj.data.vertices])
    np.testing.assert_array_equal(np.flatnonzero(selected), np.flatnonzero(d <= 0.8))
    assert 1 < selected.sum() < len(selected)
    assert "geodesic_distance" not in obj.data.attributes  # only the selection changed
    from test_blender_menus import draw, operators

    with bpy.context.temp_override(active_object=obj, object=obj):
        bpy.ops.object.mode_set(mode="EDIT")
    try:
        log = draw(bpy.types.VIEW3D_MT_select_edit_mesh)
    finally:
        with bpy.context.temp_override(active_object=obj, object=obj):
            bpy.ops.object.mode_set(mode="OBJECT")
    (entry,) = operators(log, "mesh.heat_geodesic_select_within")
    assert entry[2]["text"] == "Within Geodesic Distance"
