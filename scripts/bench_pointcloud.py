"""Point-cloud accuracy against exact geodesics and potpourri3d's PointCloudHeatSolver.

The points are the vertices of the shared test meshes; the reference is the
exact (MMP, gdist) geodesic distance on the mesh they come from. Each mesh is
run in five scenarios, from three random source points each:

clean
    every vertex.
hole
    30% of the points removed in one patch (the geodesic ball around a random
    vertex); the reference is the exact distance on the mesh without the
    triangles that lost a vertex, so paths must go around the hole.
nonuniform
    points kept with a probability rising linearly from 0.2 to 1 along the
    longest bounding-box axis (a 5x density change); reference: the full mesh.
noise
    Gaussian noise of standard deviation 0.1 h per coordinate (h = mean edge
    length); reference: the clean mesh at the original positions.
heavy noise
    Gaussian noise of 0.5% of the bounding-box diagonal per coordinate
    (issue 22's noisy clouds); reference: the clean mesh.

heatcore (``PointCloud`` with defaults, ``HeatSolver`` with defaults) and
potpourri3d (``PointCloudHeatSolver``, default ``t_coef``) get the same
points and sources in the same process.

Usage::

    python scripts/bench_pointcloud.py --meshes ../shared/meshes --out /tmp/pointcloud.md
    python scripts/bench_pointcloud.py --picture docs/images/pointcloud_spot.png

Needs the ``bench`` extra (gdist, potpourri3d) and matplotlib for the picture.
"""

import argparse
import sys
import time
from pathlib import Path

import numpy as np

import heatcore as hc
from heatcore.domains.pointcloud import PointCloud
from heatcore.reference import exact_distance, mean_relative_error

REPO = Path(__file__).resolve().parents[1]
MESHES = ["spot", "homer", "fandisk", "cheburashka", "rocker-arm", "nefertiti", "stanford-bunny"]
SCENARIOS = ["clean", "hole", "nonuniform", "noise", "heavy noise"]
HOLE_FRACTION = 0.3
NOISE = 0.1  # times the mean edge length
HEAVY_NOISE = 0.005  # times the bounding-box diagonal (issue 22's noisy clouds)


def scenario(V, F, kind, seed=0, n_sources=3):
    """Points, source indices and exact reference distances for one scenario.

    Parameters
    ----------
    V, F : the mesh
    kind : one of ``SCENARIOS``
    seed : int

    Returns
    -------
    P : (n, 3) float array, the cloud
    sources : (s,) int array, indices into ``P``
    exact : list of (n,) float arrays, exact distance from each source (inf: no reference)
    """
    rng = np.random.default_rng(seed)
    used = np.unique(F)
    keep = np.zeros(len(V), dtype=bool)
    keep[used] = True
    ref_F = F
    P_all = V.copy()
    if kind == "hole":
        center = rng.choice(used)
        d = exact_distance(V, F, center)[used]
        removed = used[np.argsort(d)[: int(HOLE_FRACTION * used.size)]]
        keep[removed] = False
        ref_F = F[keep[F].all(axis=1)]
        keep &= np.isin(np.arange(len(V)), ref_F)
    elif kind == "nonuniform":
        axis = np.argmax(np.ptp(V[used], axis=0))
        x = (V[:, axis] - V[used, axis].min()) / np.ptp(V[used, axis])
        keep &= rng.random(len(V)) < 0.2 + 0.8 * x
    elif kind == "noise":
        e = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
        h = np.linalg.norm(V[e[:, 0]] - V[e[:, 1]], axis=1).mean()
        P_all = V + rng.normal(scale=NOISE * h, size=V.shape)
    elif kind == "heavy noise":
        P_all = V + rng.normal(scale=HEAVY_NOISE * np.linalg.norm(np.ptp(V[used], axis=0)), size=V.shape)
    elif kind != "clean":
        raise ValueError(f"unknown scenario {kind!r}")
    idx = np.flatnonzero(keep)
    src = rng.choice(idx.size, n_sources, replace=False)
    exact = [exact_distance(V, ref_F, idx[s])[idx] for s in src]
    return P_all[idx], src, exact


def heatcore_errors(P, sources, exact):
    """Mean relative error of heatcore per source, and build seconds."""
    start = time.perf_counter()
    solver = hc.HeatSolver(PointCloud(P))
    build = time.perf_counter() - start
    return [mean_relative_error(solver.distance([s]), e) for s, e in zip(sources, exact)], build


def potpourri_errors(P, sources, exact):
    """The same for potpourri3d's PointCloudHeatSolver."""
    import potpourri3d as pp3d

    start = time.perf_counter()
    solver = pp3d.PointCloudHeatSolver(P)
    build = time.perf_counter() - start
    return [mean_relative_error(solver.compute_distance(int(s)), e) for s, e in zip(sources, exact)], build


def run(mesh_dir, meshes, scenarios):
    from heatcore.io import read_mesh

    rows = []
    for name in meshes:
        mesh = read_mesh(Path(mesh_dir) / f"{name}.obj")
        V, F = mesh.vertices, mesh.faces
        for kind in scenarios:
            P, sources, exact = scenario(V, F, kind)
            ours, t_ours = heatcore_errors(P, sources, exact)
            peer, t_peer = potpourri_errors(P, sources, exact)
            row = (name, kind, P.shape[0], np.mean(ours), np.mean(peer), t_ours, t_peer)
            rows.append(row)
            print(
                f"{name:15s} {kind:10s} n={P.shape[0]:6d} heatcore {100 * row[3]:.2f}% "
                f"potpourri3d {100 * row[4]:.2f}%  build {t_ours:.2f}s / {t_peer:.2f}s",
                flush=True,
            )
    return rows


def markdown(rows):
    lines = [
        "| mesh | scenario | points | heatcore | potpourri3d | heatcore build (s) | potpourri3d build (s) |",
        "|---|---|---:|---:|---:|---:|---:|",
    ]
    for name, kind, n, ours, peer, t_ours, t_peer in rows:
        lines.append(
            f"| {name} | {kind} | {n:,} | {100 * ours:.2f}% | {100 * peer:.2f}% | {t_ours:.2f} | {t_peer:.2f} |"
        )
    return "\n".join(lines) + "\n"


def picture(mesh_dir, path):
    """Scatter plots of spot as a cloud, colored by distance: all points, and with a 30% hole.

    Orthographic views drawn back to front (matplotlib's 3D scatter does not
    sort points by depth); black points mark isolines.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from heatcore.io import read_mesh

    mesh = read_mesh(Path(mesh_dir) / "spot.obj")
    V, F = mesh.vertices, mesh.faces
    fig, axes = plt.subplots(1, 2, figsize=(12, 6))
    for ax, kind in zip(axes, ["clean", "hole"]):
        P, sources, exact = scenario(V, F, kind)
        d = hc.HeatSolver(PointCloud(P)).distance([sources[0]])
        err = mean_relative_error(d, exact[0])
        if kind == "hole":  # look into the hole: its centre faces the viewer
            used = np.unique(F)
            gone = np.setdiff1d(np.arange(len(used)), _rows_in(V[used], P))
            direction = V[used][gone].mean(axis=0) - V[used].mean(axis=0)
        else:
            direction = V[sources[0]] - V.mean(axis=0)
        azim = np.arctan2(direction[0], direction[2])
        c, s = np.cos(azim), np.sin(azim)
        x = c * P[:, 0] - s * P[:, 2]
        depth = s * P[:, 0] + c * P[:, 2]
        order = np.argsort(depth)
        iso = np.mod(d / d.max() * 15, 1.0) < 0.12
        colors = plt.cm.viridis(d / d.max())
        colors[iso] = (0, 0, 0, 1)
        ax.scatter(x[order], P[order, 1], c=colors[order], s=7, linewidths=0)
        ax.scatter(x[sources[0]], P[sources[0], 1], c="red", s=80, marker="*")
        ax.set_aspect("equal")
        ax.set_axis_off()
        title = "all points" if kind == "clean" else f"{int(100 * HOLE_FRACTION)}% removed in a patch"
        ax.set_title(f"spot as a point cloud, {title}\n{P.shape[0]} points, mean rel. error {100 * err:.1f}%")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    print(f"wrote {path}")


def _rows_in(A, B):
    """Indices of the rows of ``A`` that also occur in ``B`` (exact match)."""
    from scipy.spatial import cKDTree

    dist, _ = cKDTree(B).query(A)
    return np.flatnonzero(dist == 0)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--meshes", default=str(REPO.parent / "shared" / "meshes"))
    parser.add_argument("--only", nargs="*", default=MESHES, help="mesh names")
    parser.add_argument("--scenarios", nargs="*", default=SCENARIOS)
    parser.add_argument("--out", help="write the markdown table here")
    parser.add_argument("--picture", help="write the scatter picture here and stop")
    args = parser.parse_args(argv)
    if args.picture:
        picture(args.meshes, args.picture)
        return 0
    rows = run(args.meshes, args.only, args.scenarios)
    table = markdown(rows)
    print(table)
    if args.out:
        Path(args.out).write_text(table)
    return 0


if __name__ == "__main__":
    sys.exit(main())
