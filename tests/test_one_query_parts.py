"""A one-off query builds only the connected parts its sources are on (issue 34: many-part models).

Each part is solved as if it were alone, so leaving out the parts no source
is on changes no distance there (inf before and after) and none on the
sources' parts beyond rounding, and saves their refinement and
factorizations: a model of 40 parts (121k vertices, 38 small parts refined
to 523k solver vertices) went from 5.8 s to 0.44 s, the source's part alone
taking 0.32 s.
"""

import numpy as np
import pytest
from shapes import icosphere

import heatcore as hc
from heatcore.apps.cli import main
from heatcore.domains.sources import source_vertices
from heatcore.io.mesh import read_mesh


def parts(count=3, subdivisions=2):
    """``count`` icospheres side by side (one part each), and each one's vertex range."""
    V0, F0 = icosphere(subdivisions)
    V = np.vstack([V0 + [3.0 * k, 0, 0] for k in range(count)])
    F = np.vstack([F0 + k * len(V0) for k in range(count)])
    return V, F, [np.arange(k * len(V0), (k + 1) * len(V0)) for k in range(count)]


@pytest.fixture
def built(monkeypatch):
    """The TriangleMesh objects the API builds, in order."""
    meshes = []
    original = hc.TriangleMesh.__init__

    def spy(self, *args, **kwargs):
        original(self, *args, **kwargs)
        meshes.append(self)

    monkeypatch.setattr(hc.TriangleMesh, "__init__", spy)
    return meshes


def test_the_parts_no_source_is_on_are_not_built_and_stay_unreachable(built):
    V, F, ranges = parts()
    d = hc.geodesic_distance(V, F, [ranges[1][5]])
    assert built[0].n_parts == 1 and built[0].parts_left_out == 2
    assert np.isinf(d[ranges[0]]).all() and np.isinf(d[ranges[2]]).all()
    alone = hc.geodesic_distance(V[ranges[1]], F[len(F) // 3 : 2 * len(F) // 3] - len(ranges[0]), [5])
    np.testing.assert_allclose(d[ranges[1]], alone, rtol=1e-12, atol=1e-12)


def test_every_part_a_source_is_on_is_built(built):
    V, F, ranges = parts()
    # the heat method on both ("auto" depends on the size built: the three parts refined make 123k vertices, the march)
    whole = hc.HeatSolver(hc.TriangleMesh(V, F), intent="one query", accuracy="smooth").distance([ranges[0][0], ranges[2][0]])
    d = hc.geodesic_distance(V, F, [ranges[0][0], ranges[2][0]], accuracy="smooth")
    assert built[-1].parts_left_out == 1
    np.testing.assert_allclose(d, whole, rtol=1e-12, atol=1e-12)  # inf on the middle part in both
    assert np.isinf(d[ranges[1]]).all()


@pytest.mark.parametrize("kind", ["edges", "region", "points"])
def test_each_source_kind_keeps_its_part(built, kind):
    V, F, ranges = parts(2)
    face = len(F) // 2  # the second part's first face
    value = {"edges": [F[face, :2]], "region": [face], "points": ([face], [[0.2, 0.3, 0.5]])}[kind]
    d = hc.geodesic_distance(V, F, **{kind: value})
    assert built[0].parts_left_out == 1
    assert np.isinf(d[ranges[0]]).all() and np.isfinite(d[ranges[1]]).all()


def test_welded_parts_are_one_part():
    """Two triangles that share a corner only by position: welded (the default), one part, both reached."""
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 0, 0], [2, 0, 0], [1, 1, 0]], float)
    d = hc.geodesic_distance(V, [[0, 1, 2], [3, 4, 5]], [0], refine=0)
    assert np.isfinite(d).all()
    np.testing.assert_allclose(d[4], 2.0, rtol=1e-9)
    assert np.isinf(hc.geodesic_distance(V, [[0, 1, 2], [3, 4, 5]], [0], refine=0, weld=None)[3:]).all()


def test_the_refinement_budget_is_the_sources_parts_alone():
    """Many small parts cap every part's refinement together; the source's part alone gets its full levels."""
    V, F, ranges = parts(count=40, subdivisions=1)  # 42 vertices a part: 5 levels alone, capped in all 40
    mesh = hc.TriangleMesh(V, F, only_parts_of=[ranges[7][0]])
    assert mesh.n_parts == 1 and mesh.parts_left_out == 39
    alone = hc.TriangleMesh(V[ranges[7]], F[: len(F) // 40])
    assert mesh.part_levels.tolist() == alone.part_levels.tolist() == [5]


def test_no_source_on_a_face_leaves_the_errors_to_the_source_checks():
    V, F, _ = parts(2)
    V = np.vstack([V, [[9, 9, 9]]])
    with pytest.raises(hc.InvalidSourceError, match=f"vertex {len(V) - 1} is not used by any face"):
        hc.geodesic_distance(V, F, [len(V) - 1])
    with pytest.raises(hc.InvalidSourceError, match="out of range"):
        hc.geodesic_distance(V, F, [len(V)])
    with pytest.raises(hc.InvalidSourceError, match="no source"):
        hc.geodesic_distance(V, F)


def test_source_vertices_names_each_kind():
    F = np.array([[0, 1, 2], [2, 3, 4]])
    assert source_vertices(7, F, [6]).tolist() == [6]
    assert source_vertices(7, F, edges=[[5, 6]]).tolist() == [5, 6]
    assert source_vertices(7, F, points=([1], [[1, 0, 0]])).tolist() == [2, 3, 4]
    assert source_vertices(7, F).tolist() == []
    with pytest.raises(hc.InvalidSourceError, match="face index 2 is out of range"):
        source_vertices(7, F, region=[2])


def test_the_command_line_writes_inf_on_the_parts_no_source_is_on(tmp_path):
    V, F, ranges = parts(2)
    path = tmp_path / "two.obj"
    write_obj(path, V, F)
    out = tmp_path / "d.npy"
    assert main(["distance", str(path), "-s", str(ranges[1][3]), "-o", str(out), "-q"]) == 0
    d = np.load(out)
    mesh = read_mesh(path)
    expected = hc.HeatSolver(hc.TriangleMesh(mesh.vertices, mesh.faces), intent="one query",
                             accuracy="smooth").distance([ranges[1][3]])  # the command's default
    np.testing.assert_allclose(d, expected, rtol=1e-12, atol=1e-12)
    assert np.isinf(d[ranges[0]]).all()


def write_obj(path, V, F):
    lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in V] + [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in F]
    path.write_text("\n".join(lines) + "\n")


def test_a_polygon_mesh_builds_only_the_sources_parts():
    quad = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)
    V = np.vstack([quad, quad + [5, 0, 0]])
    mesh = hc.PolygonMesh(V, [[0, 1, 2, 3], [4, 5, 6, 7]], refine=0, only_parts_of=[5])
    assert mesh.parts_left_out == 1 and mesh.n_polygons == 1
    d = hc.HeatSolver(mesh).distance([5])
    alone = hc.HeatSolver(hc.PolygonMesh(quad, [[0, 1, 2, 3]], refine=0)).distance([1])
    np.testing.assert_allclose(d[4:], alone, rtol=1e-12, atol=1e-12)
    assert np.isinf(d[:4]).all()
    with pytest.raises(hc.InvalidSourceError, match="vertex 0 lies on a part this mesh was built without"):
        hc.HeatSolver(mesh).distance([0])


def test_the_command_line_builds_only_the_sources_parts_of_a_polygon_file(tmp_path):
    quad = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)
    path = tmp_path / "quads.obj"
    lines = [f"v {x} {y} {z}" for x, y, z in np.vstack([quad, quad + [5, 0, 0]])] + ["f 1 2 3 4", "f 5 6 7 8"]
    path.write_text("\n".join(lines) + "\n")
    out = tmp_path / "d.npy"
    assert main(["distance", str(path), "-s", "6", "-o", str(out), "-q", "--refine", "0"]) == 0
    d = np.load(out)
    assert np.isinf(d[:4]).all() and d[6] == 0 and np.isfinite(d[4:]).all()
