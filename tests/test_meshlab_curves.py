"""Isoline curves as an edge-mesh layer of a pymeshlab MeshSet (real pymeshlab)."""

import numpy as np
import pymeshlab  # after conftest, which imports bpy first where present
import pytest
from conftest import shared_mesh_path

import heatcore as hc
from heatcore.apps import meshlab
from heatcore.apps.meshlab_curves import geodesic_path_layer, isoline_curves_layer


def grid(n=21):
    """A flat grid over [-1, 1]^2 with the exact distance from its centre as vertex quality."""
    x = np.linspace(-1.0, 1.0, n)
    X, Y = np.meshgrid(x, x)
    V = np.column_stack([X.ravel(), Y.ravel(), np.zeros(n * n)])
    i = np.arange(n - 1)
    a = (i[:, None] * n + i[None, :]).ravel()
    F = np.vstack([np.column_stack([a, a + 1, a + n + 1]), np.column_stack([a, a + n + 1, a + n])]).astype(np.int32)
    d = np.linalg.norm(V[:, :2], axis=1)
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(V, F, v_scalar_array=d), "grid")
    return ms, V, F, d


def test_grid_circles_are_closed_chains_at_their_levels():
    ms, V, F, d = grid()
    out = isoline_curves_layer(ms, levels=[0.3, 0.6, 0.9])
    assert ms.mesh_number() == 2 and ms.current_mesh().id() == 0  # the surface stays current
    assert (out["curves"], out["closed"]) == (3, 3)
    layer = ms.mesh(out["id"])
    P, E = layer.vertex_matrix(), layer.edge_matrix()
    assert layer.face_number() == 0 and (len(P), len(E)) == (out["points"], out["edges"])
    expected = hc.isolines(V, F, d, [0.3, 0.6, 0.9])
    np.testing.assert_array_equal(P, np.vstack([c.points for c in expected]))
    assert len(E) == len(P)  # closed: one edge per point
    for c in expected:
        a, b = c.edges.T
        np.testing.assert_allclose((1 - c.t) * d[a] + c.t * d[b], c.level, atol=1e-12)
        # on the grid the interpolated circle lies within the chord error of the true one
        np.testing.assert_allclose(np.linalg.norm(c.points[:, :2], axis=1), c.level, atol=0.01)
    # every point has two edges (closed chains), edges join points of the same curve
    np.testing.assert_array_equal(np.bincount(E.ravel(), minlength=len(P)), 2)
    assert np.linalg.norm(P[E[:, 0]] - P[E[:, 1]], axis=1).max() < 0.15


def test_spacing_open_curves_and_unreachable():
    ms, V, F, d = grid()
    q = d.copy()
    q[V[:, 0] > 0.5] = -1.0  # the filter's unreachable marker
    ms.add_mesh(pymeshlab.Mesh(V, F, v_scalar_array=q), "cut")
    out = isoline_curves_layer(ms, spacing=0.4, name="iso", set_as_current=True)
    assert ms.current_mesh().id() == out["id"] and ms.current_mesh().vertex_number() == out["points"]
    assert out["levels"] == pytest.approx([0.4, 0.8, 1.2])
    P = ms.current_mesh().vertex_matrix()
    assert P[:, 0].max() <= 0.5 + 1e-12  # the curves end where the distance is unreachable
    assert out["closed"] == 1  # r = 0.4 stays inside x <= 0.5; the others are cut open
    assert out["edges"] == out["points"] - (out["curves"] - out["closed"])


def test_after_the_filter_on_spot_from_its_attribute():
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(str(shared_mesh_path("spot")))
    ms.compute_selection_by_condition_per_vertex(condselect="vi == 0")
    meshlab.geodesic_distance_from_selection(ms, isolines=8)
    mesh = ms.current_mesh()
    d = mesh.vertex_custom_scalar_attribute_array("heat_distance")
    out = isoline_curves_layer(ms, levels=8, attribute="heat_distance")
    expected = hc.isolines(mesh.vertex_matrix(), mesh.face_matrix(), d, 8)
    assert out["curves"] == len(expected) >= 8
    assert out["levels"] == pytest.approx(hc.contours.isoline_levels(d, 8).tolist())
    np.testing.assert_array_equal(ms.mesh(out["id"]).vertex_matrix(), np.vstack([c.points for c in expected]))


def test_bad_spacing_adds_nothing():
    ms, *_ = grid(5)
    with pytest.raises(hc.errors.InvalidOptionError, match="spacing"):
        isoline_curves_layer(ms, spacing=0.0)
    assert ms.mesh_number() == 1


def test_the_layer_saves_as_obj_polylines(tmp_path):
    ms, *_ = grid(9)
    out = isoline_curves_layer(ms, levels=2, set_as_current=True)
    ms.save_current_mesh(str(tmp_path / "iso.obj"))
    lines = (tmp_path / "iso.obj").read_text().splitlines()
    E = np.array([[int(i) - 1 for i in line.split()[1:]] for line in lines if line.startswith("l ")])
    np.testing.assert_array_equal(E, ms.current_mesh().edge_matrix())
    assert sum(line.startswith("v ") for line in lines) == out["points"]


def test_geodesic_path_layer_is_the_path_as_a_chain_and_exact_on_spot():
    gdist = pytest.importorskip("gdist")
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(str(shared_mesh_path("spot")))
    mesh = ms.current_mesh()
    V, F = mesh.vertex_matrix(), mesh.face_matrix()
    # the pair where potpourri3d's edge flip is 4.7% long (docs/paths.md)
    ms.compute_selection_by_condition_per_vertex(condselect="(vi == 1706) || (vi == 2473)")
    out = geodesic_path_layer(ms)
    assert (out["source"], out["target"]) == (1706, 2473) and ms.current_mesh().id() == 0  # surface current
    layer = ms.mesh(out["id"])
    np.testing.assert_allclose(layer.vertex_matrix(), out["path"].points)
    assert layer.edge_matrix().tolist() == [[i, i + 1] for i in range(out["points"] - 1)]
    exact = gdist.compute_gdist(V.astype(np.float64), F.astype(np.int32), np.array([1706], np.int32),
                                np.array([2473], np.int32))[0]
    assert exact * (1 - 1e-9) <= out["length"] <= exact * 1.001


def test_geodesic_path_layer_refuses_a_selection_that_is_not_two_vertices():
    ms, V, F, d = grid()
    with pytest.raises(hc.errors.InvalidSourceError, match="select exactly two vertices"):
        geodesic_path_layer(ms)
    with pytest.raises(hc.errors.InvalidSourceError, match="give both"):
        geodesic_path_layer(ms, 3)
    assert ms.mesh_number() == 1
