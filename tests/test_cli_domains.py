"""The `heatcore distance` command on tetrahedral meshes, point clouds and polygon meshes."""

import meshio
import numpy as np
import scipy.spatial
from conftest import shared_mesh_path

import heatcore as hc
from heatcore.apps import cli
from heatcore.domains.pointcloud import PointCloud
from heatcore.io.domain import read_domain


def test_tet_mesh_from_vtu_to_vtu(tmp_path):
    rng = np.random.default_rng(0)
    P = rng.random((300, 3))
    T = scipy.spatial.Delaunay(P).simplices
    src = tmp_path / "cube.vtu"
    meshio.write(src, meshio.Mesh(P, [("tetra", T)]))
    out, npy = tmp_path / "d.vtu", tmp_path / "d.npy"
    assert cli.main(["distance", str(src), "-s", "5", "-o", str(out), "-o", str(npy), "-q"]) == 0
    expected = hc.HeatSolver(hc.TetMesh(P, T)).distance([5])
    assert np.allclose(np.load(npy), expected, rtol=1e-12)
    assert np.allclose(meshio.read(out).point_data["distance"], expected, rtol=1e-12)
    assert read_domain(src).kind == "tet"


def test_tet_mesh_refuses_ply_output(tmp_path, capsys):
    P = np.random.default_rng(1).random((50, 3))
    src = tmp_path / "c.vtu"
    meshio.write(src, meshio.Mesh(P, [("tetra", scipy.spatial.Delaunay(P).simplices)]))
    assert cli.main(["distance", str(src), "-s", "0", "-o", str(tmp_path / "x.ply")]) == 1
    assert "written as .vtu" in capsys.readouterr().err
    assert not (tmp_path / "x.ply").exists()


def test_point_cloud_from_xyz(tmp_path):
    V, _ = hc.io.load_demo_mesh()
    src = tmp_path / "spot.xyz"
    np.savetxt(src, V)
    out = tmp_path / "d.ply"
    assert cli.main(["distance", str(src), "-s", "0", "-o", str(out), "-q"]) == 0
    expected = hc.HeatSolver(PointCloud(np.loadtxt(src))).distance([0])
    written = meshio.read(out)
    assert len(written.points) == len(V) and not written.cells
    assert np.allclose(written.point_data["quality"], expected, rtol=1e-12)


def test_polygon_domain_keeps_quads(tmp_path):
    path = shared_mesh_path("suzanne")
    npy = tmp_path / "d.npy"
    assert cli.main(["distance", str(path), "--domain", "polygon", "-s", "0", "-o", str(npy), "-q"]) == 0
    f = read_domain(path, "polygon")
    mesh = hc.PolygonMesh(f.vertices, f.cells, only_parts_of=[0])  # one query: the source's part alone
    expected = hc.HeatSolver(mesh, hc.SolverSettings(intent="one query")).distance([0])  # as the command factors
    assert np.array_equal(np.load(npy), expected)
    assert (np.diff(f.cells[0]) == 4).sum() == 468
