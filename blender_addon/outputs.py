"""What a run writes: the output options, checked before any work and written after the query.

:func:`check_outputs` runs first (nothing is computed when an output name is
taken or an option is wrong); :func:`write_outputs` runs on the main thread
once the distance is known. Their keywords are the output options of
:func:`~.api.compute_geodesic_distance` (``OUTPUT_NAMES``).

Examples
--------
>>> outputs = check_outputs(obj, isolines=10)           # doctest: +SKIP
>>> dmax = write_outputs(obj, distance, "WORLD", **outputs)   # doctest: +SKIP
"""

import importlib
import inspect

import numpy as np

from . import adapters
from ._heatcore import colormap as colormaps
from ._heatcore import heatcore
from .adapters import AddonError
from .material import ISOLINE_STYLES, show_isoline_material
from .undo import remember_active_color

#: ``heatcore.options`` (the bundled copy's).
options = importlib.import_module(heatcore.__name__ + ".options")
#: ``heatcore.weights``: distance to weights for modifiers.
weights = importlib.import_module(heatcore.__name__ + ".weights")

#: Default output names: no two alike, so no attribute is ever named like the weight group.
DEFAULT_ATTRIBUTE = "geodesic_distance"
DEFAULT_COLOR_ATTRIBUTE = "geodesic_distance_color"
DEFAULT_WEIGHT_GROUP = "geodesic_weight"


def check_outputs(
    obj,
    *,
    source_group=None,
    attribute=DEFAULT_ATTRIBUTE,
    color_attribute=DEFAULT_COLOR_ATTRIBUTE,
    colormap="viridis",
    isolines=0,
    normalize=False,
    weight_group=None,
    weight_radius=None,
    weight_falloff="LINEAR",
    weight_invert=False,
    isoline_material=False,
    isoline_spacing=0.0,
    isoline_width=1.5,
    isoline_style="SHADED",
):
    """The output options checked (before any work), as keywords of :func:`write_outputs`.

    ``source_group`` (the vertex group whose members are the sources, if
    any) is not an output: the weight group must not be it.

    Raises
    ------
    AddonError
        An unknown colormap, output names that collide
        (:func:`~.adapters.check_output_names`), or isoline options the
        material cannot draw.
    heatcore.InvalidOptionError
        A bad isoline count or weight option.
    """
    given = locals()  # the keywords by name: OUTPUT_NAMES are this signature's
    outputs = {name: given[name] for name in OUTPUT_NAMES}
    for name in options.names("output"):  # heatcore's output options: colormap, isolines, weights
        try:
            outputs[name] = options.check(name, outputs[name])
        except heatcore.InvalidOptionError as exc:
            if name == "colormap":  # a name to pick from a list, as the output names are
                raise AddonError(str(exc)) from None
            raise
    adapters.check_output_names(obj, attribute, color_attribute, weight_group or None, source_group)
    if isoline_material:
        _check_isoline_options(attribute, isoline_spacing, isoline_width, isoline_style)
    return outputs


def _check_isoline_options(attribute, spacing, width, style):
    """The isoline material reads the distance attribute: it must be written; spacing >= 0, width > 0, a known style."""
    if attribute is None:
        raise AddonError("isoline_material=True draws the distance attribute: give an attribute name, not None")
    if not (np.isfinite(spacing) and spacing >= 0):
        raise AddonError(f"isoline_spacing must be 0 (from the isoline count) or a positive distance, got {spacing}")
    if not (np.isfinite(width) and width > 0):
        raise AddonError(f"isoline_width must be a positive number of pixels, got {width}")
    if style not in ISOLINE_STYLES:
        raise AddonError(f"isoline_style must be one of {', '.join(ISOLINE_STYLES)}, got {style!r}")


#: The output options (keywords of :func:`check_outputs` and :func:`write_outputs`).
OUTPUT_NAMES = tuple(name for name in inspect.signature(check_outputs).parameters if name not in ("obj", "source_group"))


def write_outputs(obj, d, space, *, attribute, color_attribute, colormap, isolines, normalize, weight_group,
                  weight_radius, weight_falloff, weight_invert, isoline_material, isoline_spacing, isoline_width,
                  isoline_style):
    """Write the distance ``d`` (per vertex, ``inf`` where unreachable) to the outputs of ``obj``.

    ``space`` is the space it was measured in (the isoline material's line widths depend on it).

    Returns
    -------
    float
        The largest finite distance (0 when none is finite).
    """
    mesh = obj.data
    finite = np.isfinite(d)
    dmax = float(d[finite].max()) if finite.any() else 0.0
    scale = 1.0 / dmax if (normalize and dmax > 0) else 1.0
    with adapters.writing(obj):
        if attribute is not None:
            adapters.write_float_attribute(mesh, attribute, np.where(finite, d * scale, adapters.UNREACHABLE_VALUE))
        if color_attribute is not None:
            remember_active_color(mesh, color_attribute)
            rgb = colormaps.colorize(d, colormap=colormap, isolines=int(isolines))
            adapters.write_color_attribute(mesh, color_attribute, rgb)
        if weight_group:
            w = weights.distance_weights(d, radius=weight_radius, falloff=weight_falloff, invert=weight_invert)
            adapters.write_vertex_group(obj, weight_group, w)
    if isoline_material:
        spacing = isoline_spacing or (dmax / (isolines + 1) if isolines else 0.0)
        show_isoline_material(obj, attribute, colormap=colormap, max_distance=dmax, spacing=spacing,
                              attribute_scale=1.0 / scale, line_width=isoline_width, space=space,
                              style=isoline_style)
    return dmax
