"""PNG pictures of a distance field on a triangle mesh, with isolines (matplotlib).

The mesh is projected orthographically, shaded (Lambert plus ambient light,
normals averaged at the vertices), colored by distance with a perceptual
colormap (:mod:`heatcore.viz.colormap`) and drawn back to front (painter's
algorithm). Isolines are the curves of :func:`heatcore.isolines` on the input
mesh (exact level sets of the piecewise-linear distance, at the levels of
:func:`heatcore.contours.isoline_levels`), projected with the same camera and
drawn segment by segment in the same back-to-front pass, so that nearer
surfaces hide them.

matplotlib is imported inside the functions: ``import heatcore`` never
loads it.

Examples
--------
>>> import numpy as np, tempfile, os
>>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
>>> F = np.array([[0, 1, 2], [1, 3, 2]])
>>> tmp = tempfile.TemporaryDirectory()
>>> path = os.path.join(tmp.name, "d.png")
>>> render_distance(path, V, F, np.linalg.norm(V, axis=1), sources=[0], isolines=4)
>>> os.path.getsize(path) > 0
True
>>> tmp.cleanup()
"""

import numpy as np

from ..contours import isoline_levels
from ..contours import isolines as isoline_curves
from ..errors import InvalidOptionError
from .colormap import COLORMAPS, UNREACHABLE_COLOR, colorize

#: Light direction in camera coordinates (x right, y up, z towards the viewer).
LIGHT = np.array([-0.3, 0.5, 0.8])
AMBIENT = 0.4
UP_AXES = {"x": 0, "y": 1, "z": 2}
#: Meshes with fewer faces than this are midpoint-subdivided once for smoother shading.
SMOOTH_BELOW_FACES = 40000


def camera_rotation(elevation, azimuth, up="y"):
    """World-to-camera rotation: rows are the camera's right, up and towards-viewer axes.

    Parameters
    ----------
    elevation, azimuth : float
        Degrees. Azimuth turns the camera about the ``up`` axis, starting in
        front of the ``+`` direction of the axis after ``up`` (``z`` for
        ``y``-up); elevation lifts it towards ``up``.
    up : {"x", "y", "z"}

    Returns
    -------
    (3, 3) float array

    Examples
    --------
    >>> camera_rotation(0, 0).round(6).tolist()   # y up, looking at the mesh from +z
    [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    """
    if up not in UP_AXES:
        raise InvalidOptionError(f"up axis must be one of {sorted(UP_AXES)}, got {up!r}")
    k = UP_AXES[up]
    u = np.eye(3)[k]
    f0 = np.eye(3)[(k + 1) % 3]  # default viewing side
    r0 = np.cross(u, f0)
    el, az = np.radians(elevation), np.radians(azimuth)
    horizontal = np.cos(az) * f0 + np.sin(az) * r0
    towards = np.cos(el) * horizontal + np.sin(el) * u
    right = np.cross(u, towards)
    right /= np.linalg.norm(right)
    up_cam = np.cross(towards, right)
    return np.stack([right, up_cam, towards])


def _vertex_normals(V, F):
    fn = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])  # area-weighted
    vn = np.zeros_like(V)
    for c in range(3):
        np.add.at(vn, F[:, c], fn)
    norm = np.linalg.norm(vn, axis=1, keepdims=True)
    return np.divide(vn, norm, out=np.zeros_like(vn), where=norm > 0), fn


def _is_closed(F):
    e = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    _, counts = np.unique(e, axis=0, return_counts=True)
    return bool(np.all(counts == 2))


def _smooth(V, F, d):
    """One level of midpoint subdivision, distances interpolated linearly (rendering only)."""
    from ..domains.refine import midpoint_subdivide

    sub = midpoint_subdivide(V, F, levels=1)
    n = len(V)
    dd = np.empty(len(sub.vertices))
    dd[:n] = d
    ends = sub.edges[sub.vertex_edge[n:]]
    with np.errstate(invalid="ignore"):
        dd[n:] = 0.5 * (d[ends[:, 0]] + d[ends[:, 1]])
    return sub.vertices, sub.faces, dd


def render_distance(
    path,
    V,
    F,
    distance,
    *,
    sources=None,
    colormap="viridis",
    isolines=12,
    elevation=15.0,
    azimuth=30.0,
    up="y",
    title=None,
    size=(8.0, 6.0),
    dpi=150,
):
    """Write a PNG of a triangle mesh colored by distance, with isolines.

    Parameters
    ----------
    path : str or path-like
        Output file (PNG; another extension picks matplotlib's format for it).
    V : (n, 3) float array
    F : (m, 3) int array
    distance : (n,) float array, ``inf`` where unreachable (drawn gray)
    sources : sequence of int, optional
        Source vertices, marked with a red dot where visible.
    colormap : str
        A colormap of :mod:`heatcore.viz.colormap`.
    isolines : int
        Isolines at ``max * j / (isolines + 1)``, ``j = 1..isolines`` (0: none): the curves of
        :func:`heatcore.isolines` (:func:`heatcore.contours.isoline_levels`).
    elevation, azimuth : float
        Camera angles in degrees (see :func:`camera_rotation`).
    up : {"x", "y", "z"}
        The mesh's up axis.
    title : str, optional
    size : (float, float)
        Figure size in inches.
    dpi : int

    Examples
    --------
    >>> import tempfile, os
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    >>> tmp = tempfile.TemporaryDirectory()
    >>> path = os.path.join(tmp.name, "tiny.png")
    >>> render_distance(path, V, [[0, 1, 2]], [0.0, 1.0, 1.0], isolines=0, size=(1, 1), dpi=20)
    >>> os.path.getsize(path) > 0
    True
    >>> tmp.cleanup()
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.cm import ScalarMappable
    from matplotlib.collections import PolyCollection
    from matplotlib.colors import ListedColormap, Normalize
    from matplotlib.figure import Figure

    if colormap not in COLORMAPS:
        raise InvalidOptionError(f"unknown colormap {colormap!r}; choose one of {sorted(COLORMAPS)}")
    if not (isinstance(isolines, (int, np.integer)) and isolines >= 0):
        raise InvalidOptionError(f"isolines must be a non-negative integer, got {isolines!r}")
    V = np.asarray(V, dtype=float)
    F = np.asarray(F, dtype=np.int64)
    d = np.asarray(distance, dtype=float)
    finite = np.isfinite(d)
    vmax = float(d[finite].max()) if finite.any() else 1.0
    vmax = vmax if vmax > 0 else 1.0

    closed = _is_closed(F)
    R = camera_rotation(elevation, azimuth, up)
    center = V.mean(axis=0)
    levels = isoline_levels(d, isolines)
    curves = isoline_curves(V, F, d, levels) if levels.size else []
    P0, F0 = (V - center) @ R.T, F  # the input mesh in camera coordinates: the curves' faces
    if len(F) < SMOOTH_BELOW_FACES:
        V, F, d = _smooth(V, F, d)
    P = (V - center) @ R.T  # camera coordinates; z towards the viewer
    vn, fn = _vertex_normals(P, F)

    # Shading: Lambert with normals averaged at the vertices, then per face.
    light = LIGHT / np.linalg.norm(LIGHT)
    facing = fn[:, 2] > 0
    lam = vn @ light
    if not closed:  # open surfaces: light both sides
        lam = np.abs(lam)
    shade = AMBIENT + (1 - AMBIENT) * np.clip(lam, 0, 1)
    face_shade = shade[F].mean(axis=1)
    rgb = colorize(d, colormap, vmax=vmax)
    face_rgb = np.clip(rgb[F].mean(axis=1) * face_shade[:, None], 0, 1)
    keep = facing if closed else np.ones(len(F), bool)

    depth = P[F, 2].mean(axis=1)
    polys = P[F[:, [0, 1, 2, 0]]][:, :, :2]  # closed outline: the stroke covers every side
    items_poly = list(polys[keep])
    items_depth = list(depth[keep])
    face_colors = list(face_rgb[keep])
    edge_colors = list(face_rgb[keep])
    widths = [0.5] * int(keep.sum())

    if curves:
        # Each segment of a curve lies in one input face: drawn where that face faces the viewer,
        # lifted above the face's nearest corner so that the strokes of neighboring faces do not
        # cover it (a nearer surface still does).
        segs, owner = _curve_segments(curves, R, center)
        facing0 = np.cross(P0[F0[:, 1]] - P0[F0[:, 0]], P0[F0[:, 2]] - P0[F0[:, 0]])[:, 2] > 0
        visible = facing0[owner] if closed else np.ones(len(owner), bool)
        segs, owner = segs[visible], owner[visible]
        bias = 0.25 * np.linalg.norm(P[F[:, 1]] - P[F[:, 0]], axis=1).mean()
        items_poly += list(segs[:, :, :2])
        items_depth += list(P0[F0[owner], 2].max(axis=1) + bias)
        line_rgb = (0.08, 0.08, 0.08)
        face_colors += [(0, 0, 0, 0)] * len(segs)
        edge_colors += [line_rgb] * len(segs)
        widths += [0.9] * len(segs)

    order = np.argsort(np.asarray(items_depth), kind="stable")  # far to near
    fig = Figure(figsize=size, dpi=dpi)
    FigureCanvasAgg(fig)
    ax = fig.add_axes([0.02, 0.06, 0.80, 0.86])
    coll = PolyCollection(
        [items_poly[i] for i in order],
        facecolors=[face_colors[i] for i in order],
        edgecolors=[edge_colors[i] for i in order],
        linewidths=[widths[i] for i in order],
        closed=False,
        antialiased=True,
        capstyle="round",  # consecutive segments of a curve join without notches
        joinstyle="round",
    )
    ax.add_collection(coll)
    if sources is not None and len(sources):
        # Source markers: in front of everything, only where the source's faces face the viewer.
        src = np.asarray(sources, dtype=np.int64)
        seen = np.zeros(len(P), bool)
        seen[F[keep].ravel()] = True
        src = src[(src < len(P)) & seen[np.clip(src, 0, len(P) - 1)]]
        if src.size:
            ax.scatter(P[src, 0], P[src, 1], s=40, c="#e8141c", edgecolors="white", linewidths=1.0, zorder=5)
    lo, hi = P[:, :2].min(axis=0), P[:, :2].max(axis=0)
    pad = 0.04 * (hi - lo).max()
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal")
    ax.axis("off")

    cax = fig.add_axes([0.84, 0.2, 0.025, 0.6])
    cmap = ListedColormap(colorize(np.linspace(0, 1, 256), colormap, vmax=1.0))
    bar = fig.colorbar(ScalarMappable(Normalize(0, vmax), cmap), cax=cax)
    bar.set_label("geodesic distance")
    for level in levels:
        bar.ax.axhline(level, color="0.08", linewidth=0.8)
    if not finite.all():
        fig.text(0.84, 0.14, "gray: unreachable", fontsize=8, color=UNREACHABLE_COLOR)
    if title:
        fig.suptitle(title, fontsize=12)
    fig.savefig(path, dpi=dpi, facecolor="white")


def _curve_segments(curves, R, center):
    """The segments of :class:`~heatcore.Isoline` curves in camera coordinates ``(s, 2, 3)``, and the
    input face each lies in."""
    starts = [c.points if c.closed else c.points[:-1] for c in curves]
    ends = [np.roll(c.points, -1, axis=0) if c.closed else c.points[1:] for c in curves]
    segs = np.stack([np.concatenate(starts), np.concatenate(ends)], axis=1)
    return (segs - center) @ R.T, np.concatenate([c.faces for c in curves])
