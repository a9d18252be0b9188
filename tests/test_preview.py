"""heatcore.CoarsePreview: a fast, coarse answer on a clustered copy of a large mesh (the probe's drags)."""

import numpy as np
import pytest
from shapes import icosphere

import heatcore as hc
from heatcore.domains.polygon_shape import fan_triangulate
from heatcore.domains.polygon_triangulate import covering_triangles


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


def test_of_arrays_is_the_domain_preview_without_the_domain():
    V, F = icosphere(4)
    direct = hc.CoarsePreview.of_arrays(V, F, vertices=800)
    via_domain = hc.CoarsePreview(hc.TriangleMesh(V, F, refine=0), vertices=800)
    assert direct.n_clusters == via_domain.n_clusters
    np.testing.assert_array_equal(direct.cluster, via_domain.cluster)
    np.testing.assert_array_equal(direct.distance([3]), via_domain.distance([3]))
    exact = great_circle(V, 3)
    assert np.abs(direct.distance([3]) - exact).mean() < 0.03 * np.pi  # measured 1.8% of the half circumference


def test_of_arrays_previews_only_the_parts_of_its_sources():
    V0, F0 = icosphere(3)
    V = np.vstack([V0, V0 + [3.0, 0, 0], [[9.0, 9.0, 9.0]]])  # two spheres and a loose vertex
    F = np.vstack([F0, F0 + len(V0)])
    preview = hc.CoarsePreview.of_arrays(V, F, vertices=50, only_parts_of=[len(V0) + 4])
    alone = hc.CoarsePreview.of_arrays(V[len(V0) : -1], F0, vertices=50)
    d = preview.distance([len(V0) + 4])
    assert np.isinf(d[: len(V0)]).all() and np.isinf(d[-1])
    np.testing.assert_array_equal(d[len(V0) : -1], alone.distance([4]))  # the same cells: the cells of the kept part only
    # a point's face is the input's (the first sphere's faces are not built, but still counted)
    face = len(F0) + 11
    np.testing.assert_array_equal(preview.distance(points=([face], [[0.8, 0.1, 0.1]])), preview.distance([F[face, 0]]))


@pytest.mark.parametrize("V, F, match", [
    ([[0, 0, 0], [1, 0, 0], [np.nan, 1, 0]], [[0, 1, 2]], "NaN"),
    ([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 3]], "references vertex 3"),
])
def test_of_arrays_refuses_bad_arrays(V, F, match):
    with pytest.raises(hc.InvalidMeshError, match=match):
        hc.CoarsePreview.of_arrays(V, F)



def test_of_arrays_takes_polygons_as_the_triangles_covering_them():
    # a row of L-shaped hexagons whose fans from their first corner fold across the notch, and quads
    L = np.array([[2, 1], [1, 1], [1, 2], [0, 2], [0, 0], [2, 0]], float)  # from the corner beside the notch
    V, faces = [], []
    for k in range(30):
        base = len(V)
        V += [[x + 3 * k, y, 0.1 * k] for x, y in L]
        faces.append(list(range(base, base + 6)))
    quads = [[1, 7, 9, 3]]  # joins the first two L's: one part
    offsets = np.r_[0, np.cumsum([len(f) for f in faces + quads])]
    indices = np.concatenate(faces + quads)
    V = np.array(V)
    preview = hc.CoarsePreview.of_arrays(V, (offsets, indices), vertices=40)
    covering = covering_triangles(V, offsets, indices)
    np.testing.assert_array_equal(preview.triangles, covering)
    def area(triangles):  # of the L's: their 120 triangles come first
        return sum(np.linalg.norm(np.cross(V[b] - V[a], V[c] - V[a])) / 2 for a, b, c in triangles[:120])

    assert area(covering) == pytest.approx(30 * 3, rel=1e-9)  # each L's area, 3
    assert area(fan_triangulate(offsets, indices)[0]) > 30 * 3 + 29  # a fan covers the notch too (and folds)
    np.testing.assert_array_equal(preview.distance([0]),
                                  hc.CoarsePreview.of_arrays(V, covering, vertices=40).distance([0]))
