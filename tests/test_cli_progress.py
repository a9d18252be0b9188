"""The command line's picture camera (--view) and its build progress on stderr."""

import numpy as np

from heatcore.apps import cli


def sphere_obj(path):
    import trimesh

    sphere = trimesh.creation.icosphere(subdivisions=2)
    V, F = np.asarray(sphere.vertices), np.asarray(sphere.faces)
    path.write_text("".join(f"v {x} {y} {z}\n" for x, y, z in V) + "".join(f"f {a+1} {b+1} {c+1}\n" for a, b, c in F))
    return path


def test_view_option(tmp_path, capsys):
    mesh = sphere_obj(tmp_path / "s.obj")
    assert cli.main(["distance", str(mesh), "-s", "0", "--png", str(tmp_path / "d.png"), "--view=-40,20", "-q"]) == 0
    assert cli.main(["distance", str(mesh), "-s", "0", "--png", str(tmp_path / "d.png"), "--view", "10,91"]) == 2
    assert "elevation must be between -90 and 90 degrees, got 91" in capsys.readouterr().err


def test_long_builds_report_their_stages_on_stderr(tmp_path, capsys, monkeypatch):
    mesh = sphere_obj(tmp_path / "s.obj")
    command = ["distance", str(mesh), "-s", "0", "-o", str(tmp_path / "d.npy"), "--refine", "0"]
    assert cli.main(command) == 0
    assert "%" not in capsys.readouterr().err  # a small mesh: no stage lines
    monkeypatch.setattr("heatcore.apps.reporting.PROGRESS_FROM_VERTICES", 100)
    assert cli.main(command) == 0
    lines = [line for line in capsys.readouterr().err.splitlines() if "%" in line]
    fractions = [float(line.split("%")[0].split()[-1]) for line in lines]
    assert fractions == sorted(fractions) and fractions[0] == 0 and fractions[-1] == 100
    assert any("factoring the heat matrix" in line for line in lines)
    assert cli.main([*command, "-q"]) == 0
    assert capsys.readouterr().err == ""
