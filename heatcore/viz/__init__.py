"""Pictures of a distance field: colormaps and stripes, and a software renderer to PNG.

Examples
--------
>>> import numpy as np
>>> from heatcore.viz import colorize
>>> colorize(np.array([0.0, 0.5, 1.0])).shape
(3, 3)
"""

from .colormap import COLORMAPS, UNREACHABLE_COLOR, colorize, to_uint8
from .render import render_distance

__all__ = ["COLORMAPS", "UNREACHABLE_COLOR", "colorize", "render_distance", "to_uint8"]
