"""The compiled fast marching of accuracy="high" (heatcore.fast_marching) against the vectorized pass.

tests/test_eikonal.py runs every accuracy test with both passes; here, the two side by side.
"""

import numpy as np
import pytest
from conftest import exact_distance, load_shared_mesh, mean_relative_error

import heatcore as hc
from heatcore import eikonal, fast_marching


@pytest.fixture(scope="module")
def spot():
    V, F = load_shared_mesh("spot")
    dom = hc.TriangleMesh(V, F)
    return V, F, dom, hc.HeatSolver(dom), hc.HeatSolver(dom, accuracy="high")


def test_numba_is_there():
    assert fast_marching.available(), "numba is missing: pip install -e '.[fast]'"


def test_march_needs_no_heat_and_agrees_with_the_vectorized_pass(spot, monkeypatch):
    """Measured on spot: median difference 4e-8 relative, 99% of the vertices within 2e-6."""
    _, _, dom, smooth, high = spot
    pins = dom.source_pins([0, 1500])
    heat_distance = smooth.distance_from_pins(pins)
    with monkeypatch.context() as patch:
        patch.setattr(high, "heat", lambda impulse: pytest.fail("the march solved for heat"))
        march = high.distance_from_pins(pins)
    monkeypatch.setattr(fast_marching, "available", lambda: False)
    bands = high.distance_from_pins(pins)
    np.testing.assert_array_equal(bands, eikonal.refine_distance(dom, heat_distance, pins))
    difference = np.abs(march - bands) / np.maximum(bands, 1e-300)
    assert np.median(difference) < 1e-6
    assert np.quantile(difference, 0.99) < 1e-4
    np.testing.assert_array_equal(march[pins.vertices], pins.values)


def test_march_is_at_least_as_close_to_exact(spot, monkeypatch):
    V, F, _, _, high = spot
    exact = exact_distance(V, F, 700)
    march = high.distance([700])
    monkeypatch.setattr(fast_marching, "available", lambda: False)
    bands = high.distance([700])
    # measured: 0.19% both (spot's 2,930 input vertices)
    assert mean_relative_error(march, exact) <= mean_relative_error(bands, exact) + 1e-5
    assert mean_relative_error(march, exact) < 0.003


def test_readers_hold_every_corner_twice_turned_to_its_reader():
    V = np.array([[0, 0], [2, 0], [0.5, 1], [2, 1.5]], float)
    F = np.array([[0, 1, 2], [1, 3, 2]])
    L = np.linalg.norm(V[F[:, [1, 2, 0]]] - V[F[:, [2, 0, 1]]], axis=2)
    readers = fast_marching.Readers(4, *eikonal.corner_layout([F, F[:, [1, 2, 0]]], [L, L[:, [1, 2, 0]]]))  # the same faces twice: kept once
    assert readers.layout.shape == (F.size, 5) and readers.rows.size == 2 * F.size
    for u in range(4):
        corner_vertex, other, layout = readers.turned(u)
        for C, B, (c, x, y, ca, cb) in zip(corner_vertex, other, layout):
            # the layout puts the reader u at (0, 0), B at (c, 0), C at (x, y), y > 0
            assert np.isclose(c, np.linalg.norm(V[B] - V[u]))
            assert np.isclose(np.hypot(x, y), np.linalg.norm(V[C] - V[u])) and np.isclose(ca, np.hypot(x, y))
            assert np.isclose(np.hypot(c - x, y), np.linalg.norm(V[C] - V[B])) and np.isclose(cb, np.hypot(c - x, y))
            assert y > 0


def test_a_high_solver_factors_on_first_need():
    """With the march, accuracy="high" solves nothing: its factorizations wait until something asks."""
    V, F = load_shared_mesh("spot")
    solver = hc.HeatSolver(hc.TriangleMesh(V, F), accuracy="high")
    d = solver.distance([3])
    assert "heat factorization" not in solver.timings and "poisson factorization" not in solver.timings
    assert mean_relative_error(d, exact_distance(V, F, 3)) < 0.003
    assert solver.heat_flow is not None and solver.poisson is not None  # built now, once
    assert {"heat factorization", "poisson factorization"} <= set(solver.timings)
    np.testing.assert_array_equal(solver.distance([3]), d)


def same_readers(a, b):
    """Whether two :class:`fast_marching.Readers` hold the same arrays, bit for bit (nan where nan)."""
    return all(getattr(a, k).dtype == getattr(b, k).dtype and np.array_equal(getattr(a, k), getattr(b, k), equal_nan=True)
               for k in ("start", "rows", "corners", "layout"))


@pytest.mark.parametrize("name", ["spot", "nefertiti"])
def test_the_compiled_corner_table_is_corner_layouts(name):
    """Issue 34: Readers.of_triangles (one compiled pass, 0.5 s at 1M vertices against 2.3 s) equals the numpy build."""
    dom = hc.TriangleMesh(*load_shared_mesh(name))
    faces, lengths = dom.eikonal_triangles()
    assert len(faces[1]) > 0  # flips replaced some of the mesh's faces: the two sets overlap in the rest
    compiled = fast_marching.Readers.of_triangles(dom.n_vertices, faces, lengths)
    assert same_readers(compiled, fast_marching.Readers(dom.n_vertices, *eikonal.corner_layout(faces, lengths)))
    assert compiled.layout.shape[0] == 3 * (len(faces[0]) + len(faces[1])) - 3 * np.count_nonzero(
        np.isin(np.sort(faces[1], axis=1).view("i8,i8,i8"), np.sort(faces[0], axis=1).view("i8,i8,i8")))


def test_the_compiled_corner_table_keeps_corner_layouts_odd_triangles():
    """Duplicates (turned or not), repeated vertices, a flat triangle, vertex numbers past 2**21 (its lexsort), and a
    fan of 40 triangles on one smallest vertex (a sort of its own), listed twice in part."""
    big = 2**21 + 5
    F = np.array([[0, 1, 2], [1, 2, 0], [2, 1, 3], [3, 3, 4], [4, 5, 6], [big, 1, 0], [1, 0, big], [0, big, 1]])
    L = np.array([[1.0, 1.0, 1.0], [1.0, 1.0, 1.0], [1.0, 1.2, 1.3], [1.0, 1.0, 0.0], [1.0, 2.0, 1.0],
                  [2.0, 1.5, 1.0], [1.5, 1.0, 2.0], [1.0, 2.0, 1.5]])
    ring = np.arange(1, 41)
    fan = np.column_stack([np.zeros(40, int), ring, np.roll(ring, -1)])[::-1]  # 40 triangles around vertex 0
    fan_lengths = np.tile([0.16, 1.0, 1.0], (40, 1))
    for faces, lengths in (([F], [L]), ([F[:5], F[5:]], [L[:5], L[5:]]), ([F[:0]], [L[:0]]),
                           ([fan, fan[::3, [1, 2, 0]]], [fan_lengths, fan_lengths[::3, [1, 2, 0]]])):
        expected = fast_marching.Readers(big + 1, *eikonal.corner_layout(faces, lengths))
        assert same_readers(fast_marching.Readers.of_triangles(big + 1, faces, lengths), expected)
    # kept once each: (0 1 2), (1 3 2), (3 3 4), (4 5 6) and (0 big 1) turned: 5 triangles, 3 corners each
    assert fast_marching.Readers.of_triangles(big + 1, [F], [L]).layout.shape == (15, 5)


@pytest.mark.parametrize("pieces", [1, 2, 3])
def test_corner_table_of_several_triangle_sets_is_the_vectorized_one(pieces):
    """``Readers.of_triangles`` reads the first set in place and the others stacked: ``corner_layout``'s table of
    them all (random triangles on few vertices: repeated corners, repeated triangles, every order)."""
    from heatcore.eikonal import corner_layout

    rng = np.random.default_rng(pieces)
    faces = [rng.integers(0, 30, size=(rng.integers(1, 60), 3)) for _ in range(pieces)]
    lengths = [rng.uniform(0.5, 1.5, size=f.shape) for f in faces]
    compiled, vectorized = fast_marching.Readers.of_triangles(30, faces, lengths), fast_marching.Readers(
        30, *corner_layout(faces, lengths))
    for name in ("start", "rows", "corners", "layout"):
        np.testing.assert_array_equal(getattr(compiled, name), getattr(vectorized, name))
