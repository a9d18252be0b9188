"""The right answer on the user's shape: STL soup, several parts, any scale (docs/shapes.md).

For each shared test mesh:

* **STL**: the mesh written as an STL file (triangle soup) and read back; how many vertices are
  welded, and the largest difference to the distances on the OBJ's own vertices;
* **parts**: the mesh beside a copy of cheburashka at a fifth of its size (an ogre-like body and a
  small part), both with a source; each part's mean relative error against exact geodesics (gdist)
  when solved together and alone, with ``accuracy="smooth"`` and ``"high"``;
* **scale**: the mesh scaled by 1e-100 ... 1e100; the largest relative difference to the unscaled
  distances times the scale.

Usage: ``python scripts/bench_shapes.py [--meshes spot,homer,...] [--out docs/shapes.md]``.
"""

import argparse
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np
import trimesh

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "tests"))

import heatcore as hc  # noqa: E402
from heatcore.reference import exact_distance, mean_relative_error  # noqa: E402

SCALES = (1e-100, 1e-60, 1e-8, 1e8, 1e60, 1e100)
DEFAULT_MESHES = "spot,homer,fandisk,cheburashka,rocker-arm"


def load(name):
    from conftest import load_shared_mesh

    return load_shared_mesh(name)


def stl_row(name, V, F, folder):
    path = Path(folder) / f"{name}.stl"
    trimesh.Trimesh(V, F, process=False).export(path)
    mesh = hc.io.read_mesh(path)
    soup = hc.TriangleMesh(mesh.vertices, mesh.faces)
    corner = int(np.flatnonzero(F.ravel() == 0)[0])  # a soup vertex standing for vertex 0
    d_stl = hc.HeatSolver(soup).distance([corner])
    d_obj = hc.geodesic_distance(V, F, [0])[F.ravel()]
    return {
        "mesh": name,
        "STL vertices": len(mesh.vertices),
        "welded": soup.n_welded,
        "inf": int(np.isinf(d_stl).sum()),
        "max |STL - OBJ|": float(np.abs(d_stl - d_obj).max() / d_obj.max()),
    }


def parts_rows(name, V, F, small, exact_small):
    exact = exact_distance(V, F, 0)
    offset = len(V)
    W = np.vstack([V, small[0]])
    G = np.vstack([F, small[1] + offset])
    rows = []
    for accuracy in ("smooth", "high"):
        start = time.perf_counter()
        d = hc.geodesic_distance(W, G, [0, offset], accuracy=accuracy)
        seconds = time.perf_counter() - start
        alone = hc.geodesic_distance(V, F, [0], accuracy=accuracy)
        alone_small = hc.geodesic_distance(*small, [0], accuracy=accuracy)
        rows.append(
            {
                "mesh": name,
                "accuracy": accuracy,
                "body together": mean_relative_error(d[:offset], exact),
                "body alone": mean_relative_error(alone, exact),
                "small part together": mean_relative_error(d[offset:], exact_small),
                "small part alone": mean_relative_error(alone_small, exact_small),
                "seconds together": seconds,
            }
        )
    return rows


def scale_row(name, V, F):
    d = hc.geodesic_distance(V, F, [0])
    worst = max(float(np.abs(hc.geodesic_distance(V * s, F, [0]) / s - d).max() / d.max()) for s in SCALES)
    return {"mesh": name, "largest relative difference over the scales": worst}


def table(rows, percent=()):
    keys = list(rows[0])
    lines = ["| " + " | ".join(keys) + " |", "|" + "---|" * len(keys)]
    for row in rows:
        cells = []
        for key in keys:
            value = row[key]
            if key in percent:
                cells.append(f"{100 * value:.2f}%")
            elif isinstance(value, float):
                cells.append(f"{value:.2g}")
            elif isinstance(value, (int, np.integer)):
                cells.append(f"{value:,}")
            else:
                cells.append(str(value))
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--meshes", default=DEFAULT_MESHES)
    parser.add_argument("--out", type=Path, default=None, help="write the markdown tables here")
    args = parser.parse_args(argv)
    warnings.simplefilter("ignore", hc.HeatcoreWarning)
    Vs, Fs = load("cheburashka")
    small = (0.2 * Vs + [3.0, 0.0, 0.0], Fs)
    exact_small = exact_distance(*small, 0)
    stl, parts, scale = [], [], []
    with tempfile.TemporaryDirectory() as folder:
        for name in args.meshes.split(","):
            V, F = load(name)
            stl.append(stl_row(name, V, F, folder))
            parts += parts_rows(name, V, F, small, exact_small)
            scale.append(scale_row(name, V, F))
            print(f"{name} done", file=sys.stderr)
    percent = ("body together", "body alone", "small part together", "small part alone")
    report = "\n\n".join(
        [
            "### STL files (triangle soup), read back and welded\n\n" + table(stl),
            "### Beside a small part (cheburashka at 1/5 size), mean relative error vs exact\n\n"
            + table(parts, percent),
            "### Scaled by " + ", ".join(f"{s:g}" for s in SCALES) + "\n\n" + table(scale),
        ]
    )
    print(report)
    if args.out:
        args.out.write_text(args.out.read_text().split("<!-- measured -->")[0] + "<!-- measured -->\n\n" + report + "\n")


if __name__ == "__main__":
    main()
