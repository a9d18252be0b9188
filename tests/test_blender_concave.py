"""The add-on on a dissolved grid (issue 32, row 1): concave n-gons measured as well as heatcore's PolygonMesh.

With the real ``bpy``: Blender's Dissolve Edges on a 24 x 24 grid (tests/concave_meshes.py) leaves
concave n-gons and straight corners. With its defaults (quads and n-gons kept as polygons), the
distance the add-on writes to the mesh is within ``MARGIN`` of the error of ``TriangleMesh`` on
heatcore's own triangulation of the same polygons, and of core ``PolygonMesh``'s error (the
straight-line distance is exact: the grid is a flat square).
"""

import blender_required  # noqa: F401 (first: without bpy, the module is skipped)
import numpy as np
import pytest
from test_blender import addon, attribute, empty_scene  # noqa: F401 (fixtures)
from test_blender_polygons import mesh_object

import concave_meshes as cm
from heatcore.reference import mean_relative_error

MARGIN = 1.02


@pytest.mark.parametrize("seed", [0, 1])
def test_the_addon_measures_a_dissolved_grid_as_well_as_polygon_mesh(addon, seed):  # noqa: F811
    V, P = cm.dissolved_grid(n=24, count=150, seed=seed)
    assert cm.n_concave(V, P) > 0
    obj = mesh_object(V, P, name="Dissolved")
    sources = [cm.nearest_vertex(V, (0, 0, 0)), cm.reflex_corner(V, P, (0.3, 0.2, 0))]
    exact = [np.linalg.norm(V - V[s], axis=1) for s in sources]
    polygon, triangles, _ = cm.measure(V, P, cm.heatcore_triangles(V, P), sources, exact, "auto")
    for s, e, core, tri in zip(sources, exact, polygon, triangles):
        addon.compute_geodesic_distance(obj, sources=[s], color_attribute=None)
        written = mean_relative_error(attribute(obj.data, "geodesic_distance"), e)
        assert written <= MARGIN * tri, (s, written, tri)
        assert written <= MARGIN * core, (s, written, core)
