"""The linear algebra layer's fences: nothing at import time, no global option left changed,
readers of other libraries' internals that decline loudly, one solve shape contract."""

import subprocess
import sys
import threading

import numpy as np
import pytest
import scipy.sparse as sp
from test_linalg import heat_matrix

import heatcore as hc
from heatcore import linalg
from heatcore.linalg import libraries, metis, sparse_rhs


def test_importing_heatcore_loads_no_backend_library_and_starts_nothing():
    code = """
import sys, threading
import heatcore
import heatcore.linalg
from heatcore.linalg import (cholmod, factor, libraries, memory, metis, ordering, qdldl, sparse_rhs,
                             superlu, supernodal)
loaded = [m for m in ("cvxopt", "pymetis", "cholespy", "qdldl") if m in sys.modules]
assert not loaded, f"imported at import time: {loaded}"
assert not libraries._modules, libraries._modules
assert not memory._malloc_trim.loaded(), "malloc_trim looked up at import time"
assert not metis.node_nd.loaded(), "METIS loaded at import time"
assert not ordering._background.loaded(), "thread pool created at import time"
assert threading.active_count() == 1, threading.enumerate()
maps = open("/proc/self/maps").read() if sys.platform.startswith("linux") else ""
assert "pymetis" not in maps and "cvxopt" not in maps, "a backend's shared library is mapped"
"""
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr


def test_libraries_load_once_from_many_threads():
    calls = []

    @libraries.once
    def slow():
        calls.append(1)
        threading.Event().wait(0.05)
        return object()

    results = []
    threads = [threading.Thread(target=lambda: results.append(slow())) for _ in range(8)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert len(calls) == 1 and all(r is results[0] for r in results)


@pytest.mark.parametrize("backend", linalg.available_backends())
def test_every_backend_takes_every_right_hand_side_shape(backend):
    A = heat_matrix(12, 12)
    n = A.shape[0]
    f = linalg.factor(A, backend)
    assert isinstance(f, linalg.Factor) and f.backend == backend and f.n == n
    B = np.asfortranarray(np.random.default_rng(3).standard_normal((n, 5)))
    X = f.solve(B)
    assert X.shape == (n, 5) and np.abs(A @ X - B).max() < 1e-10
    assert np.allclose(f.solve(B[:, 2]), X[:, 2], rtol=1e-12, atol=1e-14)  # a strided column
    assert np.allclose(f.solve(B[:, 1:2]), X[:, 1:2], rtol=1e-12, atol=1e-14)  # (n, 1)
    assert np.allclose(f.solve(B[:, ::2].tolist()), X[:, ::2], rtol=1e-12, atol=1e-14)  # a list, every other column
    assert f.solve(np.zeros((n, 0))).shape == (n, 0)
    for wrong in (np.ones(n + 1), np.ones((n, 2, 1)), np.ones((2, n))):
        with pytest.raises(ValueError, match="right-hand side"):
            f.solve(wrong)


@pytest.fixture
def cholmod():
    if "supernodal" not in linalg.available_backends():
        pytest.skip("needs the scale extra")
    return libraries.optional("cvxopt").cholmod


@pytest.mark.parametrize("user_options", [{}, {"supernodal": 0, "nmethods": 3, "postorder": False}])
def test_supernodal_factorization_leaves_cvxopts_options_as_they_were(cholmod, monkeypatch, user_options):
    monkeypatch.setattr(cholmod, "options", dict(user_options))
    A = heat_matrix(20, 20)
    ordering = linalg.fill_reducing_ordering(A, "supernodal")
    for kwargs in ({}, {"ordering": ordering}, {"ordering": ordering.restrict(np.arange(A.shape[0]))}):
        f = linalg.factor(A, "supernodal", **kwargs)
        assert cholmod.options == user_options
        assert np.abs(A @ f.solve(np.ones(A.shape[0])) - 1.0).max() < 1e-10
    with pytest.raises(hc.SolverError):
        linalg.factor(-A, "supernodal")
    assert cholmod.options == user_options


def test_reading_cvxopts_factor_leaves_ctypes_pythonapi_as_it_was(cholmod):
    import ctypes

    shared = [getattr(ctypes.pythonapi, name) for name in ("PyCapsule_GetName", "PyCapsule_GetPointer")]
    before = [(function.restype, function.argtypes) for function in shared]
    f = linalg.factor(heat_matrix(10, 10), "supernodal")
    assert f._sparse_forward is not None or not libraries.version_is_known("cvxopt", "this test")
    assert [(function.restype, function.argtypes) for function in shared] == before


def test_a_factor_from_another_cvxopt_version_is_not_read_and_that_is_said(cholmod, monkeypatch, caplog):
    monkeypatch.setitem(libraries.READ_INTERNALS_OF, "cvxopt", ("0.0.0",))
    monkeypatch.setattr(libraries, "_warned", set())
    A = heat_matrix(30, 30)
    b = np.zeros(A.shape[0])
    b[7] = 1.0
    before = libraries.fast_path_counts["sparse_forward"]
    with caplog.at_level("WARNING", logger="heatcore.linalg"):
        f = linalg.factor(A, "supernodal")
        x = f.solve(b)
    assert f._sparse_forward is None and libraries.fast_path_counts["sparse_forward"] == before
    assert np.abs(A @ x - b).max() < 1e-10
    assert any("not a version" in r.getMessage() and "cvxopt" in r.getMessage() for r in caplog.records)


def test_another_pymetis_version_keeps_minimum_degree_and_says_so(monkeypatch, caplog):
    if not libraries.installed("pymetis"):
        pytest.skip("needs pymetis")
    monkeypatch.setitem(libraries.READ_INTERNALS_OF, "pymetis", ("0.0.0",))
    monkeypatch.setattr(libraries, "_warned", set())
    with caplog.at_level("WARNING", logger="heatcore.linalg"):
        assert metis._load() is None
    assert any("not a version" in r.getMessage() and "pymetis" in r.getMessage() for r in caplog.records)


def test_unreadable_factors_are_declined_aloud_and_surprises_are_not_swallowed(cholmod, monkeypatch, caplog):
    monkeypatch.setattr(libraries, "_warned", set())
    with caplog.at_level("WARNING", logger="heatcore.linalg"):
        assert sparse_rhs.SparseForwardSolver.from_cvxopt(object(), 100) is None
    assert any("not a cvxopt factor" in r.getMessage() for r in caplog.records)

    def broken(capsule):
        raise RuntimeError("a bug, not a foreign layout")

    monkeypatch.setattr(sparse_rhs, "_capsule_pointer", broken)
    f = linalg.factor(sp.identity(4, format="csc"), "supernodal")  # the factor is read on its first sparse solve
    with pytest.raises(RuntimeError, match="a bug"):
        f.solve(np.array([0.0, 1.0, 0.0, 0.0]))
