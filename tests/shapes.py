"""Small analytic test domains shared by the tests."""

import numpy as np


def grid(nx, ny, size=1.0, jitter=0.0, seed=0):
    """Planar triangulated grid on [0, size]^2 (alternating diagonals); optional interior jitter."""
    x, y = np.meshgrid(np.linspace(0, size, nx), np.linspace(0, size, ny), indexing="xy")
    V = np.column_stack([x.ravel(), y.ravel(), np.zeros(x.size)])
    if jitter:
        rng = np.random.default_rng(seed)
        inner = (x.ravel() > 0) & (x.ravel() < size) & (y.ravel() > 0) & (y.ravel() < size)
        V[inner, :2] += rng.uniform(-jitter, jitter, (inner.sum(), 2)) * size / (nx - 1)
    i, j = np.meshgrid(np.arange(nx - 1), np.arange(ny - 1), indexing="xy")
    a = (j * nx + i).ravel()
    b, c, d = a + 1, a + nx, a + nx + 1
    flip = ((i + j) % 2 == 0).ravel()
    F = np.concatenate(
        [
            np.where(flip[:, None], np.stack([a, b, d], 1), np.stack([a, b, c], 1)),
            np.where(flip[:, None], np.stack([a, d, c], 1), np.stack([b, d, c], 1)),
        ]
    )
    return V, F


def icosphere(subdivisions, radius=1.0):
    """Unit icosphere scaled to ``radius`` (trimesh's construction)."""
    import trimesh

    sphere = trimesh.creation.icosphere(subdivisions=subdivisions, radius=radius)
    return np.asarray(sphere.vertices), np.asarray(sphere.faces)
