"""PyMeshLab front end, with the real pymeshlab: the filter on a MeshSet and the command line."""

import numpy as np
import pymeshlab  # after conftest, which imports bpy first where present
import pytest
from conftest import load_shared_mesh, shared_mesh_path

import heatcore as hc
from heatcore.apps import meshlab
from heatcore.domains.sources import source_vertices
from heatcore.viz.colormap import colorize, to_uint8

SOURCES = [0, 100]


def spot_meshset():
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(str(shared_mesh_path("spot")))
    return ms


def select(ms, vertices):
    cond = " || ".join(f"(vi == {int(v)})" for v in vertices)
    ms.compute_selection_by_condition_per_vertex(condselect=cond)


def reference(ms, vertices=None, faces=None, refine="auto", weld=0.0, intent="one query", **kw):
    mesh = ms.current_mesh()
    V, F = mesh.vertex_matrix(), mesh.face_matrix()
    on = source_vertices(len(V), F, vertices, region=faces)  # one query: the parts the selection is on
    solver = hc.HeatSolver(hc.TriangleMesh(V, F, refine=refine, weld=weld, only_parts_of=on),
                           intent=intent, **kw)  # the filter answers one query
    return solver.distance(vertices, region=faces)


def colors_uint8(mesh):
    return np.round(mesh.vertex_color_matrix()[:, :3] * 255).astype(np.uint8)


@pytest.fixture(scope="module")
def spot_result():
    """One filter run on spot, shared by the checks that only read it."""
    ms = spot_meshset()
    select(ms, SOURCES)
    stats = meshlab.geodesic_distance_from_selection(ms, isolines=8)
    return ms, stats, reference(ms, SOURCES)


def test_shared_meshes_load_identically_in_pymeshlab():
    V, F = load_shared_mesh("spot")
    ms = spot_meshset()  # keep the MeshSet alive: its meshes are views into it
    mesh = ms.current_mesh()
    np.testing.assert_array_equal(mesh.vertex_matrix(), V)
    np.testing.assert_array_equal(mesh.face_matrix(), F)


def test_filter_writes_quality_attribute_and_colours(spot_result):
    ms, stats, d = spot_result
    mesh = ms.current_mesh()
    assert np.isfinite(d).all() and d.max() > 1.0
    np.testing.assert_array_equal(mesh.vertex_scalar_array(), d)
    np.testing.assert_array_equal(mesh.vertex_custom_scalar_attribute_array("heat_distance"), d)
    np.testing.assert_array_equal(stats["distance"], d)
    assert mesh.vertex_scalar_array()[SOURCES].tolist() == [0.0, 0.0]
    assert mesh.has_vertex_color()
    expected = to_uint8(colorize(d, "viridis", isolines=8))
    np.testing.assert_array_equal(colors_uint8(mesh), expected)
    assert len(np.unique(expected, axis=0)) > 100  # a real ramp, not one colour
    # the selection is the input's, untouched
    assert np.flatnonzero(mesh.vertex_selection_array()).tolist() == SOURCES


def test_filter_statistics(spot_result):
    ms, stats, d = spot_result
    assert stats["sources"] == 2 and stats["source_kind"] == "vertices"
    assert (stats["vertices"], stats["faces"], stats["polygons"]) == (2930, 5856, 0)
    assert (stats["reached"], stats["unreachable"]) == (2930, 0)
    assert stats["min"] == 0.0
    assert stats["max"] == pytest.approx(d.max(), rel=1e-12)
    assert stats["mean"] == pytest.approx(d.mean(), rel=1e-12)
    assert stats["attribute"] == "heat_distance" and stats["colormap"] == "viridis"
    sec = stats["seconds"]
    assert sec["total"] == pytest.approx(sec["setup"] + sec["distance"] + sec["write"], rel=1e-6)
    assert isinstance(stats["solver"], hc.HeatSolver)


def test_rerun_with_cached_solver_overwrites_results(spot_result):
    ms, stats, _ = spot_result
    ms.set_selection_none()
    select(ms, [7])
    again = meshlab.geodesic_distance_from_selection(ms, solver=stats["solver"], colormap="magma")
    mesh = ms.current_mesh()
    d = reference(ms, [7])
    np.testing.assert_array_equal(mesh.vertex_scalar_array(), d)
    np.testing.assert_array_equal(mesh.vertex_custom_scalar_attribute_array("heat_distance"), d)
    np.testing.assert_array_equal(colors_uint8(mesh), to_uint8(colorize(d, "magma")))
    assert again["solver"] is stats["solver"]
    assert again["seconds"]["setup"] < 0.1 * stats["seconds"]["setup"]
    # restore the shared fixture's state
    ms.set_selection_none()
    select(ms, SOURCES)
    meshlab.geodesic_distance_from_selection(ms, solver=stats["solver"], isolines=8)


def test_solver_of_another_mesh_is_refused(spot_result):
    _, stats, _ = spot_result
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(str(shared_mesh_path("fandisk")))
    select(ms, [0])
    with pytest.raises(hc.InvalidOptionError, match="another mesh"):
        meshlab.geodesic_distance_from_selection(ms, solver=stats["solver"])
    assert not ms.current_mesh().has_vertex_scalar()


def test_options_reach_the_solver():
    ms = spot_meshset()
    select(ms, [0])
    meshlab.geodesic_distance_from_selection(ms, m=4.0, robust=False, refine=0, boundary="neumann")
    d = reference(ms, [0], refine=0, m=4.0)
    plain = hc.HeatSolver(hc.TriangleMesh(*load_shared_mesh("spot"), robust=False, refine=0), m=4.0).distance([0])
    np.testing.assert_allclose(ms.current_mesh().vertex_scalar_array(), plain, rtol=0, atol=1e-12)
    assert np.abs(plain - d).max() > 1e-4  # robust=False really changed the operators


def test_solver_options_pass_through(tmp_path):
    ms = spot_meshset()
    select(ms, [0])
    stats = meshlab.geodesic_distance_from_selection(ms, refine=0, accuracy="high")
    assert stats["solver"].accuracy == "high"
    high = reference(ms, [0], refine=0, accuracy="high")
    np.testing.assert_array_equal(ms.current_mesh().vertex_scalar_array(), high)
    assert np.abs(high - reference(ms, [0], refine=0)).max() > 1e-4
    # and from the command line
    out = tmp_path / "out.ply"
    args = [str(shared_mesh_path("spot")), "--sources", "0", "--refine", "0", "--accuracy", "high", "-o", str(out)]
    assert meshlab.main(args) == 0
    _ms, mesh = reopen(out)
    np.testing.assert_array_equal(mesh.vertex_scalar_array(), high)


def test_no_selection_is_an_error_and_mesh_unchanged():
    ms = spot_meshset()
    mesh = ms.current_mesh()
    with pytest.raises(hc.InvalidSourceError, match="no selected vertices or faces"):
        meshlab.geodesic_distance_from_selection(ms)
    assert not mesh.has_vertex_scalar()
    assert not mesh.has_vertex_color()
    with pytest.raises(Exception, match="heat_distance"):  # no attribute was added either
        mesh.vertex_custom_scalar_attribute_array("heat_distance")


@pytest.mark.parametrize(
    "options, message",
    [
        ({"colormap": "jet"}, "unknown colormap"),
        ({"attribute": "q"}, "attribute name"),
        ({"attribute": "two words"}, "attribute name"),
        ({"isolines": 5, "colormap": "meshlab-turbo"}, "isolines need"),
        ({"unreachable": float("inf")}, "unreachable"),
        ({"m": -1.0}, "time factor"),
    ],
)
def test_bad_options_leave_mesh_unchanged(options, message):
    ms = spot_meshset()
    select(ms, [0])
    with pytest.raises(hc.InvalidOptionError, match=message):
        meshlab.geodesic_distance_from_selection(ms, refine=0, **options)
    assert not ms.current_mesh().has_vertex_scalar()


def test_selected_faces_are_a_source_region():
    ms = spot_meshset()
    ms.compute_selection_by_condition_per_face(condselect="(fi < 4)")
    stats = meshlab.geodesic_distance_from_selection(ms, refine=0)
    assert stats["source_kind"] == "faces" and stats["sources"] == 4
    d = reference(ms, faces=[0, 1, 2, 3], refine=0)
    np.testing.assert_array_equal(ms.current_mesh().vertex_scalar_array(), d)
    corners = np.unique(ms.current_mesh().face_matrix()[:4])
    assert (d[corners] == 0).all() and (d > 0).sum() == d.size - corners.size


def test_unreachable_vertices_get_the_sentinel():
    # two separate tetrahedra: the second cannot be reached from vertex 0
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(np.r_[V, V + 5.0], np.r_[F, F + 4].astype(np.int32)))
    select(ms, [0])
    stats = meshlab.geodesic_distance_from_selection(ms, unreachable=-2.5)
    q = ms.current_mesh().vertex_scalar_array()
    assert (stats["reached"], stats["unreachable"]) == (4, 4)
    assert q[4:].tolist() == [-2.5] * 4
    assert q[0] == 0.0 and q[1] == pytest.approx(1.0, abs=0.05)
    assert np.isinf(stats["distance"][4:]).all()
    grey = to_uint8(np.array([hc.viz.colormap.UNREACHABLE_COLOR]))[0]
    assert (colors_uint8(ms.current_mesh())[4:] == grey).all()


def test_meshlab_ramp_and_no_colours():
    ms = spot_meshset()
    select(ms, [0])
    meshlab.geodesic_distance_from_selection(ms, refine=0, colormap="meshlab-turbo")
    c = colors_uint8(ms.current_mesh())
    q = ms.current_mesh().vertex_scalar_array()
    assert len(np.unique(c, axis=0)) > 50
    assert not np.array_equal(c[np.argmin(q)], c[np.argmax(q)])
    ms2 = spot_meshset()
    select(ms2, [0])
    meshlab.geodesic_distance_from_selection(ms2, refine=0, colormap="none")
    assert ms2.current_mesh().has_vertex_scalar() and not ms2.current_mesh().has_vertex_color()


# --------------------------------------------------------------------------- command line


def reopen(path):
    """(MeshSet, its current mesh) of a file; hold on to the MeshSet while using the mesh."""
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(str(path))
    return ms, ms.current_mesh()


def check_output(path, sources, isolines=0):
    """The PLY reopens in pymeshlab with quality = heatcore's distance, its colours, and the selection."""
    _ms, mesh = reopen(path)
    V, F = load_shared_mesh("spot")
    np.testing.assert_array_equal(mesh.vertex_matrix(), V)
    d = hc.HeatSolver(hc.TriangleMesh(V, F), intent="one query").distance(sources)  # the command: one query
    np.testing.assert_array_equal(mesh.vertex_scalar_array(), d)
    np.testing.assert_array_equal(colors_uint8(mesh), to_uint8(colorize(d, "viridis", isolines=isolines)))
    assert np.flatnonzero(mesh.vertex_selection_array()).tolist() == sorted(sources)


@pytest.fixture(scope="module")
def saved_selection(tmp_path_factory):
    """spot saved by pymeshlab as PLY with vertices 3 and 2000 selected (MeshLab's 'Flags')."""
    path = tmp_path_factory.mktemp("in") / "spot_selected.ply"
    ms = spot_meshset()
    select(ms, [3, 2000])
    ms.save_current_mesh(str(path), save_vertex_flag=True)
    return path


def test_cli_sources_from_saved_selection(saved_selection, tmp_path, capsys):
    out = tmp_path / "out.ply"
    assert meshlab.main([str(saved_selection), "-o", str(out), "--isolines", "6"]) == 0
    check_output(out, [3, 2000], isolines=6)
    text = capsys.readouterr().out
    assert "2 source vertices" in text and str(out) in text


def test_cli_sources_from_indices(tmp_path):
    # --sources replaces the file's selection; the output keeps exactly the sources selected
    out = tmp_path / "out.ply"
    spot = shared_mesh_path("spot")
    assert meshlab.main([str(spot), "--sources", "100", "0", "-o", str(out)]) == 0
    check_output(out, [0, 100])


def test_cli_sources_from_select_condition(tmp_path, capsys):
    out = tmp_path / "out.ply"
    V, _ = load_shared_mesh("spot")
    top = float(np.sort(V[:, 1])[-5])  # the 5 highest vertices (and ties)
    assert meshlab.main([str(shared_mesh_path("spot")), "--select", f"y >= {top!r}", "-o", str(out), "--json"]) == 0
    expected = np.flatnonzero(V[:, 1] >= top).tolist()
    assert len(expected) >= 5
    check_output(out, expected)
    assert f'"sources": {len(expected)},' in capsys.readouterr().out


def test_cli_default_output_name(saved_selection):
    out = saved_selection.with_name("spot_selected_distance.ply")
    assert meshlab.main([str(saved_selection), "--colormap", "none", "--refine", "0"]) == 0
    _ms, mesh = reopen(out)
    assert mesh.has_vertex_scalar()


@pytest.mark.parametrize(
    "extra, message",
    [
        ([], "no selected vertices or faces"),
        (["--select", "y > 1e9"], "selects no vertex"),
        (["--select", "y >>> 2"], "cannot evaluate"),
        (["--sources", "5000"], "out of range"),
        (["--refine", "lots"], "--refine"),
    ],
)
def test_cli_errors_write_no_file(tmp_path, capsys, extra, message):
    out = tmp_path / "out.ply"
    assert meshlab.main([str(shared_mesh_path("spot")), "-o", str(out), *extra]) == 2
    assert message in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


def test_cli_refuses_overwriting_input_and_missing_input(tmp_path, capsys, saved_selection):
    assert meshlab.main([str(saved_selection), "-o", str(saved_selection)]) == 2
    assert "overwrite the input" in capsys.readouterr().err
    assert meshlab.main([str(tmp_path / "missing.obj")]) == 2
    assert "does not exist" in capsys.readouterr().err


def test_polygon_input_is_triangulated_and_counted():
    # suzanne: 500 faces, quads and triangles, several connected components
    path = shared_mesh_path("suzanne")
    quads = sum(1 for line in path.read_text().splitlines() if line.startswith("f ") and len(line.split()) > 4)
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(str(path))
    select(ms, [0])
    # pymeshlab's triangulation of suzanne holds one duplicate triangle: heatcore drops it and says so.
    # Two of the eyes' vertices sit exactly on the head's: welded (the default), the eyes are reached
    # through them; weld=None keeps suzanne's three parts apart.
    with pytest.warns(hc.HeatcoreWarning, match="1 duplicate face"):
        welded = meshlab.geodesic_distance_from_selection(ms, refine=0)
    assert welded["unreachable"] == 0
    with pytest.warns(hc.HeatcoreWarning, match="1 duplicate face"):
        stats = meshlab.geodesic_distance_from_selection(ms, refine=0, weld=None)
    mesh = ms.current_mesh()
    # pymeshlab recovers 467 of suzanne's 468 quads as polygons (one comes back as two triangles)
    assert stats["polygons"] == sum(len(p) > 3 for p in mesh.polygonal_face_list())
    assert quads - 2 <= stats["polygons"] <= quads
    assert stats["faces"] == mesh.face_number() == 500 + quads  # each quad became two triangles
    with pytest.warns(hc.HeatcoreWarning, match="1 duplicate face"):
        d = reference(ms, [0], refine=0, weld=None)
    np.testing.assert_array_equal(stats["distance"], d)
    reached = np.isfinite(d)
    assert 0 < reached.sum() < d.size and stats["unreachable"] == d.size - reached.sum()
    np.testing.assert_array_equal(mesh.vertex_scalar_array(), np.where(reached, d, -1.0))
