"""Blender 5 reads the OBJ polylines of ``--isolines-out`` (heatcore.io.curves): its importer makes the
``l`` elements edges of a mesh, and converting that mesh to a curve gives one spline per isoline."""

import blender_required  # noqa: F401 (first: without bpy, the module is skipped)
import bpy
import numpy as np
from test_blender import empty_scene  # noqa: F401 (autouse fixture: each test starts with no objects)

import heatcore as hc
from heatcore.io.curves import write_obj_curves


def plane_with_hole_field():
    """A grid with boundary and a distance field whose isolines are closed circles and open arcs."""
    n = 21
    x, y = np.meshgrid(np.linspace(-1, 1, n), np.linspace(-1, 1, n))
    V = np.column_stack([x.ravel(), y.ravel(), np.zeros(n * n)])
    i, j = np.meshgrid(np.arange(n - 1), np.arange(n - 1))
    a = (j * n + i).ravel()
    F = np.concatenate([np.column_stack([a, a + 1, a + n + 1]), np.column_stack([a, a + n + 1, a + n])])
    return V, F, np.linalg.norm(V - [0.3, 0.1, 0], axis=1)


def test_blender_imports_isoline_curves_as_edges_and_splines(tmp_path):
    V, F, d = plane_with_hole_field()
    curves = hc.isolines(V, F, d, [0.3, 0.6, 1.0, 1.4])
    closed = sum(c.closed for c in curves)
    assert 0 < closed < len(curves)  # circles and arcs cut by the boundary
    path = tmp_path / "curves.obj"
    write_obj_curves(path, curves)

    assert bpy.ops.wm.obj_import(filepath=str(path)) == {"FINISHED"}
    [obj] = bpy.context.scene.objects
    n_points = sum(len(c.points) for c in curves)
    n_segments = sum(len(c.faces) for c in curves)
    assert (obj.type, len(obj.data.vertices), len(obj.data.edges), len(obj.data.polygons)) == (
        "MESH", n_points, n_segments, 0)
    co = np.empty(3 * n_points)
    obj.data.vertices.foreach_get("co", co)
    P = np.concatenate([c.points for c in curves])
    np.testing.assert_allclose(co.reshape(-1, 3), P, atol=1e-6)  # the file's coordinates (float32)
    # the importer's axis conversion (OBJ's +y up to Blender's +z up) is the object's rotation
    R = np.array(obj.matrix_world)[:3, :3]
    np.testing.assert_allclose(R, [[1, 0, 0], [0, 0, -1], [0, 1, 0]], atol=1e-6)

    bpy.context.view_layer.objects.active = obj
    obj.select_set(True)
    assert bpy.ops.object.convert(target="CURVE") == {"FINISHED"}
    splines = bpy.context.view_layer.objects.active.data.splines
    assert len(splines) == len(curves)
    assert sum(s.use_cyclic_u for s in splines) == closed
    assert sorted(len(s.points) for s in splines) == sorted(len(c.points) for c in curves)
