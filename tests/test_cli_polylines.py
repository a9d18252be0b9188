"""Polyline outputs load with their segments (issue 38): ``.vtk`` in meshio, ``.ply`` in trimesh; meshio never exits.

The CLI tests run the real entry point (:func:`heatcore.apps.cli.main`).
"""

import warnings

import numpy as np
import pytest

from heatcore.apps import cli
from heatcore.errors import InvalidMeshError

from .test_cli_sources import write_grid

FAST = ["--refine", "0", "-q"]


@pytest.fixture
def grid_obj(tmp_path):
    return write_grid(tmp_path / "grid.obj", n=8)


def run(argv, capsys):
    code = cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def meshio_lines(path):
    import meshio

    mesh = meshio.read(str(path))
    lines = [b for b in mesh.cells if b.type == "line"]
    assert len(lines) == 1
    return np.asarray(mesh.points), np.asarray(lines[0].data), mesh


def trimesh_path(path):
    import trimesh

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        loaded = trimesh.load(str(path))
    assert isinstance(loaded, trimesh.path.Path3D), type(loaded)
    return loaded


def test_path_vtk_and_ply_keep_segments(grid_obj, tmp_path, capsys):
    outs = [tmp_path / f"p.{ext}" for ext in ("vtk", "ply", "csv", "obj")]
    code, _, err = run(["path", grid_obj, "--from", "0", "--to", "63", *sum((["-o", o] for o in outs), []), *FAST],
                       capsys)
    assert code == 0, err
    csv = np.loadtxt(outs[2], delimiter=",", skiprows=1)
    points, segments, _ = meshio_lines(outs[0])
    np.testing.assert_allclose(points, csv)
    np.testing.assert_array_equal(segments, np.column_stack([np.arange(len(csv) - 1), np.arange(1, len(csv))]))
    path = trimesh_path(outs[1])
    np.testing.assert_allclose(path.vertices, csv)
    assert sum(len(e.points) - 1 for e in path.entities) == len(csv) - 1
    for out in outs:
        assert out.stat().st_mode & 0o777 == 0o644 & ~_umask()


def _umask():
    import os

    mask = os.umask(0)
    os.umask(mask)
    return mask


@pytest.mark.parametrize("ext", ["vtk", "ply", "obj"])
def test_isolines_out_every_curve_format(grid_obj, tmp_path, capsys, ext):
    out = tmp_path / f"c.{ext}"
    code, stdout, err = run(["distance", grid_obj, "-s", "0", "--isolines-out", out, "3", *FAST], capsys)
    assert code == 0, err
    n_curves = int(stdout.split("(")[1].split()[0])
    assert n_curves == 3  # a grid corner's levels: three open arcs
    if ext == "vtk":
        points, segments, mesh = meshio_lines(out)
        assert sorted(set(np.ravel(mesh.cell_data["curve"][0]).tolist())) == [0, 1, 2]
        assert len(segments) >= 3 and segments.max() < len(points)
    elif ext == "ply":
        assert len(trimesh_path(out).entities) >= 3
    else:
        assert out.read_text().count("\nl ") >= 3


def test_isolines_out_other_suffix_is_usage_error(grid_obj, tmp_path, capsys):
    code, _, err = run(["distance", grid_obj, "-s", "0", "--isolines-out", tmp_path / "c.txt", "3", *FAST], capsys)
    assert code == 2 and ".obj, .vtk, .ply" in err


def test_help_says_which_reader_keeps_what(capsys):
    for argv in (["path", "--help"], ["trace", "--help"], ["distance", "--help"], ["signed", "--help"]):
        code, out, _ = run(argv, capsys)
        text = " ".join(out.split())
        assert code == 0
        assert "segments in meshio" in text and "Path3D with its segments in trimesh" in text, argv


def edge_ply(path):
    path.write_text("ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
                    "property double z\nelement edge 2\nproperty int vertex1\nproperty int vertex2\nend_header\n"
                    "0 0 0\n1 0 0\n1 1 0\n0 1\n1 2\n")
    return path


def test_meshio_never_exits_the_process(tmp_path):
    from heatcore.io import read_mesh, read_point_cloud, read_polygon_mesh
    from heatcore.io.mesh import meshio_read

    ply = edge_ply(tmp_path / "path.ply")
    polydata = tmp_path / "poly.vtk"
    polydata.write_text("# vtk DataFile Version 4.2\nx\nASCII\nDATASET POLYDATA\nPOINTS 1 double\n0 0 0\n")
    for reader in (meshio_read, read_mesh, read_polygon_mesh, read_point_cloud):
        for path in (ply, polydata):
            try:
                reader(path)
            except InvalidMeshError:
                pass
            except SystemExit:  # pragma: no cover - the bug
                pytest.fail(f"{reader.__name__}({path.name}) exited the process")
            except Exception:  # another typed refusal (no faces, ...) is fine; exiting is not
                pass
    with pytest.raises(InvalidMeshError, match="Expected `element vertex`"):
        meshio_read(ply)


def test_cli_on_a_path_ply_is_one_error_line(tmp_path, capsys):
    code, out, err = run(["distance", edge_ply(tmp_path / "path.ply"), "-s", "0", "-o", tmp_path / "d.npy"], capsys)
    assert code == 1 and out == "" and err.startswith("heatcore: error:") and err.count("\n") == 1
