"""One source syntax on every subcommand (issue 38): ``-s 0 17``, ``-s 0,17``, ``-s 0 -s 17``.

Every test runs the real entry point (:func:`heatcore.apps.cli.main`, or the
MeshLab script's :func:`heatcore.apps.meshlab.main`).
"""

import numpy as np
import pytest

from heatcore.apps import cli

FAST = ["--refine", "0", "-q"]
SPELLINGS = (["-s", "0", "17"], ["-s", "0,17"], ["-s", "0", "-s", "17"], ["--source", "0", "--sources", "17"],
             ["--sources", "0, 17"])


def write_grid(path, n=6):
    """A flat n x n grid as OBJ (36 vertices)."""
    x, y = np.meshgrid(np.arange(n, dtype=float), np.arange(n, dtype=float))
    lines = [f"v {a:g} {b:g} 0" for a, b in zip(x.ravel(), y.ravel())]
    for j in range(n - 1):
        for i in range(n - 1):
            a = j * n + i
            lines += [f"f {a + 1} {a + 2} {a + n + 2}", f"f {a + 1} {a + n + 2} {a + n + 1}"]
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.fixture
def grid_obj(tmp_path):
    return write_grid(tmp_path / "grid.obj")


def run(argv, capsys):
    code = cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_distance_every_spelling_same_result(grid_obj, tmp_path, capsys):
    results = []
    for k, spelling in enumerate(SPELLINGS):
        out = tmp_path / f"d{k}.npy"
        code, _, err = run(["distance", grid_obj, *spelling, "-o", out, *FAST], capsys)
        assert code == 0, err
        results.append(np.load(out))
    for d in results[1:]:
        np.testing.assert_array_equal(d, results[0])
    assert results[0][0] == 0 and results[0][17] == 0


def test_batch_every_spelling_same_rows(grid_obj, tmp_path, capsys):
    rows = []
    for k, spelling in enumerate(SPELLINGS):
        out = tmp_path / f"b{k}"
        code, _, err = run(["batch", grid_obj, "-o", out, *spelling, "-j", "0", *FAST], capsys)
        assert code == 0, err
        with np.load(out / "grid.npz") as z:
            rows.append((z["sources"].tolist(), z["distances"]))
    for sources, d in rows:
        assert sources == [0, 17]
        np.testing.assert_array_equal(d, rows[0][1])


def test_batch_keywords_alone(grid_obj, tmp_path, capsys):
    code, _, err = run(["batch", grid_obj, "-o", tmp_path / "o", "-s", "farthest:2", "-j", "0", *FAST], capsys)
    assert code == 0, err
    code, _, err = run(["batch", grid_obj, "-o", tmp_path / "o", "-s", "all", "3", "-j", "0", *FAST], capsys)
    assert code == 2 and "give it alone" in err


def test_meshlab_every_spelling(grid_obj, tmp_path, capsys):
    pytest.importorskip("pymeshlab")
    from heatcore.apps import meshlab

    for k, spelling in enumerate(SPELLINGS):
        out = tmp_path / f"m{k}.ply"
        code, _, err = run(["meshlab", grid_obj, *spelling, "-o", out, "--json", "-q"], capsys)
        assert code == 0, err
        code = meshlab.main([str(grid_obj), *spelling, "-o", str(tmp_path / f"s{k}.ply"), "--json"])
        out, err = capsys.readouterr()
        assert code == 0, err
        assert '"sources": 2' in out


@pytest.mark.parametrize("spelling", [["-s", "0", "17"], ["-s", "0,17"], ["-s", "0", "-s", "17"],
                                      ["-s", "0", "--source", "17"]])
def test_logmap_refuses_two_sources(grid_obj, tmp_path, capsys, spelling):
    code, out, err = run(["logmap", grid_obj, *spelling, "-o", tmp_path / "uv.npy", *FAST], capsys)
    assert code == 2
    assert "takes one source, got 2 (0, 17)" in err and err.count("\n") == 1
    assert not (tmp_path / "uv.npy").exists()


def test_logmap_one_source_any_flag(grid_obj, tmp_path, capsys):
    for flag in ("-s", "--source", "--sources"):
        code, _, err = run(["logmap", grid_obj, flag, "14", "-o", tmp_path / "uv.npy", *FAST, "--overwrite"], capsys)
        assert code == 0, err


@pytest.mark.parametrize("points", [["--from", "0", "17", "--to", "3"], ["--from", "0,17", "--to", "3"],
                                    ["--from", "0", "--from", "17", "--to", "3"], ["--from", "3", "--to", "0", "17"]])
def test_path_refuses_two_points(grid_obj, tmp_path, capsys, points):
    code, _, err = run(["path", grid_obj, *points, "-o", tmp_path / "p.obj", *FAST], capsys)
    assert code == 2 and "takes one" in err and "got 2" in err


def test_path_face_point_kept_whole(grid_obj, tmp_path, capsys):
    code, out, err = run(["path", grid_obj, "--from", "0", "--to", "3:0.2,0.3,0.5", "-o", tmp_path / "p.csv", *FAST],
                         capsys)
    assert code == 0, err
    assert "length" in out


def test_mesh_after_sources_says_so(grid_obj, tmp_path, capsys):
    code, _, err = run(["distance", "-s", "0", grid_obj, "-o", tmp_path / "d.npy"], capsys)
    assert code == 2 and "the mesh file goes before the sources" in err


def test_help_states_the_syntax(capsys):
    for name in ("distance", "batch", "meshlab"):
        code, out, _ = run([name, "--help"], capsys)
        assert code == 0
        assert "-s 0,17" in " ".join(out.split()), name


@pytest.mark.parametrize("through", [["--through", "0", "7", "35"], ["--through", "0,7,35"],
                                     ["--through", "0", "--through", "7", "35"]])
def test_path_through_every_spelling(grid_obj, tmp_path, capsys, through):
    out = tmp_path / "p.csv"
    code, stdout, err = run(["path", grid_obj, *through, "-o", out, *FAST], capsys)
    assert code == 0, err
    points = np.loadtxt(out, delimiter=",", skiprows=1)
    np.testing.assert_allclose(points[0], [0, 0, 0])
    np.testing.assert_allclose(points[-1], [5, 5, 0])
