"""Mean relative error of ``accuracy="high"`` with default settings: the figure the README states.

For each mesh file, exact geodesics (MMP, ``gdist``, in a child process: it crashes on some
non-manifold input) from ``--sources`` random vertices (seed 0; the first 3 are the tests' and
``scripts/bench_accuracy.py``'s sources), one query per source, and the mean relative error
(:func:`heatcore.reference.mean_relative_error`) of ``HeatSolver(TriangleMesh(V, F),
accuracy="high")`` and of the default ``accuracy="smooth"``. Prints a markdown table, per mesh
the mean over the sources and the worst source, and the range over the meshes.

Usage::

    python scripts/bench_high_error.py                          # the shared test meshes (README's table)
    python scripts/bench_high_error.py --sources 10 other/*.obj # any triangle mesh files
"""

import argparse
import concurrent.futures as cf
import multiprocessing
import os
import sys
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
MESH_DIR = Path(os.environ.get("HEATCORE_MESHES", REPO.parent / "shared" / "meshes"))
MESHES = ["spot", "homer", "fandisk", "cheburashka", "rocker-arm", "nefertiti", "stanford-bunny"]


def random_sources(F, count):
    """``count`` distinct vertices used by ``F`` (seed 0: the first 3 are the tests' sources)."""
    return np.random.default_rng(0).choice(np.unique(F), count, replace=False)


def exact_rows(V, F, sources):
    """Exact distances from each source (run in a child process)."""
    from heatcore.reference import exact_distance

    return np.array([exact_distance(V, F, [int(s)]) for s in sources])


def measure(path, count):
    """``{"mesh", "vertices", "smooth", "high", "high_worst"}`` for one mesh file, or None when gdist fails."""
    import heatcore as hc
    from heatcore.reference import mean_relative_error

    mesh = hc.io.read_mesh(path)
    V, F = mesh.vertices, mesh.faces
    sources = random_sources(F, count)
    try:
        with cf.ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("spawn")) as pool:
            exact = pool.submit(exact_rows, V, F, sources).result()
    except Exception as exc:  # noqa: BLE001 - a mesh gdist cannot take is reported, not fatal
        print(f"  {path.name}: no exact reference ({type(exc).__name__})", file=sys.stderr)
        return None
    domain = hc.TriangleMesh(V, F)
    row = {"mesh": path.stem, "vertices": len(V)}
    for accuracy in ("smooth", "high"):
        solver = hc.HeatSolver(domain, accuracy=accuracy)
        errors = [mean_relative_error(solver.distance([int(s)]), e) for s, e in zip(sources, exact)]
        row[accuracy], row[f"{accuracy}_worst"] = float(np.mean(errors)), float(np.max(errors))
    return row


def markdown(rows, count):
    """The table, and a last line with the range of the means over the meshes."""
    lines = [f"| mesh | vertices | smooth | **high** | high, worst of {count} sources |", "|---|---:|---:|---:|---:|"]
    lines += [f"| {r['mesh']} | {r['vertices']:,} | {100 * r['smooth']:.2f}% | **{100 * r['high']:.2f}%** | "
              f"{100 * r['high_worst']:.2f}% |" for r in rows]
    high = [r["high"] for r in rows]
    lines.append(f"\nhigh, mean over {count} sources: {100 * min(high):.2f}-{100 * max(high):.2f}% on {len(rows)} meshes")
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("meshes", nargs="*", type=Path, help="mesh files (default: the shared test meshes)")
    parser.add_argument("--sources", type=int, default=3, help="random source vertices per mesh (default: 3)")
    args = parser.parse_args(argv)
    paths = args.meshes or [MESH_DIR / f"{name}.obj" for name in MESHES]
    rows = []
    for path in paths:
        print(f"{path.name} ...", file=sys.stderr, flush=True)
        row = measure(path, args.sources)
        if row is not None:
            rows.append(row)
    print(markdown(rows, args.sources))


if __name__ == "__main__":
    main()
