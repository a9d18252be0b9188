"""Import heatcore: the copy bundled in the extension, else the installed package.

The extension zip vendors heatcore as ``_vendor/heatcore`` (see
``scripts/build_blender_extension.py``) so that users install nothing; when
the add-on runs from a source checkout, the ``heatcore`` on ``sys.path`` is
used instead.
"""

import importlib

try:
    from ._vendor import heatcore
except ImportError:  # running from the repository: use the installed package
    import heatcore

colormap = importlib.import_module(heatcore.__name__ + ".viz.colormap")

__all__ = ["colormap", "heatcore"]
