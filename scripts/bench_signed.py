"""Accuracy and time of the signed heat method against analytic signed distances and potpourri3d (docs/signed.md).

Cases (tests/signed_cases.py): a circle of radius 0.55 on a flat unit disc through the points where it
crosses the edges; the same broken into four pieces with gaps of 10% of its length; the equator of a UV
sphere (vertices) and of an icosphere (edge points), whole and broken; another disc's circle of radius
0.4 and a coarser icosphere's circle at z = 0.5, whole and broken; the UV sphere as quads (a polygon
mesh); a Fibonacci sphere cloud with points on its equator and a disc cloud of rings. Errors: mean
absolute error over the vertices relative to the radius (0.55 or 1), and the share of vertices farther than
one gap from the curve whose sign is right. potpourri3d (1.4): ``MeshSignedHeatSolver`` (its edge points for
the curves through edges), ``PolygonMeshHeatSolver.compute_signed_distance`` and
``PointCloudHeatSolver.compute_signed_distance`` (these two put a curve's left on the negative side:
compared negated).

Usage::

    python scripts/bench_signed.py            # prints a markdown table
"""

import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

import potpourri3d as pp3d
import signed_cases as sc

import heatcore as hc

R = 0.55


def _timed(f):
    start = time.perf_counter()
    value = f()
    return value, time.perf_counter() - start


def cases():
    """(name, vertices, ours(), theirs(), exact, scale, gap) per case."""
    V, F = sc.disc()
    r = np.linalg.norm(V[:, :2], axis=1)
    points, gc = sc.level_curve(V, F, r - R, lambda X: np.arctan2(X[:, 1], X[:, 0]))
    exact = R - r
    yield ("disc, circle through edge points", V, lambda: hc.SignedHeatSolver(hc.TriangleMesh(V, F)).distance(
        [sc.closed(points)]), lambda: pp3d.MeshSignedHeatSolver(V, F).compute_distance([sc.closed(gc)]), exact, R, 0.0)
    yield ("disc, the circle broken in 4 (10% gaps)", V, lambda: hc.SignedHeatSolver(hc.TriangleMesh(V, F)).distance(
        sc.broken(points)), lambda: pp3d.MeshSignedHeatSolver(V, F).compute_distance(sc.broken(gc)), exact, R,
        0.1 * 2 * np.pi * R / 4)
    V, F = sc.uv_sphere()
    loop, exact = sc.equator_loop(V), np.arcsin(np.clip(V[:, 2], -1, 1))
    yield ("UV sphere, equator (vertices)", V, lambda: hc.SignedHeatSolver(hc.TriangleMesh(V, F)).distance([loop]),
           lambda: pp3d.MeshSignedHeatSolver(V, F).compute_distance([[(v, []) for v in loop]]), exact, 1.0, 0.0)
    band = (len(F) - 2 * 64) // 2
    polygons = [list(q) for q in np.c_[F[:band], F[band:2 * band, 2]]] + [list(t) for t in F[2 * band:]]
    yield ("UV sphere as quads (PolygonMesh), equator", V,
           lambda: hc.SignedHeatSolver(hc.PolygonMesh(V, polygons)).distance([loop]),
           lambda: -pp3d.PolygonMeshHeatSolver(V, polygons).compute_signed_distance([loop]), exact, 1.0, 0.0)
    V, F = sc.icosphere(4)
    points, gc = sc.level_curve(V, F, V[:, 2] + 1e-7, lambda X: np.arctan2(X[:, 1], X[:, 0]))
    exact = np.arcsin(np.clip(V[:, 2], -1, 1))
    yield ("icosphere, equator through edge points", V, lambda: hc.SignedHeatSolver(hc.TriangleMesh(V, F)).distance(
        [sc.closed(points)]), lambda: pp3d.MeshSignedHeatSolver(V, F).compute_distance([sc.closed(gc)]), exact, 1.0, 0.0)
    yield ("icosphere, the equator broken in 4", V, lambda: hc.SignedHeatSolver(hc.TriangleMesh(V, F)).distance(
        sc.broken(points)), lambda: pp3d.MeshSignedHeatSolver(V, F).compute_distance(sc.broken(gc)), exact, 1.0,
        0.1 * 2 * np.pi / 4)
    V, F = sc.disc(seed=1)
    r = np.linalg.norm(V[:, :2], axis=1)
    points, gc = sc.level_curve(V, F, r - 0.4, lambda X: np.arctan2(X[:, 1], X[:, 0]))
    yield ("another disc (seed 1), circle of radius 0.4", V, lambda: hc.SignedHeatSolver(hc.TriangleMesh(V, F)).distance(
        [sc.closed(points)]), lambda: pp3d.MeshSignedHeatSolver(V, F).compute_distance([sc.closed(gc)]), 0.4 - r, 0.4,
        0.0)
    yield ("another disc, that circle broken in 4", V, lambda: hc.SignedHeatSolver(hc.TriangleMesh(V, F)).distance(
        sc.broken(points)), lambda: pp3d.MeshSignedHeatSolver(V, F).compute_distance(sc.broken(gc)), 0.4 - r, 0.4,
        0.1 * 2 * np.pi * 0.4 / 4)
    V, F = sc.icosphere(3)
    points, gc = sc.level_curve(V, F, V[:, 2] - 0.5 + 1e-7, lambda X: np.arctan2(X[:, 1], X[:, 0]))
    exact = np.arcsin(np.clip(V[:, 2], -1, 1)) - np.arcsin(0.5)
    yield ("coarser icosphere, the circle at z = 0.5", V, lambda: hc.SignedHeatSolver(hc.TriangleMesh(V, F)).distance(
        [sc.closed(points)]), lambda: pp3d.MeshSignedHeatSolver(V, F).compute_distance([sc.closed(gc)]), exact, 1.0,
        0.0)
    yield ("coarser icosphere, that circle broken in 4", V, lambda: hc.SignedHeatSolver(hc.TriangleMesh(V, F)).distance(
        sc.broken(points)), lambda: pp3d.MeshSignedHeatSolver(V, F).compute_distance(sc.broken(gc)), exact, 1.0,
        0.1 * 2 * np.pi * np.sqrt(0.75) / 4)
    P, loop = sc.sphere_cloud()
    exact = np.arcsin(np.clip(P[:, 2], -1, 1))
    yield ("sphere point cloud, equator", P, lambda: hc.SignedHeatSolver(hc.PointCloud(P)).distance([loop]),
           lambda: -pp3d.PointCloudHeatSolver(P).compute_signed_distance([loop], P), exact, 1.0, 0.0)
    P, loop = sc.disc_cloud(R)
    exact = R - np.linalg.norm(P[:, :2], axis=1)
    normals = np.tile([0.0, 0.0, 1.0], (len(P), 1))
    yield ("disc point cloud, circle", P, lambda: hc.SignedHeatSolver(hc.PointCloud(P)).distance([loop]),
           lambda: -pp3d.PointCloudHeatSolver(P).compute_signed_distance([loop], normals), exact, R, 0.0)


def main():
    rows = ["| case | vertices | heatcore error | potpourri3d error | heatcore sign right | heatcore s | potpourri3d s |",
            "|---|---|---|---|---|---|---|"]
    for name, V, ours, theirs, exact, scale, gap in cases():
        mine, t_mine = _timed(ours)
        other, t_other = _timed(theirs)
        far = np.abs(exact) > max(gap, 0.02 * scale)
        sign = np.mean(np.sign(mine[far]) == np.sign(exact[far]))
        e_mine, e_other = np.abs(mine - exact).mean() / scale, np.abs(other - exact).mean() / scale
        mark = "" if e_mine <= e_other else " (worse)"
        rows.append(f"| {name} | {len(V):,} | {100 * e_mine:.3f}%{mark} | {100 * e_other:.3f}% | {100 * sign:.1f}% | "
                    f"{t_mine:.2f} | {t_other:.2f} |")
    print("\n".join(rows))


if __name__ == "__main__":
    main()
