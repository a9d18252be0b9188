"""Straightened paths and loops (issue 36): edge paths and polylines shortened to geodesics in their class,
loops to closed geodesics; lengths against exact MMP distances (gdist) and analytic answers, every bend
measured on the surface."""

import numpy as np
import pytest
import scipy.sparse as sp
from conftest import exact_distance, load_shared_mesh
from scipy.sparse.csgraph import dijkstra
from shapes import grid
from test_paths import assert_on_surface

import heatcore as hc
from heatcore.paths.surface import PathMesh

SHORTER, BEND = 1e-9, 1e-9


def jagged_path(V, F, s, t, seed=0, spread=3.0, allowed=None):
    """A shortest edge path from ``s`` to ``t`` for random edge weights (lengths times 1..spread): jagged."""
    E = np.unique(np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1), axis=0)
    if allowed is not None:
        E = E[allowed[E].all(axis=1)]
    w = np.linalg.norm(V[E[:, 0]] - V[E[:, 1]], axis=1) * np.random.default_rng(seed).uniform(1, spread, len(E))
    n = len(V)
    graph = sp.csr_matrix((np.r_[w, w], (np.r_[E[:, 0], E[:, 1]], np.r_[E[:, 1], E[:, 0]])), shape=(n, n))
    _, pred = dijkstra(graph, indices=s, return_predecessors=True)
    path = [t]
    while path[-1] != s:
        path.append(int(pred[path[-1]]))
    return path[::-1]


def edge_length(V, path):
    return float(np.linalg.norm(np.diff(V[path], axis=0), axis=1).sum())


def bend_sides(domain, path):
    """At each inner point of ``path`` that is a vertex: the angles on the two sides of the path there.

    Measured around the vertex on the surface, in the faces the segments lie in; a boundary vertex has
    one side (the other is ``inf``).
    """
    mesh = PathMesh.of(domain)
    out = []
    for i in np.flatnonzero(path.vertices[1:-1] >= 0) + 1:
        v = mesh.vertex_map[path.vertices[i]]
        faces, first, _, angles, closed = mesh.fan(v)
        offsets = np.r_[0.0, np.cumsum(angles)]

        def around(point, face, faces=faces, first=first, v=v, offsets=offsets):
            k = faces.index(int(mesh.face_row[face]))
            u, w = mesh.positions[first[k]] - mesh.positions[v], point - mesh.positions[v]
            return offsets[k] + np.arctan2(np.linalg.norm(np.cross(u, w)), u @ w)

        d = abs(around(path.points[i + 1], path.faces[i]) - around(path.points[i - 1], path.faces[i - 1]))
        out.append(sorted((d, offsets[-1] - d) if closed else (d, np.inf)))
    return np.array(out).reshape(-1, 2)


def assert_locally_shortest(domain, path):
    sides = bend_sides(domain, path)
    assert sides.size == 0 or sides.min() >= np.pi - BEND


def revolve(radius, heights, sides):
    """A surface of revolution about z: ``sides`` vertices on each ring at ``heights``, radius ``radius(z)``."""
    angle = 2 * np.pi * np.arange(sides) / sides
    V = np.array([[radius(z) * np.cos(a), radius(z) * np.sin(a), z] for z in heights for a in angle])
    F = []
    for r in range(len(heights) - 1):
        for i in range(sides):
            a, b = r * sides + i, r * sides + (i + 1) % sides
            c, d = (r + 1) * sides + (i + 1) % sides, (r + 1) * sides + i
            F += [[a, b, c], [a, c, d]]
    return V, np.array(F)


def zigzag_loop(sides, row):
    """An edge loop between rings ``row`` and ``row + 1``: two steps along a ring, up or down, and again."""
    out = []
    for i in range(0, sides, 2):
        out += [row * sides + i, row * sides + i + 1, (row + 1) * sides + i + 1, (row + 1) * sides + (i + 2) % sides]
    return out


def holed_grid(n=21):
    """The unit square (an n x n grid, no jitter) with the square hole (0.4, 0.6)^2 cut out."""
    V, F = grid(n, n)
    centre = V[F].mean(axis=1)
    inside = ((centre[:, :2] > 0.4) & (centre[:, :2] < 0.6)).all(axis=1)
    return V, F[~inside]


def test_jagged_path_on_a_plane_becomes_the_segment():
    V, F = grid(21, 21, jitter=0.3, seed=1)
    edges = jagged_path(V, F, 0, 440, spread=5.0)
    path = hc.straighten_path(V, F, edges)
    straight = np.linalg.norm(V[440] - V[0])
    assert edge_length(V, edges) > 1.2 * straight  # jagged indeed
    assert path.length == pytest.approx(straight, rel=1e-12)
    assert path.vertices[0] == 0 and path.vertices[-1] == 440
    assert np.abs(np.cross(path.points - V[0], (V[440] - V[0]) / straight)).max() <= 1e-12
    assert_on_surface(path, V, F)


def test_the_path_stays_on_its_side_of_a_hole():
    V, F = holed_grid()
    s, t = 6 * 21, 6 * 21 + 20  # (0, 0.3) and (1, 0.3)
    x, y = V[:, 0], V[:, 1]
    column = (x >= 0.4 - 1e-9) & (x <= 0.6 + 1e-9)
    above = jagged_path(V, F, s, t, seed=2, allowed=~(column & (y <= 0.6 + 1e-9)))
    below = jagged_path(V, F, s, t, seed=3, allowed=~(column & (y >= 0.4 - 1e-9)))
    domain = hc.TriangleMesh(V, F, refine=0)
    over, under = hc.straighten_path(V, F, above), hc.straighten_path(V, F, below)
    # Around the hole's two upper corners (0.4, 0.6) and (0.6, 0.6), or straight below it.
    assert over.length == pytest.approx(2 * np.hypot(0.4, 0.3) + 0.2, rel=1e-12)
    assert under.length == pytest.approx(1.0, rel=1e-12)
    assert under.length == pytest.approx(exact_distance(V, F, s)[t], rel=1e-9)  # the shortest path's class
    assert over.length <= edge_length(V, above) and under.length <= edge_length(V, below)
    assert over.points[:, 1].min() >= 0.3 - 1e-12 and under.points[:, 1].max() <= 0.3 + 1e-12
    for corner in ([0.4, 0.6, 0.0], [0.6, 0.6, 0.0]):  # it bends around the hole's corners
        assert np.abs(over.points - corner).max(axis=1).min() <= 1e-15
    assert_locally_shortest(domain, over)
    assert_locally_shortest(domain, under)


@pytest.mark.parametrize("k", [3, 10])
def test_the_long_way_round_a_cylinder_stays_the_long_way(k):
    sides, rows = 24, 9
    V, F = revolve(lambda z: 1.0, np.linspace(0, 1.5, rows), sides)
    # A staircase the long way round: one step up, one step back around the rings, until the top ring.
    moves = ["up"] * (rows - 1) + ["back"] * (sides - k)
    moves[:2 * (rows - 1)] = ["up", "back"] * (rows - 1)
    r, i, edges = 0, 0, [0]
    for move in moves:
        r, i = (r + 1, i) if move == "up" else (r, (i - 1) % sides)
        edges.append(r * sides + i)
    assert edges[-1] == (rows - 1) * sides + k
    path = hc.straighten_path(V, F, edges)
    side = np.linalg.norm(V[1] - V[0])
    assert path.length == pytest.approx(np.hypot((sides - k) * side, 1.5), rel=1e-12)
    assert path.length <= edge_length(V, edges)
    turn = np.unwrap(np.arctan2(path.points[:, 1], path.points[:, 0]))
    assert turn[-1] - turn[0] == pytest.approx(-2 * np.pi * (sides - k) / sides, abs=1e-9)


@pytest.mark.parametrize("name", ["spot", "fandisk", "homer"])
def test_jagged_paths_on_shared_meshes_become_geodesics(name):
    V, F = load_shared_mesh(name)
    domain = hc.TriangleMesh(V, F, refine=0)
    used = np.unique(F)
    s, t = int(used[10]), int(used[len(used) // 2])
    edges = jagged_path(V, F, s, t)
    exact = exact_distance(V, F, s)[t]
    path = hc.HeatSolver(domain).straighten_path(edges)
    assert path.vertices[0] == s and path.vertices[-1] == t
    assert exact * (1 - SHORTER) <= path.length <= edge_length(V, edges)
    assert_locally_shortest(domain, path)
    assert_on_surface(path, V, F)
    if name != "homer":  # there the jagged path leads to another geodesic, 5.4% longer (locally shortest)
        assert path.length == pytest.approx(exact, rel=1e-9)


def test_a_waypoint_polyline_is_straightened_between_its_ends():
    V, F = grid(15, 15, jitter=0.3, seed=5)
    solver = hc.HeatSolver(hc.TriangleMesh(V, F, refine=0))
    through = solver.geodesic_path(points=[0, 14, 224])
    path = solver.straighten_path(through)
    assert path.length == pytest.approx(np.linalg.norm(V[224] - V[0]), rel=1e-12)
    traced = solver.trace((3, [0.2, 0.3, 0.5]), [1.0, 0.5, 0.0], 0.6)  # a traced polyline is straight already
    again = solver.straighten_path(traced)
    assert again.length == pytest.approx(traced.length, rel=1e-12)
    np.testing.assert_allclose(again.points[[0, -1]], traced.points[[0, -1]], atol=1e-14)


@pytest.mark.parametrize("sides", [32, 64])
def test_jagged_loop_around_a_cylinder_becomes_a_circle(sides):
    r = 0.7
    V, F = revolve(lambda z: r, np.linspace(0, 2, 11), sides)
    loop = hc.straighten_loop(V, F, zigzag_loop(sides, 4))
    polygon = 2 * sides * r * np.sin(np.pi / sides)  # the mesh's circle: a regular polygon
    assert loop.length == pytest.approx(polygon, rel=1e-12)
    assert abs(loop.length / (2 * np.pi * r) - 1) <= 5e-3
    np.testing.assert_array_equal(loop.points[0], loop.points[-1])
    assert np.ptp(loop.points[:, 2]) <= 1e-12  # one ring of the cylinder
    assert_locally_shortest(hc.TriangleMesh(V, F, refine=0), loop)


def test_loop_around_a_neck_slides_to_the_waist():
    sides, waist = 32, 0.5
    V, F = revolve(lambda z: np.hypot(waist, z), np.linspace(-1, 1, 21), sides)
    loop = hc.straighten_loop(V, F, zigzag_loop(sides, 13))  # starts between z = 0.3 and 0.4
    polygon = 2 * sides * waist * np.sin(np.pi / sides)
    assert loop.length == pytest.approx(polygon, rel=1e-10)  # measured 9e-12
    assert np.abs(loop.points[:, 2]).max() <= 1e-8  # measured 1.5e-9
    assert_locally_shortest(hc.TriangleMesh(V, F, refine=0), loop)


def test_loop_around_a_torus_tube_is_the_tube_circle():
    R, r, n_around, n_tube = 1.0, 0.3, 48, 32
    u, w = np.meshgrid(2 * np.pi * np.arange(n_around) / n_around, 2 * np.pi * np.arange(n_tube) / n_tube,
                       indexing="ij")
    V = np.stack([(R + r * np.cos(w)) * np.cos(u), (R + r * np.cos(w)) * np.sin(u), r * np.sin(w)], -1).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(n_around), np.arange(n_tube), indexing="ij")
    a, b = i * n_tube + j, i * n_tube + (j + 1) % n_tube
    c, d = ((i + 1) % n_around) * n_tube + (j + 1) % n_tube, ((i + 1) % n_around) * n_tube + j
    F = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    edges = zigzag_loop(n_tube, 3)
    loop = hc.straighten_loop(V, F, edges)
    assert abs(loop.length / (2 * np.pi * r) - 1) <= 5e-3
    assert loop.length <= edge_length(V, edges + edges[:1])
    assert_locally_shortest(hc.TriangleMesh(V, F, refine=0), loop)


def test_loop_around_a_hole_is_its_rim_and_a_loop_around_nothing_a_point():
    V, F = holed_grid()
    ring = [6 * 21 + i for i in range(6, 15)] + [j * 21 + 14 for j in range(7, 15)]
    ring += [14 * 21 + i for i in range(13, 5, -1)] + [j * 21 + 6 for j in range(13, 6, -1)]
    rim = hc.straighten_loop(V, F, ring)  # the square (0.3, 0.7)^2 around the hole shrinks to the rim
    assert rim.length == pytest.approx(0.8, rel=1e-12)
    point = hc.straighten_loop(V, F, [22, 23, 24, 45, 66, 65, 64, 43])  # around vertex 44: nothing to hold it
    assert point.length == 0.0 and len(point) == 1


def test_bad_paths_raise_typed_errors():
    V, F = grid(5, 5)
    with pytest.raises(hc.InvalidSourceError, match="share no edge"):
        hc.straighten_path(V, F, [0, 2])
    with pytest.raises(hc.InvalidSourceError, match="vertex 1 of the path"):
        hc.straighten_path(V, F, [0, 99])
    with pytest.raises(hc.InvalidSourceError, match="list of vertex indices"):
        hc.straighten_path(V, F, [0.5, 1.5])
    with pytest.raises(hc.UnsupportedDomainError, match="triangle meshes"):
        hc.HeatSolver(hc.PointCloud(V)).straighten_path([0, 1])


def test_straighten_command_writes_the_geodesic(tmp_path, capsys):
    from heatcore.apps.cli import main

    V, F = revolve(lambda z: 0.7, np.linspace(0, 2, 11), 32)
    mesh, edges, out = tmp_path / "cylinder.obj", tmp_path / "edges.txt", tmp_path / "s.ply"
    _write_obj(mesh, V, F)
    loop = zigzag_loop(32, 4)
    edges.write_text("# a jagged loop\n" + "\n".join(map(str, loop)) + "\n")
    assert main(["straighten", str(mesh), "--path", str(edges), "--loop", "-o", str(out), "-q"]) == 0
    printed = capsys.readouterr().out.split()
    polygon = 64 * 0.7 * np.sin(np.pi / 32)
    assert float(printed[1]) == pytest.approx(polygon, rel=1e-9)
    assert float(printed[4].rstrip(",")) == pytest.approx(edge_length(V, loop + loop[:1]), rel=1e-9)
    text = out.read_text().splitlines()
    k = int(next(line.split()[2] for line in text if line.startswith("element vertex")))
    points = np.array([r.split() for r in text[text.index("end_header") + 1:][:k]], float)
    assert np.linalg.norm(np.diff(points, axis=0), axis=1).sum() == pytest.approx(polygon, rel=1e-9)
    edges.write_text("\n".join(map(str, loop[:9])) + "\n")  # open: the ends kept
    assert main(["straighten", str(mesh), "--path", str(edges), "-o", str(out), "-q"]) == 0
    assert float(capsys.readouterr().out.split()[1]) == pytest.approx(
        hc.straighten_path(V, F, loop[:9]).length, rel=1e-9)


def test_straighten_command_errors(tmp_path, capsys):
    from heatcore.apps.cli import main
    from heatcore.io import demo_mesh_path

    mesh, edges, out = str(demo_mesh_path()), tmp_path / "edges.txt", str(tmp_path / "s.obj")
    edges.write_text("0\n2\n")  # not an edge of spot
    assert main(["straighten", mesh, "--path", str(edges), "-o", out, "-q"]) == 1
    assert "share no edge" in capsys.readouterr().err
    edges.write_text("0\nseven\n")
    assert main(["straighten", mesh, "--path", str(edges), "-o", out, "-q"]) == 1
    assert "line 2" in capsys.readouterr().err
    assert main(["straighten", mesh, "--path", str(tmp_path / "none.txt"), "-o", out, "-q"]) == 1
    assert main(["straighten", mesh, "--path", str(edges), "-o", str(tmp_path / "s.txt")]) == 2
    assert main(["straighten", mesh, "-o", out]) == 2
    assert not (tmp_path / "s.obj").exists()


def _write_obj(path, V, F):
    path.write_text("".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in V.tolist())
                    + "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in F.tolist()))
