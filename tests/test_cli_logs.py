"""The command's log lines in the docs' words and in the order things happen (issue 38).

Runs the real entry point (:func:`heatcore.apps.cli.main`) and reads its stderr.
"""

import numpy as np

from heatcore.apps import cli

from .test_cli_sources import write_grid


def write_obj(path, parts):
    """An OBJ of several (V, F) parts side by side."""
    lines, offset = [], 0
    for V, F in parts:
        lines += [f"v {x:.17g} {y:.17g} {z:.17g}" for x, y, z in V]
        lines += [f"f {a + offset + 1} {b + offset + 1} {c + offset + 1}" for a, b, c in F]
        offset += len(V)
    path.write_text("\n".join(lines) + "\n")
    return path


def sphere(shift=0.0, subdivisions=2):
    import trimesh

    s = trimesh.creation.icosphere(subdivisions=subdivisions)
    return np.asarray(s.vertices) + [shift, 0, 0], np.asarray(s.faces)


def stderr_of(argv, capsys):
    assert cli.main([str(a) for a in argv]) == 0
    return capsys.readouterr().err


def test_closed_mesh_says_no_boundary_open_mesh_its_condition(tmp_path, capsys):
    closed = write_obj(tmp_path / "sphere.obj", [sphere()])
    err = stderr_of(["distance", closed, "-s", "0", "-o", tmp_path / "d.npy", "--refine", "0"], capsys)
    assert "no boundary (closed)" in err and "boundary=neumann" not in err
    grid = write_grid(tmp_path / "grid.obj")
    err = stderr_of(["distance", grid, "-s", "0", "-o", tmp_path / "d.npy", "--refine", "0"], capsys)
    assert "boundary=robin" in err and "no boundary" not in err


def test_parts_not_components(tmp_path, capsys):
    mesh = write_obj(tmp_path / "two.obj", [sphere(), sphere(5.0)])
    err = stderr_of(["distance", mesh, "-s", "0", "-o", tmp_path / "d.npy", "--refine", "0"], capsys)
    assert "component" not in err
    assert "1 part," in err  # the one-off query builds the source's part alone


def test_unreachable_vertices_say_which_parts_hold_the_sources(tmp_path, capsys):
    mesh = write_obj(tmp_path / "three.obj", [sphere(), sphere(5.0), sphere(10.0)])
    n = len(sphere()[0])
    err = stderr_of(["distance", mesh, "-s", "0", str(n), "-o", tmp_path / "d.npy", "--refine", "0"], capsys)
    assert (f"{n} vertices unreachable (inf): the sources are on 2 of the mesh's 3 parts, and distance does not "
            "cross between parts") in err


def test_welded_is_said_before_the_solver_is_ready(tmp_path, capsys):
    V, F = sphere()
    # every face its own corners: welding joins them again
    mesh = write_obj(tmp_path / "soup.obj", [(V[F].reshape(-1, 3), np.arange(3 * len(F)).reshape(-1, 3))])
    err = stderr_of(["distance", mesh, "-s", "0", "-o", tmp_path / "d.npy", "--refine", "0"], capsys)
    lines = err.splitlines()
    welded = next(i for i, line in enumerate(lines) if "welded" in line)
    ready = next(i for i, line in enumerate(lines) if "heat solver ready" in line)
    precompute = next(i for i, line in enumerate(lines) if line.startswith("heatcore: precompute:"))
    assert welded < ready < precompute


def progress_lines(err):
    return [line for line in err.splitlines() if "%" in line]


def test_progress_follows_the_solver_vertices_not_the_file(tmp_path, capsys, monkeypatch):
    mesh = write_obj(tmp_path / "sphere.obj", [sphere()])  # 162 vertices in the file
    monkeypatch.setattr("heatcore.apps.reporting.PROGRESS_FROM_VERTICES", 1000)
    command = ["distance", mesh, "-s", "0", "-o", tmp_path / "d.npy"]
    assert progress_lines(stderr_of([*command, "--refine", "0"], capsys)) == []  # 162 solver vertices
    lines = progress_lines(stderr_of([*command, "--refine", "2"], capsys))  # 2,562 solver vertices
    assert lines and lines[-1].split("%")[0].split()[-1] == "100"


def test_progress_follows_the_parts(tmp_path, capsys, monkeypatch):
    parts = [sphere(3.0 * k, subdivisions=0) for k in range(4)]
    mesh = write_obj(tmp_path / "many.obj", parts)
    monkeypatch.setattr("heatcore.apps.reporting.PROGRESS_FROM_PARTS", 4)
    command = ["distance", mesh, "-o", tmp_path / "d.npy", "--refine", "0"]
    assert progress_lines(stderr_of([*command, "-s", "0"], capsys)) == []  # the one query builds 1 part
    sources = ",".join(str(12 * k) for k in range(4))
    assert progress_lines(stderr_of([*command, "-s", sources], capsys))  # all 4 parts
