"""Paths through waypoints (issue 36): every leg against the exact MMP distance (gdist) on shared meshes,
the joined polyline, closed paths, bad input."""

import itertools

import numpy as np
import pytest
from conftest import exact_distance, load_shared_mesh
from shapes import grid
from test_paths import assert_on_surface

import heatcore as hc

LEG_EXCESS, SHORTER = 1e-3, 1e-9


@pytest.mark.parametrize("name", ["spot", "homer", "fandisk", "cheburashka"])
def test_each_leg_is_the_exact_geodesic_distance(name):
    V, F = load_shared_mesh(name)
    solver = hc.HeatSolver(hc.TriangleMesh(V, F))
    rng = np.random.default_rng(0)
    points = rng.choice(np.unique(F), 5, replace=False).tolist()
    path = solver.geodesic_path(points=points, closed=True)
    stops = points + points[:1]
    exact = np.array([exact_distance(V, F, a)[b] for a, b in itertools.pairwise(stops)])
    excess = path.leg_lengths / exact - 1
    assert excess.shape == (5,)
    assert excess.min() >= -SHORTER and excess.max() <= LEG_EXCESS
    assert path.length == pytest.approx(path.leg_lengths.sum(), rel=1e-12)
    assert path.length == pytest.approx(np.linalg.norm(np.diff(path.points, axis=0), axis=1).sum(), rel=1e-12)
    assert path.waypoints[0] == 0 and path.waypoints[-1] == len(path.points) - 1
    np.testing.assert_allclose(path.points[path.waypoints], V[stops], atol=1e-12)
    assert path.vertices[path.waypoints].tolist() == stops
    assert_on_surface(path, V, F)


def test_legs_are_the_two_point_paths_joined():
    V, F = load_shared_mesh("spot")
    solver = hc.HeatSolver(hc.TriangleMesh(V, F))
    path = solver.geodesic_path(points=[0, 1453, 200, 900])
    for k, (a, b) in enumerate([(0, 1453), (1453, 200), (200, 900)]):
        leg = solver.geodesic_path(a, b)
        assert path.leg_lengths[k] == leg.length
        np.testing.assert_array_equal(path.points[path.waypoints[k]:path.waypoints[k + 1] + 1], leg.points)
        np.testing.assert_array_equal(path.faces[path.waypoints[k]:path.waypoints[k + 1]], leg.faces)
    two = solver.geodesic_path(0, 1453)  # the two-point call is unchanged, and one leg
    assert two.leg_lengths.tolist() == [two.length] and two.waypoints.tolist() == [0, len(two) - 1]


def test_plane_waypoints_give_the_polygon():
    V, F = grid(15, 15, jitter=0.3, seed=4)
    solver = hc.HeatSolver(hc.TriangleMesh(V, F, refine=0))
    points = [0, 14, 224, 112]
    path = solver.geodesic_path(points=points, closed=True)
    sides = np.linalg.norm(V[points[1:] + points[:1]] - V[points], axis=1)
    np.testing.assert_allclose(path.leg_lengths, sides, rtol=1e-12)
    open_path = solver.geodesic_path(points=points)
    np.testing.assert_allclose(open_path.leg_lengths, sides[:3], rtol=1e-12)
    assert open_path.vertices[-1] == 112


def test_surface_points_and_repeated_waypoints():
    V, F = grid(9, 9)
    solver = hc.HeatSolver(hc.TriangleMesh(V, F, refine=0))
    inside = (5, [0.2, 0.3, 0.5])
    p = np.array([0.2, 0.3, 0.5]) @ V[F[5]]
    path = solver.geodesic_path(points=[0, inside, inside, 80])
    np.testing.assert_allclose(path.leg_lengths, [np.linalg.norm(p - V[0]), 0.0, np.linalg.norm(V[80] - p)],
                               rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(path.points[path.waypoints[1]], p, atol=1e-15)


def test_bad_waypoints_raise_typed_errors():
    V, F = grid(5, 5)
    solver = hc.HeatSolver(hc.TriangleMesh(V, F, refine=0))
    with pytest.raises(hc.InvalidSourceError, match="at least two"):
        solver.geodesic_path(points=[3])
    with pytest.raises(hc.InvalidSourceError, match="leg 1"):
        solver.geodesic_path(points=[0, 3, 99])
    with pytest.raises(hc.InvalidSourceError, match="not both"):
        solver.geodesic_path(0, 3, points=[0, 3])
    with pytest.raises(hc.InvalidSourceError, match="source and a target"):
        solver.geodesic_path(0)


def test_path_command_through_waypoints(tmp_path, capsys):
    from heatcore.apps.cli import main
    from heatcore.io import demo_mesh_path

    out, mesh = tmp_path / "w.csv", str(demo_mesh_path())
    assert main(["path", mesh, "--through", "0", "1453", "20:0.2,0.3,0.5", "--closed", "-o", str(out), "-q"]) == 0
    printed = capsys.readouterr().out.split()
    V, F = hc.io.load_demo_mesh()
    expected = hc.HeatSolver(hc.TriangleMesh(V, F)).geodesic_path(points=[0, 1453, (20, [0.2, 0.3, 0.5])],
                                                                   closed=True)
    assert float(printed[1]) == pytest.approx(expected.length, rel=1e-9)
    legs = [float(x) for x in printed[printed.index("legs") + 1:printed.index("legs") + 4]]
    np.testing.assert_allclose(legs, expected.leg_lengths, rtol=1e-9)
    points = np.loadtxt(out, delimiter=",", skiprows=1)
    np.testing.assert_array_equal(points, expected.points)
    np.testing.assert_array_equal(points[0], points[-1])
    for bad in (["--through", "0"], ["--through", "0", "5", "--from", "0"], ["--from", "0", "--to", "5", "--closed"],
                ["--from", "0"]):
        assert main(["path", mesh, *bad, "-o", str(tmp_path / "p.obj")]) == 2
    assert main(["path", mesh, "--through", "0", "99999", "-o", str(tmp_path / "p.obj"), "-q"]) == 1
    assert "leg 0" in capsys.readouterr().err
    assert not (tmp_path / "p.obj").exists()
