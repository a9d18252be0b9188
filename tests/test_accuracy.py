"""Accuracy of the default solver against exact geodesics (MMP, gdist) and potpourri3d."""

import numpy as np
import pytest
from conftest import exact_distance, load_shared_mesh, mean_relative_error

import heatcore as hc

# Measured mean relative errors with default settings (docs/accuracy.md) are
# spot 1.23%, homer 1.49%, fandisk 0.84%, cheburashka 1.19%, rocker-arm 1.63%,
# nefertiti 0.76%, stanford-bunny 0.80%; the thresholds leave a small margin
# below the 2.0% requirement.
THRESHOLDS = {
    "spot": 0.015,
    "homer": 0.017,
    "fandisk": 0.011,
    "cheburashka": 0.015,
    "rocker-arm": 0.019,
    "nefertiti": 0.010,
    "stanford-bunny": 0.011,
}
POTPOURRI_CRASHES = {"stanford-bunny"}  # it asserts on unreferenced vertices


def three_sources(F):
    rng = np.random.default_rng(0)
    return rng.choice(np.unique(F), 3, replace=False)


@pytest.mark.parametrize("name", sorted(THRESHOLDS))
def test_default_accuracy_against_exact_and_potpourri(name):
    V, F = load_shared_mesh(name)
    solver = hc.HeatSolver(hc.TriangleMesh(V, F))
    sources = three_sources(F)
    exact = [exact_distance(V, F, s) for s in sources]
    ours = np.mean([mean_relative_error(solver.distance([s]), e) for s, e in zip(sources, exact)])
    assert ours <= THRESHOLDS[name] <= 0.02
    if name not in POTPOURRI_CRASHES:
        import potpourri3d as pp3d
        peer = pp3d.MeshHeatMethodDistanceSolver(V, F, t_coef=1.0, use_robust=True)
        theirs = np.mean([mean_relative_error(peer.compute_distance(int(s)), e) for s, e in zip(sources, exact)])
        assert ours <= theirs


def test_plain_cotan_is_worse_on_badly_shaped_triangles():
    """The intrinsic Delaunay operators are what makes homer accurate."""
    V, F = load_shared_mesh("homer")
    s = three_sources(F)[0]
    exact = exact_distance(V, F, s)
    robust = mean_relative_error(hc.geodesic_distance(V, F, [s], refine=0), exact)
    plain = mean_relative_error(hc.geodesic_distance(V, F, [s], refine=0, robust=False), exact)
    assert robust < 0.025
    assert plain > 2 * robust
