"""A checker decal placed with the log map on spot's flank: heatcore against potpourri3d.

The log map from one flank vertex gives every vertex 2D coordinates; a
checker of squares of one side length, drawn where the radius is below a
limit, shows how evenly each log map spreads the texture (squares of equal
size and right angles mean little distortion). The mesh is split twice at
its edge midpoints with the coordinates interpolated linearly, shaded with
Lambert light and drawn back to front. Run through
``python scripts/bench_vector_heat.py --picture PATH``.
"""

import numpy as np

import heatcore as hc
from heatcore.viz.render import camera_rotation

LIGHT = np.array([-0.3, 0.5, 0.8])
SQUARE = 0.06  # checker square side, in spot's units
DECAL_RADIUS = 0.42


def split(V, F, uv, which=None):
    """One 1-to-4 midpoint subdivision of the faces ``which`` (all by default), carrying values linearly.

    Splitting only some faces leaves cracks at the border of the split region,
    invisible at this size.
    """
    keep = F[~which] if which is not None else F[:0]
    F = F[which] if which is not None else F
    sides = np.sort(np.stack([F[:, [0, 1, 2]], F[:, [1, 2, 0]]], axis=-1).reshape(-1, 2), axis=1)
    edges, index = np.unique(sides, axis=0, return_inverse=True)
    mid = len(V) + index.reshape(-1, 3)
    V2 = np.vstack([V, V[edges].mean(axis=1)])
    uv2 = np.vstack([uv, uv[edges].mean(axis=1)])
    a, b, c = F.T
    ab, bc, ca = mid.T
    F2 = np.concatenate([keep, np.c_[a, ab, ca], np.c_[ab, b, bc], np.c_[ca, bc, c], np.c_[ab, bc, ca]])
    return V2, F2, uv2


def draw(ax, V, F, uv, title):
    """Shaded checker where |uv| < DECAL_RADIUS, plain grey elsewhere, seen from spot's flank."""
    from matplotlib.collections import PolyCollection

    V, F, uv = split(V, F, uv)
    for _ in range(3):  # finer inside the decal, where the checker's edges are
        centre = np.where(np.isfinite(uv), uv, np.inf)[F].mean(axis=1)
        V, F, uv = split(V, F, uv, np.linalg.norm(centre, axis=1) < 1.2 * DECAL_RADIUS)
    R = camera_rotation(8.0, 75.0, "y")
    P = (V - V.mean(axis=0)) @ R.T
    normal = np.cross(P[F[:, 1]] - P[F[:, 0]], P[F[:, 2]] - P[F[:, 0]])
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    front = normal[:, 2] > 0
    shade = 0.4 + 0.6 * np.clip(normal @ (LIGHT / np.linalg.norm(LIGHT)), 0, 1)
    centre = uv[F].mean(axis=1)
    inside = np.isfinite(centre).all(axis=1) & (np.linalg.norm(centre, axis=1) < DECAL_RADIUS)
    cell = np.floor(np.where(np.isfinite(centre), centre, 0.0) / SQUARE).astype(int)
    colour = np.where(((cell[:, 0] + cell[:, 1]) % 2 == 0)[:, None], [0.95, 0.55, 0.1], [0.15, 0.25, 0.6])
    colour = np.where(inside[:, None], colour, [0.78, 0.78, 0.78])
    axis_x = inside & (np.abs(centre[:, 1]) < 0.004) & (centre[:, 0] > 0)
    colour[axis_x] = [0.85, 0.05, 0.05]  # the +x axis of the decal
    rgb = np.clip(colour * shade[:, None], 0, 1)
    order = np.flatnonzero(front)[np.argsort(P[F[front], 2].mean(axis=1))]
    ax.add_collection(PolyCollection(P[F[order]][:, :, :2], facecolors=rgb[order], edgecolors=rgb[order],
                                     linewidths=0.3))
    lo, hi = P[:, :2].min(axis=0), P[:, :2].max(axis=0)
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_aspect("equal")
    ax.axis("off")
    ax.set_title(title, fontsize=10)


def checker_picture(path, mesh_dir=None):
    """Write the two-panel picture (heatcore, potpourri3d) to ``path``."""
    import potpourri3d as pp3d
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    V, F = hc.io.load_demo_mesh()
    V, F = np.asarray(V, float), np.asarray(F, np.int64)
    flank = np.flatnonzero((np.abs(V[:, 1] - 0.1) < 0.08) & (np.abs(V[:, 2] - 0.3) < 0.08))
    source = int(flank[np.argmax(V[flank, 0])])
    up = [0.0, 1.0, 0.0]
    ours = hc.VectorHeatSolver(hc.TriangleMesh(V, F), accuracy="high").log_map(source, reference=up)
    peer = pp3d.MeshVectorHeatSolver(V, F)
    theirs = peer.compute_log_map(source)
    # potpourri3d's log map is in its own frame at the source: turn it so that "up" is +x there too.
    bx, by, _ = peer.get_tangent_frames()
    turn = np.exp(-1j * np.arctan2(np.dot(up, by[source]), np.dot(up, bx[source])))
    z = (theirs[:, 0] + 1j * theirs[:, 1]) * turn
    theirs = np.c_[z.real, z.imag]
    fig = Figure(figsize=(10, 4.6), dpi=150)
    FigureCanvasAgg(fig)
    for k, (uv, title) in enumerate(((ours, "heatcore log map (accuracy='high')"),
                                     (theirs, "potpourri3d 1.4 log map (AffineLocal)"))):
        draw(fig.add_axes([0.01 + 0.5 * k, 0.02, 0.48, 0.88]), V, F, uv, title)
    fig.suptitle(f"a checker decal of {SQUARE:g}-unit squares from spot's vertex {source}, up = +x (red)", fontsize=11)
    fig.savefig(path, facecolor="white")
    print("wrote", path, "source", source)
