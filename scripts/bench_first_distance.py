"""First distance on small meshes, end to end: heatcore against potpourri3d, with their errors.

"End to end" is what a one-off call costs: from the vertex and face arrays in
memory to the distance from one source vertex, every precomputation included
(``hc.geodesic_distance(V, F, s)`` against
``pp3d.MeshHeatMethodDistanceSolver(V, F, use_robust=True).compute_distance(s)``).
Each mesh runs in its own child process (potpourri3d aborts on some meshes),
the solvers alternating round by round; a time is the best of the rounds.
Errors are mean relative errors against exact MMP geodesics (gdist) from the
same three source vertices as ``bench_core.py``, where gdist can run.

Besides heatcore's default (``refine="auto"``: meshes under 11,000 vertices are
midpoint-subdivided first) three columns explain the gap: heatcore without the
refinement, ``accuracy="high"`` without it (the compiled fast march of the
``fast`` extra, where numba is installed), and potpourri3d run on the very mesh
heatcore's default solves (the midpoint-subdivided one).

Usage::

    python scripts/bench_first_distance.py --out table.md --plot docs/images/first_distance.png

Needs the ``bench`` extra (gdist, potpourri3d).
"""

import argparse
import json
import multiprocessing as mp
import platform
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

import heatcore as hc
from heatcore.domains.refine import midpoint_subdivide
from heatcore.reference import exact_distance, mean_relative_error

MESHES = ["suzanne", "spot", "homer", "fandisk", "cheburashka", "rocker-arm"]
DEFAULT_MESH_DIR = Path(__file__).resolve().parents[1].parent / "shared" / "meshes"
#: Columns: label -> what runs (``refined`` runs on the default's subdivided mesh).
SOLVERS = {
    "heatcore": "heatcore default",
    "heatcore refine=0": "heatcore, no refinement",
    "heatcore high refine=0": "heatcore accuracy='high', no refinement",
    "potpourri3d": "potpourri3d robust",
    "potpourri3d refined": "potpourri3d robust on heatcore's refined mesh",
}


def solve(label, V, F, source, refined):
    """One end-to-end distance by the solver ``label``, at the input vertices."""
    if label == "heatcore":
        return hc.geodesic_distance(V, F, source)
    if label == "heatcore refine=0":
        return hc.geodesic_distance(V, F, source, refine=0)
    if label == "heatcore high refine=0":
        return hc.geodesic_distance(V, F, source, refine=0, accuracy="high")
    if label == "exact":
        return exact_distance(V, F, source)
    import potpourri3d as pp3d

    n = len(V)
    V, F = refined if label == "potpourri3d refined" else (V, F)
    return pp3d.MeshHeatMethodDistanceSolver(V, F, t_coef=1.0, use_robust=True).compute_distance(source)[:n]


def child(path, labels, rounds):
    """Times (best of ``rounds``, unless ``rounds`` is 0) and distances from the three sources of
    ``labels`` on one mesh; prints a JSON line."""
    mesh = hc.io.read_mesh(path)
    V, F = mesh.vertices, mesh.faces
    sources = np.random.default_rng(0).choice(np.unique(F), 3, replace=False)
    sub = midpoint_subdivide(V, F, hc.TriangleMesh(V, F).levels)
    refined = (sub.vertices, sub.faces)
    times = {label: [] for label in labels}
    for _ in range(rounds + 1):  # the first round warms up (imports, first calls) and is not counted
        for label in labels:
            start = time.perf_counter()
            solve(label, V, F, int(sources[0]), refined)
            times[label].append(time.perf_counter() - start)
    distances = {label: [solve(label, V, F, int(s), refined).tolist() for s in sources] for label in labels}
    print(json.dumps({"time": {k: min(v[1:], default=None) for k, v in times.items()}, "distances": distances,
                      "vertices": len(V), "operator_vertices": len(sub.vertices)}))


def run_child(path, labels, rounds):
    """The child's result, or None where it did not finish (potpourri3d and gdist abort on some meshes)."""
    cmd = [sys.executable, __file__, "--child", str(path), "--labels", ",".join(labels), "--rounds", str(rounds)]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    return json.loads(proc.stdout.strip().splitlines()[-1]) if proc.returncode == 0 else None


def table(mesh_dir, rounds):
    rows = []
    for name in MESHES:
        path = Path(mesh_dir) / f"{name}.obj"
        r = run_child(path, list(SOLVERS), rounds)
        crashed = []
        if r is None:  # again without potpourri3d, which took the process down
            crashed = [label for label in SOLVERS if label.startswith("potpourri3d")]
            r = run_child(path, [label for label in SOLVERS if label not in crashed], rounds)
        if r is None:
            raise RuntimeError(f"{name}: heatcore failed (run the child by hand for its error)")
        exact = run_child(path, ["exact"], 0)
        errors = {label: None if exact is None else float(np.mean(
            [mean_relative_error(np.asarray(d), np.asarray(e)) for d, e in zip(ds, exact["distances"]["exact"])]))
            for label, ds in r["distances"].items()}
        row = {"mesh": name, "vertices": r["vertices"], "operator_vertices": r["operator_vertices"],
               "time": r["time"], "error": errors, "crashed": crashed}
        rows.append(row)
        print(json.dumps(row), flush=True)
    return rows


def cell(row, label):
    if label in row["crashed"]:
        return "crashes"
    error = row["error"].get(label)
    return f"{1000 * row['time'][label]:.1f} ms" + ("" if error is None else f" / {100 * error:.2f}%")


def ratio(row, label, digits):
    """``label``'s time over potpourri3d's on the same mesh, in bold ("-" where potpourri3d crashed)."""
    pp = row["time"].get("potpourri3d")
    return "-" if pp is None else f"**{row['time'][label] / pp:.{digits}f}x**"


def write_markdown(path, rows, rounds, note):
    lines = [
        f"Generated by `python scripts/bench_first_distance.py` on {platform.machine()} ({mp.cpu_count()} cores), "
        f"Python {platform.python_version()}, {time.strftime('%Y-%m-%d')}{note}. Time: best of {rounds} rounds, "
        "the solvers alternating; error: mean relative error against exact geodesics (gdist) over 3 sources.",
        "",
        "| mesh (vertices; heatcore's operator vertices) | heatcore default | ratio to potpourri3d | "
        "heatcore refine=0 | its ratio | heatcore high, refine=0 | potpourri3d robust | potpourri3d on the refined mesh |",
        "|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in rows:
        lines.append(f"| {r['mesh']} ({r['vertices']:,}; {r['operator_vertices']:,}) | {cell(r, 'heatcore')} | "
                     f"{ratio(r, 'heatcore', 1)} | {cell(r, 'heatcore refine=0')} | {ratio(r, 'heatcore refine=0', 2)} | "
                     f"{cell(r, 'heatcore high refine=0')} | {cell(r, 'potpourri3d')} | {cell(r, 'potpourri3d refined')} |")
    text = "\n".join(lines) + "\n"
    if path:
        Path(path).write_text(text)
    print(text)


def plot(path, rows):
    """Error against end-to-end time, one panel per mesh with an exact reference: the trade the table shows."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from matplotlib.ticker import LogLocator, NullFormatter, ScalarFormatter

    rows = [r for r in rows if r["error"].get("heatcore") is not None]
    fig, axes = plt.subplots(1, len(rows), figsize=(3.0 * len(rows), 3.9), sharey=True, squeeze=False)
    markers = {"heatcore": ("o", "tab:red"), "heatcore refine=0": ("s", "tab:orange"),
               "heatcore high refine=0": ("D", "tab:green"),
               "potpourri3d": ("^", "tab:blue"), "potpourri3d refined": ("v", "tab:cyan")}
    for ax, r in zip(axes[0], rows):
        for label, (marker, color) in markers.items():
            if r["time"].get(label) is not None and r["error"].get(label) is not None:
                ax.plot(1000 * r["time"][label], 100 * r["error"][label], marker, color=color, ms=8,
                        label=SOLVERS[label])
        ax.set_xscale("log")
        ax.xaxis.set_major_locator(LogLocator(subs=(1, 2, 5)))
        ax.xaxis.set_major_formatter(ScalarFormatter())
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.set_title(f"{r['mesh']} ({r['vertices']:,} vertices)", fontsize=9)
        ax.set_xlabel("first distance (ms)")
        ax.grid(True, which="both", alpha=0.3)
        ax.margins(x=0.2, y=0.15)
    axes[0, 0].set_ylabel("mean relative error (%)")
    axes[0, 0].set_ylim(0, None)
    fig.legend(*axes[0, 0].get_legend_handles_labels(), loc="lower center", ncol=3, fontsize=8, frameon=False)
    fig.tight_layout(rect=(0, 0.14, 1, 1))
    fig.savefig(path, dpi=110)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--mesh-dir", default=str(DEFAULT_MESH_DIR))
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--out", default=None, help="markdown table")
    parser.add_argument("--note", default="", help="added after the date, e.g. ', quiet machine'")
    parser.add_argument("--plot", default=None, help="PNG: error against time per mesh")
    parser.add_argument("--child", help=argparse.SUPPRESS)
    parser.add_argument("--labels", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        return child(args.child, args.labels.split(","), args.rounds)
    rows = table(args.mesh_dir, args.rounds)
    write_markdown(args.out, rows, args.rounds, args.note)
    if args.plot:
        plot(args.plot, rows)


if __name__ == "__main__":
    main()
