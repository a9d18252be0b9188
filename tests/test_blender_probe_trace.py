"""The probe tool's *Trace* (issue 36): Alt+drag traces the straightest geodesic towards the mouse; Enter writes it.

On a flat grid (seen from above) the trace from the press is the straight segment to the point under the
cursor, as long as it, and follows the mouse; without sources, Enter writes only the trace.
"""

import blender_required  # noqa: F401 (first: without bpy, the module is skipped)
import bpy
import numpy as np
from test_blender import addon, empty_scene  # noqa: F401 (fixtures)
from test_blender_probe import Event, grid, mods, no_leaks, session, to_mouse  # noqa: F401 (fixtures)


def test_alt_drag_traces_towards_the_mouse_and_enter_writes_it(mods):  # noqa: F811 (fixture)
    obj = grid(10)
    probe = mods["probe"].GeodesicProbe(obj, refine=0)
    s, reports = session(mods, probe)
    assert s.handle(Event("LEFTMOUSE", "PRESS", *to_mouse(-0.5, -0.4), alt=True)) == {"RUNNING_MODAL"}
    assert probe.trace is None and s.tracing
    s.handle(Event("MOUSEMOVE", "NOTHING", *to_mouse(0.3, 0.2)))
    start, end = np.array([-0.5, -0.4]), np.array([0.3, 0.2])
    P = probe.trace.points
    np.testing.assert_allclose(P[0, :2], start, atol=1e-3)  # the mouse's pixel
    np.testing.assert_allclose(P[-1, :2], end, atol=1e-3)
    np.testing.assert_allclose(probe.trace.length, np.linalg.norm(end - start), rtol=1e-3)
    assert probe.trace.stopped == "length"
    np.testing.assert_array_equal(probe.overlay_data().path, P.astype(np.float32))  # drawn in the path's place
    s.handle(Event("MOUSEMOVE", "NOTHING", *to_mouse(0.9, -0.4)))  # the trace follows the mouse
    np.testing.assert_allclose(probe.trace.points[-1, :2], [0.9, -0.4], atol=1e-3)
    s.handle(Event("LEFTMOUSE", "RELEASE", *to_mouse(0.9, -0.4), alt=True))
    assert not s.tracing
    assert s.handle(Event("RET", "PRESS")) == {"FINISHED"}
    curve = bpy.data.objects["Grid Geodesic Trace"]
    co = np.empty(4 * len(curve.data.splines[0].points))
    curve.data.splines[0].points.foreach_get("co", co)
    np.testing.assert_allclose(co.reshape(-1, 4)[:, :3], probe.trace.points, atol=1e-6)
    assert any("trace of length" in m for _, m in reports)
    assert "geodesic_distance" not in obj.data.attributes  # no source: only the trace was written

