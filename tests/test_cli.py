"""The ``heatcore`` command: outputs equal the Python API, sources, errors, demo."""

import subprocess
import sys

import numpy as np
import pytest

import heatcore as hc
from heatcore.apps import cli
from heatcore.io import MESHLAB_SELECTED_FLAG, read_mesh, write_ply
from heatcore.viz.colormap import colorize, to_uint8

# Small meshes keep every solve well under a second; --refine 1 keeps the
# refined mesh small too (the default "auto" would refine to ~12k vertices).
FAST = ["--refine", "1", "-q"]


def write_obj(path, V, F):
    lines = [f"v {x:.17g} {y:.17g} {z:.17g}" for x, y, z in V] + [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in F]
    path.write_text("\n".join(lines) + "\n")
    return path


def icosphere():
    import trimesh

    s = trimesh.creation.icosphere(subdivisions=2)
    return np.asarray(s.vertices, float), np.asarray(s.faces, np.int64)


def grid(n=9, offset=0.0):
    """Flat (n x n)-vertex square with boundary."""
    x, y = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n))
    V = np.column_stack([x.ravel() + offset, y.ravel(), np.zeros(n * n)])
    i, j = np.meshgrid(np.arange(n - 1), np.arange(n - 1))
    a = (j * n + i).ravel()
    F = np.concatenate([np.column_stack([a, a + 1, a + n + 1]), np.column_stack([a, a + n + 1, a + n])])
    return V, F


@pytest.fixture
def sphere_obj(tmp_path):
    V, F = icosphere()
    return write_obj(tmp_path / "sphere.obj", V, F), V, F


def run(argv, capsys):
    code = cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_registry_and_help(capsys):
    assert {"distance", "demo"} <= set(cli.COMMANDS)
    for name in ("distance", "demo"):
        code, out, _ = run([name, "--help"], capsys)
        assert code == 0
        parser = cli.build_parser()
        sub = parser._subparsers._group_actions[0].choices[name]
        for action in sub._actions:
            for flag in action.option_strings:
                assert flag in out, f"{name} --help misses {flag}"
            if action.option_strings and action.dest != "help":
                assert action.help, f"{name}: option {action.option_strings} has no help text"
    code, out, _ = run(["--help"], capsys)
    assert code == 0 and "distance" in out and "demo" in out


def test_distance_outputs_equal_api(sphere_obj, tmp_path, capsys):
    path, V, F = sphere_obj
    ply, npy, csv = tmp_path / "d.ply", tmp_path / "d.npy", tmp_path / "d.csv"
    code, out, err = run(["distance", path, "-s", 0, "--source", 17, "-o", ply, "-o", npy, "-o", csv, *FAST], capsys)
    assert code == 0, err
    assert err == ""  # --quiet
    for p in (ply, npy, csv):
        assert f"wrote {p}" in out

    expected = hc.geodesic_distance(V, F, [0, 17], refine=1)
    assert np.all(np.isfinite(expected)) and expected[0] == 0 and expected[17] == 0
    great_circle = np.arccos(np.clip(V @ V[[0, 17]].T, -1, 1)).min(axis=1)  # unit sphere
    far = great_circle > 0.3
    assert np.abs(expected[far] / great_circle[far] - 1).mean() < 0.03  # measured 2.0% on 162 vertices

    np.testing.assert_allclose(np.load(npy), expected, rtol=1e-12, atol=0)

    table = np.loadtxt(csv, delimiter=",", skiprows=1)
    assert csv.read_text().splitlines()[0] == "index,distance"
    np.testing.assert_array_equal(table[:, 0], np.arange(len(V)))
    np.testing.assert_allclose(table[:, 1], expected, rtol=1e-15, atol=0)  # %.17g round-trips

    mesh = read_mesh(ply)
    np.testing.assert_allclose(mesh.vertices, V)
    np.testing.assert_array_equal(mesh.faces, F)
    np.testing.assert_allclose(mesh.vertex_data["quality"], expected, rtol=1e-12, atol=0)
    rgb = np.column_stack([mesh.vertex_data[c] for c in ("red", "green", "blue")])
    np.testing.assert_array_equal(rgb, to_uint8(colorize(expected)))
    np.testing.assert_array_equal(mesh.selected_vertices(), [0, 17])


def test_options_are_forwarded(tmp_path, capsys):
    V, F = grid()
    path = write_obj(tmp_path / "grid.obj", V, F)
    out = tmp_path / "d.npy"
    opts = ["--m", "3", "--boundary", "dirichlet", "--no-robust", "--refine", "0"]
    code, _, err = run(["distance", path, "-s", 40, "-o", out, "-q", *opts], capsys)
    assert code == 0, err
    expected = hc.geodesic_distance(V, F, [40], m=3.0, boundary="dirichlet", robust=False, refine=0)
    np.testing.assert_allclose(np.load(out), expected, rtol=1e-12, atol=0)
    default = hc.geodesic_distance(V, F, [40], refine=0)
    assert np.abs(expected - default).max() > 1e-3  # the options changed the result


def test_accuracy_high_is_forwarded(tmp_path, capsys):
    V, F = grid()
    path = write_obj(tmp_path / "grid.obj", V, F)
    out = tmp_path / "d.npy"
    code, _, err = run(["distance", path, "-s", 40, "-o", out, "-q", "--accuracy", "high"], capsys)
    assert code == 0, err
    expected = hc.geodesic_distance(V, F, [40], accuracy="high")
    np.testing.assert_array_equal(np.load(out), expected)
    euclid = np.linalg.norm(V - V[40], axis=1)
    assert np.allclose(expected, euclid, rtol=1e-5)  # exact on a plane


def test_sources_file_and_union(sphere_obj, tmp_path, capsys):
    path, V, F = sphere_obj
    src = tmp_path / "sources.txt"
    src.write_text("# two sources\n0,  17\n\n 17\t")
    out = tmp_path / "d.npy"
    assert run(["distance", path, "--sources-file", src, "-o", out, *FAST], capsys)[0] == 0
    np.testing.assert_allclose(np.load(out), hc.geodesic_distance(V, F, [0, 17], refine=1), rtol=1e-12)

    assert run(["distance", path, "--sources-file", src, "-s", 50, "-o", out, *FAST], capsys)[0] == 0
    d = np.load(out)
    assert d[0] == d[17] == d[50] == 0
    np.testing.assert_allclose(d, hc.geodesic_distance(V, F, [0, 17, 50], refine=1), rtol=1e-12)


def test_selection_saved_in_ply_is_the_default_source(sphere_obj, tmp_path, capsys):
    _, V, F = sphere_obj
    selected = tmp_path / "selected.ply"
    write_ply(selected, V, F, np.zeros(len(V)), np.zeros((len(V), 3), np.uint8), selection=[5, 40])
    assert set(read_mesh(selected).vertex_data["flags"][[5, 40]]) == {MESHLAB_SELECTED_FLAG}
    out = tmp_path / "d.npy"
    code, _, err = run(["distance", selected, "-o", out, "--refine", "1"], capsys)
    assert code == 0, err
    assert "sources: 2 from the selection saved in selected.ply" in err
    np.testing.assert_allclose(np.load(out), hc.geodesic_distance(V, F, [5, 40], refine=1), rtol=1e-12)

    # --source overrides the saved selection
    assert run(["distance", selected, "-s", 3, "-o", out, *FAST], capsys)[0] == 0
    np.testing.assert_allclose(np.load(out), hc.geodesic_distance(V, F, [3], refine=1), rtol=1e-12)


def test_unreachable_vertices_are_inf(tmp_path, capsys):
    V1, F1 = grid(5)
    V2, F2 = grid(5, offset=3.0)
    V, F = np.vstack([V1, V2]), np.vstack([F1, F2 + len(V1)])
    path = write_obj(tmp_path / "two.obj", V, F)
    npy, csv = tmp_path / "d.npy", tmp_path / "d.csv"
    code, _, err = run(["distance", path, "-s", 0, "-o", npy, "-o", csv, "--refine", "0"], capsys)
    assert code == 0, err
    d = np.load(npy)
    assert np.all(np.isfinite(d[: len(V1)])) and np.all(np.isinf(d[len(V1):]))
    assert "25 vertices unreachable (inf)" in err
    assert csv.read_text().splitlines()[-1] == f"{len(V) - 1},inf"


def test_progress_lines_and_png(sphere_obj, tmp_path, capsys):
    path, _, _ = sphere_obj
    png = tmp_path / "d.png"
    code, out, err = run(["distance", path, "-s", 0, "--png", png, "--isolines", 5, "--colormap", "magma",
                          "--refine", "1"], capsys)
    assert code == 0, err
    for stage in ("read mesh:", "precompute:", "query:", "render:", "heat solver ready"):
        assert f"heatcore: {stage}" in err
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert f"wrote {png}" in out


@pytest.mark.parametrize(
    "case, message, status",
    [
        ("missing", "mesh file not found", 1),
        ("garbage", "garbage.ply: not a PLY file (it does not start with 'ply')", 1),
        ("out-of-range", "source vertex 5000 is out of range: the mesh has 162 vertices", 1),
        ("negative", "argument -s/--source/--sources: vertex indices are 0-based, got -1", 2),
        ("no-sources", "no sources", 1),
        ("extension", "unknown extension", 2),
        ("sources-file", "line 2: 'x' is not a vertex index", 1),
        ("empty-sources-file", "holds no vertex indices", 1),
        ("no-output", "nothing to write", 2),
        ("output-folder", "is a file, not a folder", 1),
        ("colormap-option", "invalid choice", 2),
        ("m-option", "must be a positive number", 2),
    ],
)
def test_bad_inputs_fail_with_one_line(case, message, status, sphere_obj, tmp_path, capsys):
    path, _, _ = sphere_obj
    out = tmp_path / "d.npy"
    garbage = tmp_path / "garbage.ply"
    garbage.write_text("not a ply file\n")
    bad_src = tmp_path / "bad.txt"
    bad_src.write_text("1 2\n3 x\n")
    empty_src = tmp_path / "empty.txt"
    empty_src.write_text("# nothing\n")
    argv = {
        "missing": ["distance", tmp_path / "nope.obj", "-s", 0, "-o", out],
        "garbage": ["distance", garbage, "-s", 0, "-o", out],
        "out-of-range": ["distance", path, "-s", 5000, "-o", out],
        "negative": ["distance", path, "-s", -1, "-o", out],
        "no-sources": ["distance", path, "-o", out],
        "extension": ["distance", path, "-s", 0, "-o", tmp_path / "d.txt"],
        "sources-file": ["distance", path, "--sources-file", bad_src, "-o", out],
        "empty-sources-file": ["distance", path, "--sources-file", empty_src, "-o", out],
        "no-output": ["distance", path, "-s", 0],
        "output-folder": ["distance", path, "-s", 0, "-o", bad_src / "d.npy"],
        "colormap-option": ["distance", path, "-s", 0, "-o", out, "--colormap", "jet"],
        "m-option": ["distance", path, "-s", 0, "-o", out, "--m", "-1"],
    }[case]
    code, stdout, err = run(argv, capsys)
    assert code == status
    assert message in err
    assert "Traceback" not in err
    assert [line for line in err.splitlines() if "error" in line] == err.splitlines()[-1:]  # one error line, last
    assert stdout == ""  # reader chatter (meshio prints on bad PLY) is swallowed
    if case in ("negative",) or case.endswith("-option"):  # argparse: names the subcommand
        assert err.startswith("heatcore distance: error: ") and err.endswith("(see 'heatcore distance --help')\n")
        assert len(err.splitlines()) == 1  # no usage block
    else:
        assert err.splitlines()[-1].startswith("heatcore: error: ")
    assert not out.exists()


def test_demo_writes_ply_and_png(tmp_path, capsys):
    outdir = tmp_path / "demo out"
    code, out, err = run(["demo", "--output-dir", outdir], capsys)
    assert code == 0, err
    ply, png = outdir / "demo.ply", outdir / "demo.png"
    assert f"wrote {ply}" in out and f"wrote {png}" in out
    assert "precompute" in out and "query" in out
    assert "heatcore: precompute:" in err
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 50_000

    V, F = hc.io.load_demo_mesh()
    mesh = read_mesh(ply)
    expected = hc.geodesic_distance(V, F, [cli.DEMO_SOURCE])
    np.testing.assert_allclose(mesh.vertex_data["quality"], expected, rtol=1e-12, atol=0)
    np.testing.assert_array_equal(mesh.selected_vertices(), [cli.DEMO_SOURCE])
    # the source sits at the tip of spot's nose: the front-most vertex (spot faces -z)
    assert cli.DEMO_SOURCE == int(np.argmin(V[:, 2]))
    assert expected[cli.DEMO_SOURCE] == 0 and 2.0 < expected.max() < 2.3


def test_subprocess_entry_point(sphere_obj, tmp_path):
    path, V, F = sphere_obj
    out = tmp_path / "d.npy"
    proc = subprocess.run(
        [sys.executable, "-m", "heatcore.apps.cli", "distance", str(path), "-s", "3", "-o", str(out), "--refine", "1"],
        capture_output=True, text=True, timeout=120,
    )
    assert proc.returncode == 0, proc.stderr
    assert "heatcore: query:" in proc.stderr and f"wrote {out}" in proc.stdout
    np.testing.assert_allclose(np.load(out), hc.geodesic_distance(V, F, [3], refine=1), rtol=1e-12)

    proc = subprocess.run(
        [sys.executable, "-m", "heatcore", "distance", str(tmp_path / "nope.ply"), "-s", "0", "-o", str(out)],
        capture_output=True, text=True, timeout=120,
    )
    assert proc.returncode == 1
    assert proc.stderr.strip().splitlines() == [f"heatcore: error: mesh file not found: {tmp_path / 'nope.ply'}"]


def test_repaired_input_warns_on_stderr_even_when_quiet(tmp_path, capsys):
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
    F = np.array([[0, 1, 2], [1, 3, 2], [0, 1, 2]])  # a duplicate face: dropped, not fatal
    path = write_obj(tmp_path / "dup.obj", V, F)
    out = tmp_path / "d.npy"
    code, _, err = run(["distance", path, "-s", 0, "-o", out, "-q", "--refine", "2"], capsys)
    assert code == 0
    assert err.startswith("heatcore: warning: ") and "duplicate" in err and len(err.splitlines()) == 1
    np.testing.assert_allclose(np.load(out), hc.geodesic_distance(V, F[:2], [0], refine=2), rtol=1e-12)
