"""The fast paths that read another library's internals are taken where they should be.

heatcore reads cvxopt's ``cholmod_factor`` (sparse right-hand sides in the heat
step), calls the CHOLMOD that cvxopt links (a shared symbolic analysis, numeric
factorizations without the GIL) and the METIS inside pymetis (nested dissection) through ctypes,
on the versions in ``libraries.READ_INTERNALS_OF``. On those versions these
tests FAIL, not skip, when a fast path is not taken (a reader that declines a
layout it should know, a solver that stops routing through it); on another
version they check that the plain path is taken with a logged warning, never
silently. They skip only where the library is not installed at all.
"""

import re
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse.linalg as spla
from shapes import grid
from test_linalg import heat_matrix

import heatcore as hc
from heatcore import linalg
from heatcore.linalg import libraries, metis, ordering
from heatcore.linalg.factor import BACKGROUND_MIN_SIZE

REPO = Path(__file__).resolve().parents[1]


def require(name):
    """The library, or a skip where it is not installed; installed but not importable fails."""
    if not libraries.installed(name):
        pytest.skip(f"{name} is not installed (the scale extra)")
    module = libraries.optional(name)
    assert module is not None, f"{name} is installed but cannot be imported"
    return module


def known(name):
    return libraries.version(name) in libraries.READ_INTERNALS_OF[name]


def warnings_about(caplog, name):
    return [r for r in caplog.records if r.levelname == "WARNING" and name in r.getMessage()]


@pytest.fixture
def fresh_warnings(monkeypatch):
    """Warnings already given once in this process are given again."""
    monkeypatch.setattr(libraries, "_warned", set())


def test_sparse_forward_solve_is_taken_on_the_cvxopt_it_was_written_for(fresh_warnings, caplog):
    require("cvxopt")
    A = heat_matrix(60, 60)
    b = np.zeros(A.shape[0])
    b[[17, 2000]] = [1.0, 0.5]
    before = libraries.fast_path_counts["sparse_forward"]
    with caplog.at_level("WARNING", logger="heatcore.linalg"):
        f = linalg.factor(A, "supernodal")
        x = f.solve(b)
    assert np.abs(x - spla.spsolve(A, b)).max() < 1e-12
    taken = libraries.fast_path_counts["sparse_forward"] - before
    if known("cvxopt"):
        assert f._sparse_forward is not None, f"cvxopt {libraries.version('cvxopt')}: the factor was not read"
        assert taken == 1, "the sparse forward solve was not taken for a right-hand side with two nonzeros"
        assert not warnings_about(caplog, "sparse right-hand sides")
    else:  # another version: the plain path, said aloud
        assert f._sparse_forward is None and taken == 0
        assert warnings_about(caplog, "sparse right-hand sides")


def test_the_heat_step_goes_through_the_sparse_forward_solve():
    require("cvxopt")
    V, F = grid(41, 41)
    solver = hc.HeatSolver(hc.TriangleMesh(V, F, refine=0), backend="supernodal")
    before = libraries.fast_path_counts["sparse_forward"]
    d = solver.distance([5])
    reference = hc.HeatSolver(hc.TriangleMesh(V, F, refine=0), backend="superlu").distance([5])
    assert np.allclose(d, reference, rtol=1e-8, atol=1e-12)
    if known("cvxopt"):
        assert libraries.fast_path_counts["sparse_forward"] > before, "the heat step no longer solves sparsely"


def test_metis_nested_dissection_is_taken_on_the_pymetis_it_was_written_for(monkeypatch, fresh_warnings, caplog):
    require("cvxopt")
    require("pymetis")
    monkeypatch.setattr(ordering, "NESTED_DISSECTION_MIN_SIZE", 0)  # as on large meshes
    V, F = grid(31, 31)
    before = libraries.fast_path_counts["metis_nested_dissection"]
    with caplog.at_level("WARNING", logger="heatcore.linalg"):
        reader = metis._load()  # not the cached one: its warnings are checked here
        d = hc.HeatSolver(hc.TriangleMesh(V, F, refine=1), backend="supernodal").distance([3, 500])
    assert np.all(np.isfinite(d))
    taken = libraries.fast_path_counts["metis_nested_dissection"] - before
    if known("pymetis"):
        assert reader is not None and metis.node_nd() is not None, (
            f"pymetis {libraries.version('pymetis')}: its METIS could not be loaded"
        )
        assert taken == 1, "the solver did not order its Poisson factor by METIS nested dissection"
        assert not warnings_about(caplog, "METIS")
    else:
        assert reader is None and taken == 0
        assert warnings_about(caplog, "METIS")


def _cvxopt_factor(A, permutation):
    """The supernodal factor of ``A`` as cvxopt alone makes it (its symbolic and numeric calls), in this order."""
    from heatcore.linalg import cholmod_direct, supernodal

    available = cholmod_direct.available
    cholmod_direct.available = lambda: False
    try:
        return supernodal.SupernodalFactor(A, linalg.Ordering(permutation))
    finally:
        cholmod_direct.available = available


def test_one_symbolic_analysis_serves_both_matrices_of_a_pattern(fresh_warnings, caplog):
    """The heat matrix and the Laplacian of one solver share CHOLMOD's analysis; the numbers are cvxopt's own."""
    require("cvxopt")
    from heatcore.linalg import cholmod_direct

    A = heat_matrix(40, 40).tocsr()
    B = A.copy()
    B.data = B.data * np.where(B.indices == np.repeat(np.arange(B.shape[0]), np.diff(B.indptr)), 3.0, 0.5)
    ordering = linalg.fill_reducing_ordering(A, "supernodal")
    before = libraries.fast_path_counts["shared_symbolic"]
    with caplog.at_level("WARNING", logger="heatcore.linalg"):
        first, second = linalg.factor(A, "supernodal", ordering=ordering), linalg.factor(B, "supernodal", ordering=ordering)
    b = np.random.default_rng(0).standard_normal((A.shape[0], 2))
    for matrix, f in ((A, first), (B, second)):
        assert np.array_equal(f.solve(b), _cvxopt_factor(matrix, ordering.permutation).solve(b))  # bit for bit
    taken = libraries.fast_path_counts["shared_symbolic"] - before
    if known("cvxopt"):
        assert cholmod_direct.available(), f"cvxopt {libraries.version('cvxopt')}: CHOLMOD could not be reached"
        assert ordering.analysis is not None and taken == 2, "the second matrix made its own analysis"
        assert not warnings_about(caplog, "CHOLMOD called directly")
    else:
        assert ordering.analysis is None and taken == 0
        assert warnings_about(caplog, "CHOLMOD called directly")
    ordering.forget_pattern()
    assert ordering.analysis is None


def test_a_factorization_started_in_the_background_is_the_same_and_says_when_it_fails():
    require("cvxopt")
    A = heat_matrix(80, 80)
    assert A.shape[0] >= BACKGROUND_MIN_SIZE  # large enough to be started in the background
    ordering = linalg.fill_reducing_ordering(A, "supernodal")
    started = linalg.start_factor(A, "supernodal", ordering=ordering)
    b = np.random.default_rng(1).standard_normal(A.shape[0])
    assert np.array_equal(started.result().solve(b), _cvxopt_factor(A, ordering.permutation).solve(b))
    broken = linalg.start_factor(-A, "supernodal", ordering=linalg.Ordering(ordering.permutation))
    for _ in range(2):  # every later use says it again
        with pytest.raises(hc.SolverError, match="not positive definite"):
            broken.result()


def test_minimum_degree_started_in_the_background_is_cvxopts_own():
    require("cvxopt")
    A = heat_matrix(40, 40).tocsr()
    started = linalg.start_fill_reducing_ordering(A, "supernodal")
    from heatcore.linalg import supernodal

    from heatcore.linalg import cholmod_direct

    available = cholmod_direct.available
    cholmod_direct.available = lambda: False
    try:
        own, _ = supernodal.minimum_degree(A)  # cvxopt.amd.order
    finally:
        cholmod_direct.available = available
    ordering = started.result()
    assert np.array_equal(ordering.permutation, np.asarray(own).ravel())
    assert ordering.pattern is not None
    if known("cvxopt"):  # CHOLMOD's analysis in that order came with it, and the factors copy it
        assert ordering.analysis is not None
        b = np.random.default_rng(2).standard_normal(A.shape[0])
        before = libraries.fast_path_counts["shared_symbolic"]
        x = linalg.factor(A, "supernodal", ordering=ordering).solve(b)
        assert libraries.fast_path_counts["shared_symbolic"] > before
        assert np.array_equal(x, _cvxopt_factor(A, ordering.permutation).solve(b))


def test_the_readers_know_the_versions_the_blender_extension_bundles():
    """Bumping a bundled version means checking the reader on it (these tests) and adding it."""
    script = (REPO / "scripts" / "build_blender_extension.py").read_text()
    pins = dict(re.findall(r'"(cvxopt|pymetis)==([^"]+)"', script))
    assert set(pins) == {"cvxopt", "pymetis"}
    for name, pinned in pins.items():
        assert pinned in libraries.READ_INTERNALS_OF[name], f"{name}=={pinned} is bundled but not known to its reader"
