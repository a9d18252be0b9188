"""Bad-input corpus: every case gives a typed, actionable error or a correct result."""

import warnings

import numpy as np
import pytest
from shapes import grid

import heatcore as hc

V0, F0 = grid(9, 9)


def distance(V, F, sources=(0,), **kw):
    return hc.geodesic_distance(V, F, list(sources), refine=0, **kw)


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_non_finite_coordinates(bad):
    V = V0.copy()
    V[7, 1] = bad
    with pytest.raises(hc.InvalidMeshError, match="vertex 7"):
        distance(V, F0)


@pytest.mark.parametrize(
    "F, message",
    [
        (np.r_[F0, [[0, 1, 900]]], "references vertex 900 but the mesh has 81 vertices"),
        (np.r_[F0, [[0, -1, 2]]], "references vertex -1"),
        (F0[:, :2], r"shape \(m, 3\)"),
        (F0.ravel(), r"shape \(m, 3\)"),
        (np.zeros((0, 3), int), "no faces"),
        (F0 + 0.5, "integer"),
        ([[0, 1, 2], [0, 1]], "ragged|shape"),
    ],
)
def test_bad_faces(F, message):
    with pytest.raises(hc.InvalidMeshError, match=message):
        distance(V0, F)


@pytest.mark.parametrize("V", [np.zeros((0, 3)), np.zeros((81, 4)), np.zeros(81), [["a", "b", "c"]] * 81])
def test_bad_vertex_arrays(V):
    with pytest.raises(hc.InvalidMeshError):
        distance(V, F0)


def test_two_dimensional_vertices_are_accepted():
    assert np.allclose(distance(V0[:, :2], F0), distance(V0, F0))


def test_integral_float_faces_are_accepted():
    assert np.allclose(distance(V0, F0.astype(float)), distance(V0, F0))


@pytest.mark.parametrize(
    "sources, message",
    [
        ([], "no source"),
        ([81], "out of range"),
        ([-1], "out of range"),
        ([0.5], "integers"),
    ],
)
def test_bad_sources(sources, message):
    with pytest.raises(hc.InvalidSourceError, match=message):
        distance(V0, F0, sources)


def test_unreferenced_vertex_as_source():
    V = np.vstack([V0, [[5, 5, 5]]])
    with pytest.raises(hc.InvalidSourceError, match="vertex 81 is not used by any face"):
        distance(V, F0, [81])


def test_bad_region_and_point_sources():
    with pytest.raises(hc.InvalidSourceError, match="not an edge"):
        hc.geodesic_distance(V0, F0, edges=[[0, 80]])
    with pytest.raises(hc.InvalidSourceError, match="out of range"):
        hc.geodesic_distance(V0, F0, region=[len(F0)])
    with pytest.raises(hc.InvalidSourceError, match="sum to 1"):
        hc.geodesic_distance(V0, F0, points=([0], [[0.5, 0.6, 0.1]]))
    with pytest.raises(hc.InvalidSourceError, match="barycentric coordinate rows"):
        hc.geodesic_distance(V0, F0, points=([0, 1], [[0.5, 0.5, 0.0]]))


def test_zero_area_and_duplicate_faces_are_handled():
    # a duplicate face, a face with a repeated vertex, a zero-area sliver face
    V = np.vstack([V0, [[0.0625, 0, 0]]])  # a point on the boundary edge 0-1 (collinear)
    F = np.vstack([F0, F0[:1], [[3, 3, 4]], [[0, 81, 1]]])
    with pytest.warns(hc.HeatcoreWarning, match="1 faces with repeated vertices and 1 duplicate"):
        d = hc.geodesic_distance(V, F, [40])
    euclid = np.linalg.norm(V - V[40], axis=1)
    clean = hc.geodesic_distance(V0, F0, [40])
    assert np.all(np.isfinite(d))
    rel = np.abs(d - euclid)[euclid > 0] / euclid[euclid > 0]
    rel_clean = np.abs(clean - euclid[:81])[euclid[:81] > 0] / euclid[:81][euclid[:81] > 0]
    assert rel.mean() < 0.03 and abs(rel.mean() - rel_clean.mean()) < 0.005


def test_collapsed_mesh_is_rejected():
    with pytest.raises(hc.InvalidMeshError, match="zero length"):
        distance(np.zeros((3, 3)), [[0, 1, 2]])


def test_non_manifold_edge_gives_finite_distances():
    # three sheets sharing the edge (0, 1)
    V = np.array([[0, 0, 0], [0, 1, 0], [1, 0.5, 0], [-1, 0.5, 0], [0, 0.5, 1]], float)
    F = np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4]])
    d = hc.geodesic_distance(V, F, [2])
    assert np.all(np.isfinite(d))
    assert abs(d[0] - np.linalg.norm(V[2] - V[0])) < 0.02
    # from vertex 2 to 3 and 4: around through the shared edge (via the closer endpoint)
    assert d[3] == pytest.approx(2.0, rel=0.02)  # unfolded across the shared edge


def test_non_manifold_vertex_bowtie():
    V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [-1, 0, 0], [-1, -1, 0]], float)
    d = hc.geodesic_distance(V, [[0, 1, 2], [0, 3, 4]], [2])
    assert np.all(np.isfinite(d)) and not np.any(np.isnan(d))
    assert d[3] == pytest.approx(np.sqrt(2) + 1, rel=0.03)


@pytest.mark.parametrize("scale", [1e-6, 1e6])
def test_results_scale_exactly(scale):
    V, F = grid(15, 15, jitter=0.3)
    d1 = hc.geodesic_distance(V, F, [0, 100])
    ds = hc.geodesic_distance(V * scale, F, [0, 100])
    assert np.allclose(ds, d1 * scale, rtol=1e-9, atol=0)


def test_no_nan_on_degenerate_heavy_mesh():
    rng = np.random.default_rng(1)
    V, F = grid(12, 12)
    V = V.copy()
    V[rng.choice(len(V), 30, replace=False), 1] = V[0, 1]  # collapse many triangles
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hc.HeatcoreWarning)
        for robust in (True, False):
            d = hc.geodesic_distance(V, F, [5], robust=robust)
            assert not np.any(np.isnan(d)) and np.all(d >= 0)


def test_bad_refine_option():
    with pytest.raises(hc.InvalidOptionError):
        hc.TriangleMesh(V0, F0, refine=-1)
    with pytest.raises(hc.InvalidOptionError):
        hc.TriangleMesh(V0, F0, refine="many")
