"""Polygon-aware refinement of PolygonMesh (heatcore.domains.polygon_refine) and its accuracy.

PolygonMesh with its defaults against TriangleMesh with its defaults on the fan
triangulation of the same polygons (the ratios of docs/polygon.md, with small
margins), and against potpourri3d's PolygonMeshHeatSolver. The hex grid and
the Catmull-Clark sphere helpers are shared with scripts/bench_polygon.py.
"""

import warnings

import numpy as np
import pytest
from conftest import mean_relative_error
from test_polygon import (
    catmull_clark,
    cube,
    exact_in_subprocess,
    load_polygons,
    manifold_part,
    potpourri_distance,
    quad_grid,
)

import heatcore as hc
from heatcore.domains.polygon import PolygonMesh, fan_triangulate, polygon_arrays
from heatcore.domains.polygon_refine import (
    refine_levels,
    split_polygons,
    vertices_inside,
)
from heatcore.domains.refine import auto_refine_levels

# ---------------------------------------------------------------- meshes


def hex_grid(rows=18, cols=26, jitter=0.0, seed=0):
    """Planar honeycomb of ``rows x cols`` unit-side hexagons (1,024 vertices by default).

    ``jitter`` moves every vertex with three hexagons around it by up to that
    many side lengths in x and y.
    """
    r, c = np.meshgrid(np.arange(rows), np.arange(cols), indexing="ij")
    cx = c.ravel() * np.sqrt(3) + (r.ravel() % 2) * np.sqrt(3) / 2
    cy = r.ravel() * 1.5
    angle = np.deg2rad(30 + 60 * np.arange(6))
    P = np.stack([cx[:, None] + np.cos(angle), cy[:, None] + np.sin(angle)], 2).reshape(-1, 2)
    _, first, idx = np.unique(np.round(P * 1000).astype(np.int64), axis=0, return_index=True, return_inverse=True)
    V = np.c_[P[first], np.zeros(first.size)]
    H = idx.reshape(-1, 6)
    if jitter:
        inner = np.bincount(H.ravel(), minlength=len(V)) == 3
        V[inner, :2] += np.random.default_rng(seed).uniform(-jitter, jitter, (int(inner.sum()), 2))
    return V, H


def cc_sphere(levels=3):
    """Catmull-Clark-subdivided cube (quads) with its vertices pushed onto the unit sphere."""
    V, Q = catmull_clark(*cube(), levels=levels)
    V = V - 0.5
    return V / np.linalg.norm(V, axis=1, keepdims=True), Q


def great_circle(V, s):
    return np.arccos(np.clip(V @ V[s], -1.0, 1.0))


def fan_exact(V, P, sources, tmp_path):
    """Exact geodesics (gdist) on the fan triangulation of the polygons."""
    F = fan_triangulate(*polygon_arrays(P, len(V)))[0]
    return [exact_in_subprocess(V, F, s, tmp_path) for s in sources]


def errors(V, P, sources, exacts, **polygon_options):
    """Mean relative errors (mean over sources) of PolygonMesh (virtual refinement) and TriangleMesh(fan), defaults."""
    F = fan_triangulate(*polygon_arrays(P, len(V)))[0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hc.HeatcoreWarning)
        poly = hc.HeatSolver(PolygonMesh(V, P, **{"virtual": True} | polygon_options))
        tri = hc.HeatSolver(hc.TriangleMesh(V, F))
    ep = np.mean([mean_relative_error(poly.distance([s]), e) for s, e in zip(sources, exacts)])
    et = np.mean([mean_relative_error(tri.distance([s]), e) for s, e in zip(sources, exacts)])
    return ep, et


# ---------------------------------------------------------------- accuracy (docs/polygon.md)


@pytest.mark.parametrize("jitter, ratio", [(0.0, 0.78), (0.2, 0.96)])
def test_hex_grid_beats_the_fan_triangulation_and_potpourri(jitter, ratio, tmp_path):
    V, H = hex_grid(jitter=jitter)
    assert len(V) == 1024
    s = int(np.argmin(np.linalg.norm(V - V.mean(0), axis=1)))
    exact = fan_exact(V, H, [s], tmp_path)  # planar: exact in the honeycomb's outline
    poly, tri = errors(V, H, [s], exact)
    assert poly <= ratio * tri and poly < 0.006  # measured 0.73x / 0.93x, 0.38% / 0.48% (both refined: two heat steps)
    pp3d = potpourri_distance(V, H, s, tmp_path)
    assert pp3d is not None and poly < 0.25 * mean_relative_error(pp3d, exact[0])


@pytest.mark.parametrize("n, jitter, ratio", [(11, 0.0, 0.35), (11, 0.3, 0.62), (31, 0.0, 0.55), (31, 0.3, 0.70)])
def test_quad_grid_beats_the_fan_triangulation(n, jitter, ratio):
    V, Q = quad_grid(n, jitter)
    sources = [(n // 2) * n + n // 2, 0, n + 2]  # centre, corner, near the boundary
    poly, tri = errors(V, Q, sources, [np.linalg.norm(V - V[s], axis=1) for s in sources])
    assert poly <= ratio * tri  # measured 0.31x, 0.57x, 0.51x, 0.66x (0.24x, 0.66x, 0.24x, 0.58x with one heat step)


def test_catmull_clark_sphere_vs_great_circles():
    V, Q = cc_sphere(3)
    sources = [0, 100, 300]
    poly, tri = errors(V, Q, sources, [great_circle(V, s) for s in sources])
    assert poly <= 0.92 * tri and poly < 0.0075  # measured 0.87x, 0.68% (0.57x, 1.00% with one heat step)


def test_catmull_clark_cube_vs_exact(tmp_path):
    V, Q = catmull_clark(*cube(), levels=4)
    poly, tri = errors(V, Q, [0, 700], fan_exact(V, Q, [0, 700], tmp_path))
    assert poly <= 0.60 * tri  # measured 0.56x (0.36x with one heat step)


def test_suzanne_vs_exact_on_its_fan_triangulation(tmp_path):
    m = load_polygons("suzanne")
    P = manifold_part(m.vertices, m.polygons)
    sources = [100, 200, 300]
    poly, tri = errors(m.vertices, P, sources, fan_exact(m.vertices, P, sources, tmp_path))
    assert poly <= 0.95 * tri  # measured 0.91x (1.80% vs 1.98%; one heat step: 0.95x, 2.05% vs 2.15%)


def test_beast_vs_exact_on_its_fan_triangulation(tmp_path):
    # not refined (32k vertices): the non-planar quads' centroid weights make the difference
    m = load_polygons("beast")
    P = manifold_part(m.vertices, m.polygons)
    sources = [0, 10000, 20000]
    poly, tri = errors(m.vertices, P, sources, fan_exact(m.vertices, P, sources, tmp_path), split_crossing=True)
    assert poly <= 0.98 * tri and poly < 0.0280  # measured 0.97x (2.76% vs 2.84%; 0.94x, 2.66%, before thin quads were triangulated)


# ---------------------------------------------------------------- the refinement


def test_split_keeps_planar_surfaces_and_remembers_origins():
    V, P = hex_grid(3, 4, jitter=0.2)
    offsets, corners = polygon_arrays(P, len(V))
    r = split_polygons(V, offsets, corners, np.full(len(P), 2))
    assert np.array_equal(r.vertices[: len(V)], V)  # input vertices first, unchanged
    assert (np.diff(r.offsets) == 4).all() and len(r.offsets) - 1 == 6 * 4 * len(P)
    # the refined quads tile the same area (shoelace sums), and no new point leaves the plane
    def area(X, o, c):
        nxt = np.arange(c.size) + 1
        nxt[o[1:] - 1] = o[:-1]
        return 0.5 * np.sum(X[c, 0] * X[c[nxt], 1] - X[c[nxt], 0] * X[c, 1])

    assert np.isclose(area(r.vertices, r.offsets, r.corners), area(V, offsets, corners))
    assert np.abs(r.vertices[:, 2]).max() == 0
    # each new vertex lies on its input edge or inside its input polygon
    on_edge = r.vertex_edge >= 0
    a, b = V[r.edges[r.vertex_edge[on_edge], 0]], V[r.edges[r.vertex_edge[on_edge], 1]]
    X = r.vertices[on_edge]
    assert np.allclose(np.linalg.norm(X - a, axis=1) + np.linalg.norm(X - b, axis=1), np.linalg.norm(a - b, axis=1))
    inside = np.flatnonzero(r.vertex_polygon >= 0)
    assert inside.size == len(P) * (1 + 6 + 6) and not (on_edge[inside]).any()  # 1 + 6 spokes + 6 sub-centres
    assert np.allclose(vertices_inside(r, offsets, corners, np.array([0])).size, 13 + 6 * 3)


def test_levels_follow_the_triangle_rule_per_part():
    V, Q = quad_grid(11)
    far = np.vstack([V, V + [5, 0, 0]])
    offsets, corners = polygon_arrays(np.vstack([Q, Q[:1] + len(V)]), len(far))  # a big part and one quad
    used = np.unique(corners)
    remap = np.full(len(far), -1)
    remap[used] = np.arange(used.size)
    part_levels, levels, part = refine_levels(used.size, offsets, remap[corners], "auto")
    assert part_levels.tolist() == [auto_refine_levels(121), auto_refine_levels(4)] == [4, 7]
    mesh = PolygonMesh(far, np.vstack([Q, Q[:1] + len(V)]), virtual=True)
    assert mesh.part_levels.tolist() == [4, 7] and mesh.levels == 7
    assert PolygonMesh(V, Q, refine=0).operators.n_vertices == 121
    assert PolygonMesh(V, Q, refine=1, virtual=True).operators.n_vertices == 121 + 220 + 100
    assert PolygonMesh(V, Q, refine=1).operators.n_vertices == 121 + 220 + 100  # side and diagonal midpoints
    assert PolygonMesh(V, Q, refine=4, virtual=True).operators.n_vertices == 161**2
    with pytest.raises(hc.InvalidOptionError):
        PolygonMesh(V, Q, refine=-1)
    # a large mesh is not refined (beast: 32k vertices)
    assert refine_levels(142 * 142, *polygon_arrays(quad_grid(142)[1], 142 * 142), "auto")[0].tolist() == [0]


def test_sources_on_the_refined_mesh():
    V, Q = quad_grid(21)
    mesh = PolygonMesh(V, Q, virtual=True)
    assert mesh.levels == 3
    solver = hc.HeatSolver(mesh)
    d = solver.distance(region=[0, 1, 20, 21])  # [0, 0.1]^2
    exact = np.linalg.norm(V[:, :2] - np.clip(V[:, :2], 0, 0.1), axis=1)
    assert d[exact == 0].max() == 0 and mean_relative_error(d, exact) < 0.012
    assert mesh.source_pins(region=[0]).vertices.size == 9 * 9  # the quad and everything inside it
    e = solver.distance(edges=[[0, 1], [1, 2]])  # the segment [0, 0.1] x {0}
    exact = np.linalg.norm(V[:, :2] - np.c_[np.clip(V[:, 0], 0, 0.1), np.zeros(len(V))], axis=1)
    assert e[0] == e[1] == e[2] == 0 and mean_relative_error(e, exact) < 0.018  # measured 1.53%
    assert mesh.source_pins(edges=[[0, 1]]).vertices.size == 9  # the edge's ends and 7 points on it
    with pytest.raises(hc.InvalidSourceError, match="not an edge"):
        solver.distance(edges=[[0, 22]])


def test_strongly_non_convex_polygons_stay_unfolded():
    # an arrow-head quad: its split quads would cross themselves; they become triangles
    V = np.array([[0, 0, 0], [2, 1, 0], [0, 2, 0], [0.3, 1, 0], [-1, 1, 0]], float)
    mesh = PolygonMesh(V, [[0, 1, 2, 3], [0, 3, 2, 4]], refine=1)
    assert mesh.n_triangulated == 2 and mesh.refinement is None  # triangles: built as TriangleMesh builds them
    sub = mesh.triangles.subdivision
    a, b, c = (sub.vertices[sub.faces[:, k]] for k in range(3))
    assert len(sub.faces) == 16 and (np.cross(b - a, c - a)[:, 2] > 0).all()  # split, none folded
    d = hc.HeatSolver(mesh).distance([4])
    assert abs(d[1] - np.linalg.norm(V[1] - V[3]) - np.linalg.norm(V[3] - V[4])) < 0.25


# ---------------------------------------------------------------- self-crossing polygons


@pytest.mark.parametrize(
    "polygon, sides",
    [([0, 1, 2, 3], "sides 0 and 2"), ([4, 6, 8, 5, 7], "sides 0 and 2")],
)
def test_self_crossing_polygon_is_a_typed_error_naming_it(polygon, sides):
    bowtie = np.array([[0, 0, 0], [1, 1, 0], [1, 0, 0], [0, 1, 0]], float)
    angle = np.pi / 2 + 2 * np.pi * np.arange(5) / 5
    pentagon = np.c_[np.cos(angle), np.sin(angle), np.zeros(5)] + [3.0, 0, 0]
    V = np.vstack([bowtie, pentagon, [[1.0, 3, 0]]])
    polygons = [[0, 2, 9], polygon]  # a good triangle first: the bad polygon is number 1
    with pytest.raises(hc.InvalidMeshError, match=rf"cross themselves, as a bowtie does: 1 \({sides}\)"):
        PolygonMesh(V, polygons)


def test_operator_weights_blend_from_area_minimizer_to_centroid():
    from heatcore.domains.polygon_refine import (
        NONPLANAR_RAMP,
        area_minimizer_weights,
        operator_weights,
    )

    kite = np.array([[0, 0, 0], [2, -1, 0], [3, 0, 0], [2, 1, 0]], float)
    heights = np.array([0.0, 0.5, 1.0, 2.0]) * NONPLANAR_RAMP
    X = np.repeat(kite[None], heights.size, axis=0)
    X[:, [1, 3], 2] = heights[:, None] * 3  # lift two opposite corners: a twist growing with the height
    w, area = operator_weights(X), area_minimizer_weights(X)
    assert np.allclose(w[0], area[0]) and not np.allclose(area[0], 0.25)  # planar: the paper's weights
    assert np.allclose(w[-1], 0.25)  # clearly twisted: the centroid
    assert np.allclose(w.sum(axis=1), 1.0)
    assert np.all(np.abs(np.diff(w, axis=0)) < 0.2)  # no jump on the way
