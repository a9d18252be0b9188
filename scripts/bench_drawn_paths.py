"""Waypoint paths, straightened edge paths and loops (issue 36) against MMP (gdist), analytic answers and potpourri3d.

Rows (``python scripts/bench_drawn_paths.py``), the inputs of ``tests/test_paths_waypoints.py`` and
``tests/test_paths_straighten.py``:

- waypoint legs on shared meshes (5 random waypoints, closed): largest relative excess of a leg over the
  exact distance; potpourri3d's ``EdgeFlipGeodesicSolver.find_geodesic_path`` per leg;
- jagged edge paths (shortest edge paths for random edge weights) on a jittered plane, over a square hole,
  and on shared meshes: relative excess of the input and of the straightened path over the exact distance
  (the analytic one in the hole's class), the smallest bend side minus pi; potpourri3d's
  ``find_geodesic_path_poly`` on the same edge path;
- jagged loops around a cylinder, off a hyperboloid's waist, around a torus's tube and its hole: relative
  error against the mesh's polygon (the closed geodesic of the polyhedron) and against the smooth circle;
  potpourri3d's ``find_geodesic_loop``.

Needs the test extras (gdist, potpourri3d) and the shared meshes (``HEATCORE_MESHES``).
"""

import itertools
import sys
import time
from pathlib import Path

import numpy as np

import heatcore as hc

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "tests"))

from conftest import exact_distance, load_shared_mesh
from shapes import grid
from test_paths_straighten import (
    bend_sides,
    edge_length,
    holed_grid,
    jagged_path,
    revolve,
    torus,
    zigzag_loop,
)


def polyline_length(points):
    return float(np.linalg.norm(np.diff(points, axis=0), axis=1).sum())


def potpourri(call):
    """potpourri3d's answer, or the reason it gave none."""
    try:
        return call()
    except Exception as exc:  # noqa: BLE001 - any failure of the peer is a table entry
        return f"fails ({type(exc).__name__})"


def fmt(x):
    return x if isinstance(x, str) else f"{x:+.2e}"


def waypoint_rows():
    import potpourri3d as pp3d

    for name in ("spot", "homer", "fandisk", "cheburashka"):
        V, F = load_shared_mesh(name)
        solver = hc.HeatSolver(hc.TriangleMesh(V, F))
        points = np.random.default_rng(0).choice(np.unique(F), 5, replace=False).tolist()
        start = time.perf_counter()
        path = solver.geodesic_path(points=points, closed=True)
        seconds = time.perf_counter() - start
        legs = list(itertools.pairwise(points + points[:1]))
        exact = np.array([exact_distance(V, F, a)[b] for a, b in legs])
        flip = pp3d.EdgeFlipGeodesicSolver(V, F)
        peer = np.array([polyline_length(flip.find_geodesic_path(a, b)) for a, b in legs])
        excess = path.leg_lengths / exact - 1
        print(f"| waypoints {name} | {fmt(excess.max())} (min {fmt(excess.min())}) | {fmt((peer / exact - 1).max())} "
              f"| {seconds:.2f} s |")


def straighten_rows():
    import potpourri3d as pp3d

    cases = []
    V, F = grid(21, 21, jitter=0.3, seed=1)
    cases.append(("plane 21x21", V, F, jagged_path(V, F, 0, 440, spread=5.0), np.linalg.norm(V[440] - V[0])))
    V, F = holed_grid()
    s, t = 6 * 21, 6 * 21 + 20
    column = (V[:, 0] >= 0.4 - 1e-9) & (V[:, 0] <= 0.6 + 1e-9)
    above = jagged_path(V, F, s, t, seed=2, allowed=~(column & (V[:, 1] <= 0.6 + 1e-9)))
    cases.append(("over a hole (its class)", V, F, above, 2 * np.hypot(0.4, 0.3) + 0.2))
    for name in ("spot", "fandisk", "homer", "stanford-bunny", "rocker-arm"):
        V, F = load_shared_mesh(name)
        used = np.unique(F)
        s, t = (int(used[10]), int(used[len(used) // 2])) if name in ("spot", "fandisk", "homer") else \
            (int(used[100]), int(used[len(used) // 3]))
        cases.append((name, V, F, jagged_path(V, F, s, t), exact_distance(V, F, s)[t]))
    for name, V, F, edges, exact in cases:
        start = time.perf_counter()
        path = hc.straighten_path(V, F, edges)
        seconds = time.perf_counter() - start
        sides = bend_sides(hc.TriangleMesh(V, F, refine=0), path)
        bend = f"{sides.min() - np.pi:+.1e}" if sides.size else "no bend"
        peer = potpourri(lambda V=V, F=F, edges=edges, exact=exact: polyline_length(
            pp3d.EdgeFlipGeodesicSolver(V, F).find_geodesic_path_poly(edges)) / exact - 1)
        print(f"| straighten {name} | input {fmt(edge_length(V, edges) / exact - 1)}, result "
              f"{fmt(path.length / exact - 1)}, bend side - pi {bend} | {fmt(peer)} | {seconds:.2f} s |")


def loop_rows():
    import potpourri3d as pp3d

    cases = []
    for sides in (32, 64):
        V, F = revolve(lambda z: 0.7, np.linspace(0, 2, 11), sides)
        cases.append((f"cylinder r 0.7, {sides} sides", V, F, zigzag_loop(sides, 4),
                      2 * sides * 0.7 * np.sin(np.pi / sides), 2 * np.pi * 0.7))
        V, F = revolve(lambda z: np.hypot(0.5, z), np.linspace(-1, 1, 21), sides)
        cases.append((f"hyperboloid waist 0.5, {sides} sides", V, F, zigzag_loop(sides, 13),
                      2 * sides * 0.5 * np.sin(np.pi / sides), np.pi))
    V, F = torus(1.0, 0.3, 48, 32)
    cases.append(("torus tube r 0.3 (48 x 32)", V, F, zigzag_loop(32, 3), 2 * 32 * 0.3 * np.sin(np.pi / 32),
                  2 * np.pi * 0.3))
    edges = []
    for i in range(0, 48, 2):
        edges += [i * 32 + 8, (i + 1) * 32 + 8, (i + 1) * 32 + 9, ((i + 2) % 48) * 32 + 9]
    cases.append(("torus hole: inner equator 0.7", V, F, edges, 2 * 48 * 0.7 * np.sin(np.pi / 48), 2 * np.pi * 0.7))
    for name, V, F, edges, polygon, circle in cases:
        start = time.perf_counter()
        loop = hc.straighten_loop(V, F, edges)
        seconds = time.perf_counter() - start

        def peer_loop(V=V, F=F, edges=edges):
            out = pp3d.EdgeFlipGeodesicSolver(V, F).find_geodesic_loop(edges)
            return polyline_length(np.r_[out, out[:1]])

        peer = potpourri(peer_loop)
        peer_text = peer if isinstance(peer, str) else f"{fmt(peer / polygon - 1)} / {fmt(peer / circle - 1)}"
        print(f"| loop {name} | {fmt(loop.length / polygon - 1)} / {fmt(loop.length / circle - 1)} | {peer_text} "
              f"| {seconds:.2f} s |")


def main():
    print("| case | heatcore (relative to exact; loops: to the mesh's polygon / the circle) | potpourri3d | time |")
    print("|---|---|---|---|")
    waypoint_rows()
    straighten_rows()
    loop_rows()


if __name__ == "__main__":
    main()
