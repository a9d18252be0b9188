"""Load and register the add-on from this checkout inside a ``bpy`` process (for the Blender scripts)."""

import importlib.util
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def load_addon():
    """Import ``blender_addon/`` from the repository as the module ``blender_addon`` and register it."""
    spec = importlib.util.spec_from_file_location(
        "blender_addon", REPO / "blender_addon" / "__init__.py", submodule_search_locations=[str(REPO / "blender_addon")]
    )
    module = importlib.util.module_from_spec(spec)
    sys.modules["blender_addon"] = module
    spec.loader.exec_module(module)
    module.register()
    return module
