"""``heatcore distance --isolines-out PATH N``: OBJ polylines equal to heatcore.isolines; MeshLab and
Blender read them as edges."""

import re

import numpy as np
import pytest

import heatcore as hc
from heatcore.apps import cli
from heatcore.contours import isoline_levels
from heatcore.io import read_mesh

FAST = ["--refine", "1", "-q"]


def write_obj(path, V, F):
    lines = [f"v {x:.17g} {y:.17g} {z:.17g}" for x, y, z in V] + [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in F]
    path.write_text("\n".join(lines) + "\n")
    return path


def read_curves(path):
    """(points, segments (1-based pairs), levels in the comments) of an --isolines-out file."""
    text = path.read_text()
    points = np.array([[float(x) for x in line.split()[1:]] for line in text.splitlines() if line.startswith("v ")])
    segments = np.array([[int(x) for x in line.split()[1:]] for line in text.splitlines() if line.startswith("l ")])
    levels = [float(x) for x in re.findall(r"^# isoline \d+: level (\S+),", text, flags=re.M)]
    return points, segments, levels


@pytest.fixture
def spot_obj(tmp_path):
    mesh = read_mesh(hc.io.demo_mesh_path())
    return write_obj(tmp_path / "spot.obj", mesh.vertices, mesh.faces), mesh.vertices, mesh.faces


def test_isolines_out_writes_the_curves_of_the_distance(spot_obj, tmp_path, capsys):
    path, V, F = spot_obj
    obj, npy = tmp_path / "curves.obj", tmp_path / "d.npy"
    assert cli.main(["distance", str(path), "-s", "1453", "-o", str(npy), "--isolines-out", str(obj), "9", *FAST]) == 0
    out = capsys.readouterr().out
    d = np.load(npy)
    curves = hc.isolines(V, F, d, 9)
    assert f"wrote {obj}  ({len(curves)} isoline curves)" in out
    points, segments, levels = read_curves(obj)
    # the same points, bit for bit (%.17g), curve after curve; one l element per segment
    np.testing.assert_array_equal(points, np.concatenate([c.points for c in curves]))
    assert len(segments) == sum(len(c.faces) for c in curves)
    start = 1
    expected = []
    for c in curves:
        k = len(c.points)
        idx = list(range(start, start + k)) + ([start] if c.closed else [])
        expected += list(zip(idx[:-1], idx[1:]))
        start += k
    assert segments.tolist() == [list(e) for e in expected]
    assert levels == [c.level for c in curves]
    assert sorted(set(levels)) == isoline_levels(d, 9).tolist()  # max * j / 10
    assert all(c.closed for c in curves)  # spot is closed


def test_isolines_out_alone_and_bad_names(spot_obj, tmp_path, capsys):
    path, _, _ = spot_obj
    obj = tmp_path / "c.obj"
    assert cli.main(["distance", str(path), "-s", "0", "--isolines-out", str(obj), "3", *FAST]) == 0
    assert obj.is_file()
    for bad, message in ((["c.txt", "3"], "give a name ending in .obj"), (["c.obj", "0"], "at least 1"),
                         (["c.obj", "many"], "not an integer")):
        code = cli.main(["distance", str(path), "-s", "0", "--isolines-out", str(tmp_path / bad[0]), bad[1], *FAST])
        assert code == 2 and message in capsys.readouterr().err
    xyz = tmp_path / "cloud.xyz"
    np.savetxt(xyz, np.random.default_rng(0).random((50, 3)))
    assert cli.main(["distance", str(xyz), "-s", "0", "--isolines-out", str(obj), "3", "-q"]) == 1
    assert "point cloud has none" in capsys.readouterr().err


def test_meshlab_reads_the_curves_as_edges(spot_obj, tmp_path):
    pymeshlab = pytest.importorskip("pymeshlab")
    path, _, _ = spot_obj
    obj = tmp_path / "curves.obj"
    assert cli.main(["distance", str(path), "-s", "1453", "--isolines-out", str(obj), "6", *FAST]) == 0
    points, segments, _ = read_curves(obj)
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(str(obj))
    m = ms.current_mesh()
    assert (m.vertex_number(), m.edge_number(), m.face_number()) == (len(points), len(segments), 0)
    np.testing.assert_allclose(m.vertex_matrix(), points, rtol=1e-6)  # MeshLab keeps floats
    np.testing.assert_array_equal(m.edge_matrix(), segments - 1)
