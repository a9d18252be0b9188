"""What one ``accuracy="high"`` query costs, in smooth queries: the figure :data:`heatcore.options.HIGH_ACCURACY_COST` states.

For each mesh of the shared mesh folder, one solver per accuracy is built on the
default domain (``refine="auto"``, ``intent="reuse"``: the factorizations are
paid once, outside the timing), then each of a few source vertices is queried;
each of ``--sources`` x ``--repeat`` distinct vertices is queried once (a solver
keeps the columns of the vertices it has seen) and the median time counts (a
first query, numba's compilation, is left out). The ratio high/smooth is printed per mesh, with numba
(the compiled fast marching, the ``fast`` extra) and without it (the vectorized
eikonal pass, ordered by the heat distance), and as the range over the meshes.

Usage::

    python scripts/bench_high_cost.py                      # both passes, the default meshes
    python scripts/bench_high_cost.py --meshes spot homer --repeat 5
"""

import argparse
import os
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
MESH_DIR = Path(os.environ.get("HEATCORE_MESHES", REPO.parent / "shared" / "meshes"))
MESHES = ["spot", "homer", "cheburashka", "rocker-arm", "nefertiti"]


def query_times(solver, sources, warm_up):
    """Each source queried once (a solver keeps the columns of vertices it has seen: no repeats)."""
    solver.distance([int(warm_up)])  # numba compiles, scratch buffers fill
    times = []
    for s in sources:
        start = time.perf_counter()
        solver.distance([int(s)])
        times.append(time.perf_counter() - start)
    return times


def measure(name, repeat, n_sources, with_numba):
    import heatcore as hc
    from heatcore import fast_marching
    from heatcore.io import read_mesh

    if not with_numba:
        fast_marching._numba = None  # noqa: SLF001 - the benchmark's switch: the vectorized pass
    mesh = read_mesh(MESH_DIR / f"{name}.obj")
    domain = hc.TriangleMesh(mesh.vertices, mesh.faces)
    sources = np.random.default_rng(0).choice(len(mesh.vertices), n_sources * repeat + 1, replace=False)
    smooth = query_times(hc.HeatSolver(domain, accuracy="smooth"), sources[1:], sources[0])
    high = query_times(hc.HeatSolver(domain, accuracy="high"), sources[1:], sources[0])
    return len(mesh.vertices), float(np.median(smooth)), float(np.median(high))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--meshes", nargs="+", default=MESHES)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--sources", type=int, default=3)
    parser.add_argument("--no-numba-only", action="store_true")
    args = parser.parse_args(argv)
    import multiprocessing

    ctx = multiprocessing.get_context("spawn")  # each pass in a fresh process: no compiled state shared
    passes = [False] if args.no_numba_only else [True, False]
    ratios = {p: [] for p in passes}
    print("| mesh | vertices | pass | smooth query (s) | high query (s) | high / smooth |")
    print("|---|---|---|---|---|---|")
    for name in args.meshes:
        for with_numba in passes:
            with ctx.Pool(1) as pool:
                n, smooth, high = pool.apply(measure, (name, args.repeat, args.sources, with_numba))
            ratios[with_numba].append(high / smooth)
            print(f"| {name} | {n:,} | {'numba' if with_numba else 'vectorized'} | {smooth:.4f} | {high:.4f} | "
                  f"{high / smooth:.1f} |", flush=True)
    for with_numba, r in ratios.items():
        print(f"{'numba' if with_numba else 'vectorized'}: {min(r):.1f}-{max(r):.1f} "
              f"(median {np.median(r):.1f}) smooth queries per high query")


if __name__ == "__main__":
    main()
