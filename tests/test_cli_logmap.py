"""``heatcore logmap``: the log map written as .npy, .csv and PLY texture coordinates; usage and input errors."""

import numpy as np
import pytest

import heatcore as hc
from heatcore.apps.cli import main
from heatcore.io import demo_mesh_path, read_mesh


@pytest.fixture(scope="module")
def expected():
    V, F = hc.io.load_demo_mesh()
    solver = hc.VectorHeatSolver(hc.TriangleMesh(V, F, refine=0))
    return solver.log_map(970, reference=[0.0, 1.0, 0.0])


def test_outputs_hold_the_log_map(tmp_path, expected, capsys):
    outs = [tmp_path / name for name in ("uv.npy", "uv.csv", "uv.ply")]
    argv = ["logmap", str(demo_mesh_path()), "-s", "970", "--reference", "0", "1", "0", "--refine", "0", "-q"]
    assert main(argv + [arg for out in outs for arg in ("-o", str(out))]) == 0
    assert capsys.readouterr().out.count("wrote") == 3
    assert np.array_equal(np.load(outs[0]), expected)
    table = np.loadtxt(outs[1], delimiter=",", skiprows=1)
    assert np.array_equal(table[:, 0], np.arange(len(expected))) and np.allclose(table[:, 1:], expected, rtol=1e-15)
    ply = read_mesh(outs[2]).vertex_data
    for u, v in (("s", "t"), ("texture_u", "texture_v")):  # Blender's names, MeshLab's names
        assert np.allclose(np.c_[ply[u], ply[v]], expected)
    assert np.allclose(ply["quality"], np.hypot(*expected.T))


def test_unreachable_vertices(tmp_path):
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [5, 0, 0], [6, 0, 0], [5, 1, 0]], float)
    mesh = tmp_path / "two.obj"
    mesh.write_text("".join(f"v {x} {y} {z}\n" for x, y, z in V) + "f 1 2 3\nf 4 5 6\n")
    npy, ply = tmp_path / "uv.npy", tmp_path / "uv.ply"
    assert main(["logmap", str(mesh), "-s", "0", "-o", str(npy), "-o", str(ply), "-q"]) == 0
    uv = np.load(npy)
    assert np.isfinite(uv[:3]).all() and np.isposinf(uv[3:]).all()
    data = read_mesh(ply).vertex_data
    assert np.array_equal(data["s"][3:], [0, 0, 0]) and np.isposinf(data["quality"][3:]).all()


def test_errors(tmp_path, capsys):
    spot = str(demo_mesh_path())
    assert main(["logmap", spot, "-o", str(tmp_path / "uv.npy")]) == 2  # no source
    assert main(["logmap", spot, "-s", "0", "-o", str(tmp_path / "uv.txt")]) == 2
    assert "unknown extension '.txt'" in capsys.readouterr().err
    assert main(["logmap", spot, "-s", "0"]) == 2
    assert "nothing to write" in capsys.readouterr().err
    assert main(["logmap", spot, "-s", "99999", "-o", str(tmp_path / "uv.npy"), "--refine", "0"]) == 1
    assert "out of range" in capsys.readouterr().err
    argv = ["logmap", spot, "-s", "0", "-o", str(tmp_path / "uv.npy"), "--refine", "0", "--reference", "0", "0", "0"]
    assert main(argv) == 1
    assert "reference direction [0.0, 0.0, 0.0] is zero" in capsys.readouterr().err
    assert not list(tmp_path.iterdir())  # nothing written
