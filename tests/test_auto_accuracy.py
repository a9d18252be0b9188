"""The one-off default (issue 34, "1M vertices, first distance"): accuracy="auto", and what makes its march cheap.

``hc.geodesic_distance`` takes ``accuracy="auto"``: the compiled fast march for one query on a triangle mesh
of ``AUTO_HIGH_VERTICES`` vertices or more where numba is installed, the heat method otherwise (and for every
solver kept for reuse). The march needs no cotan operators: ``TriangleMesh`` builds them on first use, and
``HeatSolver(accuracy="high")`` with numba reads none, so they are never built for it.
"""

import numpy as np
import pytest
from conftest import exact_distance, load_shared_mesh, mean_relative_error

import heatcore as hc
from heatcore import fast_marching
from heatcore.domains.cotan import intrinsic_operators
from heatcore.domains.refine import unique_edges
from heatcore.domains.triangle import THIN_TRIANGLE_SLACK
from heatcore.options import AUTO_HIGH_VERTICES
from heatcore.high_accuracy import resolve_accuracy
from heatcore.settings import Settings, SolverSettings


def grid(cells):
    """A flat unit-spaced square grid of ``(cells + 1)^2`` vertices, two triangles per cell."""
    i, j = np.meshgrid(np.arange(cells + 1), np.arange(cells + 1), indexing="ij")
    V = np.column_stack([i.ravel(), j.ravel(), np.zeros(i.size)]).astype(float)
    corner = (i[:-1, :-1] * (cells + 1) + j[:-1, :-1]).ravel()
    quad = np.column_stack([corner, corner + cells + 1, corner + cells + 2, corner + 1])
    return V, np.vstack([quad[:, [0, 1, 2]], quad[:, [0, 2, 3]]])


@pytest.fixture(scope="module")
def large():
    """A plane of 108,900 vertices (over ``AUTO_HIGH_VERTICES``): exact distances are Euclidean, from its middle."""
    V, F = grid(329)
    source = int(np.argmin(np.linalg.norm(V - [164, 165, 0], axis=1)))
    return V, F, source, np.linalg.norm(V - V[source], axis=1)


def test_the_operators_wait_for_their_first_use_and_are_the_eager_build():
    V, F = load_shared_mesh("spot")
    mesh = hc.TriangleMesh(V, F, refine=0)
    assert "operators" not in vars(mesh) and mesh.n_vertices == len(V)
    eager = intrinsic_operators(V, F, *unique_edges(F), part=np.zeros(len(V), np.int64), n_parts=1,
                                thin_slack=THIN_TRIANGLE_SLACK, unit_exponent=np.zeros(1, np.int64)).operators
    ops = mesh.operators
    assert mesh.operators is ops  # built once
    for name in ("laplacian", "gradient"):
        a, b = getattr(ops, name).tocsr(), getattr(eager, name).tocsr()
        for part in ("data", "indices", "indptr"):
            np.testing.assert_array_equal(getattr(a, part), getattr(b, part))
    for name in ("mass", "volumes", "boundary", "elements", "mean_edge_length", "unit_exponent"):
        np.testing.assert_array_equal(getattr(ops, name), getattr(eager, name))
    assert ops.parts[0] == 1 and (ops.parts[1] == 0).all()


def test_a_march_builds_no_operators_and_the_heat_after_it_is_unchanged():
    V, F = load_shared_mesh("spot")
    mesh = hc.TriangleMesh(V, F)
    high = hc.HeatSolver(mesh, accuracy="high").distance([7])
    assert ("operators" in vars(mesh)) != fast_marching.available()  # the march reads the triangulation only
    np.testing.assert_array_equal(high, hc.HeatSolver(hc.TriangleMesh(V, F), accuracy="high").distance([7]))
    smooth = hc.HeatSolver(mesh).distance([7])  # the operators now: the same numbers as on a fresh mesh
    np.testing.assert_array_equal(smooth, hc.HeatSolver(hc.TriangleMesh(V, F)).distance([7]))


def test_a_march_solver_prepares_its_heat_on_first_need():
    V, F = load_shared_mesh("spot")
    solver = hc.HeatSolver(hc.TriangleMesh(V, F), accuracy="high")
    eager = hc.HeatSolver(hc.TriangleMesh(V, F))
    d = solver.distance([3])
    np.testing.assert_array_equal(solver.t, eager.t)  # the time step, worked out now
    assert solver.n_components == eager.n_components == 1 and solver.boundary == eager.boundary
    np.testing.assert_array_equal(solver.distance([3]), d)
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        solver.nothing


def test_a_march_solver_says_it_marches():
    """Its progress ends on the march, not on a heat solver it has not made (the command line shows it)."""
    V, F = load_shared_mesh("spot")
    mesh = hc.TriangleMesh(V, F)
    said = []
    hc.HeatSolver(mesh, accuracy="high", progress=lambda fraction, message: said.append(message))
    assert said[-1] == ("ready to march (no heat to solve)" if fast_marching.available() else "heat solver ready")
    said.clear()
    hc.HeatSolver(mesh, progress=lambda fraction, message: said.append(message))
    assert said[-1] == "heat solver ready"


@pytest.mark.skipif(not fast_marching.available(), reason="numba is missing: pip install -e '.[fast]'")
def test_auto_is_the_march_for_one_query_on_a_large_mesh(large):
    V, F, source, exact = large
    assert len(V) >= AUTO_HIGH_VERTICES
    auto = hc.geodesic_distance(V, F, [source])
    np.testing.assert_array_equal(auto, hc.geodesic_distance(V, F, [source], accuracy="high"))
    # measured: 1.3e-15 on the plane, where the march is exact (the heat method's: 0.52%)
    assert mean_relative_error(auto, exact) < 1e-12
    assert mean_relative_error(hc.geodesic_distance(V, F, [source], accuracy="smooth"), exact) > 1e-3


def test_auto_is_the_heat_method_below_the_threshold():
    V, F = load_shared_mesh("spot")
    mesh = hc.TriangleMesh(V, F)
    assert mesh.n_vertices < AUTO_HIGH_VERTICES  # spot refined ("auto"): 46,850 vertices
    np.testing.assert_array_equal(hc.geodesic_distance(V, F, [0]), hc.geodesic_distance(V, F, [0], accuracy="smooth"))


def test_auto_is_the_heat_method_for_every_solver_kept_for_reuse(large):
    V, F, _, _ = large
    mesh = hc.TriangleMesh(V, F)
    assert hc.HeatSolver(mesh).settings.accuracy == "smooth" and hc.HeatSolver(mesh).accuracy == "smooth"
    assert hc.HeatSolver(mesh, accuracy="auto").accuracy == "smooth"
    for intent in ("reuse", "interactive"):
        assert resolve_accuracy(SolverSettings(intent=intent, accuracy="auto"), mesh).accuracy == "smooth"
    assert Settings.of("blender").solver.accuracy == "smooth"  # Blender's own default, unchanged
    one = resolve_accuracy(SolverSettings(intent="one query"), mesh).accuracy
    assert one == ("high" if fast_marching.available() else "smooth")
    tets = hc.TetMesh(np.r_[np.eye(3), [[0.0, 0.0, 0.0]]], [[0, 1, 2, 3]])  # no march on tets: smooth
    assert resolve_accuracy(SolverSettings(intent="one query"), tets).accuracy == "smooth"


def test_without_numba_auto_is_the_heat_method_and_high_still_works(large, monkeypatch):
    """A base install (no ``fast`` extra): "auto" is the heat method; "high" the vectorized pass on the operators."""
    V, F, source, exact = large
    smooth = hc.geodesic_distance(V, F, [source], accuracy="smooth")
    monkeypatch.setattr(fast_marching, "available", lambda: False)
    np.testing.assert_array_equal(hc.geodesic_distance(V, F, [source]), smooth)
    spot_V, spot_F = load_shared_mesh("spot")
    mesh = hc.TriangleMesh(spot_V, spot_F)
    high = hc.HeatSolver(mesh, accuracy="high")
    assert "operators" in vars(mesh)  # the vectorized pass orders by the heat distance
    assert mean_relative_error(high.distance([0]), exact_distance(spot_V, spot_F, 0)) < 0.003
