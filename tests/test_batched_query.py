"""HeatSolver.distances(block): many sources with multi-column solves, row for row distance()'s result."""

import numpy as np
import pytest
from scipy.spatial import Delaunay
from shapes import grid

import heatcore as hc
from heatcore.errors import InvalidSourceError
from heatcore.heat import MAX_PRECOMPUTED_PINS
from heatcore.steps.blocks import MAX_BLOCK_COLUMNS

RTOL = 1e-10


def assert_rows_match(solver, block, rows=None):
    """``distances(block)`` equals ``distance(s)`` per source: within RTOL relative, inf at the same places."""
    D = solver.distances(block) if rows is None else rows
    expected = np.stack([solver.distance(**s) if isinstance(s, dict) else solver.distance(s) for s in block])
    assert D.shape == expected.shape
    assert np.array_equal(np.isinf(D), np.isinf(expected))
    finite = np.isfinite(expected)
    scale = np.abs(expected[finite]).max()
    assert np.abs(D[finite] - expected[finite]).max() <= RTOL * scale
    return D


@pytest.fixture(scope="module")
def spot_solver():
    return hc.HeatSolver(hc.TriangleMesh(*hc.io.load_demo_mesh()))


def test_one_part_mesh_rows_equal_distance(spot_solver):
    block = [0, 17, 2929, 1000, 5, 6, 7, 8]  # more than EXACT_SOLVE_COLUMNS columns per call
    D = assert_rows_match(spot_solver, block)
    assert np.all(D[np.arange(len(block)), block] == 0.0)
    # a row does not depend on the block it is computed in
    assert np.array_equal(spot_solver.distances([17])[0], D[1])
    assert np.array_equal(spot_solver.distances(np.array(block))[3], D[3])


def test_multi_vertex_and_keyword_sources(spot_solver):
    block = [[5, 9], 3, np.array([100, 200, 300]), {"vertices": [7]}, {"region": [4, 5]}]
    D = assert_rows_match(spot_solver, block)
    assert D[0, 5] == D[0, 9] == 0.0


def test_many_pinned_vertices_fall_back_to_their_own_factorization(spot_solver):
    many = list(range(0, 2 * (MAX_PRECOMPUTED_PINS + 10), 2))
    assert len(many) > MAX_PRECOMPUTED_PINS
    assert_rows_match(spot_solver, [0, many, 11])


def test_multi_part_mesh_gets_inf_where_unreachable():
    V1, F1 = grid(11, 11)
    V2, F2 = grid(9, 9)
    V = np.vstack([V1, V2 + [5, 0, 0], [[9, 9, 9]]])  # two parts and an unreferenced vertex
    F = np.vstack([F1, F2 + len(V1)])
    solver = hc.HeatSolver(hc.TriangleMesh(V, F))
    assert solver.n_components == 2
    b = len(V1)
    block = [0, b + 3, [0, b], [1, 2, b + 5, b + 6], 60]
    D = assert_rows_match(solver, block)
    assert np.all(np.isinf(D[0, b:])) and np.all(np.isfinite(D[0, :b]))
    assert np.all(np.isinf(D[1, :b])) and np.all(np.isfinite(D[1, b:-1]))
    assert np.all(np.isinf(D[:, -1]))  # used by no face


@pytest.mark.parametrize("boundary", ["robin", "neumann", "dirichlet"])
def test_mesh_with_boundary(boundary):
    V, F = grid(21, 17)
    solver = hc.HeatSolver(hc.TriangleMesh(V, F), boundary=boundary)
    assert_rows_match(solver, [0, 20, 150, [3, 300], 356])  # corners, edge and interior sources


@pytest.mark.parametrize("backend", hc.linalg.available_backends())
def test_every_backend(backend):
    V, F = grid(15, 15)
    solver = hc.HeatSolver(hc.TriangleMesh(V, F), backend=backend)
    D = assert_rows_match(solver, [0, 3, 50, 100, 7, [8, 9], 224])
    if backend in ("qdldl", "cholmod"):  # columns solved as one column is: bit for bit distance()
        assert np.array_equal(D[:-2], np.stack([solver.distance(s) for s in [0, 3, 50, 100, 7]]))


def test_high_accuracy_runs_the_eikonal_pass_per_source(spot):
    solver = hc.HeatSolver(hc.TriangleMesh(*spot), accuracy="high")
    assert_rows_match(solver, [0, 17, [5, 900]])


def test_other_domains():
    V, _ = grid(9, 9)
    quads = np.array([[i * 9 + j, i * 9 + j + 1, (i + 1) * 9 + j + 1, (i + 1) * 9 + j] for i in range(8) for j in range(8)])
    Vt = np.stack(np.meshgrid(*[np.linspace(0, 1, 4)] * 3, indexing="ij"), -1).reshape(-1, 3)
    Vt = Vt + np.random.default_rng(0).uniform(-0.05, 0.05, Vt.shape)
    for domain in (hc.PolygonMesh(V, quads), hc.TetMesh(Vt, Delaunay(Vt).simplices),
                   hc.PointCloud(np.random.default_rng(1).random((200, 3)) * [1, 1, 0.01])):
        assert_rows_match(hc.HeatSolver(domain), [0, 5, [1, 9]])


def test_memory_bound_splits_the_block_into_chunks(spot_solver):
    assert spot_solver.block_columns(1e-9) == 1
    assert spot_solver.block_columns() == spot_solver.block_columns(1e6) == MAX_BLOCK_COLUMNS
    block = list(range(0, 2900, 100))
    assert 1 < spot_solver.block_columns(8) < len(block)
    whole = spot_solver.distances(block, max_memory_mb=1e6)
    for bound in (8, 1e-9):  # chunks of a few columns, of one column
        assert np.array_equal(whole, spot_solver.distances(block, max_memory_mb=bound))
    assert_rows_match(spot_solver, block, whole)


def test_empty_block_gives_no_rows(spot_solver):
    assert spot_solver.distances([]).shape == (0, 2930)
    assert spot_solver.distances(np.zeros(0, int)).shape == (0, 2930)


@pytest.mark.parametrize("bad", [2930, -1, 1.5, [0, 99999], [[0, 1]], []])
def test_bad_sources_raise_what_distance_raises(spot_solver, bad):
    with pytest.raises(InvalidSourceError) as single:
        spot_solver.distance(bad)
    with pytest.raises(InvalidSourceError) as batched:
        spot_solver.distances([0, bad])
    assert str(batched.value) == str(single.value)


@pytest.mark.parametrize("block", [3, "0,1", None, {"vertices": [0]}])
def test_a_block_must_be_a_sequence_of_sources(spot_solver, block):
    with pytest.raises(InvalidSourceError, match="sequence of sources"):
        spot_solver.distances(block)
