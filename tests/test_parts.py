"""The right answer on the user's shape: parts solved as if alone, any scale, welding, thin strips.

Each test below failed before parts got their own time step, refinement, units and welding
(figures in the comments are the old results).
"""

import warnings

import numpy as np
import pytest
import trimesh
from conftest import exact_distance, load_shared_mesh, mean_relative_error

import heatcore as hc
from heatcore.domains.polygon import PolygonMesh
from heatcore.steps.time_step import HEAT_DECADES_BUDGET, HOP_DECAY_FACTOR, heat_decay_per_hop


def together(*meshes):
    """One mesh made of several (V, F) parts, and the offset of each part's vertices."""
    offsets = np.cumsum([0] + [len(V) for V, _ in meshes])
    V = np.vstack([V for V, _ in meshes])
    F = np.vstack([F + o for (_, F), o in zip(meshes, offsets)])
    return V, F, offsets


@pytest.fixture(scope="module")
def spot_and_small_part():
    """spot beside a cheburashka at a fifth of its size (an ogre-like mesh: a body and a small part)."""
    spot = load_shared_mesh("spot")
    V, F = load_shared_mesh("cheburashka")
    small = (0.2 * V + [3.0, 0, 0], F)
    return spot, small, exact_distance(*spot, 0), exact_distance(*small, 0)


@pytest.mark.parametrize("accuracy", ["smooth", "high"])
def test_each_part_is_solved_as_if_alone(spot_and_small_part, accuracy):
    # before: one h for the whole mesh; spot 1.27% -> 5.2%, the small part 0.84% -> 6.9% (smooth)
    spot, small, exact_spot, exact_small = spot_and_small_part
    V, F, offsets = together(spot, small)
    d = hc.geodesic_distance(V, F, [0, offsets[1]], accuracy=accuracy)
    for (Vp, Fp), exact, part in ((spot, exact_spot, slice(0, offsets[1])), (small, exact_small, slice(offsets[1], None))):
        alone = hc.geodesic_distance(Vp, Fp, [0], accuracy=accuracy)
        assert mean_relative_error(d[part], exact) <= 1.05 * mean_relative_error(alone, exact)
        np.testing.assert_allclose(d[part], alone, rtol=1e-9, atol=1e-12 * alone.max())


def test_a_part_does_not_depend_on_the_size_of_the_others(spot):
    # before: the refinement level came from the total vertex count (spot beside rocker-arm: 0 levels, alone 1)
    alone = hc.geodesic_distance(*spot, [7])
    rocker = load_shared_mesh("rocker-arm")
    for other in ((spot[0] + 5.0, spot[1]), (rocker[0] * 3 + 100, rocker[1])):
        V, F, offsets = together(spot, other)
        d = hc.geodesic_distance(V, F, [7, offsets[1] + 3])
        assert np.abs(d[: offsets[1]] - alone).max() <= 1e-9 * alone.max()


def test_a_refined_part_beside_an_unrefined_one_each_as_alone(spot):
    """The refined part reads two heat steps, the unrefined one keeps one (``two_step_vertices`` a mask)."""
    n = 110  # 12,100 vertices: not refined by "auto"
    x, y = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n), indexing="ij")
    i, j = np.meshgrid(np.arange(n - 1), np.arange(n - 1), indexing="ij")
    a = (i * n + j).ravel()
    grid = (np.c_[x.ravel() + 5.0, y.ravel(), np.zeros(n * n)], np.r_[np.c_[a, a + n, a + n + 1], np.c_[a, a + n + 1, a + 1]])
    V, F, offsets = together(spot, grid)
    mesh = hc.TriangleMesh(V, F)
    mask = mesh.two_step_vertices()
    assert mesh.part_levels.tolist() == [1, 0] and mask.sum() == mesh.operators.n_vertices - n * n
    d = hc.HeatSolver(mesh).distance([7, offsets[1] + 3])
    for (Vp, Fp), part, source in ((spot, slice(0, offsets[1]), 7), (grid, slice(offsets[1], None), 3)):
        alone = hc.geodesic_distance(Vp, Fp, [source])
        np.testing.assert_allclose(d[part], alone, rtol=1e-9, atol=1e-12 * alone.max())


@pytest.mark.parametrize("scale", [1e-300, 1e-100, 1e-60, 3.7e-7, 1e60, 1e100, 1e300])
def test_distances_scale_with_the_mesh_at_any_finite_scale(spot, scale):
    # before: 1e-60 all zeros, 1e-100 NaN, 1e60 NaN, 1e100 SolverError
    V, F = spot
    solver = hc.HeatSolver(hc.TriangleMesh(V, F))
    scaled = hc.HeatSolver(hc.TriangleMesh(V * scale, F))
    for kind in ({"vertices": [0, 900]}, {"points": ([40], [[0.2, 0.3, 0.5]])}):
        d, ds = solver.distance(**kind), scaled.distance(**kind)
        assert np.isfinite(ds).all()
        np.testing.assert_allclose(ds / scale, d, rtol=1e-9, atol=1e-12 * d.max())


def test_scale_with_high_accuracy_and_several_parts(spot):
    V, F = spot
    W, G, offsets = together((V, F), (V * 1e-80, F))
    d = hc.geodesic_distance(W, G, [0, offsets[1]], accuracy="high")
    np.testing.assert_allclose(d[offsets[1] :] * 1e80, d[: offsets[1]], rtol=1e-9)


def strip(width, n=200):
    """A 1 x width strip of 2 (n - 1) triangles; vertices 0..n-1 on one side."""
    x = np.linspace(0.0, 1.0, n)
    V = np.r_[np.c_[x, np.zeros(n), np.zeros(n)], np.c_[x, np.full(n, width), np.zeros(n)]]
    i = np.arange(n - 1)
    F = np.r_[np.c_[i, i + 1, n + i], np.c_[i + 1, n + i + 1, n + i]]
    return V, F


@pytest.mark.parametrize("width", [1e-6, 1e-8, 1e-10])
def test_thin_strip_is_measured_along_its_length(width):
    # before: the far end of the 1e-8 strip at 0.416 (0.38 with refinement) instead of 1
    V, F = strip(width)
    d = hc.geodesic_distance(V, F, [0])
    assert abs(d[199] - 1.0) < 0.02 and abs(d[399] - 1.0) < 0.02
    np.testing.assert_allclose(d[:200], V[:200, 0], rtol=0.02, atol=0.01)


def test_thin_parts_leave_ordinary_meshes_alone(spot):
    mesh = hc.TriangleMesh(*spot)
    assert mesh.thin_parts.size == 0 and mesh.mollification.tolist() == [0.0]


def soup(V, F):
    """Every triangle with three vertices of its own, as an STL file stores it."""
    return V[F].reshape(-1, 3), np.arange(3 * len(F)).reshape(-1, 3)


def test_triangle_soup_is_welded_by_default(spot):
    # before: 17,565 of 17,568 vertices inf
    V, F = spot
    SV, SF = soup(V, F)
    mesh = hc.TriangleMesh(SV, SF)
    assert mesh.n_welded == len(SV) - len(V) and mesh.n_parts == 1
    source = int(np.flatnonzero(F.ravel() == 0)[0])  # a soup vertex standing for vertex 0
    d = hc.HeatSolver(mesh).distance([source])
    np.testing.assert_allclose(d, hc.geodesic_distance(V, F, [0])[F.ravel()], rtol=1e-9, atol=1e-12)
    apart = hc.geodesic_distance(SV, SF, [source], weld=None, refine=0)
    assert np.isinf(apart).sum() == len(SV) - 3


def test_auto_refinement_of_many_parts_keeps_to_a_budget():
    """5,856 loose triangles would each be refined to 16k vertices (96M in all)."""
    V, F = soup(*load_shared_mesh("spot"))
    with pytest.warns(hc.HeatcoreWarning, match="at most 3 levels"):
        mesh = hc.TriangleMesh(V, F, weld=None)
    assert mesh.operators.n_vertices <= 1_000_000


def test_weld_tolerance_merges_near_copies():
    grid = trimesh.creation.box().subdivide().subdivide()
    V, F = soup(np.asarray(grid.vertices), np.asarray(grid.faces))
    V = V + np.random.default_rng(0).uniform(-1e-9, 1e-9, V.shape)
    assert np.isinf(hc.geodesic_distance(V, F, [0], refine=0)).any()  # exact matching finds no twin
    d = hc.geodesic_distance(V, F, [0], weld=1e-6)
    assert np.isfinite(d).all() and d.max() > 1.0
    with pytest.raises(hc.InvalidOptionError, match="weld"):
        hc.TriangleMesh(V, F, weld=-1.0)


@pytest.mark.parametrize(
    "sources",
    [[[3], [7]], [[1, 2], [3]], [99999999999999999999], np.array([2**64 - 1], dtype=np.uint64), ["a"]],
)
def test_bad_source_lists_are_typed_errors(spot, sources):
    # before: nested lists gave an untyped ValueError; 2**64 - 1 was reported as vertex -1
    with pytest.raises(hc.InvalidSourceError) as info:
        hc.geodesic_distance(*spot, sources, refine=0)
    if np.asarray(sources, dtype=object).ravel()[0] == 2**64 - 1:
        assert str(2**64 - 1) in str(info.value)


def bowtie_and_pentagram():
    bowtie = np.array([[0, 0, 0], [1, 1, 0], [1, 0, 0], [0, 1, 0]], float)
    angle = np.pi / 2 + 2 * np.pi * np.arange(5) / 5
    pentagon = np.c_[np.cos(angle), np.sin(angle), np.zeros(5)] + [3.0, 0, 0]
    V = np.vstack([bowtie, pentagon, [[2.0, 0, 0], [2.0, 1, 0]]])
    return V, [[0, 1, 2, 3], [4, 6, 8, 5, 7], [2, 9, 10, 1]]


def test_self_crossing_polygons_are_named():
    # before: distances shorter than the straight line
    V, P = bowtie_and_pentagram()
    with pytest.raises(hc.InvalidMeshError, match=r"2 polygon\(s\) cross themselves.*: 0 \(sides 0 and 2\), 1 "):
        PolygonMesh(V, P)
    with pytest.warns(hc.HeatcoreWarning, match="split into triangles"):
        mesh = PolygonMesh(V, P, split_crossing=True, virtual=True)
    assert mesh.n_virtual == 1  # the one simple quad keeps its virtual vertex
    simple = PolygonMesh(V, [[0, 2, 1, 3]], virtual=True)  # the same four corners in their proper order
    assert simple.n_virtual == 1
    assert PolygonMesh(V, [[0, 2, 1, 3]]).n_triangulated == 1  # by default: its triangles


def test_welding_reports_every_input_vertex(spot):
    V, F = spot
    W = np.vstack([V, V[:5]])  # five unreferenced copies of referenced vertices
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        d = hc.geodesic_distance(W, F, [0])
    np.testing.assert_array_equal(d[-5:], d[:5])


def test_tet_and_polygon_parts_get_their_own_time_step():
    """Two copies of a domain, one 128 times smaller: each copy's distances as alone (scaled)."""
    from scipy.spatial import Delaunay

    from heatcore.domains.tet import TetMesh

    V = np.stack(np.meshgrid(*[np.arange(4.0)] * 3, indexing="ij"), -1).reshape(-1, 3)
    V = V + np.random.default_rng(1).uniform(-0.2, 0.2, V.shape)
    T = Delaunay(V).simplices
    quads = [[a, a + 1, a + 6, a + 5] for a in (5 * y + x for y in range(4) for x in range(4))]
    Q = np.array([[x, y, 0.1 * x * y] for y in range(5) for x in range(5)], float)
    for make, (P, E) in ((TetMesh, (V, T)), (PolygonMesh, (Q, np.array(quads)))):
        alone = hc.HeatSolver(make(P, E)).distance([0])
        n = len(P)
        both = hc.HeatSolver(make(np.vstack([P, P / 128 + 50]), np.vstack([E, E + n]))).distance([0, n])
        np.testing.assert_allclose(both[:n], alone, rtol=1e-9)
        np.testing.assert_allclose(both[n:], alone / 128, rtol=1e-9)


def test_polygon_indices_beyond_int64_are_reported_as_given():
    V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)
    with pytest.raises(hc.InvalidMeshError, match="references vertex 18446744073709551615"):
        PolygonMesh(V, np.array([[0, 1, 2, 2**64 - 1]], dtype=np.uint64))
    with pytest.raises(hc.InvalidMeshError, match="offsets must start at 0"):
        PolygonMesh(V, (np.array([0, 2**64 - 1], dtype=np.uint64), np.arange(4)))


def test_long_strip_raises_m_so_the_far_end_keeps_its_heat():
    """3,000 hops: at m = 1 the heat would fall about 1,650 decades (underflow); m is raised just enough."""
    V, F = strip(0.001, n=3001)
    solver = hc.HeatSolver(hc.TriangleMesh(V, F, refine=0))
    budget = solver.hop_diameter * HOP_DECAY_FACTOR * heat_decay_per_hop(solver.m_effective)
    assert solver.m_effective > 10 and budget == pytest.approx(HEAT_DECADES_BUDGET, rel=1e-9)
    d = solver.distance([0])
    np.testing.assert_allclose(d[:3001], V[:3001, 0], rtol=0.02, atol=0.01)
    assert hc.HeatSolver(hc.TriangleMesh(*strip(0.001), refine=0)).m_effective == 1.0  # 200 hops: no raise


@pytest.mark.parametrize("seed", range(5))
def test_breadth_first_hops_equal_dijkstra(seed):
    """One root: the search-tree depths by pointer jumping are Dijkstra's unweighted hops (inf off its part)."""
    from scipy.sparse.csgraph import dijkstra

    from heatcore.domains.parts import _hops_from, vertex_graph

    rng = np.random.default_rng(seed)
    edges = rng.integers(0, 400, (300, 2))
    graph = vertex_graph(edges, 400)  # sparse: several parts and loose vertices
    root = edges[:1, 0]
    expected = dijkstra(graph, directed=True, indices=root, unweighted=True, min_only=True)
    np.testing.assert_array_equal(_hops_from(graph, root), expected)
    assert np.isinf(expected).any() and expected[np.isfinite(expected)].max() > 3
    # A few roots, some in one part: a search from each, the nearest kept; as many as FEW_ROOTS allows
    for roots in (edges[:3, 0], edges[:16, 1]):
        expected = dijkstra(graph, directed=True, indices=roots, unweighted=True, min_only=True)
        np.testing.assert_array_equal(_hops_from(graph, roots), expected)


def test_the_estimate_reuses_the_bounds_sweep(monkeypatch):
    """A solver whose bounds ask for the double sweep makes two searches, not three (the first is the bounds')."""
    from heatcore.domains import parts

    searches = []
    real = parts._search_depths
    monkeypatch.setattr(parts, "_search_depths", lambda graph, root: searches.append(root) or real(graph, root))
    x = np.linspace(0.0, 30.0, 3001)  # a strip 3,000 hops long: its m is raised, which takes the second sweep
    V = np.r_[np.c_[x, np.zeros_like(x), np.zeros_like(x)], np.c_[x, np.full_like(x, 0.001), np.zeros_like(x)]]
    i = np.arange(3000)
    F = np.r_[np.c_[i, i + 1, i + 3001], np.c_[i + 1, i + 3002, i + 3001]]
    solver = hc.HeatSolver(hc.TriangleMesh(V, F, refine=0))
    assert solver.m_effective > 10 and len(searches) == 2
    assert 3000 <= solver.hop_diameter <= 3001  # the strip is 3,000 edges long


def test_hop_diameter_is_the_surfaces_not_the_corner_order():
    """The underflow guard's hop count does not change when each face lists another corner first.

    It counted hops on a star from each face's first corner: two meshes of the same triangles (a
    PolygonMesh of triangulated letters and its TriangleMesh twin) got 683 and 784 hops, and so
    different time steps. Counted along every side, they get the same.
    """
    from heatcore.domains.parts import edge_graph, hop_diameters, vertex_components

    n = 40
    x, y = np.meshgrid(np.arange(n), np.arange(3))
    idx = (y * n + x)[:-1, :-1].ravel()
    F = np.r_[np.c_[idx, idx + 1, idx + n + 1], np.c_[idx, idx + n + 1, idx + n]]
    rng = np.random.default_rng(0)
    rotated = np.array([np.roll(f, k) for f, k in zip(F, rng.integers(0, 3, len(F)))])
    hops = []
    for faces in (F, rotated):
        graph = edge_graph(faces, 3 * n)
        count, part = vertex_components(faces, 3 * n, graph)
        hops.append(hop_diameters(graph, part, count).tolist())
    assert hops[0] == hops[1] == [n + 1]  # corner to the opposite corner against the diagonals


@pytest.mark.parametrize("refine", [0, 2, "auto"])
def test_triangle_mesh_hands_the_solver_the_parts_of_its_operators(spot, refine):
    """The parts a TriangleMesh found on its input faces (carried to refined vertices) are those of its
    operators' elements, numbered alike: the solver takes them instead of finding them again."""
    V, F = spot
    small = (0.2 * V[: len(V) // 2] + [3.0, 0, 0], F[(F < len(V) // 2).all(axis=1)])  # spot cut in half
    V, F, _ = together((V, F), small, (np.eye(3) + [5.0, 0, 0], np.array([[0, 1, 2]])))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hc.HeatcoreWarning)
        ops = hc.TriangleMesh(V, F, refine=refine, weld=None).operators
    count, part = ops.parts
    expected = hc.domains.parts.vertex_components(ops.elements, ops.n_vertices)
    assert count == expected[0] >= 3
    assert part.dtype == expected[1].dtype and np.array_equal(part, expected[1])
