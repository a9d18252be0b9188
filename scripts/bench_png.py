"""The PNG picture of a distance field: how long ``render_distance`` takes, by mesh size.

Each mesh is drawn at the command line's size (8 x 6 inches at 150 dpi: 1200 x 900 pixels, 12
isolines, a source marker) with the distance from vertex 0 (heatcore's, default options); the
time is the median of ``--repeat`` calls in one process, after a first call on a tiny mesh that
pays matplotlib's import (timed apart: a command-line run pays it once). Larger meshes are the
shared nefertiti (49,971 vertices) with 1 and 2 levels of midpoint subdivision (same shape).

    python scripts/bench_png.py                 # the table on stdout
    python scripts/bench_png.py --write-docs    # also into docs/isolines.md
"""

import argparse
import os
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np

import heatcore as hc
from heatcore.domains.refine import midpoint_subdivide
from heatcore.io import read_mesh
from heatcore.viz.render import render_distance

REPO = Path(__file__).resolve().parents[1]
SHARED = REPO.parent / "shared" / "meshes"
BEGIN, END = "<!-- bench_png:begin -->", "<!-- bench_png:end -->"
CASES = [("spot", 0), ("homer", 0), ("nefertiti", 0), ("nefertiti", 1), ("nefertiti", 2)]


def load(name, levels):
    mesh = read_mesh(SHARED / f"{name}.obj")
    V, F = mesh.vertices, mesh.faces
    if levels:
        sub = midpoint_subdivide(V, F, levels=levels)
        V, F = sub.vertices, sub.faces
    return V, F


def bench(repeat):
    folder = tempfile.mkdtemp()
    png = os.path.join(folder, "d.png")
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    t0 = time.perf_counter()
    render_distance(png, V, [[0, 1, 2]], [0.0, 1.0, 1.0])
    first = time.perf_counter() - t0
    rows = []
    for name, levels in CASES:
        V, F = load(name, levels)
        d = hc.HeatSolver(hc.TriangleMesh(V, F)).distance([0])
        times = []
        for _ in range(repeat):
            t0 = time.perf_counter()
            render_distance(png, V, F, d, sources=[0], isolines=12, azimuth=150)
            times.append(time.perf_counter() - t0)
        label = name + (f" subdivided {levels}x" if levels else "")
        rows.append((label, len(V), len(F), statistics.median(times)))
        print(f"{label}: {len(V):,} vertices, {statistics.median(times):.2f} s", flush=True)
    return first, rows


def table(first, rows):
    lines = ["| mesh | vertices | faces | render (s) |", "|---|---|---|---|"]
    lines += [f"| {label} | {n:,} | {m:,} | {t:.2f} |" for label, n, m, t in rows]
    lines += ["", f"First picture in a process (matplotlib's import, a 3-vertex mesh): {first:.2f} s."]
    return "\n".join(lines)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--write-docs", action="store_true")
    args = parser.parse_args()
    load_average = os.getloadavg()[0]
    first, rows = bench(args.repeat)
    text = table(first, rows) + f"\n\nLoad average at the start: {load_average:.1f} (2-core machine)."
    print(text)
    if args.write_docs:
        doc = REPO / "docs" / "isolines.md"
        source = doc.read_text()
        start, stop = source.index(BEGIN) + len(BEGIN), source.index(END)
        doc.write_text(source[:start] + "\n" + text + "\n" + source[stop:])


if __name__ == "__main__":
    main()
