"""heatcore.CoarsePreview: a fast, coarse answer on a clustered copy of a large mesh (the probe's drags)."""

import numpy as np
import pytest
from shapes import icosphere

import heatcore as hc


def great_circle(V, s):
    U = V / np.linalg.norm(V, axis=1, keepdims=True)
    return np.arccos(np.clip(U @ U[s], -1.0, 1.0))


def test_the_preview_is_coarse_but_close_on_a_sphere():
    V, F = icosphere(5)  # 10,242 vertices
    preview = hc.CoarsePreview(hc.TriangleMesh(V, F, refine=0), vertices=1500)
    assert 1000 < preview.n_clusters < 3000
    d = preview.distance([0])
    exact = great_circle(V, 0)
    assert np.isfinite(d).all()
    assert np.abs(d - exact).mean() < 0.02 * np.pi  # measured 0.5%
    assert np.abs(d - exact).max() < 0.08 * np.pi


def test_points_count_as_their_nearest_corner():
    V, F = icosphere(4)
    preview = hc.CoarsePreview(hc.TriangleMesh(V, F, refine=0), vertices=800)
    corner = F[7, 2]
    np.testing.assert_array_equal(preview.distance(points=([7], [[0.1, 0.2, 0.7]])), preview.distance([corner]))


def test_separate_parts_never_merge_and_unused_vertices_are_inf():
    V0, F0 = icosphere(3)
    V = np.vstack([V0, V0 + [2.001, 0, 0], [[9.0, 9.0, 9.0]]])  # two spheres 0.001 apart, one loose vertex
    F = np.vstack([F0, F0 + len(V0)])
    preview = hc.CoarsePreview(hc.TriangleMesh(V, F, refine=0), vertices=50)  # cells far larger than the gap
    d = preview.distance([0])
    assert np.isfinite(d[: len(V0)]).all() and np.isinf(d[len(V0):]).all()


def test_other_domains_are_refused():
    with pytest.raises(hc.UnsupportedDomainError, match="triangle meshes"):
        hc.CoarsePreview(hc.PolygonMesh(np.eye(3), [[0, 1, 2]]))
