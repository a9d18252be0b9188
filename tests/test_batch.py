"""The batch runner (heatcore.apps.batch) and `heatcore batch`: local pool, a real Dask cluster, faults, resume."""

import os
import shutil

import numpy as np
import pytest

from heatcore import HeatSolver
from heatcore.apps.batch import (
    BatchError,
    iter_blocks,
    load_distances,
    load_sources,
    output_path,
    parse_sources,
    run_batch,
)
from heatcore.apps.cli import main
from heatcore.io import demo_mesh_path
from heatcore.io.domain import read_domain


def write_grid(path, nx, ny):
    """A wavy ``nx x ny`` grid of triangles (a surface with boundary) written with meshio."""
    import meshio

    x, y = np.meshgrid(np.linspace(0, 1, nx), np.linspace(0, 1, ny), indexing="ij")
    V = np.column_stack([x.ravel(), y.ravel(), 0.1 * np.sin(3 * x.ravel()) * np.cos(2 * y.ravel())])
    idx = np.arange(nx * ny).reshape(nx, ny)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    F = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    meshio.write(path, meshio.Mesh(V, [("triangle", F)]))
    return path


@pytest.fixture
def mesh_folder(tmp_path):
    """spot, two small grids and a corrupt mesh file."""
    folder = tmp_path / "meshes"
    folder.mkdir()
    shutil.copy(demo_mesh_path(), folder / "spot.obj")
    write_grid(folder / "grid_a.ply", 12, 9)
    write_grid(folder / "grid_b.obj", 7, 15)
    (folder / "broken.obj").write_text("v 0 0 0\nv 1 0 0\nf 1 2 7\n")  # face references a missing vertex
    return folder


@pytest.fixture(scope="module")
def cluster():
    """A real dask.distributed LocalCluster on loopback: 2 worker processes, 1 thread each."""
    try:
        from distributed import LocalCluster
    except ImportError:  # CI installs the 'batch' extra: missing dask is a failure, not a skip
        pytest.fail("dask.distributed is not installed: pip install -e '.[batch]'")
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address=None) as lc:
        yield lc


def summary_by_name(rows):
    return {os.path.basename(r["file"]): r for r in rows}


def read_summary(folder):
    import csv

    with open(folder / "summary.csv", newline="") as fh:
        return summary_by_name(list(csv.DictReader(fh)))


def assert_same_results(out_a, out_b, names):
    """The same sources, and the same distances to rounding.

    Not bit for bit: the supernodal factorization (cvxopt's CHOLMOD on BLAS)
    rounds differently with another number of BLAS threads, and a dask
    worker runs one thread where this process runs several (measured: 7e-16
    on a 12 x 9 grid).
    """
    for name in names:
        a, b = out_a / f"{name}.npz", out_b / f"{name}.npz"
        assert np.array_equal(load_sources(a), load_sources(b))
        np.testing.assert_allclose(load_distances(a), load_distances(b), rtol=1e-12, atol=1e-14)


def test_dask_cluster_equals_single_process_and_reports_corrupt_mesh(mesh_folder, tmp_path, cluster):
    serial = run_batch(mesh_folder, tmp_path / "serial", "0,5", workers=0, progress=False)
    dask_rows = run_batch(mesh_folder, tmp_path / "dask", "0,5", scheduler=cluster.scheduler_address,
                          progress=False)
    for rows, out in ((serial, tmp_path / "serial"), (dask_rows, tmp_path / "dask")):
        by = summary_by_name(rows)
        assert by["broken.obj"]["status"] == "error"
        assert "cannot read mesh file" in by["broken.obj"]["error"]  # the reader's message, not a traceback
        assert not (out / "broken.npz").exists()
        for name in ("spot.obj", "grid_a.ply", "grid_b.obj"):
            assert by[name]["status"] == "ok" and by[name]["sources"] == 2
        assert read_summary(out)["broken.obj"]["status"] == "error"
    assert summary_by_name(dask_rows)["spot.obj"]["vertices"] == 2930
    assert_same_results(tmp_path / "serial", tmp_path / "dask", ("spot", "grid_a", "grid_b"))
    # and the single-process batch equals a plain HeatSolver query
    solver = HeatSolver(read_domain(mesh_folder / "spot.obj").domain())
    d = load_distances(tmp_path / "dask" / "spot.npz")
    assert np.array_equal(d[1], solver.distance([5]))
    assert d.shape == (2, 2930) and d[0, 0] == 0.0 and d[1, 5] == 0.0


def test_dask_cluster_farthest_and_all_blocks(mesh_folder, tmp_path, cluster):
    grid = mesh_folder / "grid_a.ply"
    kw = dict(max_memory_mb=3 * 108 * 8 / 2**20)  # 3 rows of 108 vertices per block
    run_batch([grid], tmp_path / "serial", "all", workers=0, progress=False, **kw)
    run_batch([grid], tmp_path / "dask", "all", scheduler=cluster.scheduler_address, progress=False, **kw)
    assert_same_results(tmp_path / "serial", tmp_path / "dask", ("grid_a",))
    run_batch([grid], tmp_path / "fs", "farthest:6", workers=0, progress=False)
    run_batch([grid], tmp_path / "fd", "farthest:6", scheduler=cluster.scheduler_address, progress=False)
    assert_same_results(tmp_path / "fs", tmp_path / "fd", ("grid_a",))


def test_process_pool_equals_single_process(mesh_folder, tmp_path):
    rows = run_batch(mesh_folder, tmp_path / "pool", "3", workers=2, progress=False)
    run_batch(mesh_folder, tmp_path / "serial", "3", workers=0, progress=False)
    assert [r["status"] for r in rows].count("error") == 1
    assert_same_results(tmp_path / "serial", tmp_path / "pool", ("spot", "grid_a", "grid_b"))


def test_all_pairs_in_blocks_equals_dense_matrix(tmp_path):
    grid = write_grid(tmp_path / "grid.ply", 10, 8)  # 80 vertices
    n = 80
    bound = 7 * n * 8 / 2**20  # 7 rows per block: 12 blocks
    rows = run_batch([grid], tmp_path / "out", "all", workers=0, max_memory_mb=bound, progress=False)
    assert rows[0]["status"] == "ok" and rows[0]["sources"] == n
    index = output_path(tmp_path / "out", grid)
    with np.load(index) as z:
        assert "distances" not in z.files  # never held whole: written as blocks
    blocks = list(iter_blocks(index))
    assert len(blocks) == 12 and all(len(b) <= 7 for _, b in blocks)
    assert [s for s, _ in blocks] == list(range(0, n, 7))
    solver = HeatSolver(read_domain(grid).domain())
    dense = np.stack([solver.distance([i]) for i in range(n)])
    assert np.array_equal(load_distances(index), dense)
    assert np.array_equal(load_sources(index), np.arange(n))
    assert len(list((tmp_path / "out" / "grid.blocks").glob("rows-*.npy"))) == 12
    assert not list((tmp_path / "out").rglob(".*tmp*"))  # no temporary file left


def test_farthest_point_sampling(tmp_path):
    grid = write_grid(tmp_path / "grid.ply", 11, 11)
    run_batch([grid], tmp_path / "out", "farthest:5", workers=0, progress=False)
    index = output_path(tmp_path / "out", grid)
    sources, d = load_sources(index), load_distances(index)
    assert sources.size == 5 and np.unique(sources).size == 5 and sources[0] == 0
    assert d.shape == (5, 121)
    assert np.all(d[np.arange(5), sources] == 0)
    nearest = np.minimum.accumulate(d, axis=0)
    for i in range(1, 5):  # each next source is the farthest from the ones before
        assert sources[i] == np.argmax(nearest[i - 1])
    assert sources[1] == 120  # the grid corner opposite vertex 0


def test_interrupted_batch_resumes_without_recomputing(mesh_folder, tmp_path):
    out = tmp_path / "out"
    # "interrupted": only one mesh was done, plus a stale temporary file from a killed writer
    run_batch([mesh_folder / "grid_a.ply"], out, "0,1", workers=0, progress=False)
    done = out / "grid_a.npz"
    os.utime(done, (1_000_000_000, 1_000_000_000))
    (out / ".grid_b.npz.tmp-123-abcdef12").write_bytes(b"partial")
    rows = summary_by_name(run_batch(mesh_folder, out, "0,1", workers=0, progress=False))
    assert rows["grid_a.ply"]["status"] == "skipped" and rows["grid_a.ply"]["vertices"] == 108
    assert os.stat(done).st_mtime == 1_000_000_000  # not recomputed
    assert rows["grid_b.obj"]["status"] == "ok" and rows["spot.obj"]["status"] == "ok"
    assert load_distances(out / "grid_b.npz").shape == (2, 105)
    assert rows["broken.obj"]["status"] == "error"  # retried on every run, still reported


def test_interrupted_all_pairs_keeps_finished_blocks(tmp_path):
    grid = write_grid(tmp_path / "grid.ply", 6, 5)  # 30 vertices
    bound = 4 * 30 * 8 / 2**20
    out = tmp_path / "out"
    run_batch([grid], out, "all", workers=0, max_memory_mb=bound, progress=False)
    expected = load_distances(out / "grid.npz")
    (block,) = (out / "grid.blocks").glob("rows-000000004-000000008-*.npy")  # named by the result key
    os.utime(block, (1_000_000_000, 1_000_000_000))
    (out / "grid.npz").unlink()  # killed before the index was written: not complete
    run_batch([grid], out, "all", workers=0, max_memory_mb=bound, progress=False)
    assert os.stat(block).st_mtime == 1_000_000_000  # the finished block was reused
    assert np.array_equal(load_distances(out / "grid.npz"), expected)


def test_sources_file_suffix_and_union(tmp_path):
    grid = write_grid(tmp_path / "g.ply", 6, 6)
    (tmp_path / "g.sources.txt").write_text("# corners\n0, 35\n")
    run_batch([grid], tmp_path / "a", sources_suffix=".sources.txt", workers=0, progress=False)
    run_batch([grid], tmp_path / "b", sources_suffix=".sources.txt", union=True, workers=0, progress=False)
    solver = HeatSolver(read_domain(grid).domain())
    assert np.array_equal(load_distances(tmp_path / "a" / "g.npz"), np.stack([solver.distance([0]), solver.distance([35])]))
    assert np.array_equal(load_distances(tmp_path / "b" / "g.npz")[0], solver.distance([0, 35]))
    rows = run_batch([grid], tmp_path / "c", sources_suffix=".missing.txt", workers=0, progress=False)
    assert rows[0]["status"] == "error" and "g.missing.txt" in rows[0]["error"]


def test_bad_specifications_are_clear_errors(tmp_path):
    for text in ("abc", "farthest:0", "-1"):
        with pytest.raises(BatchError):
            parse_sources(text)
    with pytest.raises(BatchError, match="exactly one"):
        parse_sources("0", suffix=".s.txt")
    with pytest.raises(BatchError, match="no such file"):
        run_batch([tmp_path / "nothing*.ply"], tmp_path / "o", "0", progress=False)
    grid = write_grid(tmp_path / "g.ply", 5, 5)
    rows = run_batch([grid], tmp_path / "o", "0,99", workers=0, progress=False)
    assert rows[0]["status"] == "error" and "out of range" in rows[0]["error"]
    rows = run_batch([grid], tmp_path / "o2", "all", workers=0, max_memory_mb=1e-6, progress=False)
    assert rows[0]["status"] == "error" and "--max-memory" in rows[0]["error"]


def test_cli_batch(mesh_folder, tmp_path, capsys):
    status = main(["batch", str(mesh_folder / "grid_*"), "-o", str(tmp_path / "o"), "--sources", "farthest:3",
                   "-j", "0"])
    captured = capsys.readouterr()
    assert status == 0 and "2 done" in captured.out and "2/2 meshes" in captured.err
    assert load_sources(tmp_path / "o" / "grid_a.npz").size == 3
    status = main(["batch", str(mesh_folder), "-o", str(tmp_path / "o"), "--sources", "farthest:3", "-q"])
    captured = capsys.readouterr()
    assert status == 1 and "2 skipped" in captured.out and "1 failed" in captured.out
    assert "broken.obj" in captured.err and captured.err.count("\n") == 1  # quiet: only the error line
    assert main(["batch", str(mesh_folder), "-o", str(tmp_path / "x")]) == 1  # no source specification
    assert "exactly one source specification" in capsys.readouterr().err
