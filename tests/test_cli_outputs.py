"""`heatcore distance`: command-line errors before any work, outputs written atomically, inputs never overwritten.

Each test here failed on the code before issue 16: a traceback for a source
index beyond int64 and for ``--png out.obj`` (that one after the whole
computation), and an output named like the input was written over it.
"""

import os

import meshio
import numpy as np
import pytest
import scipy.spatial
from test_cli import FAST, icosphere, run, write_obj

import heatcore as hc
from heatcore.apps import cli, outputs
from heatcore.io import read_mesh


@pytest.fixture
def sphere(tmp_path):
    V, F = icosphere()
    return write_obj(tmp_path / "sphere.obj", V, F), V, F


def _no_work(monkeypatch):
    """Reading the mesh or building the solver fails the test: errors must come first."""

    def forbidden(*args, **kwargs):
        raise AssertionError("the mesh was read or the solver built before the command line was checked")

    monkeypatch.setattr(cli, "read_mesh_file", forbidden)
    monkeypatch.setattr(cli, "build_solver", forbidden)


def test_source_index_beyond_int64_is_a_usage_error(sphere, tmp_path, capsys, monkeypatch):
    path, _, _ = sphere
    _no_work(monkeypatch)
    out = tmp_path / "d.npy"
    code, stdout, err = run(["distance", path, "-s", "99999999999999999999", "-o", out], capsys)
    assert code == 2 and stdout == ""
    assert err == ("heatcore distance: error: argument -s/--source/--sources: vertex index 99999999999999999999 is too "
                   "large for any mesh (at most 9223372036854775807) (see 'heatcore distance --help')\n")
    assert not out.exists()


def test_source_index_beyond_int64_in_a_sources_file(sphere, tmp_path, capsys, monkeypatch):
    path, _, _ = sphere
    _no_work(monkeypatch)
    src = tmp_path / "s.txt"
    src.write_text("3\n99999999999999999999\n")
    code, _, err = run(["distance", path, "--sources-file", src, "-o", tmp_path / "d.npy"], capsys)
    assert code == 1
    assert err == (f"heatcore: error: {src}, line 2: 99999999999999999999 is not a vertex index "
                   f"(0-based, at most 9223372036854775807)\n")


@pytest.mark.parametrize("name", ["out.obj", "out", "out.png.ply"])
def test_png_name_is_checked_before_any_work(name, sphere, tmp_path, capsys, monkeypatch):
    path, _, _ = sphere
    _no_work(monkeypatch)
    png = tmp_path / name
    code, stdout, err = run(["distance", path, "-s", 0, "--png", png], capsys)
    assert code == 2 and stdout == ""
    assert err == f"heatcore: error: --png {png}: the picture is a PNG file; give a name ending in .png\n"
    assert list(tmp_path.iterdir()) == [path]


def test_output_given_twice_is_refused(sphere, tmp_path, capsys, monkeypatch):
    path, _, _ = sphere
    _no_work(monkeypatch)
    out = tmp_path / "d.npy"
    code, _, err = run(["distance", path, "-s", 0, "-o", out, "-o", out], capsys)
    assert code == 2 and err == f"heatcore: error: output {out} is given twice\n"


def _ply_with_normals(path):
    """An input PLY carrying a property heatcore does not write back (vertex normals)."""
    V, F = icosphere()
    meshio.write(str(path), meshio.Mesh(V, [("triangle", F.astype(np.int32))], point_data={"nx": V[:, 0], "ny": V[:, 1],
                                                                           "nz": V[:, 2]}), binary=True)
    return V, F


@pytest.mark.parametrize("how", ["same name", "relative name", "hard link", "symlink"])
def test_output_over_the_input_mesh_is_refused(how, tmp_path, capsys, monkeypatch):
    mesh = tmp_path / "scan.ply"
    _ply_with_normals(mesh)
    before = mesh.read_bytes()
    (tmp_path / "sub").mkdir()
    out = {"same name": mesh, "relative name": f"{tmp_path}/sub/../scan.ply",
           "hard link": tmp_path / "link.ply", "symlink": tmp_path / "sym.ply"}[how]
    if how == "hard link":
        os.link(mesh, out)
    elif how == "symlink":
        out.symlink_to(mesh)
    _no_work(monkeypatch)
    code, stdout, err = run(["distance", mesh, "-s", 0, "-o", out], capsys)
    assert code == 2 and stdout == ""
    assert err == (f"heatcore: error: output {out} is an input of this command; "
                   "write elsewhere, or pass --overwrite to replace it\n")
    assert mesh.read_bytes() == before


def test_output_over_a_sources_file_is_refused(sphere, tmp_path, capsys, monkeypatch):
    path, _, _ = sphere
    src = tmp_path / "s.csv"
    src.write_text("0, 5\n")
    _no_work(monkeypatch)
    code, _, err = run(["distance", path, "--sources-file", src, "-o", src], capsys)
    assert code == 2 and "is an input of this command" in err
    assert src.read_text() == "0, 5\n"


def test_overwrite_replaces_the_input_whole(tmp_path, capsys):
    mesh = tmp_path / "scan.ply"
    V, F = _ply_with_normals(mesh)
    code, out, err = run(["distance", mesh, "-s", 0, "-o", mesh, "--overwrite", *FAST], capsys)
    assert code == 0, err
    assert out == f"wrote {mesh}\n"
    written = read_mesh(mesh)
    np.testing.assert_array_equal(written.faces, F)
    np.testing.assert_allclose(written.vertex_data["quality"], hc.geodesic_distance(V, F, [0], refine=1),
                               rtol=1e-12, atol=0)
    assert "nx" not in written.vertex_data  # replaced, as --help says
    assert sorted(p.name for p in tmp_path.iterdir()) == ["scan.ply"]


class _ReplaceSpy:
    def __init__(self, monkeypatch):
        self.moves = []
        real = os.replace

        def replace(src, dst):
            self.moves.append((os.fspath(src), os.fspath(dst)))
            return real(src, dst)

        monkeypatch.setattr(outputs.os, "replace", replace)

    def check(self, paths):
        """Each path was moved into place once, from a temporary file beside it."""
        assert sorted(dst for _, dst in self.moves) == sorted(map(str, paths))
        for src, dst in self.moves:
            src, dst = os.path.split(src), os.path.split(dst)
            assert src[0] == dst[0] and src[1].startswith(f".{os.path.splitext(dst[1])[0]}.tmp-")
            assert os.path.splitext(src[1])[1] == os.path.splitext(dst[1])[1]


def test_every_surface_output_is_written_atomically(sphere, tmp_path, capsys, monkeypatch):
    path, V, F = sphere
    spy = _ReplaceSpy(monkeypatch)
    names = [tmp_path / n for n in ("d.ply", "d.npy", "d.csv", "d.png")]
    code, _, err = run(["distance", path, "-s", 0, "-o", names[0], "-o", names[1], "-o", names[2],
                        "--png", names[3], *FAST], capsys)
    assert code == 0, err
    spy.check(names)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["d.csv", "d.npy", "d.ply", "d.png", "sphere.obj"]
    np.testing.assert_allclose(np.load(names[1]), hc.geodesic_distance(V, F, [0], refine=1), rtol=1e-12)


def test_every_volume_output_is_written_atomically(tmp_path, capsys, monkeypatch):
    P = np.random.default_rng(2).random((60, 3))
    src = tmp_path / "c.vtu"
    meshio.write(src, meshio.Mesh(P, [("tetra", scipy.spatial.Delaunay(P).simplices)]))
    spy = _ReplaceSpy(monkeypatch)
    names = [tmp_path / n for n in ("d.vtu", "d.vtk", "d.msh")]
    code, _, err = run(["distance", src, "-s", 0, "-q", *(a for n in names for a in ("-o", n))], capsys)
    assert code == 0, err
    spy.check(names)
    assert np.isfinite(meshio.read(names[0]).point_data["distance"]).all()


def test_demo_outputs_are_written_atomically(tmp_path, capsys, monkeypatch):
    spy = _ReplaceSpy(monkeypatch)
    code, _, err = run(["demo", "-d", tmp_path, "--refine", "0", "-q"], capsys)
    assert code == 0, err
    spy.check([tmp_path / "demo.ply", tmp_path / "demo.png"])


def test_failed_write_keeps_the_old_file_and_leaves_no_temporary(sphere, tmp_path, capsys, monkeypatch):
    path, _, _ = sphere
    png = tmp_path / "d.png"
    png.write_bytes(b"old picture")

    def half_written(tmp, *args, **kwargs):
        with open(tmp, "wb") as f:
            f.write(b"\x89PNG half")
        raise OSError(28, "No space left on device", str(tmp))

    monkeypatch.setattr("heatcore.viz.render.render_distance", half_written)
    code, _, err = run(["distance", path, "-s", 0, "--png", png, *FAST], capsys)
    assert code == 1
    assert err.startswith("heatcore: error: ") and "No space left on device" in err
    assert png.read_bytes() == b"old picture"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["d.png", "sphere.obj"]
