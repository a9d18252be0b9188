"""Log map angles on the icosphere: against the longitude and against the polyhedron's own exact geodesics.

On the icosphere of 10,242 vertices (``trimesh.creation.icosphere(5)``), source
vertex 0, the angle of the log map (heatcore ``VectorHeatSolver`` with
``m`` = 1, 1.5, 2, 4, on the mesh as given, ``refine=0``, and with the default
refinement; potpourri3d 1.4 ``MeshVectorHeatSolver(V, F).compute_log_map``) is
compared with two references, each after the best single rotation (the
circular mean of the differences over the near hemisphere, great-circle
distance below π/2, as in ``scripts/bench_vector_heat.py``):

longitude
    the direction of the great circle on the smooth sphere: the angle of each
    vertex around the source's axis.
exact
    the initial direction of the exact shortest path on the polyhedron:
    potpourri3d's ``EdgeFlipGeodesicSolver.find_geodesic_path(0, j)``, its
    first segment, as an angle in the source's intrinsic frame (the corner it
    leaves through, its angle from that corner's first side, scaled by
    ``2π/Θ``: the angle-scaled directions both log maps use). Each path's
    length is checked against MMP (gdist): a path longer than the exact
    distance by more than 1e-12 (relative) is only locally shortest (about
    a fifth are, most beyond π/2), and is left out and counted. The
    projection of the segment on the tangent plane of heatcore's vertex
    normal, against its ``e1``, is printed too (as ``projected``).

The antipode (``|distance - π| < 1e-6``: one vertex, whose direction is
arbitrary) is left out everywhere. Errors are over every other vertex and over
the vertices closer than 0.9π. Prints a markdown table.

Usage::

    python scripts/vector_heat_sphere.py                 # every target (about a minute of paths)
    python scripts/vector_heat_sphere.py --sample 1000    # 1,000 random targets, seed 0

Needs potpourri3d, gdist and trimesh (the ``bench`` extra).
"""

import argparse
import time

import numpy as np

import heatcore as hc
from heatcore.reference import exact_directions


def wrap(a):
    """Angles wrapped to ``(-π, π]``."""
    return np.angle(np.exp(1j * a))


def fitted_error(angle, reference, fit):
    """``|angle - reference|`` (wrapped) after the constant turn that fits best on ``fit`` (circular mean)."""
    d = wrap(angle - reference)
    return np.abs(wrap(d - np.angle(np.mean(np.exp(1j * d[fit])))))


def projected_angles(d, normal, e1):
    """Angle of each direction projected on the plane of ``normal``, from ``e1``."""
    return np.arctan2(d @ np.cross(normal, e1), d @ e1)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--subdivisions", type=int, default=5)
    parser.add_argument("--sample", type=int, default=0, help="random targets (seed 0); 0: every vertex")
    args = parser.parse_args()
    import potpourri3d as pp3d
    import trimesh

    sphere = trimesh.creation.icosphere(subdivisions=args.subdivisions)
    V, F = np.asarray(sphere.vertices, dtype=float), np.asarray(sphere.faces, dtype=np.int64)
    source = 0
    p = V[source]
    great = np.arccos(np.clip(V @ p, -1.0, 1.0))
    antipode = np.abs(great - np.pi) < 1e-6
    keep = (great > 0) & ~antipode
    print(f"{len(V):,} vertices; source {source}; left out: the source and {antipode.sum()} antipode vertex(es)")
    e1 = np.cross(p, [0.3, 0.5, 0.8])
    e1 /= np.linalg.norm(e1)
    longitude = np.arctan2(V @ np.cross(p, e1), V @ e1)

    targets = np.flatnonzero(keep)
    if args.sample:
        targets = np.sort(np.random.default_rng(0).choice(targets, args.sample, replace=False))
    start = time.perf_counter()
    found = exact_directions(V, F, source, targets)
    print(f"{len(targets):,} edge-flip paths in {time.perf_counter() - start:.0f} s")
    d, length, exact_d, shortest, exact = found.direction, found.length, found.distance, found.shortest, found.angle
    good = shortest & np.isfinite(exact)
    print(f"paths longer than MMP's distance (left out): {(~shortest).sum()}; "
          f"max |length / MMP - 1| of the rest: {np.abs(length[shortest] / exact_d[shortest] - 1).max():.1e}; "
          f"no corner found: {np.isnan(exact).sum()}")
    t, exact = targets[good], exact[good]
    t_near, t_far = great[t] < np.pi / 2, great[t] < 0.9 * np.pi

    near, within = keep & (great < np.pi / 2), keep & (great < 0.9 * np.pi)
    apart = fitted_error(exact, longitude[t], t_near)
    print(f"exact polyhedral direction against the longitude (best rotation): mean {apart.mean():.5f} rad, "
          f"median {np.median(apart):.5f}, within 0.9π {apart[t_far].mean():.5f}, "
          f"within π/4 {apart[great[t] < np.pi / 4].mean():.5f}")

    maps = {}
    for refine, label in ((0, "0"), ("auto", "auto (default)")):
        domain = hc.TriangleMesh(V, F, refine=refine)
        for m in (1.0, 1.5, 2.0, 4.0):
            solver = hc.VectorHeatSolver(domain, m=m)
            name = f"heatcore m={m:g}{' (default)' if m == 1 else ''}, refine={label}"
            maps[name] = solver.log_map(source)
            if refine == 0 and m == 1:
                normal, b1, _ = (x[source] for x in solver.tangent_basis())
    maps["potpourri3d 1.4"] = pp3d.MeshVectorHeatSolver(V, F).compute_log_map(source)
    pair = (maps["potpourri3d 1.4"], maps["heatcore m=1 (default), refine=0"])
    same = [np.arctan2(L[keep, 1], L[keep, 0]) for L in pair]
    print(f"heatcore m=1 refine=0 against potpourri3d, max angle difference after the best rotation: "
          f"{fitted_error(same[0], same[1], near[keep]).max():.1e} rad")
    projected = projected_angles(d[good], normal, b1)
    gap = fitted_error(projected, exact, t_near)
    print(f"projected against intrinsic exact directions (best rotation): "
          f"mean {gap.mean():.6f} rad, max {gap.max():.6f}")

    print()
    print("| log map | vs longitude, mean (all but source and antipode) | vs longitude, mean (< 0.9π) "
          "| vs exact, mean | vs exact, median | vs exact, mean (< 0.9π) | vs projected exact, mean |")
    print("|---|---|---|---|---|---|---|")
    for name, L in maps.items():
        a = np.arctan2(L[:, 1], L[:, 0])
        lon = fitted_error(a[keep], longitude[keep], near[keep])
        lon_far = lon[within[keep]]
        ex = fitted_error(a[t], exact, t_near)
        pr = fitted_error(a[t], projected, t_near)
        print(f"| {name} | {lon.mean():.5f} | {lon_far.mean():.5f} | {ex.mean():.5f} | {np.median(ex):.5f} "
              f"| {ex[t_far].mean():.5f} | {pr.mean():.5f} |")
    print(f"\n(angles in rad; exact directions over {len(t):,} targets"
          f"{' (a random sample)' if args.sample else ''}; rotation fitted on the near hemisphere)")


if __name__ == "__main__":
    main()
