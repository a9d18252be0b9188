"""Benchmark of `heatcore batch`: throughput on a process pool and on Dask, blocks of sources, the memory bound.

Writes the measured section of docs/batch.md (the text before it is kept). Runs in about 8 minutes on 2 cores:

1. meshes per minute over the shared triangle meshes (one source each: the
   cost is reading + factoring), for the local process pool (all cores) and a
   ``dask.distributed.LocalCluster`` with 1 and 2 worker processes;
2. sources per second on nefertiti (50k vertices, 300 sources, one task);
3. an all-pairs run (``all``) on a 20k-vertex mesh with ``--max-memory 64``,
   in a child process whose peak RSS is compared with the same process after
   building the solver only, and with the dense matrix size;
4. blocks of sources: 64 sources on spot and nefertiti, one at a time (the
   code of commit ``BEFORE_COMMIT``, whose batch called ``distance()`` per
   source) against this code (``HeatSolver.distances`` on blocks): end to end
   (``heatcore batch`` in a fresh process, read + factor + solves + write)
   and the query part alone (sources per second of a built solver), each the
   best of ``--repeat`` rounds (before and after in turn) in child processes;
   the results are compared too.

Usage: ``python scripts/bench_batch.py [--meshes DIR] [--out docs/batch.md] [--only blocks] [--before DIR] [--after DIR]``

``--only blocks`` measures section 4 alone and replaces only its subsection of
the page. ``--before DIR`` is a checkout of the older code (default: ``git
archive BEFORE_COMMIT`` of this repository into a temporary folder).
"""

import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
TRIANGLE_MESHES = ("spot", "homer", "fandisk", "cheburashka", "rocker-arm", "stanford-bunny", "nefertiti")
N_SOURCES = 300
GRID = 142  # 142 x 142 = 20,164 vertices
MAX_MEMORY_MB = 64.0
#: The code before batch solved blocks of sources (its batch looped over ``distance()``).
BEFORE_COMMIT = "0d3c9d9"
BLOCK_MESHES = ("spot", "nefertiti")
BLOCK_SOURCES = 64
BLOCKS_TITLE = "### Blocks of sources"


def write_grid(path, n):
    import meshio

    x, y = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n), indexing="ij")
    V = np.column_stack([x.ravel(), y.ravel(), 0.15 * np.sin(4 * x.ravel()) * np.cos(3 * y.ravel())])
    idx = np.arange(n * n).reshape(n, n)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    F = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    meshio.write(path, meshio.Mesh(V, [("triangle", F)]))
    return path


def timed_batch(inputs, out, sources, how):
    """Run a batch with ``how`` ("pool", or a LocalCluster worker count); returns (seconds, rows)."""
    from heatcore.apps.batch import run_batch

    if how == "pool":
        start = time.perf_counter()
        rows = run_batch(inputs, out, sources, progress=False)
        return time.perf_counter() - start, rows
    from distributed import Client, LocalCluster

    with LocalCluster(n_workers=how, threads_per_worker=1, processes=True, host="127.0.0.1",
                      dashboard_address=None) as cluster, Client(cluster) as client:
        client.run(lambda: __import__("heatcore.heat"))  # warm imports: measure the work, not startup
        start = time.perf_counter()
        rows = run_batch(inputs, out, sources, scheduler=client, progress=False)
        return time.perf_counter() - start, rows


CHILD = r"""
import json, resource, sys, time
from heatcore.apps.batch import run_batch
from heatcore.io.domain import read_domain
from heatcore.heat import HeatSolver
path, out, mode, bound = sys.argv[1], sys.argv[2], sys.argv[3], float(sys.argv[4])
start = time.perf_counter()
if mode == "solver":
    solver = HeatSolver(read_domain(path).domain())
    solver.distance([0])
    rows = [{}]
else:
    rows = run_batch([path], out, "all", workers=0, max_memory_mb=bound, progress=False)
print(json.dumps({"seconds": time.perf_counter() - start, "maxrss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, "row": rows[0]}))
"""


def child(path, out, mode, bound):
    res = subprocess.run([sys.executable, "-c", CHILD, str(path), str(out), mode, str(bound)],
                         capture_output=True, text=True, check=True)
    return json.loads(res.stdout.strip().splitlines()[-1])


QUERY_CHILD = r"""
import json, sys, time
import numpy as np
from heatcore.io.domain import read_domain
from heatcore.heat import HeatSolver
path, mode, repeat = sys.argv[1], sys.argv[2], int(sys.argv[3])
solver = HeatSolver(read_domain(path).domain(), **json.loads(sys.argv[4]))
n = len(solver.domain.output_vertices)
sources = np.linspace(0, n - 1, int(sys.argv[5])).round().astype(int).tolist()
if mode == "loop":  # what batch did before: one query per source
    run = lambda: np.stack([solver.distance([s]) for s in sources])
else:  # what batch does now: blocks of block_columns() sources
    from heatcore.apps.batch import source_rows
    run = lambda: np.stack(list(source_rows(solver, sources)))
best = float("inf")
for _ in range(repeat):
    start = time.perf_counter()
    rows = run()
    best = min(best, time.perf_counter() - start)
np.save(sys.argv[6], rows)
print(json.dumps({"seconds": best, "columns": getattr(solver, "block_columns", lambda: 1)()}))
"""


def before_checkout(repo, commit, folder):
    """The code of ``commit`` (``git archive``) in ``folder``; returns ``folder``."""
    folder.mkdir(parents=True, exist_ok=True)
    archive = subprocess.run(["git", "-C", str(repo), "archive", commit], capture_output=True, check=True).stdout
    subprocess.run(["tar", "-x", "-C", str(folder)], input=archive, check=True)
    return folder


def in_code(code):
    """Environment running the heatcore of the source tree ``code``."""
    return dict(os.environ, PYTHONPATH=str(code))


def block_throughput(meshes, before, tmp, repeat, after=REPO):
    """Section 4: {mesh: {"n", "end_to_end": {name: s}, "query": {name: s}, "same", "columns", "load"}}.

    ``repeat`` rounds, each running before, after and after-with-cholmod in turn (so that a slow
    spell of the shared machine falls on all of them), 3 query runs per child; the best is kept.
    """
    configs = (("loop", before, "loop", {}), ("blocks", after, "blocks", {}),
               ("cholmod", after, "blocks", {"backend": "cholmod"}))  # this code, heat factored by cholmod too
    results = {}
    for path in meshes:
        from heatcore.io.domain import read_domain

        n = len(read_domain(path).domain().output_vertices)
        sources = ",".join(map(str, np.linspace(0, n - 1, BLOCK_SOURCES).round().astype(int)))
        entry = {"n": n, "end_to_end": {}, "query": {}, "load": []}
        for round_ in range(repeat):
            for name, code, mode, options in configs:
                entry["load"].append(os.getloadavg()[0])
                res = subprocess.run([sys.executable, "-c", QUERY_CHILD, str(path), mode, "3", json.dumps(options),
                                      str(BLOCK_SOURCES), str(tmp / f"{path.stem}-{name}.npy")],
                                     capture_output=True, text=True, check=True, env=in_code(code))
                info = json.loads(res.stdout.strip().splitlines()[-1])
                entry["query"][name] = min(entry["query"].get(name, np.inf), info["seconds"])
                if name == "blocks":
                    entry["columns"] = info["columns"]
                if options:
                    continue
                out = tmp / f"e2e-{path.stem}-{name}-{round_}"
                start = time.perf_counter()
                subprocess.run([sys.executable, "-m", "heatcore", "batch", str(path), "-o", str(out), "--sources",
                                sources, "-q"], check=True, env=in_code(code), capture_output=True)
                seconds = time.perf_counter() - start
                entry["end_to_end"][name] = min(entry["end_to_end"].get(name, np.inf), seconds)
                print(f"blocks {path.stem} {name}: query {info['seconds']:.3f} s, end to end {seconds:.2f} s",
                      file=sys.stderr)
        from heatcore.apps.batch import load_distances

        loop, blocks = np.load(tmp / f"{path.stem}-loop.npy"), np.load(tmp / f"{path.stem}-blocks.npy")
        written = [load_distances(tmp / f"e2e-{path.stem}-{name}-0" / f"{path.stem}.npz") for name in ("loop", "blocks")]
        entry["same"] = bool(np.array_equal(loop, blocks) and np.array_equal(*written))
        finite = np.isfinite(loop)
        entry["max_relative"] = float(np.abs(loop[finite] - blocks[finite]).max() / np.abs(loop[finite]).max())
        results[path.stem] = entry
    return results


def blocks_lines(results, repeat):
    """The page's subsection for :func:`block_throughput`."""
    load = max(max(e["load"]) for e in results.values())
    columns = ", ".join(f"{e['columns']} ({name})" for name, e in results.items())
    cholmod = ", ".join(f"{BLOCK_SOURCES / e['query']['cholmod']:.0f} sources/s ({name})" for name, e in results.items())
    largest = max(e["max_relative"] for e in results.values())
    same = "bit for bit the same" if all(e["same"] for e in results.values()) else "not the same"
    lines = [
        f"{BLOCKS_TITLE}: {BLOCK_SOURCES} sources per mesh, one at a time (before) or in blocks (`HeatSolver.distances`)",
        "",
        f"Before: the code of commit {BEFORE_COMMIT}, whose batch called `distance()` once per source. After: this",
        "code, whose batch solves the sources of a mesh in blocks of `block_columns()` sources (one multi-column",
        "heat solve, unit field and Poisson solve per block). End to end: `heatcore batch MESH -o DIR --sources",
        f"S0,...,S{BLOCK_SOURCES - 1}` in a fresh process (start-up, read, factor, solves, compressed write). Query:",
        f"the {BLOCK_SOURCES} sources of a built solver, in sources per second. Best of {repeat} rounds (before and",
        "after in turn; 3 query runs per round).",
        "",
        "| mesh | vertices | end to end before | end to end after | speed-up | query before | query after | speed-up |",
        "|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for name, e in results.items():
        e2e, q = e["end_to_end"], e["query"]
        lines.append(
            f"| {name} | {e['n']:,} | {e2e['loop']:.2f} s | {e2e['blocks']:.2f} s | {e2e['loop'] / e2e['blocks']:.2f}x "
            f"| {BLOCK_SOURCES / q['loop']:.0f} sources/s | {BLOCK_SOURCES / q['blocks']:.0f} sources/s "
            f"| {q['loop'] / q['blocks']:.2f}x |"
        )
    lines += [
        "",
        f"Written results before and after: {same} (largest difference {largest:.1e} of the largest distance).",
        f"Blocks of {columns} columns (`block_columns()`: at most 16, within the 256 MB working-memory bound).",
        "",
        "Where the time goes: the heat step's factor is `qdldl` below 100k unknowns (`auto` picks it for its",
        "factorization speed), and qdldl solves one column at a time; a block saves the Python work and set-up",
        "per query and part of the Poisson solves (CHOLMOD, up to 3 columns per call), not the heat solves.",
        "With the heat matrix factored by `cholmod` too (`HeatSolver(..., backend='cholmod')`), the query part",
        f"of a block reaches {cholmod}.",
        "",
        f"The machine was shared: other jobs ran tests on its {os.cpu_count()} cores during the measurement",
        f"(1-minute load average up to {load:.1f}); the best of {repeat} rounds is the least disturbed one.",
        "",
    ]
    return lines


def replace_subsection(text, title, new_lines):
    """``text`` with its ``### title...`` subsection replaced by ``new_lines`` (appended when absent)."""
    parts = text.split("\n### ")
    kept = [p for p in parts if not ("### " + p).startswith(title)]
    return "\n### ".join(kept).rstrip("\n") + "\n\n" + "\n".join(new_lines)


def page_text(path):
    """The hand-written part of the page (everything before the measured section), kept as it is."""
    text = path.read_text() if path.is_file() else "# Batch runs: `heatcore batch` on a process pool and on Dask\n"
    return text.split("\n## Measured on this machine")[0].rstrip("\n").split("\n") + [""]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--meshes", type=Path, default=Path(os.environ.get("HEATCORE_MESHES", REPO.parent / "shared" / "meshes")))
    parser.add_argument("--out", type=Path, default=REPO / "docs" / "batch.md")
    parser.add_argument("--only", choices=["blocks"], help="measure section 4 alone and replace only its subsection")
    parser.add_argument("--before", type=Path, help=f"checkout of the older code (default: git archive {BEFORE_COMMIT})")
    parser.add_argument("--after", type=Path, default=REPO, help="checkout of the newer code (default: this one)")
    parser.add_argument("--repeat", type=int, default=5, help="rounds of section 4 (the best is kept)")
    args = parser.parse_args()
    loads = [os.getloadavg()[0]]
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        before = args.before or before_checkout(REPO, BEFORE_COMMIT, tmp / "before")
        blocks = block_throughput([args.meshes / f"{m}.obj" for m in BLOCK_MESHES], before, tmp, args.repeat, args.after)
    if args.only == "blocks":
        args.out.write_text(replace_subsection(args.out.read_text(), BLOCKS_TITLE, blocks_lines(blocks, args.repeat)))
        print(f"wrote {args.out}")
        return
    import distributed

    import heatcore

    meshes = [args.meshes / f"{m}.obj" for m in TRIANGLE_MESHES]
    total_vertices = 0
    lines = []
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        through = {}
        for how in ("pool", 1, 2):
            loads.append(os.getloadavg()[0])
            seconds, rows = timed_batch(meshes, tmp / f"m-{how}", "0", how)
            assert all(r["status"] == "ok" for r in rows), rows
            total_vertices = sum(int(r["vertices"]) for r in rows)
            through[how] = seconds
            print(f"meshes {how}: {seconds:.2f} s", file=sys.stderr)
        sources = ",".join(map(str, range(0, 150 * N_SOURCES, 150)))
        rate = {}
        for how in ("pool", 1, 2):
            loads.append(os.getloadavg()[0])
            seconds, rows = timed_batch([args.meshes / "nefertiti.obj"], tmp / f"s-{how}", sources, how)
            assert rows[0]["status"] == "ok", rows
            rate[how] = (seconds, float(rows[0]["seconds"]))
            print(f"sources {how}: {seconds:.2f} s", file=sys.stderr)
        grid = write_grid(tmp / "grid20k.ply", GRID)
        n = GRID * GRID
        base = child(grid, tmp / "a", "solver", MAX_MEMORY_MB)
        allp = child(grid, tmp / "a", "all", MAX_MEMORY_MB)
        assert allp["row"]["status"] == "ok", allp
        index = tmp / "a" / "grid20k.npz"
        from heatcore.apps.batch import block_rows, iter_blocks

        n_blocks = sum(1 for _ in iter_blocks(index))
        on_disk = sum(f.stat().st_size for f in (tmp / "a" / "grid20k.blocks").glob("*.npy")) / 2**20
        rows_per_block = block_rows(n, MAX_MEMORY_MB)
        loads.append(os.getloadavg()[0])

    names = {"pool": f"process pool ({os.cpu_count()} processes)", 1: "Dask LocalCluster, 1 worker", 2: "Dask LocalCluster, 2 workers"}
    lines += [
        *page_text(args.out),
        (f"## Measured on this machine ({os.cpu_count()} cores, {platform.processor() or platform.machine()}, "
         f"Python {platform.python_version()}, numpy {np.__version__}, dask.distributed {distributed.__version__}, "
         f"heatcore {heatcore.__version__})"),
        "",
        "Reproduce: `python scripts/bench_batch.py` (writes this page).",
        "",
        (f"The machine was shared with other jobs (1-minute load average {min(loads):.1f} to {max(loads):.1f} on "
         f"its {os.cpu_count()} cores at the start and end of the sections): times vary by 10-30% from run to run."),
        "",
        (f"### Meshes per minute: {len(meshes)} shared triangle meshes ({', '.join(TRIANGLE_MESHES)}; "
         f"{total_vertices:,} vertices in all), one source each"),
        "",
        "| executor | wall time | meshes per minute |",
        "|---|---:|---:|",
    ]
    for how, s in through.items():
        lines.append(f"| {names[how]} | {s:.2f} s | {60 * len(meshes) / s:.0f} |")
    lines += [
        "",
        "Dask times exclude the cluster start (workers are started and have imported heatcore); they",
        "include scheduling and result transfer. The largest meshes (nefertiti, bunny) dominate: with 2",
        "workers the wall time is bounded below by the longest single task.",
        "",
        f"### Sources per second: nefertiti (49,971 vertices), {N_SOURCES} sources in one task",
        "",
        "| executor | wall time | task time (read + factor + solves) | sources per second (wall) |",
        "|---|---:|---:|---:|",
    ]
    for how, (s, task) in rate.items():
        lines.append(f"| {names[how]} | {s:.2f} s | {task:.2f} s | {N_SOURCES / s:.0f} |")
    lines += [
        "",
        "One mesh is one task (its factorization lives on one worker), so more workers do not speed up a",
        "single mesh; they run more meshes at once. Split the sources over several batch runs (or use",
        "several meshes) to spread one mesh over workers, at the cost of one factorization per task.",
        "",
        f"### All pairs under a memory bound: {n:,}-vertex mesh (a {GRID} x {GRID} wavy grid), `--max-memory {MAX_MEMORY_MB:g}`",
        "",
        "| quantity | value |",
        "|---|---:|",
        f"| dense distance matrix (float64) | {n * n * 8 / 2**20:,.0f} MB |",
        f"| rows per block (bound / (8 bytes x n)) | {rows_per_block} |",
        f"| blocks written | {n_blocks} ({on_disk:,.0f} MB on disk) |",
        f"| wall time | {allp['seconds']:.0f} s ({n / allp['seconds']:.0f} sources per second) |",
        f"| peak RSS, solver built + one query (same child process setup) | {base['maxrss_mb']:.0f} MB |",
        f"| peak RSS, whole all-pairs run | {allp['maxrss_mb']:.0f} MB |",
        (f"| difference (block buffer + temporaries) | {allp['maxrss_mb'] - base['maxrss_mb']:.0f} MB "
         f"(bound {MAX_MEMORY_MB:g} MB) |"),
        "",
        "Peak RSS of the whole run is that of building the solver: the factorization's temporaries",
        "are larger than the 64 MB block buffer that later reuses the freed memory, and it does not grow",
        "with the 3 GB of rows written. The bound covers the distance rows a task holds; the solver (mesh,",
        "operators, factorizations) and the working memory of a block of sources (`HeatSolver.distances`:",
        "at most 256 MB, and the rows of one block of at most 16 sources) come on top and do not depend on",
        "the number of sources. With a local pool or several Dask worker threads, each running task has its",
        "own bound.",
        "",
        *blocks_lines(blocks, args.repeat),
    ]
    args.out.write_text("\n".join(lines))
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
