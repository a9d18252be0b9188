#!/usr/bin/env python3
"""heatcore's MeshLab filter side by side with MeshLab's own geodesic filters.

For each triangle mesh of the shared test meshes and three source vertices,
one at a time: mean relative error against exact geodesics (MMP, ``gdist``,
computed on the referenced-vertex submesh, in a child process because gdist
can crash) and time, for

* heatcore: :func:`heatcore.apps.meshlab.geodesic_distance_from_selection` (default
  options; colours off so that every method only writes quality); the
  repeated call passes the cached solver back;
* heatcore high: the same with ``accuracy="high"`` (heat method, then an
  ordered eikonal pass);
* MeshLab's heat filter, ``compute_scalar_by_heat_geodesic_distance_from_selection_per_vertex``
  (m = 1, plain cotan operators);
* MeshLab's geodesic filter, ``compute_scalar_by_geodesic_distance_from_selection_per_vertex``
  (``maxdistance`` raised so that every vertex is reached).

"first" is the first call on a freshly loaded MeshSet (source 1), "repeated"
the mean of the calls for sources 2 and 3 on the same MeshSet. Prints the
markdown table (docs/meshlab.md) and, with ``--figures``, draws the pictures
of docs/images/meshlab_*.png.

Usage::

    python scripts/bench_meshlab.py                     # table on all meshes
    python scripts/bench_meshlab.py --meshes spot homer --figures docs/images
"""

import argparse
import concurrent.futures as cf
import multiprocessing
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from heatcore.reference import mean_relative_error

REPO = Path(__file__).resolve().parents[1]
MESH_DIR = Path(os.environ.get("HEATCORE_MESHES", REPO.parent / "shared" / "meshes"))
MESHES = ["spot", "homer", "fandisk", "cheburashka", "rocker-arm", "nefertiti", "stanford-bunny"]
N_SOURCES = 3
SEED = 0


def load(name):
    """A fresh MeshSet holding the mesh (pymeshlab's reader: same vertex order as the file)."""
    import pymeshlab

    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(str(MESH_DIR / f"{name}.obj"))
    return ms


def pick_sources(F, n_vertices, count=N_SOURCES, seed=SEED):
    """``count`` distinct referenced vertices, reproducibly."""
    used = np.unique(F)
    rng = np.random.default_rng(seed)
    return [int(v) for v in rng.choice(used, size=count, replace=False)]


def _exact_worker(V, F, sources):
    import gdist

    used = np.unique(F)
    vmap = np.full(len(V), -1)
    vmap[used] = np.arange(used.size)
    out = []
    for s in sources:
        d = gdist.compute_gdist(
            np.ascontiguousarray(V[used], dtype=np.float64),
            np.ascontiguousarray(vmap[F], dtype=np.int32),
            np.asarray([vmap[s]], dtype=np.int32),
        )
        full = np.full(len(V), np.inf)
        full[used] = d
        out.append(full)
    return np.array(out)


def exact_distances(name, V, F, sources, cache_dir):
    """Exact distances from each source (rows), cached on disk; gdist runs in a child process."""
    cache = Path(cache_dir) / f"exact_{name}_{'_'.join(map(str, sources))}.npy"
    if cache.is_file():
        return np.load(cache)
    ctx = multiprocessing.get_context("spawn")
    with cf.ProcessPoolExecutor(max_workers=1, mp_context=ctx) as pool:
        d = pool.submit(_exact_worker, V, F, sources).result()
    cache.parent.mkdir(parents=True, exist_ok=True)
    np.save(cache, d)
    return d


def select_vertex(ms, v):
    ms.set_selection_none(allfaces=True, allverts=True)
    ms.compute_selection_by_condition_per_vertex(condselect=f"vi == {int(v)}")


def run_heatcore(ms, sources, **options):
    from heatcore.apps.meshlab import geodesic_distance_from_selection

    results, solver = [], None
    for v in sources:
        select_vertex(ms, v)
        start = time.perf_counter()
        stats = geodesic_distance_from_selection(ms, colormap="none", solver=solver, **options)
        seconds = time.perf_counter() - start
        solver = stats["solver"]
        results.append((ms.current_mesh().vertex_scalar_array().copy(), seconds))
    return results


def run_meshlab(ms, sources, which):
    import pymeshlab

    results = []
    for v in sources:
        select_vertex(ms, v)
        start = time.perf_counter()
        if which == "heat":
            ms.compute_scalar_by_heat_geodesic_distance_from_selection_per_vertex(m=1.0)
        else:
            # an absolute bound far beyond any distance (percentages stop at 100% of the diagonal)
            ms.compute_scalar_by_geodesic_distance_from_selection_per_vertex(
                maxdistance=pymeshlab.PureValue(1e6 * ms.current_mesh().bounding_box().diagonal())
            )
        seconds = time.perf_counter() - start
        results.append((ms.current_mesh().vertex_scalar_array().copy(), seconds))
    return results


METHODS = {
    "heatcore": run_heatcore,
    "heatcore high": lambda ms, s: run_heatcore(ms, s, accuracy="high"),
    "MeshLab heat": lambda ms, s: run_meshlab(ms, s, "heat"),
    "MeshLab geodesic": lambda ms, s: run_meshlab(ms, s, "geodesic"),
}


def warm_up():
    """One small run of every method, so that first-call times exclude imports and library start-up."""
    ms = load("spot")
    for runner in METHODS.values():
        runner(ms, [0])


def bench_mesh(name, cache_dir):
    ms = load(name)
    mesh = ms.current_mesh()
    V = np.asarray(mesh.vertex_matrix(), dtype=np.float64)
    F = np.asarray(mesh.face_matrix(), dtype=np.int64)
    sources = pick_sources(F, len(V))
    exact = exact_distances(name, V, F, sources, cache_dir)
    row = {"mesh": name, "vertices": len(V), "faces": len(F), "sources": sources, "methods": {}}
    for method, runner in METHODS.items():
        ms = load(name)
        try:
            runs = runner(ms, sources)
        except Exception as exc:  # report a failing filter in the table instead of stopping
            row["methods"][method] = {"failed": f"{type(exc).__name__}: {exc}".splitlines()[0]}
            continue
        errors = [mean_relative_error(d, e) for (d, _), e in zip(runs, exact)]
        # vertices (other than the source) left at 0: unreached by the filter
        zeros = [int(np.sum((d == 0) & np.isfinite(e) & (e > 0))) for (d, _), e in zip(runs, exact)]
        row["methods"][method] = {
            "error": float(np.mean(errors)),
            "errors": errors,
            "first": runs[0][1],
            "repeated": float(np.mean([t for _, t in runs[1:]])),
            "zeros": max(zeros),
            "distances": [d for d, _ in runs],
        }
        print(f"  {name:15s} {method:17s} error {100 * np.mean(errors):6.2f}%  "
              f"first {runs[0][1]:7.3f} s  repeated {row['methods'][method]['repeated']:7.3f} s"
              + (f"  ({max(zeros)} vertices left at 0)" if max(zeros) else ""), file=sys.stderr)  # fmt: skip
    row["exact"] = exact
    row["notes"] = []
    unreferenced = len(V) - np.unique(F).size
    if unreferenced:
        row["notes"].append(cleaned_meshlab_heat(name, V, F, sources, exact, unreferenced))
    return row


def cleaned_meshlab_heat(name, V, F, sources, exact, unreferenced):
    """MeshLab's heat filter after MeshLab's 'Remove Unreferenced Vertices' (it yields all zeros before)."""
    ms = load(name)
    ms.meshing_remove_unreferenced_vertices()
    used = np.unique(F)
    assert np.array_equal(ms.current_mesh().vertex_matrix(), V[used])
    vmap = np.full(len(V), -1)
    vmap[used] = np.arange(used.size)
    runs = run_meshlab(ms, [int(vmap[s]) for s in sources], "heat")
    errors = [mean_relative_error(d, e[used]) for (d, _), e in zip(runs, exact)]
    first, repeated = runs[0][1], float(np.mean([t for _, t in runs[1:]]))
    return (
        f"{name} has {unreferenced:,} unreferenced vertices; MeshLab's heat filter returns 0 everywhere on it. "
        f"After MeshLab's *Remove Unreferenced Vertices*, it gives {100 * np.mean(errors):.2f}% "
        f"(per source: {', '.join(f'{100 * e:.2f}%' for e in errors)}; time {first:.3f} / {repeated:.3f} s)."
    )


def markdown_table(rows):
    names = list(METHODS)
    head = (
        "| mesh | vertices | "
        + " | ".join(f"{m} error" for m in names)
        + " | "
        + " | ".join(f"{m} first / repeated (s)" for m in names)
        + " |"
    )
    lines = [head, "|" + "---|" * (2 + 2 * len(names))]
    for row in rows:
        errs, times = [], []
        for m in names:
            r = row["methods"][m]
            if "failed" in r:
                errs.append("failed")
                times.append("–")
                continue
            best = min(row["methods"][k].get("error", np.inf) for k in names)
            e = f"{100 * r['error']:.2f}%"
            if r["zeros"] >= 0.5 * row["vertices"]:
                e += " (all 0)"
            errs.append(f"**{e}**" if r["error"] == best else e)
            times.append(f"{r['first']:.3f} / {r['repeated']:.3f}")
        lines.append(f"| {row['mesh']} | {row['vertices']:,} | " + " | ".join(errs) + " | " + " | ".join(times) + " |")
    notes = [note for row in rows for note in row.get("notes", [])]
    if notes:
        lines += [""] + [f"- {note}" for note in notes]
    return "\n".join(lines)


# --------------------------------------------------------------------------- figures


def figure_cli_output(out_dir, work):
    """What a MeshLab user gets: the command's output PLY, reopened, drawn from its quality."""
    import pymeshlab

    from heatcore.apps.meshlab import main
    from heatcore.viz.render import render_distance

    src = MESH_DIR / "spot.obj"
    out = Path(work) / "spot_distance.ply"
    main([str(src), "--sources", "1000", "--isolines", "12", "-o", str(out)])
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(str(out))
    mesh = ms.current_mesh()
    sel = np.flatnonzero(mesh.vertex_selection_array())
    path = Path(out_dir) / "meshlab_spot.png"
    render_distance(
        path, mesh.vertex_matrix(), mesh.face_matrix(), mesh.vertex_scalar_array(), sources=sel,
        isolines=12, azimuth=60, title="spot: quality from scripts/heatcore_meshlab.py --sources 1000",
    )  # fmt: skip
    return path


def figure_comparison(out_dir, row, work, index=0):
    """Exact, heatcore, MeshLab heat and MeshLab geodesic on one mesh, same isolines."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from heatcore.viz.render import render_distance

    ms = load(row["mesh"])
    V, F = ms.current_mesh().vertex_matrix(), ms.current_mesh().face_matrix()
    exact = row["exact"][index]
    vmax = float(exact[np.isfinite(exact)].max())
    panels = [("exact (MMP)", exact)] + [
        (f"{m}: {100 * row['methods'][m]['errors'][index]:.1f}%", row["methods"][m]["distances"][index])
        for m in METHODS
        if "failed" not in row["methods"][m]
    ]
    images = []
    for k, (title, d) in enumerate(panels):
        png = Path(work) / f"panel{k}.png"
        # common scale: clip each field at the exact maximum so the isolines are comparable
        render_distance(png, V, F, np.minimum(d, vmax), sources=[row["sources"][index]], isolines=16,
                        title=title, size=(5, 5), dpi=110, azimuth=20)  # fmt: skip
        images.append(plt.imread(png))
    fig, axes = plt.subplots(1, len(images), figsize=(4.2 * len(images), 4.6))
    for ax, img in zip(axes, images):
        ax.imshow(img)
        ax.axis("off")
    fig.suptitle(f"{row['mesh']}: geodesic distance from one vertex (16 isolines); error = mean relative error")
    fig.tight_layout()
    path = Path(out_dir) / f"meshlab_{row['mesh']}_comparison.png"
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--meshes", nargs="+", default=MESHES, choices=MESHES)
    parser.add_argument("--cache", default=str(REPO / "out" / "bench_meshlab"), help="exact-distance cache folder")
    parser.add_argument("--figures", metavar="DIR", help="also draw docs pictures into DIR")
    parser.add_argument("--figure-mesh", default="homer", help="mesh of the comparison picture")
    args = parser.parse_args(argv)
    warm_up()
    rows = []
    for name in args.meshes:
        rows.append(bench_mesh(name, args.cache))
    print(markdown_table(rows))
    if args.figures:
        Path(args.figures).mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryDirectory() as work:
            print(figure_cli_output(args.figures, work), file=sys.stderr)
            for row in rows:
                if row["mesh"] == args.figure_mesh:
                    print(figure_comparison(args.figures, row, work), file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
