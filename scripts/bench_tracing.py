"""Traced geodesics (heatcore.trace_geodesic) against straight lines, great circles and potpourri3d's GeodesicTracer.

Rows (``python scripts/bench_tracing.py [--picture docs/images/trace.png]``):

- flat grid (21 x 21, jittered): end point against the straight line's end, from points inside faces and from
  vertices, random directions and lengths;
- UV sphere, from the pole along a meridian (through a ring vertex at every step): distance of the trace from the
  meridian plane, and of its end from the point at that arc length on the polyhedron's meridian polygon;
- icosphere in its mirror plane z = 0 (along edges and through vertices): distance from the plane;
- icosphere, random starts and directions: distance between the two tracers' end points (both trace the
  polyhedron's straightest geodesic, which off the mirror planes leaves the great circle by O(h));
- time per trace on spot (length 1, random face points and directions).
"""

import argparse
import sys
import time
from pathlib import Path

import numpy as np

import heatcore as hc

REPO = Path(__file__).resolve().parents[1]


def uv_sphere(n_lat, n_lon):
    """Unit UV sphere: poles and ``n_lat - 1`` rings of ``n_lon`` vertices, each planar ring quad two triangles."""
    sys.path.insert(0, str(REPO / "tests"))
    from test_tracing import uv_sphere as build

    return build(n_lat, n_lon)


def icosphere(level):
    import trimesh

    sphere = trimesh.creation.icosphere(subdivisions=level)
    return np.asarray(sphere.vertices), np.asarray(sphere.faces)


def flat_rows(pp3d, n=200):
    sys.path.insert(0, str(REPO / "tests"))
    from shapes import grid

    V, F = grid(21, 21, jitter=0.3)
    tracer, rng = pp3d.GeodesicTracer(V, F), np.random.default_rng(0)
    inner = np.flatnonzero(np.linalg.norm(V[F].mean(1) - [0.5, 0.5, 0], axis=1) < 0.15)
    ours, theirs = [], []
    for _ in range(n):
        f, bary = int(rng.choice(inner)), rng.dirichlet([1, 1, 1])
        a, length = rng.uniform(0, 2 * np.pi), rng.uniform(0.05, 0.3)
        d = np.array([np.cos(a), np.sin(a), 0.0])
        for start, ends in (((f, bary), bary @ V[F[f]]), (int(F[f, 0]), V[F[f, 0]])):
            exact = ends + length * d
            ours.append(np.linalg.norm(hc.trace_geodesic(V, F, start, d, length).points[-1] - exact))
            q = tracer.trace_geodesic_from_face(f, bary, length * d) if isinstance(start, tuple) else \
                tracer.trace_geodesic_from_vertex(start, length * d)
            theirs.append(np.linalg.norm(q[-1] - exact))
    return ("flat grid 21x21 jittered: end point vs the straight line", 2 * n, max(ours), max(theirs))


def meridian_rows(pp3d):
    rows = []
    for n_lat in (16, 64):
        V, F = uv_sphere(n_lat, 2 * n_lat)
        tracer = pp3d.GeodesicTracer(V, F)
        perimeter = 2 * n_lat * 2 * np.sin(np.pi / n_lat / 2)
        ours, theirs = [], []
        for length in (1.0, 0.5 * perimeter, 1.5 * perimeter):
            ours.append(np.abs(hc.trace_geodesic(V, F, 0, [1.0, 0, 0], length).points[:, 1]).max() / length)
            theirs.append(np.abs(tracer.trace_geodesic_from_vertex(0, [length, 0, 0])[:, 1]).max() / length)
        rows.append((f"UV sphere {n_lat}x{2 * n_lat}, meridian from the pole: off the plane / length", 3, max(ours),
                     max(theirs)))
    return rows


def mirror_rows(pp3d):
    rows = []
    for level in (2, 4):
        V, F = icosphere(level)
        on = np.flatnonzero(np.abs(V[:, 2]) < 1e-12)
        edges = np.r_[F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]
        v, w = (int(x) for x in edges[np.isin(edges, on).all(axis=1)][0])
        d = (V[w] - V[v]) / np.linalg.norm(V[w] - V[v])
        tracer = pp3d.GeodesicTracer(V, F)
        ours = [np.abs(hc.trace_geodesic(V, F, v, d, L).points[:, 2]).max() / L for L in (1.0, 7.0, 50.0)]
        theirs = [np.abs(tracer.trace_geodesic_from_vertex(v, L * d)[:, 2]).max() / L for L in (1.0, 7.0, 50.0)]
        rows.append((f"icosphere level {level} ({len(V)} v), mirror plane: off the plane / length", 3, max(ours),
                     max(theirs)))
    return rows


def generic_row(pp3d, n=50):
    V, F = icosphere(4)
    tracer, rng = pp3d.GeodesicTracer(V, F), np.random.default_rng(1)
    apart = []
    for _ in range(n):
        f, bary, d = int(rng.integers(len(F))), rng.dirichlet([1, 1, 1]), rng.normal(size=3)
        normal = np.cross(V[F[f, 1]] - V[F[f, 0]], V[F[f, 2]] - V[F[f, 0]])
        d -= (d @ normal) / (normal @ normal) * normal
        d /= np.linalg.norm(d)
        ours = hc.trace_geodesic(V, F, (f, bary), d, np.pi).points[-1]
        apart.append(np.linalg.norm(ours - tracer.trace_geodesic_from_face(f, bary, np.pi * d)[-1]))
    return ("icosphere level 4, random face starts, length pi: heatcore vs potpourri3d end", n, max(apart), None)


def timing_row(pp3d, n=200):
    V, F = hc.io.load_demo_mesh()
    mesh, tracer, rng = hc.TriangleMesh(V, F, refine=0), pp3d.GeodesicTracer(V, F), np.random.default_rng(2)
    starts = [(int(rng.integers(len(F))), rng.dirichlet([1, 1, 1]), rng.normal(size=3)) for _ in range(n)]
    from heatcore.paths.tracing import trace

    t0 = time.perf_counter()
    for f, bary, d in starts:
        trace(mesh, (f, bary), d, 1.0)
    ours = (time.perf_counter() - t0) / n
    t0 = time.perf_counter()
    for f, bary, d in starts:
        tracer.trace_geodesic_from_face(f, bary, d / np.linalg.norm(d))
    return ours, (time.perf_counter() - t0) / n


def picture(path, pp3d):
    """Left: a great circle traced 8 times around a coarse icosphere. Right: a fan of traces on spot."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from heatcore.viz.render import camera_rotation

    fig = Figure(figsize=(10, 5), dpi=150)
    V, F = icosphere(2)
    on = np.flatnonzero(np.abs(V[:, 2]) < 1e-12)
    edges = np.r_[F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]
    v, w = (int(x) for x in edges[np.isin(edges, on).all(axis=1)][0])
    d = (V[w] - V[v]) / np.linalg.norm(V[w] - V[v])
    ours = hc.trace_geodesic(V, F, v, d, 50.0).points
    theirs = pp3d.GeodesicTracer(V, F).trace_geodesic_from_vertex(v, 50.0 * d)
    ax = fig.add_axes([0.0, 0.0, 0.5, 0.88])
    draw(ax, V, F, camera_rotation(35.0, 20.0, "z"), [(theirs, (0.15, 0.35, 0.95), 1.0), (ours, (0.9, 0.1, 0.1), 2.0)])
    ax.set_title("icosphere (162 v), 8 times around the great circle z = 0:\nheatcore (red) stays on it, "
                 f"potpourri3d (blue) drifts {np.abs(theirs[:, 2]).max():.2f} off", fontsize=8)
    V, F = hc.io.load_demo_mesh()
    solver = hc.HeatSolver(hc.TriangleMesh(V, F, refine=0))
    start = 1453
    fan = [solver.trace(start, [np.cos(a), np.sin(a)], 1.2).points for a in np.arange(16) * np.pi / 8]
    ax = fig.add_axes([0.5, 0.0, 0.5, 0.88])
    draw(ax, V, F, camera_rotation(12.0, 205.0, "y"), [(p, (0.9, 0.1, 0.1), 1.5) for p in fan])
    ax.set_title(f"spot: 16 traces of length 1.2 from vertex {start},\nevery 22.5 degrees in its tangent basis",
                 fontsize=8)
    FigureCanvasAgg(fig).print_png(str(path))


def draw(ax, V, F, R, paths):
    """Shaded faces back to front, with the paths' segments in the same depth order (as bench_paths draws)."""
    from matplotlib.collections import PolyCollection

    P = (V - V.mean(0)) @ R.T
    fn = np.cross(P[F[:, 1]] - P[F[:, 0]], P[F[:, 2]] - P[F[:, 0]])
    fn /= np.linalg.norm(fn, axis=1, keepdims=True)
    light = np.array([-0.3, 0.5, 0.8]) / np.linalg.norm([-0.3, 0.5, 0.8])
    rgb = np.outer(0.45 + 0.55 * np.clip(fn @ light, 0, 1), [0.93, 0.9, 0.85])
    items = [(P[F[f], 2].mean(), P[F[f]][:, :2], tuple(rgb[f]), tuple(rgb[f] * 0.9), 0.3)
             for f in np.flatnonzero(fn[:, 2] > 0)]
    lift = 0.008 * np.ptp(P[:, 1])
    for points, color, width in paths:
        Q = (points - V.mean(0)) @ R.T
        items += [(max(Q[i, 2], Q[i + 1, 2]) + lift, Q[i:i + 2, :2], (0, 0, 0, 0), color, width)
                  for i in range(len(Q) - 1)]
    items.sort(key=lambda item: item[0])
    ax.add_collection(PolyCollection([i[1] for i in items], facecolors=[i[2] for i in items],
                                     edgecolors=[i[3] for i in items], linewidths=[i[4] for i in items], closed=False))
    ax.set_xlim(P[:, 0].min() - 0.02, P[:, 0].max() + 0.02)
    ax.set_ylim(P[:, 1].min() - 0.02, P[:, 1].max() + 0.02)
    ax.set_aspect("equal")
    ax.axis("off")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--picture", type=Path)
    args = parser.parse_args()
    import potpourri3d as pp3d

    rows = [flat_rows(pp3d), *meridian_rows(pp3d), *mirror_rows(pp3d), generic_row(pp3d)]
    print("| check | traces | heatcore max error | potpourri3d max error |\n|---|---|---|---|")
    for name, n, ours, theirs in rows:
        print(f"| {name} | {n} | {ours:.1e} | {'-' if theirs is None else f'{theirs:.1e}'} |")
    ours, theirs = timing_row(pp3d)
    print(f"\nspot, length 1: heatcore {1000 * ours:.2f} ms per trace, potpourri3d {1000 * theirs:.3f} ms")
    if args.picture:
        picture(args.picture, pp3d)


if __name__ == "__main__":
    main()
