"""Sparse factorization backends: agreement, shared orderings, failures, the automatic choice."""

import numpy as np
import pytest
import scipy.sparse as sp
from shapes import grid

import heatcore as hc
from heatcore import linalg
from heatcore.linalg import libraries, metis, ordering


def heat_matrix(rows=30, cols=30):
    """``M + L`` of a grid: the kind of matrix the heat method factors."""
    V, F = grid(rows, cols)
    ops = hc.TriangleMesh(V, F, refine=0, robust=False).operators
    return (sp.diags(ops.mass) + ops.laplacian).tocsc()


@pytest.mark.parametrize("backend", linalg.available_backends())
def test_every_backend_solves_one_and_several_right_hand_sides(backend):
    A = heat_matrix()
    rng = np.random.default_rng(0)
    b = rng.standard_normal((A.shape[0], 3))
    f = linalg.factor(A, backend)
    assert np.abs(A @ f.solve(b) - b).max() < 1e-10
    x = f.solve(b[:, 1])
    assert x.shape == (A.shape[0],) and np.abs(A @ x - b[:, 1]).max() < 1e-10


def test_supernodal_shares_one_ordering_with_a_principal_submatrix():
    A = heat_matrix()
    ordering = linalg.fill_reducing_ordering(A, "supernodal")
    assert np.array_equal(np.sort(ordering.permutation), np.arange(A.shape[0]))
    rows = np.flatnonzero(np.arange(A.shape[0]) % 7 != 3)
    sub = A[rows][:, rows]
    restricted = linalg.restrict_ordering(ordering, rows)
    assert np.array_equal(np.sort(restricted.permutation), np.arange(rows.size))
    # the restriction keeps the relative order of the kept unknowns
    kept_in_order = ordering.permutation[np.isin(ordering.permutation, rows)]
    assert np.array_equal(rows[restricted.permutation], kept_in_order)
    b = np.linspace(-1.0, 1.0, rows.size)
    x = linalg.factor(sub, "supernodal", ordering=restricted).solve(b)
    assert np.abs(sub @ x - b).max() < 1e-12


needs_metis = pytest.mark.skipif(
    metis.node_nd() is None or libraries.optional("cvxopt") is None, reason="needs the scale extra"
)


@needs_metis
def test_nested_dissection_runs_metis_in_the_background_and_fills_in_less(monkeypatch):
    import pymetis
    from cvxopt import cholmod

    A = heat_matrix(60, 60)
    n = A.shape[0]
    assert linalg.start_nested_dissection(A, "supernodal") is None  # below the size where it pays
    monkeypatch.setattr(ordering, "NESTED_DISSECTION_MIN_SIZE", n)
    assert linalg.start_nested_dissection(A, "cholmod") is None
    permutation = linalg.start_nested_dissection(A, "supernodal").result()
    # the GIL-free call computes what pymetis computes with the same options
    graph = A.tocsr()
    graph.setdiag(0)
    graph.eliminate_zeros()
    expected = pymetis.nested_dissection(
        pymetis.CSRAdjacency(graph.indptr, graph.indices), options=pymetis.Options(niter=1, ctype=0, no2hop=1)
    )[0]
    assert np.array_equal(permutation, expected)

    amd = linalg.fill_reducing_ordering(A, "supernodal")
    nested = amd.reordered(permutation)

    def factor_entries(ordering):
        f = linalg.factor(A, "supernodal", ordering=ordering)
        x = f.solve(np.ones(n))
        assert np.abs(A @ x - 1.0).max() < 1e-10
        return len(cholmod.getfactor(f._factor))

    # a 60 x 60 grid: measured 90k stored entries by nested dissection, 99k by AMD, 243k in natural order
    by_amd = factor_entries(amd)
    assert factor_entries(nested) < 0.95 * by_amd and by_amd < 0.5 * factor_entries(linalg.Ordering(np.arange(n)))


@needs_metis
def test_nested_dissection_of_a_graph_with_isolated_vertices(monkeypatch):
    monkeypatch.setattr(ordering, "NESTED_DISSECTION_MIN_SIZE", 0)
    A = sp.csr_matrix(sp.block_diag([sp.eye(3), heat_matrix(5, 5), sp.eye(2)]))
    permutation = linalg.start_nested_dissection(A, "supernodal").result()
    assert np.array_equal(np.sort(permutation), np.arange(A.shape[0]))


def test_supernodal_reuses_the_pattern_only_where_it_matches():
    A = heat_matrix()
    ordering = linalg.fill_reducing_ordering(A, "supernodal")
    b = np.cos(np.arange(A.shape[0]))
    same_pattern = (A + sp.diags(np.linspace(1.0, 2.0, A.shape[0]))).tocsr()
    assert np.array_equal(same_pattern.indptr, A.tocsr().indptr)
    reverse = np.arange(A.shape[0])[::-1]
    other_pattern = A.tocsr()[reverse][:, reverse]  # renumbered: same matrix, other pattern
    for M in (same_pattern, other_pattern, A):
        x = linalg.factor(M, "supernodal", ordering=ordering).solve(b)
        assert np.abs(M @ x - b).max() < 1e-10


@pytest.mark.parametrize("backend", ["supernodal", "cholmod"])
def test_cholesky_of_a_negative_definite_matrix_raises_solver_error(backend):
    A = heat_matrix(6, 6)
    with pytest.raises(hc.SolverError):
        linalg.factor(-A, backend)


def test_auto_choice_by_size():
    assert linalg.choose_backend(1000, "factor") == "supernodal"  # the fastest factorization, solves as qdldl's
    assert linalg.choose_backend(1000, "solve") == "cholmod"
    big = linalg.SUPERNODAL_MIN_SIZE
    assert linalg.choose_backend(big, "factor") == linalg.choose_backend(big, "solve") == "supernodal"
    with pytest.raises(hc.SolverError):
        linalg.factor(heat_matrix(4, 4), "nope")
    with pytest.raises(hc.SolverError, match="prefer"):
        linalg.choose_backend(1000, "fast")


def test_one_query_uses_the_fastest_factorization(monkeypatch):
    """geodesic_distance factors for one query (supernodal, or qdldl without cvxopt): the same distances."""
    V, F = grid(21, 21)
    chosen = []
    original = hc.HeatSolver.__init__

    def spy(self, *args, **kw):
        original(self, *args, **kw)
        chosen.append(self.factors.heat_backend)  # the backend "auto" became

    monkeypatch.setattr(hc.HeatSolver, "__init__", spy)
    d = hc.geodesic_distance(V, F, [0], refine=0)
    reference = hc.HeatSolver(hc.TriangleMesh(V, F, refine=0), backend="superlu").distance([0])
    assert chosen[0] == "supernodal"
    assert np.allclose(d, reference, rtol=1e-9, atol=1e-12)
    monkeypatch.setitem(libraries._modules, "cvxopt", None)
    assert linalg.choose_backend(1000, "factor") == "qdldl"
    assert np.allclose(hc.geodesic_distance(V, F, [0], refine=0), reference, rtol=1e-9, atol=1e-12)
    assert chosen[-1] == "qdldl"


def test_many_pins_use_the_shared_ordering():
    """More pins than the dense Schur path takes: the pinned Laplacian gets its own factorization."""
    V, F = grid(41, 41)
    mesh = hc.TriangleMesh(V, F, refine=0)
    band = np.flatnonzero(V[:, 0] < 0.2)  # 8 columns of 41 vertices: a band as the source
    assert band.size > hc.heat.MAX_PRECOMPUTED_PINS
    reference = hc.HeatSolver(mesh, backend="superlu").distance(band)
    d = hc.HeatSolver(mesh, backend="supernodal").distance(band)
    assert np.allclose(d, reference, rtol=1e-8, atol=1e-12)
    exact = np.maximum(V[:, 0] - V[band, 0].max(), 0.0)
    assert np.abs(d - exact).max() < 0.02


def test_large_matrix_without_cvxopt_falls_back_and_hints_once(monkeypatch, caplog):
    monkeypatch.setitem(libraries._modules, "cvxopt", None)
    monkeypatch.setattr(libraries, "_warned", set())
    big = linalg.SUPERNODAL_MIN_SIZE
    with caplog.at_level("WARNING", logger="heatcore.linalg"):
        assert linalg.choose_backend(big, "solve") == "cholmod"
        assert linalg.choose_backend(4 * big, "factor") == "cholmod"  # above QDLDL_MAX_SIZE
        assert linalg.choose_backend(big, "factor") == "qdldl"
    hints = [r for r in caplog.records if "heatcore[scale]" in r.getMessage()]
    assert len(hints) == 1
    with pytest.raises(hc.SolverError, match="scale"):
        linalg.factor(heat_matrix(4, 4), "supernodal")


def test_resolve_backend_takes_an_intent():
    """'one query' and 'interactive': the fastest factorization for both matrices; 'reuse': each stage its own."""
    for n in (1000, linalg.SUPERNODAL_MIN_SIZE):
        for stage in ("factor", "solve"):
            for intent in ("one query", "interactive"):
                assert linalg.resolve_backend("auto", n, intent=intent, stage=stage) == linalg.choose_backend(n)
            assert linalg.resolve_backend("auto", n, intent="reuse", stage=stage) == linalg.choose_backend(n, stage)
            assert linalg.resolve_backend("superlu", n, intent="one query", stage=stage) == "superlu"
    assert linalg.resolve_backend("auto", 1000) == linalg.choose_backend(1000, "factor")
    with pytest.raises(hc.InvalidOptionError, match="intent"):
        linalg.resolve_backend("auto", 10, intent="once")
    with pytest.raises(hc.InvalidOptionError, match="stage"):
        linalg.resolve_backend("auto", 10, stage="once")


def test_backends_import_the_interface_not_the_factor_module():
    """No cycle: the backend modules (gpu among them) subclass Factor from linalg.interface."""
    from heatcore.linalg import cholmod, gpu, interface, qdldl, superlu, supernodal

    for module in (cholmod, gpu, qdldl, superlu, supernodal):
        assert "heatcore.linalg.factor" not in {getattr(v, "__module__", None) for v in vars(module).values()
                                                if isinstance(v, type) or callable(v)}
    assert gpu.GPUFactor.__mro__[1] is interface.Factor is linalg.Factor
