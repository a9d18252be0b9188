"""Shared test fixtures.

``bpy`` must be imported before ``pymeshlab`` in one process (the other order
fails with an undefined symbol), so it is imported first here when present.
"""

import os
from pathlib import Path

import pytest

try:  # noqa: SIM105 - import order matters, see the module docstring
    import bpy  # noqa: F401
except ImportError:
    pass

from heatcore.reference import exact_distance, mean_relative_error  # noqa: E402,F401 (used by tests)

REPO = Path(__file__).resolve().parents[1]

#: A script run inside a bare Blender process by tests/test_blender.py (no pytest there), not a test module.
collect_ignore = ["blender_install_check.py"]
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


@pytest.fixture
def spot():
    return load_shared_mesh("spot")


# Hypothesis profiles (tests/test_properties.py): "ci" is the default; HYPOTHESIS_PROFILE=local runs
# many more examples. hypothesis is a test extra: the numpy-2 run in .ci/run does without it.
try:
    from hypothesis import HealthCheck, settings
except ImportError:  # pragma: no cover - only where the test extra is not installed
    settings = None
if settings is not None:
    _SLOW_OK = [HealthCheck.too_slow, HealthCheck.data_too_large, HealthCheck.filter_too_much]
    _COMMON = {"deadline": None, "print_blob": True, "suppress_health_check": _SLOW_OK}
    settings.register_profile("ci", max_examples=6, derandomize=True, database=None, **_COMMON)
    settings.register_profile("local", max_examples=300, **_COMMON)
    settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))
