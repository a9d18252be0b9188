"""``heatcore signed``: the signed heat method from curve files, written as .npy/.csv/.ply, a picture and isolines."""

import numpy as np
import pytest

import heatcore as hc
from heatcore.apps.cli import main
from heatcore.io import demo_mesh_path, read_mesh

NOSE = 1453


@pytest.fixture(scope="module")
def nose_loop():
    """The boundary of the faces within 0.35 of spot's nose: a closed loop of 36 edges, the nose on its left."""
    V, F = hc.io.load_demo_mesh()
    d = hc.geodesic_distance(V, F, [NOSE])
    (loop,) = hc.region_boundary_curves(F, np.flatnonzero(d[F].max(axis=1) < 0.35))
    return [int(v) for v in loop]


def _curve_file(path, points):
    lines = [f"{p}" if isinstance(p, int) else f"{p[0]}:{','.join(map(str, p[1]))}" for p in points]
    path.write_text("# a curve\n" + "".join(line + "\n" for line in lines))
    return path


def test_outputs_hold_the_signed_field(tmp_path, nose_loop, capsys):
    curve = _curve_file(tmp_path / "loop.txt", nose_loop)
    outs = [tmp_path / n for n in ("s.npy", "s.csv", "s.ply")]
    png, iso = tmp_path / "s.png", tmp_path / "zero.obj"
    argv = ["signed", str(demo_mesh_path()), "--curve", str(curve), "--refine", "0", "--png", str(png),
            "--isolines-out", str(iso), "2", "-q"]
    assert main(argv + [a for out in outs for a in ("-o", str(out))]) == 0
    assert capsys.readouterr().out.count("wrote") == 5
    expected = hc.SignedHeatSolver(hc.TriangleMesh(*hc.io.load_demo_mesh(), refine=0)).distance([nose_loop])
    phi = np.load(outs[0])
    np.testing.assert_allclose(phi, expected, rtol=1e-9, atol=1e-12)  # the one-query backend: the same numbers
    assert phi[NOSE] > 0.2 and phi[0] < 0  # the nose is on the loop's left
    table = np.loadtxt(outs[1], delimiter=",", skiprows=1)
    assert np.allclose(table[:, 1], expected, rtol=1e-15)
    ply = read_mesh(outs[2])
    assert np.allclose(ply.vertex_data["quality"], expected)
    assert sorted(ply.selected_vertices().tolist()) == sorted(set(nose_loop))
    red, blue = ply.vertex_data["red"], ply.vertex_data["blue"]
    assert red[NOSE] > blue[NOSE] and blue[0] > red[0]  # positive warm, negative cool
    assert png.read_bytes()[:4] == b"\x89PNG"
    levels = [float(line.split("level ")[1].split(",")[0]) for line in iso.read_text().splitlines()
              if line.startswith("# isoline")]
    spacing = np.abs(expected).max() / 3  # two levels on each side of 0; the positive ones lie beyond the nose's 0.3
    np.testing.assert_allclose(sorted(set(np.round(levels, 9))), [-2 * spacing, -spacing, 0.0], atol=1e-8)


def test_face_points_and_unsigned_curves(tmp_path, capsys):
    V, F = hc.io.load_demo_mesh()
    points = [(f, (1 / 3, 1 / 3, 1 / 3)) for f in (0, 1, 2)]
    curve = _curve_file(tmp_path / "c.txt", points)
    out = tmp_path / "s.npy"
    assert main(["signed", str(demo_mesh_path()), "--unsigned-curve", str(curve), "-o", str(out), "-q",
                 "--refine", "0"]) == 0
    faces, bary = np.array([p[0] for p in points]), np.array([p[1] for p in points])
    heat = hc.HeatSolver(hc.TriangleMesh(V, F, refine=0)).distance(points=(faces, bary))
    assert np.allclose(np.load(out), heat)


def test_errors(tmp_path, capsys):
    spot = str(demo_mesh_path())
    good = _curve_file(tmp_path / "good.txt", [738, 734])  # an edge of spot
    out = str(tmp_path / "s.npy")
    assert main(["signed", spot, "-o", out]) == 2  # no curve
    assert "no curve" in capsys.readouterr().err
    assert main(["signed", spot, "--curve", str(good)]) == 2
    assert "nothing to write" in capsys.readouterr().err
    assert main(["signed", spot, "--curve", str(tmp_path / "missing.txt"), "-o", out]) == 2
    assert "cannot read curve file" in capsys.readouterr().err
    (tmp_path / "bad.txt").write_text("0\nzero\n")
    assert main(["signed", spot, "--curve", str(tmp_path / "bad.txt"), "-o", out]) == 2
    assert "bad.txt line 2" in capsys.readouterr().err
    (tmp_path / "one.txt").write_text("738\n")
    assert main(["signed", spot, "--curve", str(tmp_path / "one.txt"), "-o", out]) == 2
    assert "needs two" in capsys.readouterr().err
    assert main(["signed", spot, "--curve", str(good), "-o", out, "--accuracy", "high"]) == 2  # not offered
    capsys.readouterr()
    far = _curve_file(tmp_path / "far.txt", [0, 10**6])
    assert main(["signed", spot, "--curve", str(far), "-o", out, "--refine", "0"]) == 1
    assert "out of range" in capsys.readouterr().err
    assert not (tmp_path / "s.npy").exists()
