"""Messages that say what to do, sensible defaults, help that matches the command (issue 38, messages row).

Every case runs the real entry point (``heatcore.apps.cli.main``): a text point cloud that is
not a table of numbers names the line and the formats read; 1-based faces get the hint
"indices look 1-based"; ``--isolines-out PATH`` without ``N`` writes the PNG's levels;
``logmap --help`` (a command without a picture) mentions no PNG. The one rule for output
folders (created when missing, in every command) is in tests/test_cli_inputs.py.
"""

from pathlib import Path

import numpy as np
import pytest

import heatcore as hc
from heatcore.apps import cli
from heatcore.apps.outputs import PNG_ISOLINES
from heatcore.io import demo_mesh_path

REPO = Path(__file__).resolve().parents[1]
V = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
FORMATS = (".csv/.pts/.txt/.xyz point clouds hold 3 (x y z) or 6 (x y z nx ny nz) numbers per line, separated "
           "by spaces or commas, with '#' or '//' comments and no header line; point clouds are also read from "
           ".ply and .obj files")
ONE_BASED = "; the indices look 1-based (they run from 1 to {n}): subtract 1, heatcore counts vertices from 0"


def run(argv, capsys):
    code = cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.parametrize("text, why", [
    ("x,y,z\n0,0,0\n1,0,0\n", "line 1 ('x,y,z') is not numbers"),
    ("# scan 3\nx y z\n0 0 0\n", "line 2 ('x y z') is not numbers"),
    ("0 0 0\n1 0 0 1\n", "line 2 has 4 numbers, the lines before it 3"),
])
def test_a_text_point_cloud_that_is_not_numbers_names_the_line_and_the_formats(text, why, tmp_path, capsys):
    path = tmp_path / "cloud.txt"  # was numpy's "could not convert string 'x' to float64 at row 0, column 1."
    path.write_text(text)
    code, out, err = run(["distance", path, "-s", 0, "-o", tmp_path / "d.npy", "-q"], capsys)
    assert (code, out) == (1, "")
    assert err == f"heatcore: error: cannot read point cloud file {path}: {why}; {FORMATS}\n"


def test_one_based_faces_get_the_hint(tmp_path, capsys):
    mesh = tmp_path / "m.ply"  # triangles through meshio: checked by TriangleMesh
    hc.io.write_ply(mesh, V, F, np.zeros(4), np.zeros((4, 3)))
    text = mesh.read_bytes()
    start = text.index(b"end_header\n") + len(b"end_header\n") + 4 * (3 * 8 + 8 + 3)  # after the vertices
    faces = np.frombuffer(text[start:], dtype=np.dtype([("n", "u1"), ("i", "<i4", 3)])).copy()
    faces["i"] += 1
    mesh.write_bytes(text[:start] + faces.tobytes())
    code, _, err = run(["distance", mesh, "-s", 0, "-o", tmp_path / "d.npy", "-q"], capsys)
    assert code == 1
    assert err == (f"heatcore: error: {mesh}: face 1 references vertex 4 but the mesh has 4 vertices "
                   f"(valid indices are 0..3){ONE_BASED.format(n=4)}\n")

    off = tmp_path / "m.off"
    off.write_text("OFF\n4 4 0\n" + "".join(f"{x:g} {y:g} {z:g}\n" for x, y, z in V)
                   + "".join(f"3 {a + 1} {b + 1} {c + 1}\n" for a, b, c in F))
    code, _, err = run(["distance", off, "-s", 0, "-o", tmp_path / "d.npy", "-q"], capsys)
    why = "line 8: face 1 references vertex 4, which is out of range (the file has 4 vertices)"
    assert (code, err) == (1, f"heatcore: error: cannot read mesh file {off}: {why}{ONE_BASED.format(n=4)}\n")


def test_the_api_says_so_too():
    Vd, Fd = hc.io.load_demo_mesh()
    with pytest.raises(hc.InvalidMeshError) as raised:
        hc.TriangleMesh(Vd, Fd + 1)
    assert str(raised.value) == (f"face 2925 references vertex 2930 but the mesh has 2930 vertices (valid indices "
                                 f"are 0..2929){ONE_BASED.format(n=2930)}")
    with pytest.raises(hc.InvalidMeshError) as raised:  # out of range, not 1-based: no hint
        hc.TriangleMesh(V, [[0, 1, 7]])
    assert str(raised.value) == "face 0 references vertex 7 but the mesh has 4 vertices (valid indices are 0..3)"


def test_isolines_out_without_n_writes_the_pngs_levels(tmp_path, capsys):
    base = ["distance", demo_mesh_path(), "-s", 0, "--refine", "0", "-q"]
    written = {}
    for name, extra in [("default", []), ("twelve", [PNG_ISOLINES]), ("five-flag", ["--isolines", 5]),
                        ("five", [5])]:
        argv = [*base, "--isolines-out", tmp_path / f"{name}.obj", *extra]
        if name == "five-flag":
            argv = [*base, "--isolines", 5, "--isolines-out", tmp_path / f"{name}.obj"]
        code, _, err = run(argv, capsys)
        assert code == 0, err
        written[name] = (tmp_path / f"{name}.obj").read_text()
    assert written["default"] == written["twelve"].replace("twelve", "default")
    assert written["five-flag"] == written["five"].replace("five", "five-flag")
    assert written["default"].count("# isoline") > written["five"].count("# isoline") > 0
    code, _, err = run([*base, "--isolines-out", tmp_path / "c.obj", 3, 4], capsys)
    assert code == 2 and "expected PATH [N], got 3 values" in err


def test_signed_isolines_out_without_n(tmp_path, capsys):
    curve = tmp_path / "c.txt"
    curve.write_text("738\n734\n")  # an edge of spot
    base = ["signed", demo_mesh_path(), "--unsigned-curve", curve, "--refine", "0", "-q", "--isolines-out"]
    assert run([*base, tmp_path / "a.obj"], capsys)[0] == 0
    assert run([*base, tmp_path / "b.obj", 5], capsys)[0] == 0  # 5: the signed PNG's levels
    assert (tmp_path / "a.obj").read_text() == (tmp_path / "b.obj").read_text()


def test_help_matches_the_command(capsys):
    code, out, _ = run(["logmap", "--help"], capsys)
    out = " ".join(out.split())  # argparse wraps at the terminal's width
    assert code == 0 and "PNG" not in out and "picture" not in out
    assert ("--isolines N number of evenly spaced isolines (0: none): dark stripes in the vertex colors "
            "(default: 0)") in out
    code, out, _ = run(["distance", "--help"], capsys)
    out = " ".join(out.split())
    assert code == 0 and "[--isolines-out PATH [N]]" in out
    assert ("--isolines N number of evenly spaced isolines (0: none): dark stripes in the vertex colors (and "
            "lines in the PNG picture) (default: none in the PLY, 12 in the PNG)") in out


def test_demo_outputs_are_ignored_by_git():
    ignored = (REPO / ".gitignore").read_text().split()
    assert "/demo.ply" in ignored and "/demo.png" in ignored  # `heatcore demo` writes them into the current folder
