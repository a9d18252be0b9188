"""A z-buffer rasterizer for triangle meshes, in vectorized numpy.

:func:`rasterize` finds, for every pixel centre of an orthographic image, the
nearest triangle covering it and the pixel's barycentric coordinates in that
triangle: all a picture needs to interpolate colors, normals and distances per
pixel, with hidden surfaces removed exactly (unlike drawing faces back to front,
whose order is only right face by face). It works on all faces at once: each
face's bounding box of pixel centres becomes candidate pixels (``np.repeat``),
the candidates inside the face are kept, and the nearest per pixel wins
(``np.maximum.at`` on a depth buffer). Faces are taken in batches so that
memory stays bounded (about 100 bytes per candidate pixel of a batch); faces whose
boxes have the same size are drawn together, as one broadcast.

Examples
--------
>>> import numpy as np
>>> P = np.array([[0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [0.0, 4.0, 0.0],   # far triangle
...               [0.0, 0.0, 1.0], [2.0, 0.0, 1.0], [0.0, 2.0, 1.0]])  # a nearer, smaller one
>>> raster = rasterize(P, np.array([[0, 1, 2], [3, 4, 5]]), 4, 4)
>>> raster.face[::-1].tolist()          # rows from the top; -1: no face
[[0, -1, -1, -1], [0, 0, -1, -1], [1, 0, 0, -1], [1, 1, 0, 0]]
"""

from dataclasses import dataclass

import numpy as np

__all__ = ["Raster", "rasterize"]

#: Candidate pixels per batch of faces (about 100 bytes each while a batch is resolved).
BATCH_CANDIDATES = 2_000_000


@dataclass
class Raster:
    """What :func:`rasterize` found per pixel.

    Attributes
    ----------
    face : (height, width) int array
        The nearest face covering the pixel's centre, -1 where none does. Row 0 is
        the bottom of the image (``y`` up).
    pixels : (k,) int array
        The covered pixels, as indices into ``face.ravel()``.
    barycentric : (k, 3) float array
        Each covered pixel centre's barycentric coordinates in its face.
    depth : (height, width) float array
        The ``z`` of the surface at the pixel centre (``-inf`` where no face).

    Examples
    --------
    >>> P = np.array([[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]])
    >>> r = rasterize(P, np.array([[0, 1, 2]]), 2, 2)
    >>> r.pixels.tolist(), r.barycentric[0].tolist(), float(r.depth[0, 0])
    ([0, 1, 2], [0.5, 0.25, 0.25], 0.0)
    """

    face: np.ndarray
    pixels: np.ndarray
    barycentric: np.ndarray
    depth: np.ndarray


def rasterize(P, F, width, height, cull_back=False):
    """The nearest face and barycentric coordinates at every pixel centre.

    Parameters
    ----------
    P : (n, 3) float array
        Vertex positions in pixel units: ``x`` from 0 (left edge) to ``width``,
        ``y`` from 0 (bottom edge) to ``height``, ``z`` towards the viewer
        (larger is nearer). Pixel ``(row, column)`` has its centre at
        ``(column + 0.5, row + 0.5)``.
    F : (m, 3) int array
    width, height : int
        Image size in pixels.
    cull_back : bool
        Skip faces whose projection is clockwise (facing away from the viewer,
        for a closed surface with outward counter-clockwise faces).

    Returns
    -------
    Raster

    Examples
    --------
    >>> P = np.array([[0.0, 0.0, 0.0], [0.0, 2.0, 0.0], [2.0, 0.0, 0.0]])  # clockwise
    >>> int((rasterize(P, np.array([[0, 1, 2]]), 2, 2).face >= 0).sum())
    3
    >>> int((rasterize(P, np.array([[0, 1, 2]]), 2, 2, cull_back=True).face >= 0).sum())
    0
    """
    P = np.asarray(P, dtype=float)
    F = np.asarray(F, dtype=np.int64).reshape(-1, 3)
    depth = np.full(width * height, -np.inf)
    owner = np.full(width * height, -1, dtype=np.int64)
    faces, x0, y0, w, h = _pixel_boxes(P, F, width, height, cull_back)
    planes = _planes(P, F[faces])
    order = np.lexsort((h, w))  # faces with boxes of one size together: each group is one broadcast
    first = np.flatnonzero(np.diff(w[order]) | np.diff(h[order])) + 1
    for group in np.split(order, first) if len(order) else []:
        bw, bh = int(w[group[0]]), int(h[group[0]])
        step = max(1, BATCH_CANDIDATES // (bw * bh))
        for start in range(0, len(group), step):
            batch = group[start:start + step]
            _draw_boxes(planes[batch], batch, x0[batch], y0[batch], bw, bh, width, depth, owner)
    pixels = np.flatnonzero(owner >= 0)
    b = _evaluate(planes[owner[pixels]], pixels % width + 0.5, pixels // width + 0.5)
    bary = np.column_stack([1.0 - b[:, 0] - b[:, 1], b[:, 0], b[:, 1]])
    owner[pixels] = faces[owner[pixels]]
    return Raster(owner.reshape(height, width), pixels, bary, depth.reshape(height, width))


def _pixel_boxes(P, F, width, height, cull_back):
    """Faces that may cover a pixel centre, and each one's box of pixel centres ``(x0, y0, w, h)``."""
    X, Y = P[:, 0][F], P[:, 1][F]
    area = (X[:, 1] - X[:, 0]) * (Y[:, 2] - Y[:, 0]) - (Y[:, 1] - Y[:, 0]) * (X[:, 2] - X[:, 0])
    x0 = np.maximum(np.ceil(np.minimum(np.minimum(X[:, 0], X[:, 1]), X[:, 2]) - 0.5), 0)
    y0 = np.maximum(np.ceil(np.minimum(np.minimum(Y[:, 0], Y[:, 1]), Y[:, 2]) - 0.5), 0)
    x1 = np.minimum(np.floor(np.maximum(np.maximum(X[:, 0], X[:, 1]), X[:, 2]) - 0.5), width - 1)
    y1 = np.minimum(np.floor(np.maximum(np.maximum(Y[:, 0], Y[:, 1]), Y[:, 2]) - 0.5), height - 1)
    faces = np.flatnonzero((x1 >= x0) & (y1 >= y0) & (area > 0 if cull_back else area != 0))
    x0, y0 = x0[faces].astype(np.int64), y0[faces].astype(np.int64)
    return faces, x0, y0, x1[faces].astype(np.int64) - x0 + 1, y1[faces].astype(np.int64) - y0 + 1


def _planes(P, corners):
    """Per face, the affine functions of the image point ``(x, y)`` that give its barycentric coordinates
    of the second and third corner and its depth: ``(m, 3, 3)``, rows ``[constant, x, y]``-coefficients."""
    A, B, C = P[corners[:, 0]], P[corners[:, 1]], P[corners[:, 2]]
    e1, e2 = B - A, C - A
    det = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    # b1 = ((x - Ax) e2y - (y - Ay) e2x) / det,  b2 = ((y - Ay) e1x - (x - Ax) e1y) / det
    b1 = np.stack([(A[:, 1] * e2[:, 0] - A[:, 0] * e2[:, 1]), e2[:, 1], -e2[:, 0]], axis=1) / det[:, None]
    b2 = np.stack([(A[:, 0] * e1[:, 1] - A[:, 1] * e1[:, 0]), -e1[:, 1], e1[:, 0]], axis=1) / det[:, None]
    z = A[:, 2, None] * np.array([1.0, 0.0, 0.0]) + e1[:, 2, None] * b1 + e2[:, 2, None] * b2
    return np.stack([b1, b2, z], axis=1)


def _evaluate(planes, x, y):
    """The affine functions ``planes`` (k, j, 3) at the points ``(x, y)`` (k,): (k, j)."""
    return planes[:, :, 0] + planes[:, :, 1] * x[:, None] + planes[:, :, 2] * y[:, None]


def _draw_boxes(planes, faces, x0, y0, box_width, box_height, width, depth, owner):
    """Depth-test the pixel centres in the equal-sized boxes of ``faces`` into ``depth`` and ``owner``."""
    x = (x0[:, None, None] + np.arange(box_width)[None, None, :] + 0.5).astype(float)
    y = (y0[:, None, None] + np.arange(box_height)[None, :, None] + 0.5).astype(float)
    c = planes[:, :, :, None, None]
    b1 = c[:, 0, 0] + c[:, 0, 1] * x + c[:, 0, 2] * y
    b2 = c[:, 1, 0] + c[:, 1, 1] * x + c[:, 1, 2] * y
    inside = (b1 >= -1e-9) & (b2 >= -1e-9) & (b1 + b2 <= 1.0 + 1e-9)
    face, row, col = np.nonzero(inside)
    xi, yi = x[face, 0, col], y[face, row, 0]
    z = planes[face, 2, 0] + planes[face, 2, 1] * xi + planes[face, 2, 2] * yi
    pixel = (yi - 0.5).astype(np.int64) * width + (xi - 0.5).astype(np.int64)
    np.maximum.at(depth, pixel, z)
    won = z >= depth[pixel]
    owner[pixel[won]] = faces[face[won]]
