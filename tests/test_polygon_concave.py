"""PolygonMesh on the concave n-gons Blender makes, and on polygon meshes virtual refinement spans badly (issue 32).

The rule: on every polygon mesh, ``PolygonMesh`` is never worse than ``TriangleMesh`` on heatcore's
own triangulation of the same polygons (``triangulate_polygons``), within ``MARGIN``, at every
``refine``; and ``refine="auto"`` is never worse than ``refine=0`` (same margin). Error: the mean
relative error over the vertices with exact distance > 0, for each source on its own.

The meshes come from Blender's own operators (tests/concave_meshes.py): Dissolve Edges on grids,
Limited Dissolve on a UV sphere and on a subdivided cube with extruded bumps, a plate with holes
whose surrounding faces are dissolved, and a text object's letters; and from the meshes where
virtual refinement (``PolygonMesh(virtual=True)``, the default until 2026-11-29) broke the rule:
jittered hexagon and quad grids and a Catmull-Clark sphere (1.10-1.75 times the triangulation's
error unrefined), suzanne (1.08-1.21 refined), hexagons stretched 2:1 (2.1 refined) and the plate
(1.07-1.19 refined). Exact references: the straight-line distance on planar grids; elsewhere exact
geodesics (gdist, MMP) on heatcore's triangulation of the polygons, computed once per session (in a
child process: gdist segfaults on non-manifold input).
"""

import functools

import numpy as np
import pytest

pytest.importorskip("bpy")

import bmesh  # noqa: E402
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


def _planar(V, P, sources):
    return V, P, sources, None


def _hexagons(jitter, stretch=1.0):
    from test_polygon_refine import hex_grid

    V, H = hex_grid(jitter=jitter)
    V[:, 1] *= stretch
    return _planar(V, H.tolist(), [cm.nearest_vertex(V, V.mean(axis=0)), 0])


def _quads(n, jitter, stretch=1.0):
    from test_polygon import quad_grid

    V, Q = quad_grid(n, jitter)
    V[:, 0] *= stretch
    return _planar(V, Q.tolist(), [(n // 2) * n + n // 2, 0, n + 2])


def _catmull_clark_sphere():
    from test_polygon_refine import cc_sphere

    V, Q = cc_sphere(3)
    return V, Q.tolist(), [0, 100, 300], "gdist"


def _catmull_clark_cube():
    from test_polygon import catmull_clark, cube

    V, Q = catmull_clark(*cube(), levels=4)
    return V, Q.tolist(), [0, 700, 1200], "gdist"


def _cylinder(segments=32, rings=8):
    """Blender's cylinder (its caps: two 32-gons), its sides cut into ``rings + 1`` rows of quads."""
    bm = bmesh.new()
    bmesh.ops.create_cone(bm, cap_ends=True, cap_tris=False, segments=segments, radius1=1.0, radius2=1.0, depth=2.0)
    sides = [e for e in bm.edges if abs(e.verts[0].co.z - e.verts[1].co.z) > 1e-6]
    bmesh.ops.subdivide_edges(bm, edges=sides, cuts=rings, use_grid_fill=False)
    V, P = cm.arrays(bm)
    return V, P, [0, len(V) // 3, len(V) // 2], "gdist"


def _smooth_subdivided_cube(levels=2):
    """A cube subdivided with Blender's Subdivide (Smoothness 1), ``levels`` times."""
    bm = bmesh.new()
    bmesh.ops.create_cube(bm, size=2.0)
    for _ in range(levels):
        bmesh.ops.subdivide_edges(bm, edges=bm.edges[:], cuts=1, use_grid_fill=True, smooth=1.0)
    V, P = cm.arrays(bm)
    return V, P, [0, len(V) // 3, len(V) // 2], "gdist"


def _suzanne():
    from test_polygon import load_polygons, manifold_part

    mesh = load_polygons("suzanne")
    return mesh.vertices, manifold_part(mesh.vertices, mesh.polygons), [100, 200, 300], "gdist"


BLENDER_BUILDERS = {
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

BUILDERS = BLENDER_BUILDERS | {
    "hexagons": lambda: _hexagons(0.0),
    "hexagons-jittered": lambda: _hexagons(0.2),
    "hexagons-jittered-stretched": lambda: _hexagons(0.2, stretch=2.0),
    "quads11": lambda: _quads(11, 0.0),
    "quads31-jittered": lambda: _quads(31, 0.3),
    "quads21-jittered-stretched": lambda: _quads(21, 0.3, stretch=2.0),
    "catmull-clark-sphere": _catmull_clark_sphere,
    "catmull-clark-cube": _catmull_clark_cube,
    "suzanne": _suzanne,
    "cylinder": _cylinder,
    "smooth-subdivided-cube": _smooth_subdivided_cube,
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


@pytest.mark.parametrize("name", BLENDER_BUILDERS)
def test_blender_leaves_concave_polygons_and_polygon_mesh_triangulates_them(name):
    V, P, T, sources, exact = case(name)
    concave = cm.n_concave(V, P)
    assert concave > 0, f"{name}: Blender left no concave polygon: the case tests nothing"
    assert len(T) == sum(len(p) - 2 for p in P)
    assert measured(name, 0)[2] >= concave  # n_triangulated: concave ones and straight-cornered ones


@pytest.mark.parametrize(("name", "refine"), [(n, r) for n in BUILDERS for r in REFINES])
def test_polygon_mesh_is_never_worse_than_heatcores_triangulation(name, refine):
    polygon, triangles, _ = measured(name, refine)
    ratio = polygon / triangles
    assert (ratio <= MARGIN).all(), f"{name} refine={refine}: {polygon.round(5)} against {triangles.round(5)}"


@pytest.mark.parametrize("name", BUILDERS)
def test_refine_auto_is_never_worse_than_refine_0(name):
    """Held on every mesh since the heat method reads two steps (2026-11-29; before: 1.04-1.36x on jittered grids
    from a source beside the boundary, 1.06-1.07x from a Catmull-Clark surface's corner)."""
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
