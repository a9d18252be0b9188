"""The table of docs/polygon.md: PolygonMesh's default and virtual refinement against the triangulated twin.

For every mesh of ``tests/test_polygon_concave.py`` (made by Blender's own operators, and the meshes
where virtual refinement broke the rule) and every ``refine`` (0, 1, 2, "auto"), the mean relative
error over the mesh's sources (each on its own) of

* ``PolygonMesh`` with its defaults (heatcore's triangulation of every polygon),
* ``PolygonMesh(virtual=True)`` (virtual refinement of the convex, flat, not thin polygons),
* ``TriangleMesh`` on heatcore's triangulation of the same polygons (the triangulated twin),

against the straight-line distance (planar grids) or exact geodesics (gdist) on that triangulation.
Per mesh: the worst ratio of the default to the twin over all sources and ``refine``; per ``refine``: the
twin's and virtual refinement's mean error, and virtual refinement's worst source ratio to the twin.

Usage::

    python scripts/bench_polygon_rule.py --out docs/polygon_rule_table.md

Needs the ``test`` and ``blender`` extras (bpy, gdist) and the shared meshes.
"""

import argparse
import sys
import time
import warnings
from pathlib import Path

import bpy  # noqa: F401  (before pymeshlab and the tests' helpers)
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from test_polygon_concave import BUILDERS, REFINES, case  # noqa: E402

import heatcore as hc  # noqa: E402
from heatcore.reference import mean_relative_error  # noqa: E402


def errors(V, P, T, sources, exact, refine):
    """Mean relative errors per source: ``{"default": ..., "virtual": ..., "twin": ...}``."""
    domains = {
        "default": lambda: hc.PolygonMesh(V, P, refine=refine),
        "virtual": lambda: hc.PolygonMesh(V, P, refine=refine, virtual=True),
        "twin": lambda: hc.TriangleMesh(V, T, refine=refine, weld=None),  # unwelded, as PolygonMesh builds them
    }
    out = {}
    for name, build in domains.items():
        solver = hc.HeatSolver(build())
        out[name] = np.array([mean_relative_error(solver.distance([s]), e) for s, e in zip(sources, exact)])
    return out


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, help="markdown file to write")
    args = parser.parse_args(argv)
    warnings.simplefilter("ignore")
    start = time.perf_counter()
    refines = " | ".join(f"refine={r}: twin, virtual (worst)" for r in REFINES)
    rows = [f"| mesh | vertices | polygons | default / twin (worst) | {refines} |",
            "|---|---:|---:|---|" + "---|" * len(REFINES)]
    for name in BUILDERS:
        V, P, T, sources, exact = case(name)
        measured = [errors(V, P, T, sources, exact, refine) for refine in REFINES]
        default = max((e["default"] / e["twin"]).max() for e in measured)
        cells = " | ".join(f"{100 * e['twin'].mean():.2f}%, {100 * e['virtual'].mean():.2f}% "
                           f"(x{(e['virtual'] / e['twin']).max():.2f})" for e in measured)
        rows.append(f"| {name} | {len(V)} | {len(P)} | x{default:.2f} | {cells} |")
        print(rows[-1], flush=True)
    table = "\n".join(rows) + f"\n\n*{time.perf_counter() - start:.0f} s on the 2-core machine.*\n"
    if args.out:
        args.out.write_text(table)
        print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
