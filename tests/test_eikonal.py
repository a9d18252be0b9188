"""accuracy="high": the heat-ordered eikonal refinement (heatcore.eikonal)."""


import numpy as np
import pytest
from conftest import exact_distance, load_shared_mesh, mean_relative_error
from shapes import grid

import heatcore as hc
from heatcore import eikonal, fast_marching

MESHES = ["spot", "homer", "fandisk", "cheburashka", "rocker-arm", "nefertiti", "stanford-bunny"]


@pytest.fixture(autouse=True, params=["march", "bands"])
def eikonal_pass(request, monkeypatch):
    """Every test runs twice: with the compiled fast marching (numba) and with the vectorized pass (without it)."""
    if request.param == "march":
        assert fast_marching.available(), "numba is missing: pip install -e '.[fast]'"
    else:
        monkeypatch.setattr(fast_marching, "available", lambda: False)
    return request.param


def three_sources(F):
    rng = np.random.default_rng(0)
    return rng.choice(np.unique(F), 3, replace=False)


def sheared_lattice(nx, ny, spacing=0.2):
    """A parallelogram (convex) whose every triangle has a 136 degree angle."""
    j, i = np.meshgrid(np.arange(ny), np.arange(nx), indexing="ij")
    V = np.column_stack([(i + 0.5 * j).ravel(), (spacing * j).ravel(), np.zeros(i.size)]).astype(float)
    a = (j[:-1, :-1] * nx + i[:-1, :-1]).ravel()
    F = np.concatenate([np.stack([a, a + 1, a + nx], 1), np.stack([a + 1, a + nx + 1, a + nx], 1)])
    return V, F


def max_angle(V, F):
    P = V[F]
    cos = []
    for k in range(3):
        u, w = P[:, (k + 1) % 3] - P[:, k], P[:, (k + 2) % 3] - P[:, k]
        cos.append(np.sum(u * w, 1) / np.linalg.norm(u, axis=1) / np.linalg.norm(w, axis=1))
    return np.degrees(np.arccos(np.min(cos, axis=0)))


# --- the triangle update -------------------------------------------------------------------------


def test_triangle_update_exact_on_a_flat_triangle_never_below_otherwise():
    rng = np.random.default_rng(1)
    k = 20000
    A = np.zeros((k, 2))
    B = np.column_stack([rng.uniform(0.5, 2.0, k), np.zeros(k)])
    C = np.column_stack([rng.uniform(-1.0, 3.0, k), rng.uniform(0.05, 1.5, k)])  # many obtuse
    S = np.column_stack([rng.uniform(-8, 8, k), rng.uniform(-8, 8, k)])  # either side of AB
    dist = lambda P: np.linalg.norm(P - S, axis=1)  # noqa: E731
    c = B[:, 0]
    ca, cb = dist(A) * 0 + np.linalg.norm(C - A, axis=1), np.linalg.norm(C - B, axis=1)
    got = eikonal.triangle_update(dist(A), dist(B), c, C[:, 0], C[:, 1], ca, cb)
    true = dist(C)
    # never an underestimate, whatever side the source is on and however obtuse the triangle
    assert np.all(got >= true - 1e-12 * true.max())
    # exact when the source lies below AB and the segment S->C crosses AB between A and B
    below = S[:, 1] < 0
    cross = S[:, 0] + (C[:, 0] - S[:, 0]) * (-S[:, 1]) / (C[:, 1] - S[:, 1])
    through = below & (cross > 1e-9) & (cross < c - 1e-9)
    assert through.sum() > 1000
    np.testing.assert_allclose(got[through], true[through], rtol=1e-12, atol=1e-12)
    # otherwise the edge (path) updates: at most the shorter path through A or B
    np.testing.assert_array_less(got[~through], np.minimum(dist(A) + ca, dist(B) + cb)[~through] + 1e-12)


def test_triangle_update_unknown_vertices():
    got = eikonal.triangle_update(np.array([np.inf, 1.0, np.inf]), np.array([2.0, np.inf, np.inf]), 1.0, 0.5, 1.0, 1.2, 1.3)
    np.testing.assert_allclose(got, [3.3, 2.2, np.inf])


# --- flat meshes: the refined distance is the Euclidean distance -------------------------------------


@pytest.mark.parametrize("robust", [False, True])
@pytest.mark.parametrize("refine", [0, 1])
def test_flat_jittered_grid_is_exact(robust, refine):
    V, F = grid(25, 25, jitter=0.35)  # about half of the triangles are obtuse, up to ~180 degrees
    assert (max_angle(V, F) > 90).mean() > 0.4
    solver = hc.HeatSolver(hc.TriangleMesh(V, F, robust=robust, refine=refine), accuracy="high")
    smooth = hc.HeatSolver(hc.TriangleMesh(V, F, robust=robust, refine=refine))
    for s in [0, 312, 624]:
        exact = np.linalg.norm(V - V[s], axis=1)
        d = solver.distance([s])
        assert np.abs(d - exact).max() <= 1e-5 * exact.max()
        assert np.abs(d - exact).mean() <= 1e-7 * exact.max()
        assert np.abs(smooth.distance([s]) - exact).max() > 1e-3 * exact.max()  # the heat method is not


def test_flat_all_obtuse_lattice_is_exact():
    """Every triangle of the input obtuse (136 degrees); the update set keeps all of them."""
    V, F = sheared_lattice(30, 40)
    assert max_angle(V, F).min() > 130
    solver = hc.HeatSolver(hc.TriangleMesh(V, F, refine=0), accuracy="high")
    for s in [0, 15 + 30 * 20, len(V) - 1]:
        exact = np.linalg.norm(V - V[s], axis=1)
        d = solver.distance([s])
        assert np.abs(d - exact).max() <= 1e-5 * exact.max()
        assert np.all(d >= exact - 1e-12 * exact.max())


def test_relaxation_reaches_the_exact_distance_even_from_a_useless_order():
    """Plain cotan (robust=False) on the all-obtuse lattice: the heat distance is meaningless (its
    error is the size of the mesh), yet global relaxation sweeps converge to the exact distance."""
    V, F = sheared_lattice(30, 40)
    dom = hc.TriangleMesh(V, F, robust=False, refine=0)
    pins = dom.source_pins([0])
    phi = hc.HeatSolver(dom).distance_from_pins(pins)
    exact = np.linalg.norm(V - V[0], axis=1)
    assert np.abs(phi - exact).max() > 0.5 * exact.max()
    d = eikonal.refine_distance(dom, phi, pins, tol=1e-12, polish=100_000)
    np.testing.assert_allclose(d, exact, rtol=0, atol=1e-12 * exact.max())


def test_flat_surface_point_and_several_sources():
    V, F = grid(21, 21, jitter=0.3)
    solver = hc.HeatSolver(hc.TriangleMesh(V, F), accuracy="high")
    # a point inside face 100
    bary = np.array([[0.2, 0.5, 0.3]])
    p = bary[0] @ V[F[100]]
    d = solver.distance(points=([100], bary))
    exact = np.linalg.norm(V - p, axis=1)
    assert np.abs(d - exact).max() <= 1e-5 * exact.max()
    # two source vertices: the distance to the nearer one. Where the two vertices of a triangle
    # see different sources (at the bisector), the virtual source is no real source and the
    # update may undershoot a little, as in any fast marching: measured 4% of an edge at most.
    exact = np.minimum(np.linalg.norm(V - V[0], axis=1), np.linalg.norm(V - V[440], axis=1))
    d = solver.distance([0, 440])
    h = 1.0 / 20
    assert np.all(d >= exact - 0.1 * h)
    assert mean_relative_error(d, exact) < 1e-4


def test_unreachable_vertices_stay_infinite():
    V, F = grid(10, 10)
    V2 = np.vstack([V, V + [20.0, 0, 0]])
    F2 = np.vstack([F, F + len(V)])
    d = hc.HeatSolver(hc.TriangleMesh(V2, F2), accuracy="high").distance([3])
    assert np.all(np.isfinite(d[: len(V)])) and np.all(np.isinf(d[len(V) :]))
    np.testing.assert_allclose(d[: len(V)], np.linalg.norm(V - V[3], axis=1), rtol=1e-5)


def test_refine_distance_contract():
    """Same length as phi, inf where phi is inf, pins keep their values, results never below 0."""
    V, F = load_shared_mesh("spot")
    dom = hc.TriangleMesh(V, F)
    pins = dom.source_pins([5, 900])
    phi = hc.HeatSolver(dom).distance_from_pins(pins)
    cut = np.setdiff1d(np.arange(len(phi) - 10, len(phi)), pins.vertices)
    phi_cut = phi.copy()
    phi_cut[cut] = np.inf
    d = eikonal.refine_distance(dom, phi_cut, pins)
    assert d.shape == phi.shape
    assert np.all(np.isinf(d[cut])) and np.isfinite(np.delete(d, cut)).all()
    np.testing.assert_array_equal(d[pins.vertices], pins.values)
    assert d.min() == 0.0


# --- the shared meshes: <= 0.5% mean relative error with 3 sources each ---------------------------


@pytest.fixture(scope="module")
def nefertiti():
    V, F = load_shared_mesh("nefertiti")
    dom = hc.TriangleMesh(V, F)
    return V, F, dom, hc.HeatSolver(dom), hc.HeatSolver(dom, accuracy="high")


@pytest.mark.parametrize("name", MESHES)
def test_high_accuracy_on_shared_meshes(name, request):
    if name == "nefertiti":
        V, F, _, smooth, high = request.getfixturevalue("nefertiti")
    else:
        V, F = load_shared_mesh(name)
        dom = hc.TriangleMesh(V, F)
        smooth, high = hc.HeatSolver(dom), hc.HeatSolver(dom, accuracy="high")
    errs_high, errs_smooth = [], []
    for s in three_sources(F):
        exact = exact_distance(V, F, s)
        d = high.distance([s])
        assert np.array_equal(np.isinf(d), np.isinf(exact))
        errs_high.append(mean_relative_error(d, exact))
        errs_smooth.append(mean_relative_error(smooth.distance([s]), exact))
    # measured (docs/accuracy-high.md): 0.10% (nefertiti) to 0.27% (cheburashka); the README states 0.1-0.3%
    assert np.mean(errs_high) <= 0.003
    assert max(errs_high) <= 0.005
    assert np.mean(errs_high) < 0.4 * np.mean(errs_smooth)


def test_high_accuracy_with_several_sources_at_once():
    V, F = load_shared_mesh("homer")
    s = three_sources(F)
    exact = exact_distance(V, F, s)
    d = hc.HeatSolver(hc.TriangleMesh(V, F), accuracy="high").distance(s)
    assert mean_relative_error(d, exact) <= 0.005

