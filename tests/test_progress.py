"""Progress of heatcore's builds (``progress=`` of TriangleMesh and HeatSolver, :mod:`heatcore.progress`).

The stages are reported in order with rising fractions that end at 1; the
callback changes no number; a callback that raises aborts the build with its
own exception, and the domain stays usable (a later solver on it equals one
built on a fresh domain).
"""

import re

import numpy as np
import pytest

import heatcore as hc
from heatcore.progress import Progress


class Abort(Exception):
    pass


def grid(n=30):
    """A flat n x n grid of unit squares (a mesh with boundary: Robin uses both heat factorizations)."""
    x, y = np.meshgrid(np.arange(n, dtype=float), np.arange(n, dtype=float), indexing="ij")
    V = np.column_stack([x.ravel(), y.ravel(), np.zeros(n * n)])
    i = np.arange(n - 1)[:, None] * n + np.arange(n - 1)[None, :]
    i = i.ravel()
    F = np.vstack([np.column_stack([i, i + n, i + 1]), np.column_stack([i + 1, i + n, i + n + 1])])
    return V, F


def recorded(build):
    seen = []
    result = build(lambda fraction, message: seen.append((fraction, message)))
    return result, seen


def test_stages_rise_to_one_and_name_the_work():
    V, F = grid()
    seen = []
    whole = Progress(lambda fraction, message: seen.append((fraction, message)))
    mesh = hc.TriangleMesh(V, F, progress=whole.part(0.0, 0.3))
    hc.HeatSolver(mesh, progress=whole.part(0.3, 1.0))
    assert mesh.levels == 2  # a 900-vertex grid is refined twice ("auto")
    fractions = [f for f, _ in seen]
    assert fractions[0] == 0.0 and fractions[-1] == 1.0
    assert all(b >= a for a, b in zip(fractions, fractions[1:])), fractions
    messages = [m for _, m in seen]
    assert messages == [
        "welding coincident vertices",
        "finding connected parts",
        "midpoint subdivision (2 levels)",
        "intrinsic Delaunay flips",
        "triangle mesh ready",  # the operators are built on first use: the solver's, in its first stage
        "connected components",
        "factoring the heat matrix (interior vertices, for the Dirichlet condition)",
        "factoring the heat matrix",
        "factoring the heat matrix (long step; interior vertices, for the Dirichlet condition)",
        "factoring the heat matrix (long step)",  # refined: two heat steps (heatcore.steps.time_step)
        "factoring the Poisson matrix",
        "heat solver ready",
    ]
    # the domain's 1.0 is the solver's 0.0: 0.3 of the whole
    assert seen[4][0] == pytest.approx(0.3) and seen[5][0] == pytest.approx(0.3)


def test_closed_mesh_and_no_weld_skip_their_stages():
    V, F = hc.io.load_demo_mesh()  # spot: closed, so the heat step is Neumann only
    (_, seen) = recorded(lambda cb: hc.HeatSolver(hc.TriangleMesh(V, F, weld=None, refine=0), progress=cb))
    assert [m for _, m in seen] == [
        "connected components", "factoring the heat matrix", "factoring the Poisson matrix", "heat solver ready",
    ]
    assert [f for f, _ in seen] == [0.0, 0.05, 0.7, 1.0]
    _, seen = recorded(lambda cb: hc.TriangleMesh(V, F, weld=None, refine=0, robust=False, progress=cb))
    assert [m for _, m in seen][0] == "reading the triangles"
    assert "mollifying the triangles" in [m for _, m in seen]


def test_progress_changes_no_number():
    V, F = grid(20)
    quiet = hc.HeatSolver(hc.TriangleMesh(V, F)).distance([0])
    calls = []
    loud = hc.HeatSolver(
        hc.TriangleMesh(V, F, progress=lambda *a: calls.append(a)), progress=lambda *a: calls.append(a)
    ).distance([0])
    assert len(calls) == 12  # refined: the short and the long step's heat matrices, each with its Dirichlet one
    np.testing.assert_array_equal(quiet, loud)
    # the corner-to-corner distance of the flat 19 x 19 grid is the diagonal 19 * sqrt(2), within 2%
    assert loud[-1] == pytest.approx(19 * np.sqrt(2), rel=0.02)


@pytest.mark.parametrize("stage", ["factoring the heat matrix", "factoring the heat matrix (long step)",
                                   "factoring the Poisson matrix", "heat solver ready"])
def test_a_raising_callback_aborts_the_solver_and_the_domain_stays_usable(stage):
    V, F = grid(20)
    mesh = hc.TriangleMesh(V, F)
    seen = []

    def cancel_at(fraction, message):
        seen.append(message)
        if message == stage:
            raise Abort(message)

    with pytest.raises(Abort, match=re.escape(stage)):
        hc.HeatSolver(mesh, progress=cancel_at)
    assert seen[-1] == stage and seen.count(stage) == 1
    # what the aborted build left on the domain (orderings, a started nested dissection) is whole:
    after = hc.HeatSolver(mesh).distance([3])
    fresh = hc.HeatSolver(hc.TriangleMesh(V, F)).distance([3])
    np.testing.assert_allclose(after, fresh, rtol=1e-12, atol=1e-12)


def test_a_raising_callback_aborts_the_domain_build():
    V, F = grid(10)

    def cancel_at_flips(fraction, message):
        if message == "intrinsic Delaunay flips":
            raise Abort(message)

    with pytest.raises(Abort):
        hc.TriangleMesh(V, F, progress=cancel_at_flips)


def test_parts_compose_and_clip():
    seen = []
    whole = Progress(lambda f, m: seen.append(f))
    inner = whole.part(0.2, 0.6).part(0.5, 1.0)  # 0.4 .. 0.6 of the whole
    inner(0.0, "a")
    inner(0.5, "b")
    inner(2.0, "clipped")
    inner(-1.0, "clipped")
    assert seen == pytest.approx([0.4, 0.5, 0.6, 0.4])
    assert Progress(None).silent and not whole.silent
    Progress(None)(0.5, "nobody listens")


@pytest.mark.parametrize("kind", ["points", "tets", "polygons"])
def test_point_clouds_tet_and_polygon_meshes_report_their_stages(kind):
    """Every domain reports its build stages (issue 34: a build stuck at one fraction for seconds)."""
    rng = np.random.default_rng(0)
    quads = [[0, 1, 2, 3], [1, 4, 5, 2]]
    square = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0], [2, 1, 0.3]], float)
    if kind == "polygons":
        mesh, seen = recorded(lambda p: hc.PolygonMesh(square, quads, progress=p))
        last = "polygon mesh ready"
    elif kind == "points":
        V, _ = grid(20)
        mesh, seen = recorded(lambda p: hc.PointCloud(V + 0.01 * rng.random(V.shape), progress=p))
        last = "point cloud ready"
    else:
        corners = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 1]], float)
        mesh, seen = recorded(lambda p: hc.TetMesh(corners, [[0, 1, 2, 3], [1, 2, 3, 4]], progress=p))
        last = "tet mesh ready"
    fractions = [f for f, _ in seen]
    assert len(seen) >= 4 and fractions[0] == 0.0 and seen[-1] == (1.0, last)
    assert all(b > a for a, b in zip(fractions, fractions[1:])), seen
    with pytest.raises(Abort):  # a raising callback aborts the build
        arguments = {"points": lambda: (V,), "tets": lambda: (corners, [[0, 1, 2, 3]]), "polygons": lambda: (square, quads)}
        type(mesh)(*arguments[kind](), progress=_abort_at(0.3))


def _abort_at(fraction):
    def callback(f, message):
        if f >= fraction:
            raise Abort(message)

    return callback
