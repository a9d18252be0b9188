"""Several pinned vertices in the Poisson step (a point source pins its face's corners): the two ways that
save solves give what one solve per pin gives.

On the supernodal backend the pins cost one solve in all (the factor's two halves,
``PinnedPoisson._solve_in_halves``); on the others the unit responses of recently pinned vertices
are kept (``heatcore.steps.column_cache``). Both are checked against the plain path (a full solve per pin)
on the same factorization, with pins in two parts of a mesh and a pin on a ground vertex.
"""

import numpy as np
import pytest

import heatcore as hc
from heatcore.steps import column_cache


def two_spheres():
    V, F = hc.io.load_demo_mesh()
    return np.vstack([V, V + [3.0, 0.0, 0.0]]), np.vstack([F, F + len(V)])


F_DEMO = hc.io.load_demo_mesh()[1]
SOURCES = [
    {"points": ([5, 900], [[0.2, 0.3, 0.5], [0.6, 0.2, 0.2]])},  # a point in each part
    {"points": ([5], [[0.2, 0.3, 0.5]]), "vertices": [0]},       # vertex 0: the ground of its part
    {"region": [10, 11, 12, 13]},                                 # a few faces: 8 pins in one part
    {"edges": [F_DEMO[0, :2].tolist()]},
]


def plain(solver, sources):
    """The distance with one full solve per pin (the path without halves or kept responses)."""
    factor, responses = solver.poisson.factor, solver.poisson._responses
    solver.poisson.factor = type("Plain", (), {"solve": factor.solve})()  # no forward/backward halves
    saved = column_cache.COLUMN_CACHE_MB, column_cache.MIN_CACHED_COLUMNS
    column_cache.COLUMN_CACHE_MB, column_cache.MIN_CACHED_COLUMNS = 0, 0
    solver.poisson._responses = column_cache.ColumnCache(responses.rows)
    try:
        return solver.distance(**sources)
    finally:
        solver.poisson.factor, solver.poisson._responses = factor, responses
        column_cache.COLUMN_CACHE_MB, column_cache.MIN_CACHED_COLUMNS = saved


@pytest.mark.parametrize("backend", ["supernodal", "qdldl"])
def test_pins_with_halves_or_kept_responses_equal_one_solve_per_pin(backend):
    V, F = two_spheres()
    solver = hc.HeatSolver(hc.TriangleMesh(V, F, refine=1), backend=backend)
    assert solver.n_components == 2
    has_halves = hasattr(solver.poisson.factor, "forward")
    assert has_halves == (backend == "supernodal")
    for sources in SOURCES:
        expected = plain(solver, sources)
        for _ in range(2):  # the second time with the responses kept (qdldl)
            d = solver.distance(**sources)
            np.testing.assert_allclose(d, expected, rtol=1e-9, atol=1e-12 * np.nanmax(expected[np.isfinite(expected)]))
            np.testing.assert_array_equal(np.isinf(d), np.isinf(expected))


def test_the_pins_cost_what_was_promised():
    V, F = hc.io.load_demo_mesh()
    point = {"points": ([5], [[0.2, 0.3, 0.5]])}
    solver = hc.HeatSolver(hc.TriangleMesh(V, F, refine=0), backend="supernodal")
    full_solves = []
    solve = solver.poisson.factor._solve
    solver.poisson.factor._solve = lambda b: full_solves.append(b.shape) or solve(b)
    solver.distance(**point)
    assert full_solves == []  # forward (dense, and sparse per pin) and one backward: no full solve
    solver = hc.HeatSolver(hc.TriangleMesh(V, F, refine=0), backend="qdldl")
    solved = []
    units = solver.poisson._solve_units
    solver.poisson._solve_units = lambda vertices: solved.append(vertices.tolist()) or units(vertices)
    solver.distance(**point)
    solver.distance(**point)  # the same corners: their responses are kept
    solver.distance(points=([6], [[0.2, 0.3, 0.5]]))  # a neighbouring face: only its new corners
    assert len(solved) == 2 and len(solved[0]) == 3
    assert not set(solved[1]) & set(solved[0]) and len(solved[1]) < 3


def test_the_kept_responses_stay_within_their_memory(monkeypatch):
    monkeypatch.setattr(column_cache, "COLUMN_CACHE_MB", 1)
    V, F = hc.io.load_demo_mesh()
    solver = hc.HeatSolver(hc.TriangleMesh(V, F, refine=0), backend="qdldl")
    keep = max(column_cache.MIN_CACHED_COLUMNS, column_cache.COLUMN_CACHE_MB * 2**20 // (8 * len(V)))
    assert keep == 44 == solver.poisson._responses.keep < column_cache.MAX_CACHED_COLUMNS
    for face in range(0, 3 * keep, 3):
        solver.distance(points=([face], [[1 / 3, 1 / 3, 1 / 3]]))
    assert len(solver.poisson._responses) == keep
    assert set(F[3 * keep - 3]) <= set(solver.poisson._responses)  # the last pinned are kept


def test_a_dragged_point_reuses_the_forward_halves_of_its_corners():
    V, F = hc.io.load_demo_mesh()
    solver = hc.HeatSolver(hc.TriangleMesh(V, F, refine=0), backend="supernodal")
    fresh = hc.HeatSolver(hc.TriangleMesh(V, F, refine=0), backend="supernodal")
    halves = []
    compute = solver.poisson._forward_halves
    solver.poisson._forward_halves = lambda vertices: halves.append(vertices.tolist()) or compute(vertices)
    first, second = ([5], [[0.2, 0.3, 0.5]]), ([6], [[0.2, 0.3, 0.5]])  # faces 5 and 6 share corners
    d1 = solver.distance(points=first)
    d2 = solver.distance(points=first)
    d3 = solver.distance(points=second)
    assert len(halves) == 2 and len(halves[0]) == 3  # the same face again: nothing new
    assert not set(halves[1]) & set(halves[0]) and len(halves[1]) < 3  # the next face: its new corners only
    for d, point in ((d1, first), (d2, first), (d3, second)):
        np.testing.assert_allclose(d, fresh.distance(points=point), rtol=1e-12, atol=1e-14)
