"""Shared test fixtures.

``bpy`` must be imported before ``pymeshlab`` in one process (the other order
fails with an undefined symbol), so it is imported first here when present.
"""

import os
from pathlib import Path

import numpy as np
import pytest

try:  # noqa: SIM105 - import order matters, see the module docstring
    import bpy  # noqa: F401
except ImportError:
    pass

REPO = Path(__file__).resolve().parents[1]
MESH_DIR = Path(os.environ.get("HEATCORE_MESHES", REPO.parent / "shared" / "meshes"))


def shared_mesh_path(name):
    """Path of a test mesh from the shared mesh folder (``HEATCORE_MESHES`` overrides it)."""
    path = MESH_DIR / f"{name}.obj"
    if not path.is_file():
        pytest.fail(f"test mesh {path} is missing: set HEATCORE_MESHES to the shared meshes folder")
    return path


def load_shared_mesh(name):
    """(V, F) of a shared test mesh."""
    from heatcore.io import read_mesh

    mesh = read_mesh(shared_mesh_path(name))
    return mesh.vertices, mesh.faces


def exact_distance(V, F, sources):
    """Exact geodesic distance (MMP, gdist) on a manifold mesh; inf at unreferenced vertices."""
    import gdist

    used = np.unique(F)
    vmap = np.full(len(V), -1)
    vmap[used] = np.arange(used.size)
    d = gdist.compute_gdist(
        np.ascontiguousarray(V[used], dtype=np.float64),
        np.ascontiguousarray(vmap[F], dtype=np.int32),
        np.asarray(vmap[np.atleast_1d(sources)], dtype=np.int32),
    )
    out = np.full(len(V), np.inf)
    out[used] = d
    return out


def mean_relative_error(d, exact):
    """Mean of |d - exact| / exact over vertices with finite exact distance > 0."""
    mask = np.isfinite(exact) & (exact > 0)
    return float(np.mean(np.abs(d[mask] - exact[mask]) / exact[mask]))


@pytest.fixture
def spot():
    return load_shared_mesh("spot")
