"""Geodesic Voronoi labels (HeatSolver.nearest_source): one multi-column solve, ties, unreachable vertices."""

import numpy as np
import pytest
from conftest import load_shared_mesh
from mesh_strategies import _icosphere

import heatcore as hc
from heatcore.errors import InvalidSourceError


@pytest.fixture(scope="module")
def spot_solver():
    V, F = load_shared_mesh("spot")
    return hc.HeatSolver(hc.TriangleMesh(V, F, refine=0))


def count_heat_solves(solver, monkeypatch):
    """Record the right-hand side's shape of every heat solve the solver runs."""
    shapes = []
    heat = solver.heat

    def counted(impulse):
        shapes.append(impulse.shape)
        return heat(impulse)

    monkeypatch.setattr(solver, "heat", counted)
    return shapes


def test_labels_are_the_argmin_of_single_source_distances(spot_solver, monkeypatch):
    solver = spot_solver
    n = len(solver.domain.output_vertices)
    sources = [0, 400, 1453, 2000, [2500, 2600], {"points": ([100], [[0.2, 0.3, 0.5]])}, 2929]
    single = np.stack([solver.distance(**s) if isinstance(s, dict) else solver.distance(s) for s in sources])
    shapes = count_heat_solves(solver, monkeypatch)
    labels, nearest = solver.nearest_source(sources, return_distance=True)
    # one heat solve of all the sources as columns (then one unit field and one Poisson solve)
    assert shapes == [(n, len(sources))]
    top2 = np.sort(single, axis=0)[:2]
    clear = top2[1] - top2[0] > 1e-9 * single.max()  # away from ties, the labels are exact
    assert clear.mean() > 0.99
    np.testing.assert_array_equal(labels[clear], np.argmin(single, axis=0)[clear])
    np.testing.assert_allclose(nearest, single.min(axis=0), rtol=1e-10, atol=0)
    assert labels[[0, 400, 1453, 2000, 2500, 2600, 2929]].tolist() == [0, 1, 2, 3, 4, 4, 6]
    # every source keeps a region of its own, and the regions cover the mesh
    assert set(labels.tolist()) == set(range(len(sources)))


def test_many_sources_go_in_blocks_of_columns(spot_solver, monkeypatch):
    solver = spot_solver
    n = len(solver.domain.output_vertices)
    assert solver.block_columns(max_memory_mb=4.5) == 3
    sources = list(range(0, 2930, 400))  # 8 sources: blocks of 3, 3 and 2 columns
    shapes = count_heat_solves(solver, monkeypatch)
    labels = solver.nearest_source(sources, max_memory_mb=4.5)
    assert shapes == [(n, 3), (n, 3), (n, 2)]
    reference = np.argmin(solver.distances(sources), axis=0)
    np.testing.assert_array_equal(labels, reference)


def test_ties_go_to_the_source_listed_first(spot_solver):
    labels = spot_solver.nearest_source([5, 7, 5], max_memory_mb=0.001)  # one column per block
    assert spot_solver.block_columns(max_memory_mb=0.001) == 1
    assert 2 not in labels and set(labels.tolist()) == {0, 1}
    assert (spot_solver.nearest_source([5, 5]) == 0).all()


def test_unreachable_vertices_get_minus_one():
    V1, F1 = _icosphere(2)
    V = np.concatenate([V1, V1 + [3.0, 0, 0], [[10.0, 0, 0]]])  # two spheres and a loose vertex
    F = np.concatenate([F1, F1 + len(V1)])
    solver = hc.HeatSolver(hc.TriangleMesh(V, F, refine=0))
    labels, d = solver.nearest_source([0, 5], return_distance=True)
    first = np.arange(len(V)) < len(V1)
    assert (labels[first] >= 0).all() and (labels[~first] == -1).all()
    assert np.isinf(d[~first]).all() and np.isfinite(d[first]).all()
    labels = solver.nearest_source([0, len(V1) + 3])  # one source per sphere
    assert (labels[first] == 0).all() and (labels[len(V1) : 2 * len(V1)] == 1).all() and labels[-1] == -1


def test_bad_sources_are_refused(spot_solver):
    with pytest.raises(InvalidSourceError, match="at least one source"):
        spot_solver.nearest_source([])
    with pytest.raises(InvalidSourceError):
        spot_solver.nearest_source([0, 99999])
    with pytest.raises(InvalidSourceError, match="sequence of sources"):
        spot_solver.nearest_source(3)
