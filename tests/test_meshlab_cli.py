"""``heatcore meshlab`` and the MeshLab script alike (issue 38): permissions, exit codes, flags.

Both real entry points run: :func:`heatcore.apps.cli.main` (``heatcore meshlab``) and
:func:`heatcore.apps.meshlab.main` (``scripts/heatcore_meshlab.py``).
"""

import os

import pytest

from heatcore.apps import cli

from .test_cli_sources import write_grid

pymeshlab = pytest.importorskip("pymeshlab")
from heatcore.apps import meshlab  # noqa: E402  (after the skip)

ENTRY_POINTS = {
    "heatcore meshlab": lambda argv: cli.main(["meshlab", *map(str, argv)]),
    "heatcore_meshlab.py": lambda argv: meshlab.main(list(map(str, argv))),
}


@pytest.fixture
def grid_obj(tmp_path):
    return write_grid(tmp_path / "grid.obj")


@pytest.fixture
def umask_022():
    saved = os.umask(0o022)
    yield
    os.umask(saved)


@pytest.mark.parametrize("entry", ENTRY_POINTS)
def test_written_ply_is_0644_like_every_writer(grid_obj, tmp_path, capsys, umask_022, entry):
    out = tmp_path / "out.ply"
    assert ENTRY_POINTS[entry]([grid_obj, "-s", "0", "-o", out, "--refine", "0", "-q"]) == 0
    assert out.stat().st_mode & 0o777 == 0o644
    d = tmp_path / "d.npy"  # the distance command's writer, for comparison
    assert cli.main(["distance", str(grid_obj), "-s", "0", "-o", str(d), "--refine", "0", "-q"]) == 0
    assert d.stat().st_mode & 0o777 == out.stat().st_mode & 0o777
    assert sorted(p.name for p in tmp_path.iterdir()) == ["d.npy", "grid.obj", "out.ply"]  # no temporary left


@pytest.mark.parametrize("entry", ENTRY_POINTS)
@pytest.mark.parametrize("case, message", [
    ("missing file", "does not exist"),
    ("a folder", "it is a folder, not a regular file"),
    ("no selection", "no selected vertices or faces"),
    ("out of range", "out of range"),
    ("selects nothing", "selects no vertex"),
])
def test_documented_exit_status_2(grid_obj, tmp_path, capsys, entry, case, message):
    extra = {"missing file": [], "a folder": [], "no selection": [], "out of range": ["-s", "999"],
             "selects nothing": ["--select", "y > 1e9"]}[case]
    mesh = {"missing file": tmp_path / "missing.obj", "a folder": tmp_path / "meshes.obj"}.get(case, grid_obj)
    if case == "a folder":
        mesh.mkdir()
    out = tmp_path / "out.ply"
    assert ENTRY_POINTS[entry]([mesh, "-o", out, *extra]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1
    assert not out.exists()


@pytest.mark.parametrize("entry", ENTRY_POINTS)
def test_same_flags_quiet_included(grid_obj, tmp_path, capsys, entry):
    out = tmp_path / "out.ply"
    assert ENTRY_POINTS[entry]([grid_obj, "--sources", "0", "5", "-o", out, "--quiet", "--refine", "0"]) == 0
    assert capsys.readouterr().err == ""
    script = {a.dest for a in meshlab.build_parser()._actions} - {"help"}
    command = cli.build_parser()._subparsers._group_actions[0].choices["meshlab"]
    assert script == {a.dest for a in command._actions} - {"help"}
