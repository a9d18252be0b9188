"""The compiled kernels of a large mesh's build (heatcore.domains.build_kernels) give the numpy path's arrays, bit for bit.

A build takes them from ``heatcore.compiled.LARGE_BUILD_FACES`` faces on; here
that size is moved to 0 (every build compiled) or out of reach (numpy) to put
the two side by side on small meshes.
"""

import numpy as np
import pytest
from conftest import load_shared_mesh
from hypothesis import given, settings
from mesh_strategies import meshes

import heatcore as hc
from heatcore import compiled
from heatcore.domains import build_kernels
from heatcore.domains.intrinsic import IntrinsicTriangulation, face_edge_lengths
from heatcore.domains.refine import unique_edges

NUMPY, KERNELS = 10**18, 0  # LARGE_BUILD_FACES for either path


def test_numba_is_there():
    assert compiled.available(), "numba is missing: pip install -e '.[fast]'"


def test_only_large_builds_take_the_kernels(monkeypatch):
    assert not compiled.use_build_kernels(compiled.LARGE_BUILD_FACES - 1)
    assert compiled.use_build_kernels(compiled.LARGE_BUILD_FACES)
    monkeypatch.setattr(compiled, "available", lambda: False)  # without numba: numpy at any size
    assert not compiled.use_build_kernels(10**9)


def both_paths(monkeypatch, build):
    """``build()`` on the numpy path and with the kernels, and how often each kernel ran in the second."""
    runs = dict.fromkeys(("edge_table", "vertex_components", "twins_of_pairs", "cotangent_sums", "flip_pairs"), 0)

    def counting(name, kernel):
        def counted(*args):
            runs[name] += 1
            return kernel(*args)

        return counted

    for name in runs:
        monkeypatch.setattr(build_kernels, name, counting(name, getattr(build_kernels, name)))
    monkeypatch.setattr(compiled, "LARGE_BUILD_FACES", NUMPY)
    plain = build()
    assert not any(runs.values())
    monkeypatch.setattr(compiled, "LARGE_BUILD_FACES", KERNELS)
    return plain, build(), runs


def assert_same_triangulation(a, b):
    np.testing.assert_array_equal(a.faces, b.faces)
    np.testing.assert_array_equal(a.lengths, b.lengths)  # bit for bit: the same operations in the same order
    np.testing.assert_array_equal(a.twin, b.twin)


def flipped(V, F):
    """The intrinsic Delaunay triangulation of (V, F), and its number of flips."""
    F = np.asarray(F, dtype=np.int64)
    _, side_edge, pairs = unique_edges(F, with_pairs=True)
    tri = IntrinsicTriangulation.from_mesh(None, F, lengths=face_edge_lengths(V, F), side_edge=side_edge,
                                           side_pairs=pairs)
    return tri, tri.flip_to_delaunay()


@given(meshes(max_parts=2))
@settings(max_examples=60, deadline=None)
def test_edge_table_is_unique_edges(mesh):
    expected = unique_edges(mesh.F, with_pairs=True)
    got = build_kernels.edge_table(mesh.F)
    for a, b in zip(expected, got):
        np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize("seed", range(3))
def test_edge_table_on_soups_fans_and_repeated_edges(seed):
    """Random faces on few vertices: loops, edges of one, two and many sides, fans longer than the insertion sort."""
    rng = np.random.default_rng(seed)
    F = rng.integers(0, 12, size=(400, 3))
    F[:40, 0] = 0  # vertex 0 in a fan of over 16 sides
    for a, b in zip(unique_edges(F, with_pairs=True), build_kernels.edge_table(F)):
        np.testing.assert_array_equal(a, b)


def noisy(name, seed=0):
    V, F = load_shared_mesh(name)
    edge = np.linalg.norm(V[F[:, 0]] - V[F[:, 1]], axis=1).mean()
    return V + np.random.default_rng(seed).normal(scale=0.3 * edge, size=V.shape), F


def skewed_grid(n=60):
    """A sheared grid whose rows crowd together (cubed heights), cut along the long diagonals: thin triangles,
    thousands of flips over several rounds."""
    x, y = np.meshgrid(np.arange(n), np.linspace(0, 1, n) ** 3)
    x = x + 0.8 * np.arange(n)[:, None]  # each row shifted: parallelograms
    V = np.column_stack([x.ravel() / n, y.ravel(), np.zeros(n * n)])
    c = (np.arange(n - 1)[:, None] * n + np.arange(n - 1)).ravel()
    return V, np.vstack([np.column_stack([c, c + 1, c + n + 1]), np.column_stack([c, c + n + 1, c + n])])


@pytest.mark.parametrize("case", ["spot", "homer", "noisy spot", "noisy fandisk", "skewed grid"])
def test_flips_are_the_numpy_flips(case, monkeypatch):
    V, F = {"noisy spot": lambda: noisy("spot"), "noisy fandisk": lambda: noisy("fandisk", 1),
            "skewed grid": skewed_grid}.get(case, lambda: load_shared_mesh(case))()
    (plain, n_plain), (fast, n_fast), runs = both_paths(monkeypatch, lambda: flipped(V, F))
    assert n_plain == n_fast > 100
    assert runs["cotangent_sums"] >= 2 and runs["flip_pairs"] >= 1  # a flipping round, then the final check
    assert_same_triangulation(plain, fast)


def test_flip_of_two_faces_sharing_three_edges(monkeypatch):
    """A pillow (two triangles glued along all three sides): a flip's outer edges are twins of each other."""
    V = np.array([[0, 0, 0], [4, 0, 0], [0, 0.5, 0]], float)
    F = np.array([[0, 1, 2], [0, 2, 1]])

    def pillow():
        tri = IntrinsicTriangulation(F.copy(), face_edge_lengths(V, F), np.array([3, 5, 4, 0, 2, 1]))
        h0, h1 = np.array([0]), np.array([3])
        if not compiled.use_build_kernels(2):
            tri._flip(h0, h1, np.full(6, -1))
        else:
            build_kernels.flip_pairs(tri.faces, tri.lengths, tri.twin, h0, h1)
        return tri

    plain, fast, _ = both_paths(monkeypatch, pillow)
    assert_same_triangulation(plain, fast)
    assert (fast.twin[fast.twin] == np.arange(6)).all()


def test_a_mesh_built_with_the_kernels_is_the_same_mesh(monkeypatch):
    """The whole build and a distance: the same bits (noisy nefertiti: 21k flips)."""
    V, F = noisy("nefertiti", 2)

    def built():
        mesh = hc.TriangleMesh(V, F)
        return mesh, hc.HeatSolver(mesh).distance([0])

    (plain, d_plain), (fast, d_fast), runs = both_paths(monkeypatch, built)
    assert all(runs.values()), runs
    assert_same_triangulation(plain.intrinsic, fast.intrinsic)
    np.testing.assert_array_equal(d_plain, d_fast)


def test_a_one_off_on_many_parts_is_the_same(monkeypatch):
    """Three noisy spots side by side, the source on the second: the same parts kept, the same distances."""
    V, F = noisy("spot", 3)
    width = np.ptp(V[:, 0]) * 1.5
    V = np.vstack([V + [k * width, 0, 0] for k in range(3)])
    F = np.vstack([F + k * len(V) // 3 for k in range(3)])
    source = [int(F.max() + 1) // 3 + 10]
    plain, fast, runs = both_paths(monkeypatch, lambda: hc.geodesic_distance(V, F, source))
    assert runs["vertex_components"] >= 1
    np.testing.assert_array_equal(plain, fast)
    assert np.isinf(fast).sum() == 2 * len(V) // 3 and np.isfinite(fast[len(V) // 3 : 2 * len(V) // 3]).all()


@given(meshes(max_parts=3))
@settings(max_examples=40, deadline=None)
def test_components_and_twins_are_the_numpy_ones(mesh):
    from heatcore.domains.intrinsic import halfedge_twins
    from heatcore.domains.parts import vertex_components

    n = mesh.V.shape[0]
    count, part = vertex_components(mesh.F, n)
    got_count, got_part = build_kernels.vertex_components(mesh.F, n)
    assert count == got_count
    np.testing.assert_array_equal(part, got_part)
    pairs = unique_edges(mesh.F, with_pairs=True)[2]
    for oriented in (True, False):
        np.testing.assert_array_equal(halfedge_twins(mesh.F, pairs=pairs, oriented=oriented),
                                      build_kernels.twins_of_pairs(mesh.F, pairs, oriented))


def test_components_of_edges_and_soups():
    """Elements of two corners and of four; repeated and lone vertices."""
    rng = np.random.default_rng(5)
    from heatcore.domains.parts import vertex_components

    for k in (2, 3, 4):
        E = rng.integers(0, 300, size=(120, k))
        expected = vertex_components(E, 310)
        got = build_kernels.vertex_components(E, 310)
        assert expected[0] == got[0]
        np.testing.assert_array_equal(expected[1], got[1])
