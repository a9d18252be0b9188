"""Isoline curves (heatcore.isolines): analytic plane and sphere cases, degenerate levels, properties."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from mesh_strategies import _icosphere, meshes

import heatcore as hc
from heatcore.contours import isoline_levels
from heatcore.errors import InvalidMeshError, InvalidOptionError
from heatcore.viz.colormap import colorize


def grid(n, lo=-1.0, hi=1.0, diagonal="random", seed=0):
    """An n x n grid of the square [lo, hi]^2 in the plane z = 0, faces counterclockwise seen from +z.

    ``diagonal``: "up" (cells split along (i, j)-(i+1, j+1)), "down" (along (i+1, j)-(i, j+1)) or "random".
    """
    x = np.linspace(lo, hi, n)
    X, Y = np.meshgrid(x, x, indexing="xy")
    V = np.column_stack([X.ravel(), Y.ravel(), np.zeros(n * n)])
    i, j = np.meshgrid(np.arange(n - 1), np.arange(n - 1), indexing="xy")
    a = (j * n + i).ravel()
    b, c, d = a + 1, a + n, a + n + 1
    up = {"up": np.ones(a.size, bool), "down": np.zeros(a.size, bool)}.get(diagonal)
    if up is None:
        up = np.random.default_rng(seed).random(a.size) < 0.5
    F = np.concatenate([np.where(up[:, None], np.stack([a, b, d], 1), np.stack([a, b, c], 1)),
                        np.where(up[:, None], np.stack([a, d, c], 1), np.stack([b, d, c], 1))])
    return V, F


def mesh_edges(F):
    e = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    return {tuple(x) for x in e.tolist()}


def assert_valid(V, F, values, curves, levels=None):
    """Every property a curve must have, on any mesh and field."""
    V, F, values = np.asarray(V, float), np.asarray(F), np.asarray(values, float)
    edges = mesh_edges(F)
    if levels is not None:
        assert {c.level for c in curves} <= set(np.asarray(levels, float).tolist())
    assert [c.level for c in curves] == sorted(c.level for c in curves)
    for curve in curves:
        c, P, k = curve.level, curve.points, len(curve.points)
        assert P.shape == (k, 3) and k >= (3 if curve.closed else 2)
        assert np.isfinite(P).all()
        a, b = curve.edges[:, 0], curve.edges[:, 1]
        vertex = a == b
        # on a vertex: the vertex itself, whose value is the level (or rounds onto it: a point on an edge
        # 1e-200 of the way from a vertex is that vertex)
        assert np.array_equal(P[vertex], V[a[vertex]]) and (curve.t[vertex] == 0).all()
        assert (np.abs(values[a[vertex]] - c) <= 1e-9 * max(abs(c), np.abs(values[np.isfinite(values)]).max())).all()
        # on an edge of the mesh, below the level at a, at or above it at b
        assert all((min(x, y), max(x, y)) in edges for x, y in zip(a[~vertex], b[~vertex]))
        va, vb = values[a[~vertex]], values[b[~vertex]]
        assert (va < c).all() and (c <= vb).all()
        assert ((curve.t >= 0) & (curve.t < 1)).all()
        # the linear interpolation of the values at the point (read back from its position) is the level
        Va, Vb = V[a[~vertex]], V[b[~vertex]]
        along = Vb - Va
        t = np.einsum("ij,ij->i", P[~vertex] - Va, along) / np.einsum("ij,ij->i", along, along)
        scale = np.maximum.reduce([np.abs(va), np.abs(vb), np.full(va.shape, abs(c)), np.full(va.shape, 1e-300)])
        assert (np.abs(va + t * (vb - va) - c) <= 1e-9 * scale).all()
        off_edge = np.linalg.norm(Va + t[:, None] * along - P[~vertex], axis=1)
        assert (off_edge <= 1e-12 * np.linalg.norm(along, axis=1)).all()
        # no two consecutive points equal (a closed curve: its last and first neither)
        following = np.roll(P, -1, axis=0) if curve.closed else P[1:]
        assert (np.abs(following - P[: len(following)]).max(axis=1) > 0).all()
        # each segment inside one face holding both points' edges (or vertices), all values finite
        assert len(curve.faces) == (k if curve.closed else k - 1)
        ends = np.stack([np.arange(len(curve.faces)), (np.arange(len(curve.faces)) + 1) % k], axis=1)
        for f, (i, j) in zip(curve.faces, ends):
            corners = set(F[f].tolist())
            assert set(curve.edges[i].tolist()) <= corners and set(curve.edges[j].tolist()) <= corners
            assert np.isfinite(values[F[f]]).all()


def signed_area(P):
    x, y = P[:, 0], P[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


# --------------------------------------------------------------------------- plane and sphere


def test_plane_distance_from_a_point_gives_circles():
    n = 61
    V, F = grid(n)
    h = 2.0 / (n - 1) * np.sqrt(2)  # longest edge
    center = np.array([0.013, -0.021, 0.0])  # no vertex, no edge midpoint exactly at a level
    d = np.linalg.norm(V - center, axis=1)
    levels = [0.25, 0.5, 0.75]
    curves = hc.isolines(V, F, d, levels)
    assert_valid(V, F, d, curves, levels)
    assert [c.level for c in curves] == levels and all(c.closed for c in curves)
    for curve in curves:
        r = np.linalg.norm(curve.points - center, axis=1)
        # |x| is convex along an edge: its linear interpolation is above it, by at most h^2 / (8 r_min)
        assert (r <= curve.level + 1e-12).all()
        assert (curve.level - r <= h * h / (8 * (curve.level - h))).all()
        assert len({tuple(p) for p in curve.points.tolist()}) == len(curve.points)  # no point twice
        assert signed_area(curve.points) < 0  # higher values (outside) on the left: clockwise
        assert curve.length == pytest.approx(2 * np.pi * curve.level, rel=2e-3)


def test_sphere_latitudes_are_one_closed_curve_each():
    V, F = _icosphere(4)  # 2562 vertices on the unit sphere
    z = V[:, 2]
    h = max(np.linalg.norm(V[F[:, 0]] - V[F[:, 1]], axis=1))
    heights = [-0.8, -0.35, 0.1, 0.6, 0.0]  # z = 0: the equator runs through vertices and along edges
    curves = hc.isolines(V, F, z, heights)
    assert_valid(V, F, z, curves, heights)
    assert [c.level for c in curves] == sorted(heights) and all(c.closed for c in curves)
    for curve in curves:
        radius = np.sqrt(1 - curve.level**2)  # 2 pi r cos(latitude)
        # the polyline runs on the facets (inside the sphere by at most h^2/8) and zigzags across them
        assert curve.length == pytest.approx(2 * np.pi * radius, rel=h * h)
        assert np.allclose(curve.points[:, 2], curve.level, atol=1e-12)
    equator = curves[2]
    assert (equator.edges[:, 0] == equator.edges[:, 1]).sum() >= 10  # many points on vertices, each once
    assert len({tuple(p) for p in equator.points.tolist()}) == len(equator.points)


def test_levels_count_evenly_spaced():
    V, F = grid(21)
    d = np.linalg.norm(V - [-1, -1, 0], axis=1)
    curves = hc.isolines(V, F, d, 3)
    vmax = d.max()
    assert [c.level for c in curves] == pytest.approx([vmax / 4, vmax / 2, 3 * vmax / 4], rel=1e-15)
    assert isoline_levels(d, 3).tolist() == [c.level for c in curves]
    assert isoline_levels([-1.0, 1.0, np.nan], 1).tolist() == [0.0]  # a signed field: from its minimum
    assert hc.isolines(V, F, d, 0) == [] and hc.isolines(V, F, np.ones(len(V)), 5) == []
    # the dark stripes of colorize(isolines=N) sit on the same levels
    stripes = isoline_levels(d, 4)
    x = np.linspace(0, vmax, 4001)
    dark = colorize(x, isolines=4).sum(axis=1) < 0.5 * colorize(x).sum(axis=1)
    runs = np.split(x[dark], np.flatnonzero(np.diff(np.flatnonzero(dark)) > 1) + 1)
    assert [float(np.mean(r)) for r in runs[1:5]] == pytest.approx(stripes.tolist(), abs=vmax / 2000)  # [0]: at 0+
    assert [c.level for c in hc.isolines(V, F, d, 4)] == stripes.tolist()


# --------------------------------------------------------------------------- degenerate levels


def test_levels_through_vertices_and_along_edges():
    n = 9
    V, F = grid(n, 0.0, n - 1.0, diagonal="down")  # integer coordinates; diagonals along x + y = const
    s = V[:, 0] + V[:, 1]
    levels = [1.0, 4.0, 8.0, 13.0]
    curves = hc.isolines(V, F, s, levels)
    assert_valid(V, F, s, curves, levels)
    assert [c.level for c in curves] == levels
    for curve in curves:  # the level line runs along diagonals: every point a vertex, each once
        k = int(curve.level)
        expected = {(x, k - x) for x in range(n) if 0 <= k - x < n}
        assert not curve.closed and (curve.edges[:, 0] == curve.edges[:, 1]).all()
        assert {tuple(p) for p in curve.points[:, :2].tolist()} == expected and len(curve.points) == len(expected)
    # the other diagonal: the level crosses it at midpoints, between vertices on the level
    V, F = grid(n, 0.0, n - 1.0, diagonal="up")
    curves = hc.isolines(V, F, s, levels)
    assert_valid(V, F, s, curves, levels)
    for curve in curves:
        on_vertex = curve.edges[:, 0] == curve.edges[:, 1]
        assert not curve.closed and on_vertex[::2].all() and not on_vertex[1::2].any()
        assert np.allclose(curve.t[~on_vertex], 0.5)


def test_flat_region_at_the_level_is_outlined_once():
    V, F = grid(21, -1.0, 1.0, seed=3)
    r = np.linalg.norm(V, axis=1)
    values = np.minimum(2.0 - r / 0.45, 1.0)  # a plateau at 1 on the disk r <= 0.45, lower outside
    plateau = values == 1.0
    [curve] = hc.isolines(V, F, values, [1.0])
    assert_valid(V, F, values, [curve], [1.0])
    assert curve.closed and (curve.edges[:, 0] == curve.edges[:, 1]).all()
    on = curve.edges[:, 0]
    assert plateau[on].all() and len(set(on.tolist())) == len(on)
    # exactly the plateau vertices that have a lower neighbour
    lower_neighbour = np.zeros(len(V), bool)
    for x, y in mesh_edges(F):
        lower_neighbour[x] |= plateau[x] and not plateau[y]
        lower_neighbour[y] |= plateau[y] and not plateau[x]
    assert set(on.tolist()) == set(np.flatnonzero(lower_neighbour).tolist())
    # a plateau at the level surrounded by higher values is no curve; neither is a peak at the level
    assert hc.isolines(V, F, 2.0 - values, [1.0]) == []
    peak = np.zeros(len(V))
    peak[np.argmin(r)] = 1.0
    assert hc.isolines(V, F, peak, [1.0]) == []


def test_ridge_and_spur_at_the_level_are_drawn_once():
    n = 11
    V, F = grid(n, 0.0, n - 1.0, diagonal="up")
    x, y = V[:, 0], V[:, 1]
    block = (x >= 2) & (x <= 4) & (y >= 2) & (y <= 4)
    spur = (x == y) & (x >= 5) & (x <= 7)  # vertices at the level along diagonals, out of the block's corner
    ridge = (y == 9) & (x >= 2) & (x <= 6)  # a line on its own
    values = np.where(block | spur | ridge, 1.0, 0.0)
    curves = hc.isolines(V, F, values, [1.0])
    assert_valid(V, F, values, curves, [1.0])
    closed = [c for c in curves if c.closed]
    opened = sorted((c for c in curves if not c.closed), key=lambda c: c.points[:, 1].max())
    assert len(closed) == 1 and len(opened) == 2
    assert {tuple(p) for p in closed[0].points[:, :2].tolist()} == {
        (a, b) for a in range(2, 5) for b in range(2, 5) if a in (2, 4) or b in (2, 4)}
    assert len(closed[0].points) == 8
    spur_line, ridge_line = opened
    assert sorted(map(tuple, spur_line.points[:, :2].tolist())) == [(4, 4), (5, 5), (6, 6), (7, 7)]
    assert sorted(ridge_line.points[:, 0].tolist()) == [2, 3, 4, 5, 6] and (ridge_line.points[:, 1] == 9).all()


def test_open_mesh_curves_end_on_the_boundary():
    V, F = grid(31, seed=5)
    d = np.linalg.norm(V - [0.9, 0.95, 0], axis=1)  # a source near a corner: arcs cut by the boundary
    levels = [0.4, 0.8, 1.2, 1.6, 2.0]
    curves = hc.isolines(V, F, d, levels)
    assert_valid(V, F, d, curves, levels)
    assert len(curves) == 5 and not any(c.closed for c in curves)
    e = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    keys, counts = np.unique(e, axis=0, return_counts=True)
    boundary = {tuple(k) for k in keys[counts == 1].tolist()}
    for curve in curves:
        for end in (curve.edges[0], curve.edges[-1]):
            assert tuple(sorted(end.tolist())) in boundary
            assert np.isclose(np.abs(curve.points[[0, -1], :2]).max(), 1.0)


def test_unreachable_values_give_no_curve_there():
    V, F = grid(31, seed=7)
    d = np.linalg.norm(V - [-0.3, 0.0, 0.0], axis=1)
    d[V[:, 0] > 0.3] = np.inf
    d[np.flatnonzero(V[:, 0] > 0.3)[:5]] = np.nan
    curves = hc.isolines(V, F, d, [0.3, 0.65])
    assert_valid(V, F, d, curves, [0.3, 0.65])
    assert [c.closed for c in curves] == [True, False]  # the larger circle ends where d turns inf
    for curve in curves[1:]:
        assert (curve.points[:, 0] <= 0.3).all()
    assert hc.isolines(V, F, np.full(len(V), np.inf), 4) == []


def test_bad_input_is_refused():
    V, F = grid(3)
    with pytest.raises(InvalidOptionError, match="one value per vertex"):
        hc.isolines(V, F, np.zeros(4), 2)
    with pytest.raises(InvalidOptionError, match="finite"):
        hc.isolines(V, F, np.zeros(len(V)), [np.nan])
    with pytest.raises(InvalidOptionError, match="non-negative"):
        hc.isolines(V, F, np.zeros(len(V)), -1)
    with pytest.raises(InvalidMeshError):
        hc.isolines(V, F + 100, np.zeros(len(V)), 2)


def test_inconsistently_oriented_faces_still_join():
    V, F = grid(21, seed=2)
    d = np.linalg.norm(V - [0.05, 0.02, 0], axis=1)
    flipped = F.copy()
    flipped[::3] = flipped[::3, ::-1]
    [curve] = hc.isolines(V, flipped, d, [0.5])
    [reference] = hc.isolines(V, F, d, [0.5])
    assert_valid(V, flipped, d, [curve], [0.5])
    assert curve.closed and len(curve.points) == len(reference.points)
    assert curve.length == pytest.approx(reference.length, rel=1e-12)


# --------------------------------------------------------------------------- properties


def _strict_crossings(F, values, level):
    D = values[F]
    finite = np.isfinite(D).all(axis=1)
    with np.errstate(invalid="ignore"):
        clear = (np.abs(D - level) > 1e-9 * np.abs(D).max(axis=1, keepdims=True)).all(axis=1)  # no corner near it
        return np.flatnonzero(finite & clear & (D.min(axis=1) < level) & (D.max(axis=1) > level))


@st.composite
def fields(draw, n):
    kind = draw(st.sampled_from(["float", "integer", "mixed"]))
    seed = draw(st.integers(0, 2**16))
    rng = np.random.default_rng(seed)
    if kind == "float":
        values = rng.uniform(-10, 10, n)
    else:  # integer values and integer levels: vertices, edges and faces exactly at the level
        values = rng.integers(-3, 4, n).astype(float)
    if kind == "mixed":
        values[rng.random(n) < 0.2] = np.inf
    return values


@given(st.data())
def test_properties_on_random_meshes(data):
    mesh = data.draw(meshes(max_parts=2, scaled_parts=data.draw(st.sampled_from([False, True]))))
    values = data.draw(fields(mesh.n))
    levels = data.draw(st.one_of(st.integers(0, 6), st.lists(st.integers(-3, 3).map(float), max_size=4),
                                 st.lists(st.floats(-10, 10), max_size=4)))
    curves = hc.isolines(mesh.V, mesh.F, values, levels)
    assert_valid(mesh.V, mesh.F, values, curves)
    # every face that a level crosses clear of its corners holds exactly one segment at that level
    wanted = isoline_levels(values, levels) if isinstance(levels, int) else np.unique(levels)
    for level in wanted:
        got = np.concatenate([c.faces for c in curves if c.level == level] or [np.zeros(0, int)])
        strict = _strict_crossings(mesh.F, values, level)
        counts = np.bincount(got, minlength=len(mesh.F))
        assert (counts[strict] == 1).all()
