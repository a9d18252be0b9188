"""Welding on the command line: STL files (triangle soup) are welded by default, and the count said.

Before issue 16 an STL was solved as it is read, one part per triangle:
every vertex but the source's triangle got ``inf``, with exit status 0.
"""

import numpy as np
import pytest
import trimesh
from test_cli import FAST, icosphere, run

import heatcore as hc
from heatcore.io import read_mesh


def soup(V, F):
    """Each triangle with its own three vertices, as STL stores them."""
    return V[F].reshape(-1, 3), np.arange(3 * len(F)).reshape(-1, 3)


@pytest.fixture
def sphere_stl(tmp_path):
    V, F = icosphere()
    path = tmp_path / "sphere.stl"
    trimesh.Trimesh(V, F, process=False).export(path)
    Vs, Fs = soup(V, F)
    mesh = read_mesh(path)  # the file's own vertices: one per triangle corner
    np.testing.assert_allclose(mesh.vertices, Vs, atol=1e-6)
    np.testing.assert_array_equal(mesh.faces, Fs)
    return path, V, F, mesh.vertices


def test_stl_is_welded_by_default_and_the_count_is_said(sphere_stl, tmp_path, capsys):
    path, V, F, Vs = sphere_stl
    out = tmp_path / "d.npy"
    code, _, err = run(["distance", path, "-s", 0, "-o", out, "--refine", "1"], capsys)
    assert code == 0, err
    n_file = 3 * len(F)  # 960
    assert f"heatcore: welded {n_file - len(V):,} coincident vertices: {len(V):,} remain\n" in err
    d = np.load(out)
    assert d.shape == (n_file,) and np.isfinite(d).all()  # at the file's own vertices, all reached
    # the same answer as the indexed mesh (at the file's float32 positions), copied to every corner
    corner = F.ravel()
    Vf = np.zeros_like(V)
    Vf[corner] = Vs
    expected = hc.geodesic_distance(Vf, F, [corner[0]], refine=1)
    np.testing.assert_allclose(d, expected[corner], rtol=1e-9, atol=1e-12)


def test_quiet_says_nothing_about_welding(sphere_stl, tmp_path, capsys):
    path, *_ = sphere_stl
    code, out, err = run(["distance", path, "-s", 0, "-o", tmp_path / "d.npy", *FAST], capsys)
    assert code == 0 and err == "" and out == f"wrote {tmp_path / 'd.npy'}\n"


def test_no_weld_solves_the_soup_as_read(sphere_stl, tmp_path, capsys):
    path, _, F, _ = sphere_stl
    out = tmp_path / "d.npy"
    code, _, err = run(["distance", path, "-s", 0, "-o", out, "--no-weld", "--refine", "1"], capsys)
    assert code == 0, err
    assert "welded" not in err
    d = np.load(out)
    assert np.isfinite(d[:3]).all() and np.isinf(d[3:]).all()  # only the source's own triangle
    assert "957 vertices unreachable (inf)" in err


def test_ply_output_keeps_the_files_vertices_and_faces(sphere_stl, tmp_path, capsys):
    path, _, F, Vs = sphere_stl
    ply = tmp_path / "d.ply"
    code, _, err = run(["distance", path, "-s", 0, "-o", ply, *FAST], capsys)
    assert code == 0, err
    written = read_mesh(ply)
    np.testing.assert_allclose(written.vertices, Vs)
    np.testing.assert_array_equal(written.faces, np.arange(3 * len(F)).reshape(-1, 3))
    assert np.isfinite(written.vertex_data["quality"]).all()


def test_weld_tolerance_merges_near_vertices(tmp_path, capsys):
    V, F = icosphere()
    Vs, Fs = soup(V, F)
    Vs = Vs + np.random.default_rng(0).uniform(-1e-6, 1e-6, Vs.shape)  # corners that miss each other
    path = tmp_path / "jitter.obj"
    path.write_text("".join(f"v {x:.17g} {y:.17g} {z:.17g}\n" for x, y, z in Vs)
                    + "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in Fs))
    out = tmp_path / "d.npy"
    code, _, err = run(["distance", path, "-s", 0, "-o", out, "--refine", "1"], capsys)  # exact match only
    assert code == 0, err
    assert "welded" not in err and np.isinf(np.load(out)).sum() == len(Vs) - 3

    code, _, err = run(["distance", path, "-s", 0, "-o", out, "--refine", "1", "--weld-tolerance", "1e-4"], capsys)
    assert code == 0, err
    assert f"heatcore: welded {len(Vs) - len(V):,} coincident vertices: {len(V):,} remain\n" in err
    assert np.isfinite(np.load(out)).all()


def test_weld_options_reach_the_mesh(sphere_stl, monkeypatch, tmp_path, capsys):
    path, *_ = sphere_stl
    seen = []
    real = hc.TriangleMesh.__init__

    def spy(self, V, F, settings=None, **kwargs):  # the command hands over the mesh part of its settings
        seen.append(settings.weld)
        real(self, V, F, settings, **kwargs)

    monkeypatch.setattr(hc.TriangleMesh, "__init__", spy)
    for flags in ([], ["--weld-tolerance", "0.25"], ["--no-weld"]):
        assert run(["distance", path, "-s", 0, "-o", tmp_path / "d.npy", *FAST, *flags], capsys)[0] == 0
    assert seen == [0.0, 0.25, None]


@pytest.mark.parametrize("argv, message", [
    (["--weld-tolerance", "-1"], "argument --weld-tolerance: must be a number >= 0, got '-1'"),
    (["--weld-tolerance", "nan"], "argument --weld-tolerance: must be a number >= 0, got 'nan'"),
    (["--weld-tolerance", "1e-6", "--no-weld"], "argument --no-weld: not allowed with argument --weld-tolerance"),
])
def test_bad_weld_options_are_usage_errors(argv, message, sphere_stl, tmp_path, capsys):
    path, *_ = sphere_stl
    code, out, err = run(["distance", path, "-s", 0, "-o", tmp_path / "d.npy", *argv], capsys)
    assert code == 2 and out == ""
    assert err == f"heatcore distance: error: {message} (see 'heatcore distance --help')\n"


def test_other_domains_refuse_the_weld_options(tmp_path, capsys):
    V, _ = icosphere()
    path = tmp_path / "cloud.xyz"
    np.savetxt(path, V)
    out = tmp_path / "d.npy"
    code, _, err = run(["distance", path, "-s", 0, "-o", out, "-q"], capsys)  # the default passes
    assert code == 0, err
    assert np.isfinite(np.load(out)).all() and len(np.load(out)) == len(V)
    for flag in (["--weld-tolerance", "0.5"], ["--no-weld"]):  # set, it is refused (issue 33: once dropped)
        code, _, err = run(["distance", path, "-s", 0, "-o", out, "-q", *flag], capsys)
        assert code != 0 and "a point cloud does not take the option weld" in err


def test_batch_welds_stl_files_too(sphere_stl, tmp_path, capsys):
    path, V, F, _ = sphere_stl
    outdir = tmp_path / "out"
    code, _, err = run(["batch", path, "-o", outdir, "--sources", "0", "-j", "0", "-q", "--refine", "1"], capsys)
    assert code == 0, err
    with np.load(outdir / "sphere.npz") as z:
        d = z["distances"]
    assert d.shape == (1, 3 * len(F)) and np.isfinite(d).all()
