"""Parts with no area (every face collinear or coincident) and face soups: a clear error or a right answer, fast.

Before: a million zero-area faces over 3,000 collinear vertices gave 31.9
where the answer is 1 at ``refine=0``, and took 233-292 s by default (the
part was refined by its vertex count into 4.5M vertices).
"""

import time
import warnings

import numpy as np
import pytest

import heatcore as hc
from heatcore.domains.flat_parts import flat_faces, flat_parts
from heatcore.errors import HeatcoreWarning, InvalidMeshError, InvalidSourceError


def collinear(n=3000):
    V = np.zeros((n, 3))
    V[:, 0] = np.arange(n)
    return V


def random_faces(n, m, seed=0):
    F = np.sort(np.random.default_rng(seed).choice(n, (m, 3)), axis=1)
    return F[(F[:, 0] != F[:, 1]) & (F[:, 1] != F[:, 2])]


def triangle_and_segment():
    """A right triangle (vertices 0-2) and, apart from it, a flat face on a line (vertices 3-5)."""
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [5, 0, 0], [6, 0, 0], [7, 0, 0]], float)
    return V, np.array([[0, 1, 2], [3, 4, 5]])


@pytest.mark.parametrize("refine", [0, "auto"])
def test_a_million_zero_area_faces_are_refused_within_seconds(refine):
    V, F = collinear(), random_faces(3000, 1_000_000)
    start = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", HeatcoreWarning)  # the duplicate faces
        with pytest.raises(InvalidMeshError, match="no area.*collinear or coincident"):
            hc.geodesic_distance(V, F, [0], refine=refine)
    assert time.perf_counter() - start < 30  # was 233-292 s (a generous bound: the CI box may be busy)


@pytest.mark.parametrize("F", [[[0, 1, 2], [0, 2, 3], [0, 3, 4]], [[i, i + 1, i + 2] for i in range(48)]])
def test_small_flat_fans_and_strips_are_refused(F):
    with pytest.raises(InvalidMeshError, match="no area"):
        hc.TriangleMesh(collinear(50), F)


def test_coincident_corners_are_flat():
    V = np.array([[0, 0, 0], [0, 0, 0], [0, 0, 0], [1, 0, 0]], float)
    with pytest.raises(InvalidMeshError, match="no area"):
        hc.TriangleMesh(V, [[0, 1, 2], [1, 2, 3]])


def test_a_flat_part_beside_a_surface_is_unreachable_with_a_warning():
    V, F = triangle_and_segment()
    with pytest.warns(HeatcoreWarning, match="ignored 1 faces on 3 vertices.*no area"):
        d = hc.geodesic_distance(V, F, [0], refine=0)
    np.testing.assert_allclose(d[:3], [0, 1, 1], atol=1e-12)
    assert np.isinf(d[3:]).all()


@pytest.mark.filterwarnings("ignore::heatcore.errors.HeatcoreWarning")
def test_a_source_on_a_flat_part_is_refused_with_the_reason():
    V, F = triangle_and_segment()
    solver = hc.HeatSolver(hc.TriangleMesh(V, F, refine=0))
    with pytest.raises(InvalidSourceError, match="vertex 4 lies on a part with no area"):
        solver.distance([4])
    with pytest.raises(InvalidSourceError, match="face 1 was ignored.*no area"):
        solver.distance(points=([1], [[0.2, 0.3, 0.5]]))


def test_a_vertex_shared_by_a_flat_face_and_a_surface_stays_a_source():
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [2, 0, 0], [3, 0, 0]], float)
    # face 1 is flat (on the x axis) and touches the triangle at vertex 1: one part, with area
    with warnings.catch_warnings():
        warnings.simplefilter("error", HeatcoreWarning)
        d = hc.geodesic_distance(V, [[0, 1, 2], [1, 3, 4]], [1], refine=0)
    assert np.isfinite(d).all()
    np.testing.assert_allclose(d[[0, 1, 2]], [1, 0, np.sqrt(2)], rtol=0.05)


@pytest.mark.filterwarnings("error::RuntimeWarning")  # no overflow or underflow reaches the user
@pytest.mark.parametrize("scale", [1e-200, 1e-100, 1.0, 1e100, 1e200])
def test_ordinary_triangles_at_any_scale_are_not_flat(scale):
    V = scale * np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 1e-6]], float)
    F = np.array([[0, 1, 2], [1, 3, 2]])
    assert not flat_faces(V, F).any()
    d = hc.geodesic_distance(V, F, [0], refine=0)
    np.testing.assert_allclose(d[1] / scale, 1.0, rtol=1e-9)


def test_a_sliver_inside_a_surface_is_kept():
    V = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [1, 1, 0]], float)
    F = np.array([[0, 1, 2], [0, 2, 3]])
    assert flat_faces(V, F).tolist() == [True, False]
    assert flat_parts(V, F, np.array([0, 0]), 1).tolist() == [False]
    assert flat_parts(V, F[::-1], np.array([0, 0]), 1).tolist() == [False]  # the flat face first or last


def test_a_dense_soup_is_refined_by_its_faces_not_its_vertices():
    """1M random faces on 3,000 points: refining by vertex count would make 16M faces; the budget counts faces."""
    V = np.random.default_rng(1).random((3000, 3))
    with pytest.warns(HeatcoreWarning, match="refined to at most 0 levels"):
        mesh = hc.TriangleMesh(V, random_faces(3000, 1_000_000))
    assert mesh.part_levels.tolist() == [0]
    assert mesh.operators.n_vertices == 3000
