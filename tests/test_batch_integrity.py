"""Batch integrity: results keyed by their inputs, Ctrl-C, killed runs, temporary files, a lost Dask worker.

A rerun is how users recover from a crash, so it must never serve stale data:
every test here failed on the batch runner before results were keyed.
"""

import csv
import json
import os
import shutil
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from heatcore import HeatSolver
from heatcore.apps.batch import (
    BatchError,
    clean_temporaries,
    load_distances,
    load_key,
    load_sources,
    parse_sources,
    result_key,
    run_batch,
)
from heatcore.apps.cli import main
from heatcore.io import demo_mesh_path
from heatcore.io.domain import read_domain
from heatcore.settings import Settings

REPO = Path(__file__).resolve().parents[1]


def write_grid(path, nx, ny, amplitude=0.1):
    """A wavy ``nx x ny`` triangle grid (OBJ), ``amplitude`` the height of the waves."""
    x, y = np.meshgrid(np.linspace(0, 1, nx), np.linspace(0, 1, ny), indexing="ij")
    V = np.column_stack([x.ravel(), y.ravel(), amplitude * np.sin(3 * x.ravel()) * np.cos(2 * y.ravel())])
    idx = np.arange(nx * ny).reshape(nx, ny)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    F = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])]) + 1
    lines = [f"v {p[0]!r} {p[1]!r} {p[2]!r}" for p in V] + [f"f {i} {j} {k}" for i, j, k in F]
    Path(path).write_text("\n".join(lines) + "\n")
    return Path(path)


FAST = {"refine": 0}  # no subdivision of the tiny grids: fast solves


def fresh(path, sources, mesh_options=None, **solver_options):
    solver = HeatSolver(read_domain(path).domain(**(mesh_options or {})), **solver_options)
    return np.stack([solver.distance([s]) for s in sources])


def summary(folder):
    with open(Path(folder) / "summary.csv", newline="") as fh:
        return {Path(r["file"]).name: r for r in csv.DictReader(fh)}


def temporaries(folder):
    return [p for p in Path(folder).rglob(".*") if ".tmp-" in p.name]


# --------------------------------------------------------------------------- keyed results


def test_rerun_with_other_sources_recomputes_and_same_sources_skip(tmp_path):
    grid = write_grid(tmp_path / "g.obj", 9, 8)
    out = tmp_path / "out"
    run_batch([grid], out, "0", workers=0, progress=False)
    rows = run_batch([grid], out, "5", workers=0, progress=False)  # used to report "skipped", keeping source 0
    assert rows[0]["status"] == "ok"
    assert load_sources(out / "g.npz").tolist() == [5]
    assert np.array_equal(load_distances(out / "g.npz"), fresh(grid, [5]))
    os.utime(out / "g.npz", (1_000_000_000, 1_000_000_000))
    rows = run_batch([grid], out, "5", workers=0, progress=False)  # same inputs: reused, not recomputed
    assert rows[0]["status"] == "skipped" and rows[0]["sources"] == 1
    assert os.stat(out / "g.npz").st_mtime == 1_000_000_000


def test_rerun_with_edited_mesh_or_sources_file_recomputes(tmp_path):
    grid = write_grid(tmp_path / "g.obj", 9, 8, amplitude=0.1)
    (tmp_path / "g.src.txt").write_text("0 7\n")
    out = tmp_path / "out"
    run_batch([grid], out, sources_suffix=".src.txt", workers=0, progress=False)
    before = load_distances(out / "g.npz")
    write_grid(grid, 9, 8, amplitude=0.6)  # same vertex count, other shape
    assert run_batch([grid], out, sources_suffix=".src.txt", workers=0, progress=False)[0]["status"] == "ok"
    after = load_distances(out / "g.npz")
    assert np.array_equal(after, fresh(grid, [0, 7]))
    assert np.abs(after - before).max() > 0.05  # the old rows really were wrong for the new mesh
    (tmp_path / "g.src.txt").write_text("3\n")  # edited sources file
    assert run_batch([grid], out, sources_suffix=".src.txt", workers=0, progress=False)[0]["status"] == "ok"
    assert load_sources(out / "g.npz").tolist() == [3]
    assert np.array_equal(load_distances(out / "g.npz"), fresh(grid, [3]))


def test_rerun_with_other_solver_options_recomputes_and_cli_defaults_match_api(tmp_path, capsys):
    grid = write_grid(tmp_path / "g.obj", 9, 8)
    out = tmp_path / "out"
    assert main(["batch", str(grid), "-o", str(out), "--sources", "4", "-j", "0", "-q"]) == 0
    # the command line names every option; the API fills in the same defaults: same key, reused
    assert run_batch([grid], out, "4", workers=0, progress=False)[0]["status"] == "skipped"
    assert main(["batch", str(grid), "-o", str(out), "--sources", "4", "-j", "0", "-q", "--m", "4"]) == 0
    assert "recomputing 1 result(s) made from other inputs (g.npz: m 1.0 -> 4.0)" in capsys.readouterr().err
    assert json.loads(load_key(out / "g.npz"))["solver_options"]["m"] == 4.0
    assert np.array_equal(load_distances(out / "g.npz"), fresh(grid, [4], m=4.0))
    assert not np.array_equal(fresh(grid, [4], m=4.0), fresh(grid, [4]))
    spec = parse_sources("4")  # an option added later (e.g. weld) is keyed without a change in batch
    assert result_key(grid, spec, Settings.of("batch", weld=None)) != result_key(grid, spec)
    assert result_key(grid, spec, Settings.of("batch", m=1)) == result_key(grid, spec, Settings.of("batch", m=1.0))


#: Keys of format 1 as heatcore wrote them before the settings object (mesh and solver options read from the
#: signatures of DomainFile.domain and HeatSolver, progress among them), for spot.obj.
FORMAT_1_KEYS = [
    ("0,17", {}, '{"format":1,"heatcore":"0.1.0","kind":"auto","mesh_options":{"progress":null,"refine":"auto",'
     '"robust":true,"weld":0.0},"mesh_sha256":"0738b5e8608fed74e5e8c7aa8dd0af97b4b74f9f6cbf7aac84cd7e40b2e44a75",'
     '"solver_options":{"accuracy":"smooth","backend":"auto","boundary":"robin","m":1.0,"progress":null},'
     '"sources":{"indices":[0,17],"mode":"indices","union":false}}'),
    ("all", {"domain": "polygon", "refine": 0, "weld": None, "m": 4, "accuracy": "high", "backend": "superlu"},
     '{"format":1,"heatcore":"0.1.0","kind":"polygon","mesh_options":{"progress":null,"refine":0.0,"robust":true,'
     '"weld":null},"mesh_sha256":"0738b5e8608fed74e5e8c7aa8dd0af97b4b74f9f6cbf7aac84cd7e40b2e44a75",'
     '"solver_options":{"accuracy":"high","backend":"superlu","boundary":"robin","m":4.0,"progress":null},'
     '"sources":{"mode":"all","union":false}}'),
]


@pytest.mark.parametrize(("sources", "options", "key"), FORMAT_1_KEYS)
def test_keys_from_settings_equal_the_keys_written_before(sources, options, key):
    import heatcore

    expected = json.loads(key) | {"heatcore": heatcore.__version__}
    new = result_key(demo_mesh_path(), parse_sources(sources), Settings.of("batch", **options))
    assert json.loads(new) == expected and new == json.dumps(expected, sort_keys=True, separators=(",", ":"))


def test_result_of_an_older_version_without_key_is_recomputed(tmp_path):
    grid = write_grid(tmp_path / "g.obj", 6, 6)
    out = tmp_path / "out"
    out.mkdir()
    np.savez_compressed(out / "g.npz", sources=np.array([0]), n_vertices=np.int64(36), spec=np.str_("0"),
                        distances=np.zeros((1, 36)))  # what heatcore 0.1.0 wrote, here with wrong rows
    assert run_batch([grid], out, "0", workers=0, progress=False)[0]["status"] == "ok"
    assert np.array_equal(load_distances(out / "g.npz"), fresh(grid, [0]))


def test_blocks_of_other_inputs_are_never_reused(tmp_path):
    grid = write_grid(tmp_path / "g.obj", 6, 5, amplitude=0.1)  # 30 vertices, 4 rows per block: 8 blocks
    out = tmp_path / "out"
    bound = 4 * 30 * 8 / 2**20
    run_batch([grid], out, "all", workers=0, max_memory_mb=bound, mesh_options=FAST, progress=False)
    old_blocks = sorted(p.name for p in (out / "g.blocks").glob("rows-*.npy"))
    (out / "g.npz").unlink()  # killed before the index was written, then the mesh was edited
    write_grid(grid, 6, 5, amplitude=0.7)
    run_batch([grid], out, "all", workers=0, max_memory_mb=bound, mesh_options=FAST, progress=False)
    assert np.array_equal(load_distances(out / "g.npz"), fresh(grid, range(30), FAST))
    new_blocks = sorted(p.name for p in (out / "g.blocks").glob("rows-*.npy"))
    assert len(new_blocks) == 8 and not set(new_blocks) & set(old_blocks)  # the old key's blocks are gone


def test_resume_only_refuses_results_of_other_inputs(tmp_path, capsys):
    a, b = write_grid(tmp_path / "a.obj", 6, 6), write_grid(tmp_path / "b.obj", 5, 7)
    out = tmp_path / "out"
    run_batch([a], out, "0", workers=0, progress=False)
    with pytest.raises(BatchError, match=r"a\.npz: sources 0 -> 5\)"):
        run_batch([a, b], out, "5", workers=0, progress=False, resume_only=True)
    assert load_sources(out / "a.npz").tolist() == [0] and not (out / "b.npz").exists()  # nothing done
    assert main(["batch", str(a), str(b), "-o", str(out), "--sources", "5", "-j", "0", "--resume-only"]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "heatcore: error: resume only" in err and "--resume-only" in err
    rows = run_batch([a, b], out, "0", workers=0, progress=False, resume_only=True)  # a true resume
    assert [r["status"] for r in rows] == ["skipped", "ok"]
    assert np.array_equal(load_distances(out / "b.npz"), fresh(b, [0]))


# --------------------------------------------------------------------------- temporary files


def dead_pid():
    child = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True)
    return int(child.stdout)


def test_temporary_files_of_a_killed_run_are_removed_and_ignored(tmp_path):
    grid = write_grid(tmp_path / "g.obj", 6, 5)
    out = tmp_path / "out"
    (out / "g.blocks").mkdir(parents=True)
    pid = dead_pid()
    planted = [out / f".g.npz.tmp-{pid}-abcdef12", out / f".summary.csv.tmp-{pid}-0badc0de",
               out / "g.blocks" / f".rows-000000000-000000004.npy.tmp-{pid}-12345678"]
    for p in planted:
        p.write_bytes(b"partial")
    mine = out / f".x.npz.tmp-{os.getpid()}-abcdef12"  # a live writer's file is left alone
    mine.write_bytes(b"being written")
    run_batch([grid], out, "all", workers=0, max_memory_mb=4 * 30 * 8 / 2**20, mesh_options=FAST, progress=False)
    assert temporaries(out) == [mine]
    assert np.array_equal(load_distances(out / "g.npz"), fresh(grid, range(30), FAST))


# --------------------------------------------------------------------------- signals


def spot_folder(tmp_path, count):
    folder = tmp_path / "meshes"
    folder.mkdir()
    for i in range(count):
        shutil.copy(demo_mesh_path(), folder / f"s{i:02d}.obj")
    return folder


def start_batch(folder, out, *extra):
    cmd = [sys.executable, "-m", "heatcore", "batch", str(folder), "-o", str(out), "-q", *extra]
    # SIGINT back to its default: a suite started in the background of a shell inherits it ignored,
    # and so would the batch (Ctrl-C is what these tests send)
    return subprocess.Popen(cmd, cwd=REPO, start_new_session=True, stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))


def wait_for(predicate, timeout=60.0):
    deadline = time.monotonic() + timeout
    while not predicate():
        assert time.monotonic() < deadline, "timed out"
        time.sleep(0.02)


def kill_all(procs):
    """Test cleanup: end what is left of the processes a failed test started."""
    import psutil

    for p in procs:
        try:
            p.kill()
        except psutil.NoSuchProcess:
            pass


def gone(procs):
    import psutil

    def dead(p):
        try:
            return p.status() == psutil.STATUS_ZOMBIE  # exited; waits for init to reap it
        except psutil.NoSuchProcess:
            return True

    return all(dead(p) for p in procs)


@pytest.mark.parametrize("target", ["process group", "main process"])
def test_ctrl_c_stops_within_2s_and_summary_lists_what_is_on_disk(tmp_path, target):
    import psutil

    folder = spot_folder(tmp_path, 12)
    out = tmp_path / "out"
    proc = start_batch(folder, out, "--sources", "farthest:12", "-j", "2")
    workers = []
    try:
        wait_for(lambda: list(out.glob("*.npz")))
        workers = psutil.Process(proc.pid).children(recursive=True)
        start = time.monotonic()
        if target == "process group":  # what a terminal's Ctrl-C does
            os.killpg(proc.pid, signal.SIGINT)
        else:
            os.kill(proc.pid, signal.SIGINT)
        rc = proc.wait(timeout=30)
        stopped = time.monotonic() - start
        assert rc == 130 and "interrupted" in proc.stderr.read()
        assert stopped < 2.0, f"took {stopped:.2f} s to stop"
        wait_for(lambda: gone(workers), timeout=2.0)
    finally:
        if proc.poll() is None:
            proc.kill()
        kill_all(workers)
    on_disk = sorted(p.stem for p in out.glob("*.npz"))
    time.sleep(0.5)
    assert sorted(p.stem for p in out.glob("*.npz")) == on_disk  # nothing writes after the exit
    rows = summary(out)
    assert len(rows) == 12
    assert sorted(Path(n).stem for n, r in rows.items() if r["status"] == "ok") == on_disk
    assert {r["status"] for n, r in rows.items() if Path(n).stem not in on_disk} == {"interrupted"}
    assert len(on_disk) < 12  # the queue was cancelled
    assert temporaries(out) == []
    d = load_distances(out / f"{on_disk[0]}.npz")
    assert d.shape == (12, 2930) and np.array_equal(d[0], fresh(demo_mesh_path(), [0])[0])


def test_sigkill_of_the_main_process_ends_its_workers(tmp_path):
    import psutil

    folder = spot_folder(tmp_path, 8)
    out = tmp_path / "out"
    proc = start_batch(folder, out, "--sources", "farthest:12", "-j", "2")
    workers = []
    try:
        wait_for(lambda: list(out.glob("*.npz")))
        workers = psutil.Process(proc.pid).children(recursive=True)
        assert workers
        proc.kill()
        proc.wait()
        start = time.monotonic()
        wait_for(lambda: gone(workers), timeout=2.0)  # orphans used to run the whole queue
    finally:
        proc.kill()
        kill_all(workers)
    on_disk = sorted(p.name for p in out.glob("*.npz"))
    time.sleep(0.5)
    assert sorted(p.name for p in out.glob("*.npz")) == on_disk and len(on_disk) < 8
    assert time.monotonic() - start < 2.5
    clean_temporaries(out)  # what the next run does first: every partial file is a dead writer's
    assert temporaries(out) == []


def test_watchdog_alone_ends_a_worker_whose_parent_is_killed(tmp_path):
    """The portable path (no prctl): a thread polling the parent process."""
    import psutil

    child = ("import os, time; from heatcore.apps.batch.runners import watch_parent; "
             "watch_parent(os.getppid(), interval=0.05); print('ready', flush=True); time.sleep(60)")
    parent = ("import subprocess, sys; p = subprocess.Popen([sys.executable, '-c', sys.argv[1]]); "
              "print(p.pid, flush=True); p.wait()")
    proc = subprocess.Popen([sys.executable, "-c", parent, child], stdout=subprocess.PIPE, text=True)
    pid = int(proc.stdout.readline())
    grandchild = psutil.Process(pid)
    try:
        assert proc.stdout.readline().strip() == "ready"
        proc.kill()
        proc.wait()
        wait_for(lambda: gone([grandchild]), timeout=1.0)
    finally:
        proc.kill()
        kill_all([grandchild])


# --------------------------------------------------------------------------- Dask: a lost worker


def test_dask_worker_lost_mid_run_gives_every_result_exactly_once(tmp_path):
    """A real ``dask scheduler`` and two ``dask worker`` processes (no nanny) on 127.0.0.1."""
    import psutil
    from distributed import Client

    sched_file = tmp_path / "scheduler.json"
    common = dict(cwd=REPO, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    procs = [subprocess.Popen([sys.executable, "-m", "dask", "scheduler", "--host", "127.0.0.1", "--port", "0",
                               "--no-dashboard", "--scheduler-file", str(sched_file)], **common)]
    procs += [subprocess.Popen([sys.executable, "-m", "dask", "worker", "--scheduler-file", str(sched_file),
                                "--host", "127.0.0.1", "--nthreads", "1", "--no-nanny", "--no-dashboard"], **common)
              for _ in range(2)]  # they wait for the scheduler file
    try:
        folder = spot_folder(tmp_path, 4)
        out = tmp_path / "out"
        run_batch([folder / "s00.obj"], tmp_path / "ref", "farthest:4", workers=0, progress=False)
        expected = load_distances(tmp_path / "ref" / "s00.npz")
        wait_for(sched_file.exists, timeout=30)
        with Client(scheduler_file=str(sched_file), timeout="30s") as client:
            client.wait_for_workers(2, timeout=30)
            pids = client.run(os.getpid)
            killed = []

            def kill_one_busy_worker():
                deadline = time.monotonic() + 60
                while time.monotonic() < deadline:
                    busy = [a for a, keys in client.processing().items() if keys]
                    if busy:
                        time.sleep(0.3)  # mid-task
                        psutil.Process(pids[busy[0]]).kill()
                        killed.append(busy[0])
                        return
                    time.sleep(0.02)

            killer = threading.Thread(target=kill_one_busy_worker)
            killer.start()
            rows = run_batch(folder, out, "farthest:4", scheduler=client, progress=False)
            killer.join()
        assert len(killed) == 1
        assert [Path(r["file"]).name for r in rows] == [f"s{i:02d}.obj" for i in range(4)]  # once each
        assert all(r["status"] == "ok" for r in rows), rows
        assert len(summary(out)) == 4
        for i in range(4):
            assert np.array_equal(load_distances(out / f"s{i:02d}.npz"), expected)
        assert temporaries(out) == []
    finally:
        for p in procs:
            p.kill()
            p.wait()
