"""A batch worker process that dies (SIGKILL, out of memory, a crash) fails the mesh it held, and only that one.

The task that kills its own worker is arranged here, not in the package: a tiny module written to a
temporary folder (``crashy.py``, on ``sys.path`` and on the workers' ``PYTHONPATH``) wraps
:func:`heatcore.apps.batch.task.process_mesh` and sends SIGKILL to its own process when the mesh's file
name starts with ``crash``. The batch runs it in place of ``process_mesh`` (a monkeypatch of
:mod:`heatcore.apps.batch.run` in this process; the pool's workers import ``crashy`` by name, Dask's get
it by value through cloudpickle). Before the fix every test here failed: the local pool's
``BrokenProcessPool`` marked every mesh not yet finished "worker failed" (queued ones too).
"""

import csv
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
from test_batch_integrity import write_grid

from heatcore.apps.batch import load_distances, run_batch
from heatcore.apps.batch import run as batch_run

pytestmark = pytest.mark.skipif(os.name == "nt", reason="SIGKILL of one's own process: POSIX")

CRASHY = textwrap.dedent(
    """
    import os
    import signal
    from pathlib import Path

    from heatcore.apps.batch.task import process_mesh


    def die_on_marked(task):
        if Path(task.path).name.startswith("crash"):
            os.kill(os.getpid(), signal.SIGKILL)  # what the out-of-memory killer does
        return process_mesh(task)
    """
)

FAST = {"refine": 0}
N_GOOD = 6


@pytest.fixture
def crashy(tmp_path, monkeypatch):
    """The ``crashy`` module (importable here and in the workers), and a folder of grids with one crasher."""
    helper = tmp_path / "helper"
    helper.mkdir()
    (helper / "crashy.py").write_text(CRASHY)
    monkeypatch.syspath_prepend(str(helper))
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join(filter(None, [str(helper), os.environ.get("PYTHONPATH")])))
    import crashy as module

    folder = tmp_path / "meshes"
    folder.mkdir()
    for i in range(N_GOOD):
        write_grid(folder / f"g{i}.obj", 6 + i, 7)
    write_grid(folder / "crash.obj", 8, 8)  # sorts first: every grid is still queued when its worker dies
    return module, folder


def expected_rows(folder, tmp_path):
    """The good meshes' distances computed in this process."""
    out = tmp_path / "reference"
    run_batch(sorted(folder.glob("g*.obj")), out, "0,3", workers=0, progress=False, mesh_options=FAST)
    return {p.stem: load_distances(out / f"{p.stem}.npz") for p in folder.glob("g*.obj")}


def check(rows, out, expected):
    by_name = {Path(r["file"]).name: r for r in rows}
    assert sorted(by_name) == sorted(["crash.obj"] + [f"g{i}.obj" for i in range(N_GOOD)])  # one row each
    bad = by_name.pop("crash.obj")
    assert {name: r["status"] for name, r in by_name.items()} == {name: "ok" for name in by_name}, by_name
    assert bad["status"] == "error"
    assert "worker process died" in bad["error"] and "crash.obj" in bad["error"], bad["error"]
    for stem, d in expected.items():
        assert np.array_equal(load_distances(out / f"{stem}.npz"), d)
    with open(out / "summary.csv", newline="") as fh:
        summary = {Path(r["file"]).name: r["status"] for r in csv.DictReader(fh)}
    assert summary.pop("crash.obj") == "error" and set(summary.values()) == {"ok"}
    return bad


def test_local_pool_fails_only_the_mesh_whose_worker_was_killed(crashy, tmp_path, monkeypatch):
    module, folder = crashy
    expected = expected_rows(folder, tmp_path)
    monkeypatch.setattr(batch_run, "process_mesh", module.die_on_marked)
    out = tmp_path / "out"
    rows = run_batch(folder, out, "0,3", workers=2, progress=False, mesh_options=FAST)
    bad = check(rows, out, expected)
    assert "killed by signal 9" in bad["error"], bad["error"]


def test_local_pool_one_worker_replaced_after_each_death(crashy, tmp_path, monkeypatch):
    """One process and two crashers: each death gets a fresh worker for the meshes queued behind it."""
    module, folder = crashy
    write_grid(folder / "crash2.obj", 5, 5)
    monkeypatch.setattr(batch_run, "process_mesh", module.die_on_marked)
    rows = run_batch(folder, tmp_path / "out", "0", workers=1, progress=False, mesh_options=FAST)
    status = {Path(r["file"]).name: r["status"] for r in rows}
    assert status.pop("crash.obj") == status.pop("crash2.obj") == "error"
    assert set(status.values()) == {"ok"} and len(status) == N_GOOD


def test_cli_exit_status_and_message_name_the_one_failed_mesh(crashy, tmp_path):
    _, folder = crashy
    out = tmp_path / "out"
    code = ("import sys, crashy; from heatcore.apps.batch import run; from heatcore.apps.cli import main; "
            "run.process_mesh = crashy.die_on_marked; sys.exit(main(sys.argv[1:]))")
    proc = subprocess.run([sys.executable, "-c", code, "batch", str(folder), "-o", str(out), "--sources", "0",
                           "--refine", "0", "-j", "2", "-q"], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 1, proc.stderr
    assert f"{N_GOOD} done" in proc.stdout and "1 failed" in proc.stdout, proc.stdout
    errors = [line for line in proc.stderr.splitlines() if "worker" in line]
    assert len(errors) == 1 and "crash.obj" in errors[0] and "killed by signal 9" in errors[0], proc.stderr


def test_dask_fails_only_the_crasher_after_bounded_tries(crashy, tmp_path, monkeypatch):
    """A LocalCluster whose nannies restart killed workers: the crasher is tried allowed-failures + 1 times."""
    import cloudpickle
    import dask
    from distributed import Client, LocalCluster

    module, folder = crashy
    expected = expected_rows(folder, tmp_path)
    cloudpickle.register_pickle_by_value(module)
    out = tmp_path / "out"
    try:
        with dask.config.set({"distributed.scheduler.allowed-failures": 1}), \
                LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                             dashboard_address=None) as cluster, Client(cluster) as client:
            monkeypatch.setattr(batch_run, "process_mesh", module.die_on_marked)
            rows = run_batch(folder, out, "0,3", scheduler=client, progress=False, mesh_options=FAST)
    finally:
        cloudpickle.unregister_pickle_by_value(module)
    bad = check(rows, out, expected)
    assert "4 Dask workers died running it, the last 2 with no other mesh" in bad["error"], bad["error"]
