"""PNG pictures of a distance field on a triangle mesh, with isolines.

The mesh is projected orthographically and rasterized with a z-buffer
(:mod:`heatcore.viz.raster`) at :data:`SUPERSAMPLE` times the output resolution:
per pixel, the distance and the light (Lambert plus ambient, normals averaged at
the vertices) are interpolated in the nearest face, colored with a perceptual
colormap (:mod:`heatcore.viz.colormap`), and darkened where the pixel is within
half a line width of an isoline level (:func:`heatcore.contours.isoline_levels`):
the level sets of the piecewise-linear distance, the curves of
:func:`heatcore.isolines`, drawn the same width everywhere. Nearer surfaces
hide farther ones, their isolines and source markers.

matplotlib (imported inside the functions: ``import heatcore`` never loads it)
places the image and draws the colour bar and title.

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

from typing import NamedTuple

import numpy as np

from ..contours import isoline_levels, signed_levels
from ..errors import InvalidMeshError, InvalidOptionError
from .colormap import COLORMAPS, UNREACHABLE_COLOR, colorize, colorize_signed
from .raster import rasterize

#: Light direction in camera coordinates (x right, y up, z towards the viewer).
LIGHT = np.array([-0.3, 0.5, 0.8])
AMBIENT = 0.4
UP_AXES = {"x": 0, "y": 1, "z": 2}
#: Where the picture of the mesh goes in the figure (left, bottom, width, height; fractions).
AXES_BOX = (0.02, 0.06, 0.80, 0.86)
#: Pixels rendered per output pixel, in each direction (antialiasing).
SUPERSAMPLE = 2
#: Isolines: width in points, and color.
LINE_WIDTH_PT = 0.9
LINE_RGB = np.array([0.08, 0.08, 0.08])


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


def _vertex_normals(P, F):
    """Vertex normals from the area-weighted normals of the faces around, each turned towards the viewer
    (``+z``): unit, zero where undefined. Whatever the winding of the faces (inconsistent, inside out,
    an open surface seen from behind), the side of the surface the viewer sees is lit."""
    a, b = P[F[:, 1]] - P[F[:, 0]], P[F[:, 2]] - P[F[:, 0]]
    towards = np.sign(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])
    fn = [(a[:, 1] * b[:, 2] - a[:, 2] * b[:, 1]) * towards, (a[:, 2] * b[:, 0] - a[:, 0] * b[:, 2]) * towards,
          np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])]
    corners = F.T.ravel()  # every face's first corners, then second, then third
    vn = np.stack([np.bincount(corners, np.tile(c, 3), minlength=len(P)) for c in fn], axis=1)
    norm = np.linalg.norm(vn, axis=1, keepdims=True)
    return np.divide(vn, norm, out=np.zeros_like(vn), where=norm > 0)


def _closed_outward(P, F):
    """Whether back faces can be skipped: a closed surface, consistently oriented, faces turned outwards.

    Closed and consistent means every directed edge ``(a, b)`` of a face meets its reverse ``(b, a)``
    in another face: hashed edge keys (splitmix64) summed over the edges with ``a < b`` and over those
    with ``a > b`` are then equal (mod 2^64), and any edge left unmatched makes them differ, except
    with odds of about 2^-64: one pass over the edges, no sort. Outwards: a positive signed volume.
    """
    a, b = F.ravel(), np.roll(F, -1, axis=1).ravel()
    x = (np.minimum(a, b) * len(P) + np.maximum(a, b)).astype(np.uint64) + np.uint64(0x9E3779B97F4A7C15)
    x = (x ^ (x >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    x = (x ^ (x >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    x ^= x >> np.uint64(31)
    forward = a < b
    if x[forward].sum(dtype=np.uint64) != x[~forward].sum(dtype=np.uint64):
        return False
    A, B, C = P[F[:, 0]], P[F[:, 1]], P[F[:, 2]]
    return float(np.einsum("ij,ij->", A, np.cross(B, C))) > 0


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
    signed=False,
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
        Source vertices, marked with a red dot where no nearer surface hides them.
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
    signed : bool, default False
        A signed field: the diverging map (:func:`~heatcore.viz.colormap.colorize_signed`, ``colormap``
        unused; each side to its own extreme), and lines at 0 and ``isolines`` levels on each side
        (:func:`heatcore.contours.signed_levels`).

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
    from matplotlib.colors import ListedColormap, Normalize, TwoSlopeNorm
    from matplotlib.figure import Figure

    if colormap not in COLORMAPS:
        raise InvalidOptionError(f"unknown colormap {colormap!r}; choose one of {sorted(COLORMAPS)}")
    if not (isinstance(isolines, (int, np.integer)) and isolines >= 0):
        raise InvalidOptionError(f"isolines must be a non-negative integer, got {isolines!r}")
    V = np.asarray(V, dtype=float).reshape(-1, 3)
    F = np.asarray(F, dtype=np.int64).reshape(-1, 3)
    d = np.asarray(distance, dtype=float).ravel()
    if not len(V) or (F.size and (F.min() < 0 or F.max() >= len(V))):
        raise InvalidMeshError(f"a picture needs vertices and faces that index them: {len(V)} vertices, "
                               f"face indices {F.min() if F.size else '-'}..{F.max() if F.size else '-'}")
    if len(d) != len(V):
        raise InvalidOptionError(f"one distance per vertex: {len(d)} distances for {len(V)} vertices")
    finite = np.isfinite(d)
    vmax = float((np.abs(d) if signed else d)[finite].max()) if finite.any() else 1.0
    vmax = vmax if vmax > 0 else 1.0
    levels = signed_levels(d, isolines) if signed else isoline_levels(d, isolines)
    low = min(float(d[finite].min()), 0.0) if finite.any() else 0.0  # a signed field: each side to its extreme
    high = max(float(d[finite].max()), 0.0) if finite.any() else 0.0
    paint = (lambda v: colorize_signed(v, vmin=low, vmax=high)) if signed else (lambda v: colorize(v, colormap, vmax=vmax))

    R = camera_rotation(elevation, azimuth, up)
    P = (V - V.mean(axis=0)) @ R.T  # camera coordinates; z towards the viewer
    fig = Figure(figsize=size, dpi=dpi)
    FigureCanvasAgg(fig)
    ax = fig.add_axes(AXES_BOX)
    box = _image_box(P, AXES_BOX[2] * size[0] * dpi, AXES_BOX[3] * size[1] * dpi)
    Q = (P - [box.x0, box.y0, 0.0]) * box.scale  # pixels of the supersampled image
    raster = rasterize(Q, F, box.width, box.height, cull_back=_closed_outward(P, F))
    face = raster.face.flat[raster.pixels]
    seen, index = np.unique(face, return_inverse=True)  # the faces in the picture, and each pixel's
    color = _pixel_colors(Q, F, d, seen, index, raster.barycentric, paint, levels,
                          0.5 * LINE_WIDTH_PT / 72 * dpi * SUPERSAMPLE)
    color *= _shading(P, F, seen, index, raster.barycentric)[:, None]
    image = np.ones((raster.face.size, 3), dtype=np.float32)
    image[raster.pixels] = color
    image = _downsample(image.reshape(raster.face.shape + (3,)), SUPERSAMPLE)
    extent = (box.x0, box.x0 + box.width / box.scale, box.y0, box.y0 + box.height / box.scale)
    ax.imshow(image, extent=extent, origin="lower", interpolation="nearest")
    if sources is not None and len(sources):
        src = _visible_sources(Q, F, raster, np.asarray(sources, dtype=np.int64))
        if src.size:
            ax.scatter(P[src, 0], P[src, 1], s=40, c="#e8141c", edgecolors="white", linewidths=1.0, zorder=5)
    ax.set_xlim(extent[:2])
    ax.set_ylim(extent[2:])
    ax.set_aspect("equal")
    ax.axis("off")

    cax = fig.add_axes([0.84, 0.2, 0.025, 0.6])
    if signed:
        cmap = ListedColormap(colorize_signed(np.linspace(-1, 1, 256), vmin=-1.0, vmax=1.0))
        norm = TwoSlopeNorm(0.0, low if low < 0 else -1e-300, high if high > 0 else 1e-300)
        bar = fig.colorbar(ScalarMappable(norm, cmap), cax=cax)
        bar.set_label("signed geodesic distance")
    else:
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


class _ImageBox(NamedTuple):
    """The supersampled image's placement: pixel ``(0, 0)``'s corner at ``(x0, y0)`` in camera units,
    ``scale`` pixels per unit."""

    x0: float
    y0: float
    scale: float
    width: int
    height: int


def _image_box(P, axes_width, axes_height):
    """The image that fills an axes box of ``axes_width`` x ``axes_height`` output pixels with ``P``."""
    lo, hi = P[:, :2].min(axis=0), P[:, :2].max(axis=0)
    span = max(float((hi - lo).max()), 1e-300)
    lo, hi = lo - 0.04 * span, hi + 0.04 * span
    extent = np.maximum(hi - lo, 1e-3 * span)
    scale = min(axes_width / extent[0], axes_height / extent[1])
    width, height = np.maximum(np.ceil(extent * scale), 1).astype(int) * SUPERSAMPLE
    return _ImageBox(float(lo[0]), float(lo[1]), scale * SUPERSAMPLE, int(width), int(height))


def _shading(P, F, seen, index, barycentric):
    """Per covered pixel, Lambert plus ambient light: ``n . light`` at the vertices (normals turned
    towards the viewer), interpolated in the pixel's face ``seen[index]``."""
    lam = _vertex_normals(P, F) @ (LIGHT / np.linalg.norm(LIGHT))
    lit = np.einsum("ij,ij->i", barycentric, lam[F[seen]][index])
    return AMBIENT + (1 - AMBIENT) * np.clip(lit, 0, 1)


def _pixel_colors(Q, F, d, seen, index, barycentric, paint, levels, half_width):
    """Per covered pixel, its color: the distance interpolated in its face ``seen[index]`` (colored by
    ``paint``), and isolines ``half_width`` pixels either side of each level.

    The distance is linear in each face, so in the image it is linear in each face's projection:
    its gradient there gives every pixel's distance to a level curve in pixels, and the curves are
    drawn the same width everywhere, exactly where the piecewise-linear field crosses each level.
    """
    dc = d[F[seen]]
    reached = np.all(np.isfinite(dc), axis=1)
    dc[~reached] = 0.0
    value = np.einsum("ij,ij->i", barycentric, dc[index])
    value[~reached[index]] = np.inf
    color = paint(value)
    if levels.size:
        slope = _image_slope(Q, F[seen], dc)[index]  # distance per pixel
        above = np.searchsorted(levels, value)  # the levels either side: above - 1 and above
        gap = np.minimum(np.abs(value - levels[np.maximum(above - 1, 0)]),
                         np.abs(value - levels[np.minimum(above, len(levels) - 1)]))
        with np.errstate(divide="ignore", invalid="ignore"):
            alpha = np.clip(half_width + 0.5 - gap / slope, 0.0, 1.0)
        alpha = np.where(np.isfinite(alpha), alpha, 0.0)[:, None]
        color = color * (1 - alpha) + LINE_RGB * alpha
    return color


def _image_slope(Q, F, dc):
    """Per face, the length of the image-plane gradient of the distance ``dc`` (per corner)."""
    xy = Q[F][:, :, :2]
    e1, e2 = xy[:, 1] - xy[:, 0], xy[:, 2] - xy[:, 0]
    d1, d2 = dc[:, 1] - dc[:, 0], dc[:, 2] - dc[:, 0]
    det = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.hypot(d1 * e2[:, 1] - d2 * e1[:, 1], e1[:, 0] * d2 - e2[:, 0] * d1) / np.abs(det)


def _downsample(image, factor):
    """Average ``factor`` x ``factor`` blocks of pixels (the antialiasing of a supersampled image)."""
    total = sum(image[i::factor, j::factor] for i in range(factor) for j in range(factor))
    return total / factor**2


def _visible_sources(Q, F, raster, sources):
    """The sources no nearer surface hides: at the source's pixel or one around it, the nearest face
    is one of the source's own, or the nearest surface there is not in front of it."""
    height, width = raster.face.shape
    sources = sources[(sources >= 0) & (sources < len(Q))]
    sources = sources[np.isin(sources, F)]
    if not sources.size:
        return sources
    col = np.clip(np.floor(Q[sources, 0]).astype(int), 0, width - 1)
    row = np.clip(np.floor(Q[sources, 1]).astype(int), 0, height - 1)
    in_front = raster.depth[row, col] > Q[sources, 2] + 2.0  # nearer by more than two pixels
    own = np.zeros(len(sources), bool)
    for dr in (-1, 0, 1):
        for dc in (-1, 0, 1):
            face = raster.face[np.clip(row + dr, 0, height - 1), np.clip(col + dc, 0, width - 1)]
            own |= (face >= 0) & np.any(F[np.maximum(face, 0)] == sources[:, None], axis=1)
    return sources[own | ~in_front]
