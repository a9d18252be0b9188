"""HeatSolver behaviour: analytic distances, sources, components, options."""

import numpy as np
import pytest
from shapes import grid, icosphere

import heatcore as hc


def relative_error(d, exact, mask=None):
    mask = (exact > 0) if mask is None else mask & (exact > 0)
    return float(np.mean(np.abs(d[mask] - exact[mask]) / exact[mask]))


def test_sphere_great_circle_distance():
    V, F = icosphere(4)  # 2562 vertices, auto-refined once
    d = hc.geodesic_distance(V, F, [0])
    exact = np.arccos(np.clip(V @ V[0], -1, 1))
    assert relative_error(d, exact) < 0.007  # measured 0.54%


def test_plane_with_hole_matches_euclidean_where_visible():
    V, F = grid(41, 41, 2.0)
    V[:, :2] -= 1.0
    F = F[np.linalg.norm(V[F].mean(axis=1)[:, :2], axis=1) > 0.35]
    source = int(np.argmin(np.linalg.norm(V[:, :2] - [-0.8, 0.1], axis=1)))
    d = hc.geodesic_distance(V, F, [source])
    p, q = V[source, :2], V[:, :2]
    seg = q - p
    s = np.clip(-(seg @ p) / np.maximum((seg * seg).sum(1), 1e-30), 0, 1)
    clearance = np.linalg.norm(p + s[:, None] * seg, axis=1)
    visible = clearance > 0.35 + 0.1
    euclid = np.linalg.norm(q - p, axis=1)
    assert relative_error(d, euclid, visible & np.isfinite(d)) < 0.015  # measured 1.2%
    # behind the hole the geodesic bends around it: longer than the straight line
    hidden = np.isfinite(d) & (clearance < 0.2) & (q[:, 0] > 0.5)
    assert hidden.any() and np.all(d[hidden] > euclid[hidden] * 1.005)
    # vertices inside the hole belong to no face
    inside = np.linalg.norm(q, axis=1) < 0.3
    assert np.all(np.isinf(d[inside]))


def test_boundary_conditions_all_give_distances():
    V, F = grid(31, 31)
    src = 31 * 15 + 15
    euclid = np.linalg.norm(V - V[src], axis=1)
    errors = {}
    for bc in ("robin", "neumann", "dirichlet"):
        d = hc.geodesic_distance(V, F, [src], boundary=bc)
        errors[bc] = relative_error(d, euclid)
        assert errors[bc] < 0.05
    assert errors["robin"] < errors["neumann"]  # the paper's recommendation pays off


def test_dirichlet_source_on_boundary_falls_back_to_neumann():
    V, F = grid(21, 21)
    d = hc.geodesic_distance(V, F, [0], boundary="dirichlet")
    euclid = np.linalg.norm(V - V[0], axis=1)
    assert np.all(np.isfinite(d)) and relative_error(d, euclid) < 0.03


def test_multiple_sources_each_sit_at_zero():
    V, F = grid(31, 31)
    sources = [0, 480, 960, 47]
    d = hc.geodesic_distance(V, F, sources)
    assert np.all(d[sources] == 0.0)
    euclid = np.min(np.linalg.norm(V[:, None] - V[sources][None], axis=2), axis=1)
    assert relative_error(d, euclid) < 0.03


def test_many_source_vertices_use_a_pinned_factorization():
    V, F = grid(41, 41)
    left = np.flatnonzero(V[:, 0] < 0.3)  # more pins than MAX_PRECOMPUTED_PINS
    assert left.size > hc.heat.MAX_PRECOMPUTED_PINS
    d = hc.geodesic_distance(V, F, left)
    exact = np.maximum(V[:, 0] - V[left, 0].max(), 0)
    assert np.all(d[left] == 0)
    assert relative_error(d, exact) < 0.02


def test_face_point_source_is_euclidean_on_a_plane():
    V, F = grid(31, 31)
    f, bary = 400, np.array([0.2, 0.3, 0.5])
    p = bary @ V[F[f]]
    d = hc.geodesic_distance(V, F, points=([f], [bary]))
    euclid = np.linalg.norm(V - p, axis=1)
    assert np.allclose(d[F[f]], euclid[F[f]], rtol=1e-12)
    assert relative_error(d, euclid) < 0.02


def test_edge_and_face_region_sources():
    V, F = grid(31, 31)
    bottom = np.flatnonzero(V[:, 1] == 0)
    bottom = bottom[np.argsort(V[bottom, 0])]
    edges = np.stack([bottom[:-1], bottom[1:]], 1)
    d = hc.geodesic_distance(V, F, edges=edges)
    assert np.all(d[bottom] == 0)
    assert relative_error(d, V[:, 1]) < 0.01
    low = np.flatnonzero(V[F].mean(axis=1)[:, 1] < 0.2)
    d = hc.geodesic_distance(V, F, region=low)
    top = V[F[low]][:, :, 1].max()
    assert relative_error(d, np.maximum(V[:, 1] - top, 0)) < 0.01


def test_sources_on_refined_coarse_mesh_keep_exact_values():
    """A 2-triangle square is refined automatically; region and point sources follow."""
    V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)
    F = np.array([[0, 1, 2], [0, 2, 3]])
    d = hc.geodesic_distance(V, F, edges=[[0, 1]])
    assert np.allclose(d, [0, 0, 1, 1], atol=0.01)
    d = hc.geodesic_distance(V, F, points=([0], [[1 / 3, 1 / 3, 1 / 3]]))
    centroid = V[F[0]].mean(axis=0)
    assert np.allclose(d[:3], np.linalg.norm(V[:3] - centroid, axis=1))
    assert abs(d[3] - np.linalg.norm(V[3] - centroid)) < 0.02


def test_single_triangle_gives_edge_lengths():
    V = np.array([[0, 0, 0], [3, 0, 0], [0, 1, 0]], float)
    d = hc.geodesic_distance(V, [[0, 1, 2]], [1])
    assert np.allclose(d, [3, 0, np.sqrt(10)], rtol=0.02)


def test_components_and_unreferenced_vertices_get_inf():
    V1, F1 = grid(11, 11)
    V2, F2 = grid(11, 11)
    V = np.vstack([V1, V2 + [5, 0, 0], [[9, 9, 9]]])
    F = np.vstack([F1, F2 + len(V1)])
    d = hc.geodesic_distance(V, F, [0])
    assert np.all(np.isfinite(d[: len(V1)])) and np.all(np.isinf(d[len(V1) :]))
    both = hc.geodesic_distance(V, F, [0, len(V1)])
    assert np.allclose(both[: len(V1)], both[len(V1) : 2 * len(V1)])
    assert np.isinf(both[-1])


def test_solver_reuses_factorizations_across_queries(monkeypatch):
    V, F = grid(21, 21)
    solver = hc.HeatSolver(hc.TriangleMesh(V, F))
    calls = []
    monkeypatch.setattr(hc.steps.factors, "factor", lambda *a, **k: calls.append(1))
    for s in (0, 5, 100):
        assert np.isfinite(solver.distance([s])).all()
    solver.distance([0, 1, 2])
    assert calls == []


def test_smoothed_distance_with_large_m_stays_a_distance(spot):
    from conftest import exact_distance

    V, F = spot
    exact = exact_distance(V, F, 0)
    mesh = hc.TriangleMesh(V, F)
    errors = [relative_error(hc.HeatSolver(mesh, m=m).distance([0]), exact) for m in (1, 10, 100)]
    # measured 1.3%, 2.4%, 6.0%: smoothing trades accuracy for smoothness, gradually
    assert errors[0] < 0.015 and errors[0] < errors[1] < errors[2] < 0.08


@pytest.mark.parametrize("backend", hc.linalg.available_backends())
def test_backends_agree(backend):
    V, F = grid(21, 21)
    mesh = hc.TriangleMesh(V, F, refine=1)
    a = hc.HeatSolver(mesh, backend=backend).distance([3, 50])
    b = hc.HeatSolver(mesh, backend="superlu").distance([3, 50])
    assert np.allclose(a, b, rtol=1e-8, atol=1e-12)


@pytest.mark.skipif(
    hc.linalg.metis.node_nd() is None or hc.linalg.libraries.optional("cvxopt") is None, reason="needs the scale extra"
)
def test_large_mesh_poisson_factor_uses_nested_dissection(monkeypatch):
    V, F = grid(31, 31)
    mesh = hc.TriangleMesh(V, F, refine=1)
    with_amd = hc.HeatSolver(mesh, backend="supernodal").distance([3, 500])
    monkeypatch.setattr(hc.linalg.ordering, "NESTED_DISSECTION_MIN_SIZE", 0)  # as on large meshes
    mesh = hc.TriangleMesh(V, F, refine=1)
    solver = hc.HeatSolver(mesh, backend="supernodal")
    cache = mesh.derived  # the domain's cache of what is derived from it
    nested, quick = cache["nested", "supernodal"], cache["ordering", "supernodal"]
    assert isinstance(nested, hc.linalg.Ordering) and not np.array_equal(nested.permutation, quick.permutation)
    assert np.allclose(solver.distance([3, 500]), with_amd, rtol=1e-9, atol=1e-12)
    # many pins: the pinned Laplacian is ordered by the same nested dissection
    many = np.arange(0, 961, 3)  # more than MAX_PRECOMPUTED_PINS
    assert np.allclose(solver.distance(many), hc.HeatSolver(mesh, backend="superlu").distance(many), atol=1e-9)


@pytest.mark.skipif(
    hc.linalg.metis.node_nd() is None or hc.linalg.libraries.optional("cvxopt") is None, reason="needs the scale extra"
)
def test_one_query_solvers_keep_minimum_degree(monkeypatch):
    """A solver built for one query does not wait for METIS: its Laplacian keeps the minimum degree ordering."""
    monkeypatch.setattr(hc.linalg.ordering, "NESTED_DISSECTION_MIN_SIZE", 0)  # as on large meshes
    V, F = grid(31, 31)
    mesh = hc.TriangleMesh(V, F, refine=1)
    solver = hc.HeatSolver(mesh, backend="supernodal", intent="one query")
    assert ("nested", "supernodal") not in mesh.derived and ("poisson", "supernodal") in mesh.derived
    for kept_for in ("reuse", "interactive"):  # further queries: nested dissection
        kept = hc.HeatSolver(hc.TriangleMesh(V, F, refine=1), backend="supernodal", intent=kept_for)
        assert isinstance(kept.domain.derived["nested", "supernodal"], hc.linalg.Ordering)
        assert np.allclose(solver.distance([3, 500]), kept.distance([3, 500]), rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize("option", [{"m": 0}, {"m": -1}, {"m": np.nan}, {"boundary": "x"}, {"accuracy": "x"}])
def test_bad_options_raise(option):
    V, F = grid(5, 5)
    with pytest.raises(hc.InvalidOptionError):
        hc.HeatSolver(hc.TriangleMesh(V, F), **option)
