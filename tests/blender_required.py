"""Imported first by every test module that needs Blender's ``bpy``: without it the module is skipped.

``bpy`` comes with the ``blender`` extra only (``pip install -e ".[test]"`` leaves it out): each
such module imports this one before ``bpy``, ``bmesh`` or a module that imports them, so that
pytest reports it skipped ("could not import 'bpy'") instead of a collection error.
"""

import pytest

bpy = pytest.importorskip("bpy", reason="Blender's bpy is not installed (the 'blender' extra)")
