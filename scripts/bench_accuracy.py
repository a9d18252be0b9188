"""Accuracy and time of accuracy="smooth" vs accuracy="high", against exact and peer methods.

For every triangle mesh of the shared mesh folder and the same 3 source vertices (one query per
source, the tests' choice), it measures the mean relative error against exact geodesics (MMP,
``gdist``) and the time per query of:

* heatcore smooth (default) and heatcore high (``accuracy="high"``), on the default domain
  (``refine="auto"``), and high on a domain midpoint-subdivided once more (``refine=+1`` level:
  the most accurate setting, with its precomputation cost);
* potpourri3d's heat method (``MeshHeatMethodDistanceSolver``, robust, t_coef 1);
* MeshLab's propagation filter ``compute_scalar_by_geodesic_distance_from_selection_per_vertex``
  (pymeshlab, ``maxdistance`` raised so every vertex is reached);
* gdist itself (one exact solve).

Peers that crash on a mesh (potpourri3d asserts on unreferenced vertices) run in a child process
and are reported as "-". Writes a markdown table (``--out``) and prints it.

Usage::

    python scripts/bench_accuracy.py --out /tmp/accuracy_high_table.md \
        --figure docs/images/accuracy_modes.png
"""

import argparse
import concurrent.futures as cf
import contextlib
import multiprocessing
import os
import sys
import time
from pathlib import Path

import numpy as np

from heatcore.reference import mean_relative_error

REPO = Path(__file__).resolve().parents[1]
MESH_DIR = Path(os.environ.get("HEATCORE_MESHES", REPO.parent / "shared" / "meshes"))
MESHES = ["spot", "homer", "fandisk", "cheburashka", "rocker-arm", "nefertiti", "stanford-bunny"]


def three_sources(F):
    rng = np.random.default_rng(0)
    return rng.choice(np.unique(F), 3, replace=False)


def _exact_worker(V, F, sources):
    import gdist

    used = np.unique(F)
    vmap = np.full(len(V), -1)
    vmap[used] = np.arange(used.size)
    out, times = [], []
    for s in sources:
        start = time.perf_counter()
        d = gdist.compute_gdist(
            np.ascontiguousarray(V[used], dtype=np.float64),
            np.ascontiguousarray(vmap[F], dtype=np.int32),
            np.asarray([vmap[s]], dtype=np.int32),
        )
        times.append(time.perf_counter() - start)
        full = np.full(len(V), np.inf)
        full[used] = d
        out.append(full)
    return np.array(out), float(np.mean(times))


def _potpourri_worker(V, F, sources):
    import potpourri3d as pp3d

    solver = pp3d.MeshHeatMethodDistanceSolver(V, F, t_coef=1.0, use_robust=True)
    out, times = [], []
    for s in sources:
        start = time.perf_counter()
        out.append(solver.compute_distance(int(s)))
        times.append(time.perf_counter() - start)
    return np.array(out), float(np.mean(times))


def _meshlab_worker(path, sources):
    import pymeshlab

    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(str(path))
    out, times = [], []
    for s in sources:
        ms.set_selection_none(allfaces=True, allverts=True)
        ms.compute_selection_by_condition_per_vertex(condselect=f"vi == {int(s)}")
        start = time.perf_counter()
        ms.compute_scalar_by_geodesic_distance_from_selection_per_vertex(
            maxdistance=pymeshlab.PureValue(1e6 * ms.current_mesh().bounding_box().diagonal())
        )
        times.append(time.perf_counter() - start)
        out.append(ms.current_mesh().vertex_scalar_array().copy())
    return np.array(out), float(np.mean(times))


def in_child(fn, *args):
    """Run ``fn(*args)`` in a fresh process; None if it crashes."""
    ctx = multiprocessing.get_context("spawn")
    try:
        with cf.ProcessPoolExecutor(max_workers=1, mp_context=ctx) as pool:
            return pool.submit(fn, *args).result()
    except Exception as exc:  # noqa: BLE001 - a crashing peer is reported, not fatal
        print(f"  ({fn.__name__} failed: {type(exc).__name__})", file=sys.stderr)
        return None


def heatcore_runs(V, F, sources, exact, **mesh_options):
    import heatcore as hc

    start = time.perf_counter()
    dom = hc.TriangleMesh(V, F, **mesh_options)
    smooth = hc.HeatSolver(dom)
    t_pre = time.perf_counter() - start
    high = hc.HeatSolver(dom, accuracy="high")
    high.distance([int(sources[0])])  # corner table (built once per domain)
    rows = {}
    for label, solver in [("smooth", smooth), ("high", high), ("high_vectorized", high)]:
        if label == "high_vectorized" and "refine" in mesh_options:
            continue
        errs, times = [], []
        with without_numba(label == "high_vectorized"):
            solver.distance([int(sources[0])])  # the vectorized pass's own corner table
            for s, e in zip(sources, exact):
                best = np.inf
                for _ in range(3):
                    t = time.perf_counter()
                    d = solver.distance([int(s)])
                    best = min(best, time.perf_counter() - t)
                times.append(best)
                errs.append(mean_relative_error(d, e))
        rows[label] = (float(np.mean(errs)), float(np.mean(times)))
    return rows, t_pre, dom.operators.n_vertices, dom.levels


@contextlib.contextmanager
def without_numba(active=True):
    """Inside: accuracy="high" takes the vectorized pass, as where numba is not installed."""
    from heatcore import fast_marching

    available = fast_marching.available
    if active:
        fast_marching.available = lambda: False
    try:
        yield
    finally:
        fast_marching.available = available


def bench(name):
    from heatcore.io import read_mesh

    mesh = read_mesh(MESH_DIR / f"{name}.obj")
    V, F = mesh.vertices, mesh.faces
    sources = three_sources(F)
    exact, t_exact = in_child(_exact_worker, V, F, sources)
    base, t_pre, n_ops, levels = heatcore_runs(V, F, sources, exact)
    finer, t_pre_fine, n_fine, _ = heatcore_runs(V, F, sources, exact, refine=levels + 1)
    row = {
        "mesh": name,
        "n": len(V),
        "n_ops": n_ops,
        "levels": levels,
        "smooth": base["smooth"],
        "high": base["high"],
        "high_vectorized": base["high_vectorized"],
        "high_fine": finer["high"],
        "n_fine": n_fine,
        "pre": t_pre,
        "pre_fine": t_pre_fine,
        "exact": t_exact,
    }
    for key, fn, args in [
        ("potpourri3d", _potpourri_worker, (V, F, sources)),
        ("meshlab", _meshlab_worker, (MESH_DIR / f"{name}.obj", sources)),
    ]:
        res = in_child(fn, *args)
        if res is None:
            row[key] = None
        else:
            d, t = res
            row[key] = (float(np.mean([mean_relative_error(di, e) for di, e in zip(d, exact)])), t)
    return row


def fmt(cell):
    return "-" if cell is None else f"{100 * cell[0]:.2f}% / {1e3 * cell[1]:.0f} ms"


def markdown(rows):
    lines = [
        ("| mesh (vertices; operator vertices, levels) | smooth | **high** | high / smooth time | high without "
         "numba | high, one more level (vertices; precompute) | potpourri3d | MeshLab geodesic | exact (gdist) |"),
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['mesh']} ({r['n']:,}; {r['n_ops']:,}, {r['levels']}) | {fmt(r['smooth'])} | "
            f"**{fmt(r['high'])}** | {r['high'][1] / r['smooth'][1]:.1f}x | {fmt(r['high_vectorized'])} | "
            f"{fmt(r['high_fine'])} ({r['n_fine']:,}; {r['pre_fine']:.1f} s vs "
            f"{r['pre']:.1f} s) | {fmt(r.get('potpourri3d'))} | {fmt(r.get('meshlab'))} | "
            f"{1e3 * r['exact']:.0f} ms |"
        )
    wins = sum(1 for r in rows if r.get("meshlab") and r["high"][0] < r["meshlab"][0])
    lines.append("")
    lines.append(
        f"Cells: mean relative error over the 3 sources / time per query. high is below MeshLab's "
        f"propagation filter on {wins} of {len(rows)} meshes."
    )
    return "\n".join(lines) + "\n"


def figure(path, name="nefertiti"):
    """Isolines of smooth (left) and high (right) over exact ones (dashed), on a PCA projection."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.tri as mtri

    import heatcore as hc
    from heatcore.io import read_mesh

    mesh = read_mesh(MESH_DIR / f"{name}.obj")
    V, F = mesh.vertices, mesh.faces
    s = int(three_sources(F)[0])
    exact = in_child(_exact_worker, V, F, [s])[0][0]
    dom = hc.TriangleMesh(V, F)
    d = {mode: hc.HeatSolver(dom, accuracy=mode).distance([s]) for mode in ("smooth", "high")}
    used = np.unique(F)
    X = V - V[used].mean(axis=0)
    axes = np.linalg.svd(X[used], full_matrices=False)[2]
    P = X @ axes[:2].T  # nefertiti is a relief: its two main axes give a faithful flat view
    tri = mtri.Triangulation(P[:, 0], P[:, 1], F)
    levels = np.linspace(0, np.nanmax(exact[np.isfinite(exact)]), 26)[1:]
    fig, axs = plt.subplots(1, 2, figsize=(12, 7.2), constrained_layout=True)
    for ax, mode in zip(axs, ("smooth", "high")):
        err = mean_relative_error(d[mode], exact)
        ax.tricontour(tri, np.where(np.isfinite(exact), exact, 0), levels=levels, colors="k",
                      linewidths=0.6, linestyles="--")
        ax.tricontour(tri, d[mode], levels=levels, colors="tab:red", linewidths=1.0)
        ax.plot(*P[s], "o", color="tab:blue", ms=7)
        ax.set_title(f'accuracy="{mode}": {100 * err:.2f}% mean relative error', fontsize=12)
        ax.set_aspect("equal")
        ax.axis("off")
    fig.suptitle(f"{name}: isolines of heatcore (red) over exact geodesic distance (dashed)", fontsize=13)
    fig.savefig(path, dpi=110)
    print(f"wrote {path}", file=sys.stderr)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, help="write the markdown table here")
    parser.add_argument("--meshes", nargs="*", default=MESHES)
    parser.add_argument("--figure", type=Path, help="also draw smooth vs high isolines to this PNG")
    parser.add_argument("--figure-only", action="store_true", help="only draw the figure")
    args = parser.parse_args(argv)
    if args.figure:
        figure(args.figure)
        if args.figure_only:
            return
    rows = []
    for name in args.meshes:
        print(f"{name} ...", file=sys.stderr, flush=True)
        rows.append(bench(name))
    table = markdown(rows)
    print(table)
    if args.out:
        args.out.write_text(table)


if __name__ == "__main__":
    main()
