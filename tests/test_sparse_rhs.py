"""Forward solves that skip the zeros of a sparse right-hand side on a supernodal factor."""

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from test_linalg import heat_matrix

from heatcore import linalg
from heatcore.linalg import sparse_rhs


def supernodal(A):
    f = linalg.factor(A, "supernodal")
    assert f._sparse_forward is not None  # the factor's layout was recognized
    return f


def test_one_hot_and_few_sources_solve_sparsely_and_exactly():
    A = heat_matrix(60, 60)
    f = supernodal(A)
    rng = np.random.default_rng(0)
    for k in (1, 3, 12):
        b = np.zeros(A.shape[0])
        b[rng.choice(A.shape[0], k, replace=False)] = rng.uniform(0.1, 1.0, k)
        assert f._sparse_forward.forward(b) is not None
        x, exact = f.solve(b), spla.spsolve(A, b)
        assert np.abs(x - exact).max() <= 1e-12 * np.abs(exact).max()
        assert np.allclose(x, f.solve(b[:, None])[:, 0], rtol=1e-13, atol=0)  # the dense path


def test_forward_half_is_the_triangular_solve_it_claims():
    A = heat_matrix(40, 40)
    f = supernodal(A)
    solver = f._sparse_forward
    b = np.zeros(A.shape[0])
    b[[5, 700]] = [1.0, -2.0]
    y = solver.forward(b)
    # A = P^T L L^T P, so L y = P b gives y^T y = b^T A^{-1} b.
    assert np.isclose(y @ y, b @ spla.spsolve(A, b), rtol=1e-12)
    assert 0 < np.count_nonzero(y) < A.shape[0] / 2  # only the sources' paths to the root


def test_dense_right_hand_sides_and_large_reaches_use_the_dense_solve():
    A = heat_matrix(40, 40)
    f = supernodal(A)
    rng = np.random.default_rng(1)
    dense = rng.standard_normal(A.shape[0])
    assert f._sparse_forward.forward(dense) is None
    many = np.zeros(A.shape[0])
    many[::3] = 1.0  # a third of the unknowns: the reach is most of the factor
    assert f._sparse_forward.forward(many) is None
    for b in (dense, many):
        assert np.abs(A @ f.solve(b) - b).max() < 1e-10


def test_several_elimination_trees():
    """A block-diagonal matrix (a mesh in pieces) has one root per block."""
    A = sp.block_diag([heat_matrix(20, 20), heat_matrix(15, 25), sp.identity(3)]).tocsc()
    f = supernodal(A)
    assert np.sum(f._sparse_forward._parent < 0) >= 3
    for source in (0, 450, A.shape[0] - 1):
        b = np.zeros(A.shape[0])
        b[source] = 2.0
        assert f._sparse_forward.forward(b) is not None
        assert np.abs(f.solve(b) - spla.spsolve(A, b)).max() < 1e-13


def test_unreadable_factors_are_declined():
    f = supernodal(heat_matrix(10, 10))
    assert sparse_rhs.SparseForwardSolver.from_cvxopt(f._factor, 99) is None  # wrong size
    assert sparse_rhs.SparseForwardSolver.from_cvxopt(object(), 100) is None  # not a capsule
