"""PolygonMesh on the concave n-gons Blender makes (issue 32, row 1).

The rule: on every polygon mesh, ``PolygonMesh`` is never worse than ``TriangleMesh`` on heatcore's
own triangulation of the same polygons (``triangulate_polygons``), within ``MARGIN``, at every
``refine``; and ``refine="auto"`` is never worse than ``refine=0`` (same margin). Error: the mean
relative error over the vertices with exact distance > 0, for each source on its own.

The meshes come from Blender's own operators (tests/concave_meshes.py): Dissolve Edges on grids,
Limited Dissolve on a UV sphere and on a subdivided cube with extruded bumps, a plate with holes
whose surrounding faces are dissolved, and a text object's letters. Exact references: the
straight-line distance on the dissolved grids (a convex planar domain); elsewhere exact geodesics
(gdist, MMP) on heatcore's triangulation of the polygons, computed once per session (in a child
process: gdist segfaults on non-manifold input).

Measured (2026-11-28) where the rule does not hold yet: those cases are marked ``xfail(strict=True)``
with their figures, so that they report when a change makes them pass.
"""

import functools

import numpy as np
import pytest

pytest.importorskip("bpy")

import concave_meshes as cm  # noqa: E402
from hypothesis import given  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

#: PolygonMesh's error may exceed the triangulation's by this factor (and refine="auto" that of refine=0).
MARGIN = 1.02

REFINES = (0, 1, 2, "auto")


def _grid(seed, n=24, count=150):
    V, P = cm.dissolved_grid(n=n, count=count, seed=seed)
    centre, corner = cm.nearest_vertex(V, (0, 0, 0)), cm.nearest_vertex(V, (-1, -1, 0))
    sources = [centre, corner, cm.reflex_corner(V, P, (0.3, 0.2, 0))]
    return V, P, sources, None  # None: straight-line distance


def _sphere(angle):
    V, P = cm.dissolved_uv_sphere(angle=angle)
    pole, equator = cm.nearest_vertex(V, (0, 0, 1)), cm.nearest_vertex(V, (1, 0, 0))
    return V, P, [pole, equator, cm.reflex_corner(V, P, (0, -1, 0))], "gdist"


def _cube():
    V, P = cm.bumpy_cube(cuts=5, bumps=8, seed=0)
    sources = [cm.nearest_vertex(V, (1, 1, 1)), cm.nearest_vertex(V, (0, 0, 1)), cm.reflex_corner(V, P, (0, -1, 0))]
    return V, P, sources, "gdist"


def _plate():
    V, P = cm.holed_plate()
    sources = [cm.nearest_vertex(V, (0, 0, 0)), cm.nearest_vertex(V, (-1, -1, 0)), cm.reflex_corner(V, P, (0, 0, 0))]
    return V, P, sources, "gdist"


def _text():
    V, P = cm.text_mesh("heat GS")
    first, second = cm.reflex_corner(V, P, (0.3, 0.3, 0)), cm.reflex_corner(V, P, (1.5, 0.3, 0))
    sources = [first, second, cm.nearest_vertex(V, (4, 0.3, 0))]
    return V, P, sources, "gdist"


BUILDERS = {
    "grid24-seed0": lambda: _grid(0),
    "grid24-seed1": lambda: _grid(1),
    "grid24-seed2": lambda: _grid(2),
    "grid7-count21-seed3": lambda: _grid(3, n=7, count=21),  # what the hypothesis test below found
    "uvsphere-limited10": lambda: _sphere(10.0),
    "uvsphere-limited20": lambda: _sphere(20.0),
    "cube-bumps-limited5": _cube,
    "plate-holes": _plate,
    "text-heat-GS": _text,
}

#: (case, refine) -> measured failure of the rule (PolygonMesh / triangulation, worst source), 2026-11-28, after
#: concave, straight-cornered, thin and non-planar n-gons were triangulated and the mesh's own triangles flipped to
#: Delaunay, and parts of triangles only built as TriangleMesh builds them (the text: 1.18-1.33x before).
KNOWN = {
    ('grid7-count21-seed3', 1): 'measured 1.58 / 1.71 / 1.44% against 2.11 / 1.65 / 1.75% (x1.03)',
    ('plate-holes', 1): 'measured 3.19 / 1.48 / 2.56% against 2.77 / 1.35 / 2.15% (x1.19)',
    ('plate-holes', 2): 'measured 2.08 / 1.03 / 1.77% against 1.80 / 1.15 / 1.62% (x1.15)',
    ('plate-holes', 'auto'): 'measured 1.30 / 0.71 / 1.20% against 1.21 / 1.11 / 1.35% (x1.07)',
}


@functools.cache
def case(name):
    """``(V, P, T, sources, exact)`` of a named mesh; built and its exact distances computed once per session."""
    V, P, sources, reference = BUILDERS[name]()
    T = cm.heatcore_triangles(V, P)
    if reference is None:
        exact = [np.linalg.norm(V - V[s], axis=1) for s in sources]
    else:
        edges = np.sort(np.concatenate([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]]), axis=1)
        assert np.unique(edges, axis=0, return_counts=True)[1].max() <= 2, "gdist needs a manifold triangulation"
        exact = list(cm.exact_geodesics(V, T, sources))
    return V, P, T, sources, exact


@functools.cache
def measured(name, refine):
    """``(polygon errors, triangulation errors, n_triangulated)`` per source."""
    V, P, T, sources, exact = case(name)
    return cm.measure(V, P, T, sources, exact, refine)


def with_known(params, key=lambda p: p):
    """``params`` with the KNOWN failures marked ``xfail(strict=True)``."""
    marked = []
    for p in params:
        values = p if isinstance(p, tuple) else (p,)
        reason = KNOWN.get(key(p))
        marked.append(pytest.param(*values, marks=pytest.mark.xfail(strict=True, reason=reason)) if reason else p)
    return marked


@pytest.mark.parametrize("name", BUILDERS)
def test_blender_leaves_concave_polygons_and_polygon_mesh_triangulates_them(name):
    V, P, T, sources, exact = case(name)
    concave = cm.n_concave(V, P)
    assert concave > 0, f"{name}: Blender left no concave polygon: the case tests nothing"
    assert len(T) == sum(len(p) - 2 for p in P)
    assert measured(name, 0)[2] >= concave  # n_triangulated: concave ones and straight-cornered ones


@pytest.mark.parametrize(("name", "refine"), with_known([(n, r) for n in BUILDERS for r in REFINES]))
def test_polygon_mesh_is_never_worse_than_heatcores_triangulation(name, refine):
    polygon, triangles, _ = measured(name, refine)
    ratio = polygon / triangles
    assert (ratio <= MARGIN).all(), f"{name} refine={refine}: {polygon.round(5)} against {triangles.round(5)}"


@pytest.mark.parametrize("name", with_known(list(BUILDERS), key=lambda n: (n, "auto-vs-0")))
def test_refine_auto_is_never_worse_than_refine_0(name):
    auto, zero = measured(name, "auto")[0], measured(name, 0)[0]
    assert (auto <= MARGIN * zero).all(), f"{name}: refine='auto' {auto.round(5)} against refine=0 {zero.round(5)}"


@pytest.mark.parametrize("refine", [1, "auto"])
def test_letters_of_triangles_only_are_built_as_their_triangulation(refine):
    """Every letter is triangulated: each part is then built as TriangleMesh builds it, same time step included.

    Measured before (2026-11-28): 1.30x, 1.33x and 1.18x the triangulation's error at refine 1, 2 and auto (the
    refined polygons' longer step applied to triangles, thin letters not mollified as TriangleMesh mollifies them,
    and the underflow guard counting 683 hops on one letter where the twin counted 784).
    """
    import heatcore as hc

    V, P, T, sources, _ = case("text-heat-GS")
    polygon_mesh = hc.PolygonMesh(V, P, refine=refine)
    assert polygon_mesh.n_virtual == 0
    polygons, triangles = hc.HeatSolver(polygon_mesh), hc.HeatSolver(hc.TriangleMesh(V, T, refine=refine))
    np.testing.assert_allclose(polygons.t, triangles.t, rtol=1e-9)
    np.testing.assert_allclose(polygons.distance([sources[1]]), triangles.distance([sources[1]]), rtol=1e-6)


@pytest.mark.xfail(strict=True, reason="measured: n=7, 21 edges, seed=3 at refine=1 (grid7-count21-seed3 above)")
@given(
    n=st.integers(min_value=6, max_value=16),
    fraction=st.floats(min_value=0.1, max_value=0.45),
    seed=st.integers(min_value=0, max_value=2**16),
)
def test_random_dissolves_keep_the_rule(n, fraction, seed):
    """Dissolve Edges on a random share of a grid's interior edges: the rule at refine 0, 1 and auto."""
    count = int(fraction * 2 * n * (n - 1))
    V, P = cm.dissolved_grid(n=n, count=count, seed=seed)
    T = cm.heatcore_triangles(V, P)
    sources = [cm.nearest_vertex(V, (0, 0, 0)), cm.nearest_vertex(V, (-1, -1, 0))]
    exact = [np.linalg.norm(V - V[s], axis=1) for s in sources]
    errors = {r: cm.measure(V, P, T, sources, exact, r) for r in (0, 1, "auto")}
    for r, (polygon, triangles, _) in errors.items():
        assert (polygon <= MARGIN * triangles).all(), (r, polygon, triangles)
    assert (errors["auto"][0] <= MARGIN * errors[0][0]).all(), (errors["auto"][0], errors[0][0])
