"""Sources on the boundary of a tet mesh: Robin heat shaped by the source (heatcore/steps/boundary_source.py).

Accuracy against analytic distances on the meshes of ``tests/test_tet.py``
(jittered BCC cube and ball, jittered Kuhn L prism), each figure against the
heat of before (Neumann heat for a boundary source: the same mesh with no
``boundary_surface`` in its operators), and interior sources unchanged.
Measured figures (docs/tet.md) are asserted with small margins.
"""

import numpy as np
import pytest
from test_tet import (
    ball_mesh,
    cube_mesh,
    l_prism_distance,
    l_prism_mesh,
    mean_relative_error,
    nearest_vertex,
)

import heatcore as hc
from heatcore.domains.tet import TetMesh
from heatcore.steps.boundary_source import ROBIN_COEFFICIENT, BoundarySourceHeat


def boundary_vertex(mesh, V, point):
    """The boundary vertex nearest to ``point`` (input index)."""
    used = np.flatnonzero(mesh.vertex_map >= 0)
    on = used[mesh.operators.boundary[mesh.vertex_map[used]]]
    return int(on[np.argmin(np.linalg.norm(V[on] - np.asarray(point, float), axis=1))])


def distance_before(solver, source):
    """The distance with the Neumann heat for boundary sources, as before (the solver's Robin heat switched off)."""
    robin = solver.heat_flow.boundary_source
    surface, robin.surface = robin.surface, None
    try:
        return solver.distance([source])
    finally:
        robin.surface = surface


def euclid(V, s):
    return np.linalg.norm(V - s, axis=1)


CASES = {
    "cube": (lambda: cube_mesh(17), euclid, {
        "face centre": (0.5, 0.5, 0.0), "edge": (0.5, 0.0, 0.0), "corner": (0.0, 0.0, 0.0),
        "face (0.3, 0.6)": (0.3, 0.6, 0.0), "interior": (0.3, 0.4, 0.2)}),
    "ball": (lambda: ball_mesh(17), euclid, {"pole": (0.0, 0.0, 1.0), "interior": (0.3, 0.2, 0.1)}),
    "L prism 8": (lambda: l_prism_mesh(8), lambda V, s: l_prism_distance(V, s)[0], {
        "end wall": (2.0, 0.5, 0.5), "floor": (1.75, 0.5, 0.0), "side wall": (1.5, 0.0, 0.5),
        "interior": (1.75, 0.5, 0.5)}),
    "L prism 12": (lambda: l_prism_mesh(12), lambda V, s: l_prism_distance(V, s)[0], {
        "end wall": (2.0, 0.5, 0.5), "floor": (1.75, 0.5, 0.0), "side wall": (1.5, 0.0, 0.5),
        "interior": (1.75, 0.5, 0.5)}),
}


@pytest.fixture(scope="module")
def errors():
    """(domain, source) -> (error now, error before, distance now, distance before, exact)."""
    out = {}
    for domain, (build, exact_fn, sources) in CASES.items():
        V, T = build()
        solver = hc.HeatSolver(TetMesh(V, T))
        for name, point in sources.items():
            s = nearest_vertex(V, point) if name == "interior" else boundary_vertex(solver.domain, V, point)
            exact = exact_fn(V, V[s])
            d, d0 = solver.distance([s]), distance_before(solver, s)
            out[domain, name] = (mean_relative_error(d, exact), mean_relative_error(d0, exact), d, d0, exact)
            print(f"{domain:10s} {name:16s} {100 * out[domain, name][0]:.2f}% (before {100 * out[domain, name][1]:.2f}%)")
    return out


# measured (docs/tet.md): now, before (the L prism 8's "before" re-measured with the near-source
# bounds of heatcore/steps/source_bounds.py, which both columns now get: 0.0542 -> 0.0536, 0.0797 -> 0.0789)
MEASURED = {
    ("cube", "face centre"): (0.0093, 0.0241),
    ("cube", "edge"): (0.0067, 0.0148),
    ("cube", "corner"): (0.0162, 0.0146),
    ("cube", "face (0.3, 0.6)"): (0.0098, 0.0233),
    ("ball", "pole"): (0.0169, 0.0391),
    ("L prism 8", "end wall"): (0.0203, 0.0536),
    ("L prism 8", "floor"): (0.0250, 0.0789),
    ("L prism 8", "side wall"): (0.0149, 0.0496),
    ("L prism 12", "end wall"): (0.0165, 0.0408),
    ("L prism 12", "floor"): (0.0159, 0.0550),
    ("L prism 12", "side wall"): (0.0101, 0.0343),
}


@pytest.mark.parametrize("case", sorted(MEASURED), ids=" - ".join)
def test_boundary_source_accuracy(errors, case):
    now, before, *_ = errors[case]
    measured_now, measured_before = MEASURED[case]
    assert before == pytest.approx(measured_before, abs=5e-4)  # the heat of before, for the comparison
    assert now <= measured_now + 0.0012
    # the targets of issue 22: <= 2% on the cube, <= 3% on the L prism; better than before but at
    # the cube's corner, where the Neumann heat of before is already right (its walls pass through it)
    assert now <= (0.03 if case[0].startswith("L prism") else 0.02)
    assert now < before or case == ("cube", "corner")


@pytest.mark.parametrize("domain", sorted(CASES))
def test_interior_sources_are_unchanged(errors, domain):
    now, _, d, d0, _ = errors[domain, "interior"]
    assert np.array_equal(d, d0)  # bit for bit: interior sources never take the Robin heat
    assert now == pytest.approx({"cube": 0.0074, "ball": 0.0087, "L prism 8": 0.0307, "L prism 12": 0.0216}[domain],
                                abs=5e-4)


def test_boundary_source_distance_goes_around_the_reentrant_edge(errors):
    V, _ = l_prism_mesh(12)
    # behind the edge: measured now (before); the interior source (1.75, 0.5, 0.5) measures 3.65% there
    for name, measured, before in (("end wall", 0.0269, 0.0642), ("floor", 0.0350, 0.0801), ("side wall", 0.0170, 0.0455)):
        _, _, d, d0, exact = errors["L prism 12", name]
        s = int(np.argmin(exact))
        hidden = l_prism_distance(V, V[s])[1]
        assert hidden.mean() > 0.05
        assert np.mean(d[hidden] > euclid(V, V[s])[hidden]) > 0.99
        assert mean_relative_error(d[hidden], exact[hidden]) <= measured + 0.0015
        assert mean_relative_error(d0[hidden], exact[hidden]) == pytest.approx(before, abs=5e-4)


def test_leak_follows_the_source():
    """No Robin leak on the wall through the source (rays run along it), the most on the wall facing it."""
    V, T = cube_mesh(9)
    solver = hc.HeatSolver(TetMesh(V, T))
    heat = solver.heat_flow.boundary_source
    ops = solver.ops
    s = boundary_vertex(solver.domain, V, (0.5, 0.5, 0.0))
    leak = heat.leak(np.array([solver.domain.vertex_map[s]]))
    P = heat.surface.positions
    inner = (P > 1e-9) & (P < 1 - 1e-9)
    floor = (P[:, 2] < 1e-9) & inner[:, 0] & inner[:, 1]
    top = (P[:, 2] > 1 - 1e-9) & inner[:, 0] & inner[:, 1]
    assert np.all(leak[floor] == 0) and np.all(leak[~ops.boundary] == 0)
    # on the top face the rays meet the wall at cos = 1 / |x - s| (height 1): kappa = c cos / sqrt(t)
    cosine = 1.0 / np.linalg.norm(P[top] - P[solver.domain.vertex_map[s]], axis=1)
    area = np.bincount(heat.surface.faces.ravel(), weights=np.repeat(np.linalg.norm(heat.surface.area_vectors, axis=1) / 3, 3),
                       minlength=ops.n_vertices)
    expected = ROBIN_COEFFICIENT * np.sqrt(solver.t[0]) * cosine * area[top]
    assert leak[top] == pytest.approx(expected, rel=1e-9)


def test_blocks_match_single_queries_and_regions():
    V, T = cube_mesh(9)
    mesh = TetMesh(V, T)
    solver = hc.HeatSolver(mesh)
    a, b = boundary_vertex(mesh, V, (0.5, 0.5, 0.0)), boundary_vertex(mesh, V, (1.0, 0.2, 0.7))
    c = nearest_vertex(V, (0.4, 0.4, 0.4))
    bottom = mesh.boundary_faces[(V[mesh.boundary_faces][:, :, 2] < 1e-12).all(axis=1)]
    block = solver.distances([a, [a, b], c, {"region": bottom}])
    single = [solver.distance([a]), solver.distance([a, b]), solver.distance([c]), solver.distance(region=bottom)]
    for row, d in zip(block, single):
        assert np.abs(row - d).max() <= 1e-10 * d.max()
    exact = np.minimum(euclid(V, V[a]), euclid(V, V[b]))
    assert mean_relative_error(single[1], exact) <= 0.0325  # two boundary sources: measured 3.11% (4.89% before)
    # a region on the boundary: distance to the face z = 0 (measured 3.16%, 3.18% before)
    assert mean_relative_error(single[3], V[:, 2]) <= 0.033


def test_other_piece_and_other_boundary_conditions():
    V, T = cube_mesh(7)
    V2 = np.vstack([V, V + [3.0, 0, 0]])
    T2 = np.vstack([T, T + len(V)])
    s = boundary_vertex(TetMesh(V, T), V, (0.5, 0.5, 0.0))
    d = hc.HeatSolver(TetMesh(V2, T2)).distance([s])
    assert np.isinf(d[len(V):]).all() and np.isfinite(d[: len(V)]).all()
    assert np.allclose(d[: len(V)], hc.HeatSolver(TetMesh(V, T)).distance([s]), rtol=1e-9, atol=1e-12)
    # Neumann and Dirichlet conditions keep the Neumann heat for a boundary source
    before = TetMesh(V, T)
    before.operators.boundary_surface = None
    for boundary in ("neumann", "dirichlet"):
        assert np.array_equal(hc.HeatSolver(TetMesh(V, T), boundary=boundary).distance([s]),
                              hc.HeatSolver(before, boundary=boundary).distance([s]))


def test_boundary_source_heat_without_surface_is_the_neumann_heat():
    ops = hc.TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0).operators
    heat = BoundarySourceHeat(ops, ops.laplacian.tocsr(), 1.0, None)
    u = np.array([0.5, 0.25, 0.25])
    assert heat.heat(np.array([1.0, 0, 0]), u, np.ones(3, bool)) is u
