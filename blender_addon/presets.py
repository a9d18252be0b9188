"""Operator presets of *Geodesic Distance* for common uses: a mask, falloff weights, isolines.

The redo panel's preset menu (the operator has ``"PRESET"`` in its
``bl_options``) lists the files of ``presets/operator/mesh.heat_geodesic_distance``
in Blender's script folders. :func:`register` writes :data:`PRESETS` there, in
the user's scripts folder, once: a preset file already there (the user's
own, or one they changed) is left as it is. Each preset sets every output
option (so that one preset after another gives the same result) and leaves
the sources, the measure and the solver as they are.

Examples
--------
>>> write_presets(Path("/tmp/presets"))                    # doctest: +SKIP
[PosixPath('/tmp/presets/Falloff_Weights.py'), ...]
"""

import os
from pathlib import Path

import bpy

#: The operator whose presets these are.
OPERATOR = "mesh.heat_geodesic_distance"
#: The output options and their values when a preset does not set them.
OUTPUT_DEFAULTS = {
    "normalize": False, "isolines": 0, "isoline_material": True, "isoline_style": "SHADED",
    "write_weights": False,
    "weight_radius": 0.0, "weight_falloff": "LINEAR", "weight_invert": False,
}
#: Preset name -> the options it sets (over :data:`OUTPUT_DEFAULTS`).
PRESETS = {
    # the distance 0..1 as an attribute (a mask for shaders and Geometry Nodes), weights 1 -> 0 for modifiers
    "Mask": {"normalize": True, "write_weights": True},
    # weights for modifiers falling smoothly from 1 at the sources to 0 at the radius
    "Falloff Weights": {"write_weights": True, "weight_falloff": "SMOOTH"},
    # lines of equal distance: stripes in the colors and the isoline material
    "Isolines": {"isolines": 10, "isoline_material": True},
}


def preset_text(options):
    """The preset file setting ``options`` (over :data:`OUTPUT_DEFAULTS`) on the active operator.

    Examples
    --------
    >>> print(preset_text({"isolines": 10}).splitlines()[4])
    op.isolines = 10
    """
    lines = ["import bpy", "op = bpy.context.active_operator", ""]
    lines += [f"op.{name} = {value!r}" for name, value in {**OUTPUT_DEFAULTS, **options}.items()]
    return "\n".join(lines) + "\n"


def write_presets(folder):
    """Write the :data:`PRESETS` files into ``folder`` (made if missing), keeping files already there; their paths."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    paths = []
    for name, options in PRESETS.items():
        path = folder / (name.replace(" ", "_") + ".py")
        if not path.exists():
            path.write_text(preset_text(options))
        paths.append(path)
    return paths


def register():
    """Write the presets into the user's preset folder (not in background Blender: no redo panel there)."""
    if bpy.app.background:
        return
    try:
        folder = bpy.utils.user_resource("SCRIPTS", path=os.path.join("presets", "operator", OPERATOR), create=True)
        write_presets(folder)
    except OSError:  # a read-only user folder: the operator works, without presets
        pass
