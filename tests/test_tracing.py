"""Straightest geodesics traced from a point and a direction (heatcore.paths.tracing, HeatSolver.trace).

References: straight lines on flat grids; great circles on spheres traced in a mirror plane of the mesh (the
straightest geodesic of the polyhedron stays in that plane by symmetry, through every vertex it meets); and
potpourri3d 1.4's GeodesicTracer on the same inputs.
"""

import numpy as np
import pytest
from shapes import grid, icosphere

import heatcore as hc
from heatcore.paths.tracing import input_tangent_basis


def uv_sphere(n_lat, n_lon):
    """Unit UV sphere: poles and ``n_lat - 1`` rings of ``n_lon`` vertices; each ring quad is planar (two triangles)."""
    theta = np.linspace(0, np.pi, n_lat + 1)[1:-1]
    phi = np.arange(n_lon) * 2 * np.pi / n_lon
    T, P = np.meshgrid(theta, phi, indexing="ij")
    ring = np.c_[(np.sin(T) * np.cos(P)).ravel(), (np.sin(T) * np.sin(P)).ravel(), np.cos(T).ravel()]
    V = np.r_[[[0.0, 0.0, 1.0]], ring, [[0.0, 0.0, -1.0]]]

    def idx(i, j):
        return 1 + i * n_lon + j % n_lon

    F = []
    for j in range(n_lon):
        F.append([0, idx(0, j), idx(0, j + 1)])
        for i in range(n_lat - 2):
            a, b, c, d = idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)
            F += [[a, b, c], [a, c, d]]
        F.append([len(V) - 1, idx(n_lat - 2, j + 1), idx(n_lat - 2, j)])
    return V, np.array(F)


def tracer(V, F):
    pp3d = pytest.importorskip("potpourri3d")
    return pp3d.GeodesicTracer(V, F)


def test_flat_grid_ends_on_the_straight_line_and_no_worse_than_potpourri():
    V, F = grid(21, 21, jitter=0.3)
    rng = np.random.default_rng(1)
    pp = tracer(V, F)
    centre = np.array([0.5, 0.5, 0.0])
    inner = np.flatnonzero(np.linalg.norm(V[F].mean(axis=1) - centre, axis=1) < 0.15)
    for _ in range(20):
        f, bary = int(rng.choice(inner)), rng.dirichlet([1, 1, 1])
        angle, length = rng.uniform(0, 2 * np.pi), rng.uniform(0.05, 0.3)
        d = np.array([np.cos(angle), np.sin(angle), 0.0])
        start = bary @ V[F[f]]
        path = hc.trace_geodesic(V, F, (f, bary), d, length)
        error = np.linalg.norm(path.points[-1] - (start + length * d))
        theirs = np.linalg.norm(pp.trace_geodesic_from_face(f, bary, length * d)[-1] - (start + length * d))
        assert path.stopped == "length" and path.length == pytest.approx(length, abs=1e-12)
        assert error < 1e-9 and error <= max(theirs, 1e-13)
        face, end_bary = path.end
        assert np.linalg.norm(end_bary @ V[F[face]] - path.points[-1]) < 1e-12
        v = int(F[f, 0])
        from_vertex = hc.trace_geodesic(V, F, v, d, length)
        error = np.linalg.norm(from_vertex.points[-1] - (V[v] + length * d))
        theirs = np.linalg.norm(pp.trace_geodesic_from_vertex(v, length * d)[-1] - (V[v] + length * d))
        assert error < 1e-9 and error <= max(theirs, 1e-13)


def test_segments_lie_in_their_faces():
    V, F = grid(11, 11, jitter=0.3)
    path = hc.trace_geodesic(V, F, 60, [0.3, 1.0, 0.0], 0.4)
    for a, b, f in zip(path.points[:-1], path.points[1:], path.faces):
        A = np.c_[V[F[f], :2], np.ones(3)].T
        for p in (a, b, (a + b) / 2):
            assert np.linalg.solve(A, np.r_[p[:2], 1.0]).min() > -1e-12


def test_through_grid_vertices_straight_on():
    V, F = grid(11, 11)
    path = hc.trace_geodesic(V, F, 12, [1.0, 1.0, 0.0], 0.5)  # vertex (0.1, 0.1) up the diagonals
    assert np.abs(path.points[-1] - (V[12] + 0.5 * np.array([1, 1, 0]) / np.sqrt(2))).max() < 1e-12


def test_boundary_stops_the_walk_on_the_boundary():
    V, F = grid(11, 11, jitter=0.2)
    start = V[60]
    path = hc.trace_geodesic(V, F, 60, [1.0, 0.3, 0.0], 5.0)
    hit = np.array([1.0, start[1] + 0.3 * (1.0 - start[0]), 0.0])
    assert path.stopped == "boundary"
    assert np.linalg.norm(path.points[-1] - hit) < 1e-12
    assert path.length == pytest.approx(np.linalg.norm(hit - start), abs=1e-12)
    face, bary = path.end
    assert (bary == 0).sum() >= 1 and np.linalg.norm(bary @ V[F[face]] - hit) < 1e-12
    corner = hc.trace_geodesic(*grid(11, 11), 0, [1.0, 1.0, 0.0], 5.0)  # up the diagonal into corner vertex 120
    assert corner.stopped == "boundary" and np.abs(corner.points[-1] - [1, 1, 0]).max() < 1e-12


def polygon_meridian_point(n_lat, arc):
    """The point at ``arc`` along the UV sphere's meridian polygon (through the poles, longitude 0 then pi)."""
    chord = 2 * np.sin(np.pi / n_lat / 2)
    k, rest = divmod(arc % (2 * n_lat * chord), chord)
    angles = (np.array([k, k + 1]) * np.pi / n_lat)
    a, b = (np.array([np.sin(t), 0.0, np.cos(t)]) for t in angles)
    return a + rest / chord * (b - a)


@pytest.mark.parametrize("n_lat", [16, 64])
def test_uv_sphere_meridian_stays_on_the_great_circle(n_lat):
    V, F = uv_sphere(n_lat, 2 * n_lat)
    pp = tracer(V, F)
    perimeter = 2 * n_lat * 2 * np.sin(np.pi / n_lat / 2)
    for length in (1.0, 0.5 * perimeter, 1.5 * perimeter):
        path = hc.trace_geodesic(V, F, 0, [1.0, 0.0, 0.0], length)  # from the north pole through ring vertices
        theirs = pp.trace_geodesic_from_vertex(0, [length, 0.0, 0.0])
        ours_off, their_off = np.abs(path.points[:, 1]).max(), np.abs(theirs[:, 1]).max()
        assert ours_off < 1e-6 * length and ours_off <= their_off
        assert np.linalg.norm(path.points[-1] - polygon_meridian_point(n_lat, length)) < 1e-9


@pytest.mark.parametrize("level", [2, 4])
def test_icosphere_mirror_plane_geodesic_stays_in_it(level):
    V, F = icosphere(level)  # z = 0 is a mirror plane of the mesh
    on = np.flatnonzero(np.abs(V[:, 2]) < 1e-12)
    edges = np.r_[F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]
    v, w = edges[np.isin(edges, on).all(axis=1)][0]
    d = (V[w] - V[v]) / np.linalg.norm(V[w] - V[v])
    pp = tracer(V, F)
    for length in (1.0, 3.0, 7.0):
        path = hc.trace_geodesic(V, F, int(v), d, length)
        theirs = pp.trace_geodesic_from_vertex(int(v), length * d)
        ours_off, their_off = np.abs(path.points[:, 2]).max(), np.abs(theirs[:, 2]).max()
        assert path.stopped == "length" and ours_off < 1e-6 * length and ours_off <= their_off


def test_icosphere_generic_direction_matches_potpourri():
    """Off the mirror planes the polyhedron's geodesic leaves the great circle (O(h) wobble): both tracers agree."""
    V, F = icosphere(4)
    pp = tracer(V, F)
    rng = np.random.default_rng(3)
    for _ in range(5):
        f, bary = int(rng.integers(len(F))), rng.dirichlet([1, 1, 1])
        d = rng.normal(size=3)
        path = hc.trace_geodesic(V, F, (f, bary), d, np.pi)
        n = np.cross(V[F[f, 1]] - V[F[f, 0]], V[F[f, 2]] - V[F[f, 0]])
        d = d - (d @ n) / (n @ n) * n
        theirs = pp.trace_geodesic_from_face(f, bary, np.pi * d / np.linalg.norm(d))
        assert np.linalg.norm(path.points[-1] - theirs[-1]) < 1e-9
        start = bary @ V[F[f]]
        normal = np.cross(start, d)
        normal /= np.linalg.norm(normal)
        ours_off = np.abs(path.points @ normal / np.linalg.norm(path.points, axis=1)).max()
        their_off = np.abs(theirs @ normal / np.linalg.norm(theirs, axis=1)).max()
        assert ours_off <= their_off + 1e-12


def test_2d_directions_are_in_the_vector_heat_tangent_basis():
    V, F = icosphere(2)
    mesh = hc.TriangleMesh(V, F)
    basis = hc.VectorHeatSolver(mesh).tangent_basis()
    assert all(np.allclose(a, b) for a, b in zip(basis, input_tangent_basis(mesh)))
    solver = hc.HeatSolver(mesh)
    for v, (x, y) in [(0, (1.0, 0.0)), (7, (0.3, -0.8))]:
        two = solver.trace(v, [x, y], 1.2)
        three = solver.trace(v, x * basis.e1[v] + y * basis.e2[v], 1.2)
        assert np.abs(two.points - three.points).max() < 1e-12
    face = hc.trace_geodesic(V, F, (5, [0.2, 0.3, 0.5]), [1.0, 0.0], 0.01)  # a face's e1: along its first edge
    edge = V[F[5, 1]] - V[F[5, 0]]
    step = face.points[-1] - face.points[0]
    assert np.allclose(step / np.linalg.norm(step), edge / np.linalg.norm(edge))


def test_solver_trace_is_the_function():
    V, F = hc.io.load_demo_mesh()
    solver = hc.HeatSolver(hc.TriangleMesh(V, F))
    a = solver.trace((10, [0.2, 0.3, 0.5]), [0.0, 0.0, 1.0], 0.3)
    b = hc.trace_geodesic(V, F, (10, [0.2, 0.3, 0.5]), [0.0, 0.0, 1.0], 0.3)
    assert np.array_equal(a.points, b.points) and np.array_equal(a.faces, b.faces)
    assert a.length == pytest.approx(0.3, abs=1e-12) and a.stopped == "length"
    again = solver.trace(a.end, [0.0, 0.0, 1.0], 0.0)  # the end is a start
    assert again.points.shape == (1, 3) and np.allclose(again.points[0], a.points[-1])


def test_bad_inputs_raise_typed_errors():
    V, F = grid(5, 5)
    with pytest.raises(hc.InvalidSourceError, match="direction"):
        hc.trace_geodesic(V, F, 6, [0.0, 0.0, 0.0], 1.0)
    with pytest.raises(hc.InvalidSourceError, match="direction"):
        hc.trace_geodesic(V, F, 6, [1.0, 0.0, 0.0, 0.0], 1.0)
    with pytest.raises(hc.InvalidSourceError, match="normal to the surface"):
        hc.trace_geodesic(V, F, 6, [0.0, 0.0, 1.0], 1.0)
    with pytest.raises(hc.InvalidSourceError, match="normal to the surface"):
        hc.trace_geodesic(V, F, (3, [0.2, 0.3, 0.5]), [0.0, 0.0, 1.0], 1.0)
    with pytest.raises(hc.InvalidSourceError, match="start"):
        hc.trace_geodesic(V, F, 99, [1.0, 0.0, 0.0], 1.0)
    with pytest.raises(hc.InvalidOptionError, match="length"):
        hc.trace_geodesic(V, F, 6, [1.0, 0.0, 0.0], -1.0)
    polygons = hc.PolygonMesh(V, [[0, 1, 6, 5]])
    with pytest.raises(hc.UnsupportedDomainError, match="triangle meshes"):
        hc.HeatSolver(polygons).trace(0, [1.0, 0.0, 0.0], 1.0)


def test_leaving_a_boundary_vertex_off_the_surface_stops_at_once():
    V, F = grid(5, 5)
    path = hc.trace_geodesic(V, F, 0, [-1.0, -1.0, 0.0], 1.0)
    assert path.stopped == "boundary" and path.length == 0.0 and path.points.shape == (1, 3)


def test_trace_command_writes_a_polyline_that_reads_back(tmp_path, capsys):
    from heatcore.apps.cli import main

    V, F = grid(11, 11)
    mesh = tmp_path / "grid.obj"
    mesh.write_text("".join(f"v {x} {y} {z}\n" for x, y, z in V) + "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in F))
    out = tmp_path / "t.csv"
    assert main(["trace", str(mesh), "--from", "60", "--direction", "1", "0", "0", "--length", "0.3", "-o", str(out),
                 "-o", str(tmp_path / "t.obj"), "-q"]) == 0
    points = np.loadtxt(out, delimiter=",", skiprows=1)
    assert np.abs(points[-1] - (V[60] + [0.3, 0, 0])).max() < 1e-12
    printed = capsys.readouterr().out
    assert "stopped: length" in printed
    end = printed.split(" end ")[1].split()[0]  # FACE:B0,B1,B2, a start again
    assert main(["trace", str(mesh), "--from", end, "--direction", "1", "0", "0", "--length", "0.1", "-o", str(out),
                 "-q"]) == 0
    assert np.abs(np.loadtxt(out, delimiter=",", skiprows=1)[0] - points[-1]).max() < 1e-12
    assert main(["trace", str(mesh), "--from", "3:0.2,0.3,0.5", "--direction", "1", "0", "0", "--length", "9",
                 "-o", str(out), "-q"]) == 0
    assert "stopped: boundary" in capsys.readouterr().out
    assert main(["trace", str(mesh), "--from", "0", "--direction", "1", "0", "0", "0", "--length", "1", "-o", str(out)]) == 2
    assert main(["trace", str(mesh), "--from", "0", "--direction", "1", "0", "0", "--length", "-1", "-o", str(out)]) == 2
    assert main(["trace", str(mesh), "--from", "0", "--direction", "1", "0", "0", "--length", "1", "-o", "t.txt"]) == 2
    assert main(["trace", str(mesh), "--from", "999", "--direction", "1", "0", "0", "--length", "1", "-o", str(out)]) == 1
    assert main(["trace", str(mesh), "--from", "0", "--direction", "0", "0", "1", "--length", "1", "-o", str(out)]) == 1


def test_faces_oriented_either_way_unfold_alike():
    V, F = grid(21, 21, jitter=0.3)
    rng = np.random.default_rng(0)
    flip = rng.random(len(F)) < 0.5
    mixed = np.where(flip[:, None], F[:, ::-1], F)
    centre = np.flatnonzero(np.linalg.norm(V[F].mean(axis=1) - [0.5, 0.5, 0], axis=1) < 0.15)
    for f in rng.choice(centre, 10):
        bary, angle = rng.dirichlet([1, 1, 1]), rng.uniform(0, 2 * np.pi)
        d = np.array([np.cos(angle), np.sin(angle), 0.0])
        path = hc.trace_geodesic(V, mixed, (int(f), bary[::-1] if flip[f] else bary), d, 0.3)
        assert np.linalg.norm(path.points[-1] - (bary @ V[F[f]] + 0.3 * d)) < 1e-12


def ring_mesh(heights):
    """A vertex at the origin with one ring at the given heights and a second ring twice as far (a cone or saddle)."""
    n = len(heights)
    angle = np.arange(n) * 2 * np.pi / n
    ring = np.c_[np.cos(angle), np.sin(angle), heights]
    V = np.r_[[[0.0, 0.0, 0.0]], ring, 2 * ring]
    F = []
    for k in range(n):
        a, b = 1 + k, 1 + (k + 1) % n
        F += [[0, a, b], [a, a + n, b + n], [a, b + n, b]]
    return V, np.array(F)


def fan_angle(mesh, v, x):
    """Angle of direction ``x - P[v]`` around vertex ``v``, from the first edge of its fan."""
    faces, first, second, angles, _ = mesh.fan(v)
    P, x = mesh.positions, x - mesh.positions[v]

    def between(u, w):
        return np.arctan2(np.linalg.norm(np.cross(u, w)), u @ w)

    for k in range(len(faces)):
        t = between(P[first[k]] - P[v], x)
        if abs(t + between(P[second[k]] - P[v], x) - angles[k]) < 1e-9:
            return sum(angles[:k]) + t
    raise AssertionError("direction in no face of the fan")


@pytest.mark.parametrize("heights", [[-0.5] * 7, [0.5 * (-1) ** k for k in range(8)],
                                     [0.6 * np.cos(6 * np.pi * k / 9) for k in range(9)]],
                         ids=["cone", "saddle", "monkey saddle"])
def test_through_a_vertex_half_the_angle_on_either_side(heights):
    from heatcore.paths.surface import PathMesh

    V, F = ring_mesh(heights)
    mesh = PathMesh(hc.TriangleMesh(V, F, refine=0))
    total = sum(mesh.fan(0)[3])
    for g in (2, 5):  # faces of the outer ring, aimed at the centre vertex
        start = np.array([0.3, 0.3, 0.4]) @ V[F[g]]
        path = hc.trace_geodesic(V, F, (g, [0.3, 0.3, 0.4]), V[0] - start, 3.0)
        k = int(np.flatnonzero(np.linalg.norm(path.points - V[0], axis=1) < 1e-12)[0])
        side = (fan_angle(mesh, 0, path.points[k + 1]) - fan_angle(mesh, 0, path.points[k - 1])) % total
        assert side == pytest.approx(total / 2, abs=1e-9)
