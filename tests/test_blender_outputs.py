"""The add-on's output options: one list (``check_outputs``' keywords), heatcore's checked from ``heatcore.options``."""

import importlib
import inspect

import blender_required  # noqa: F401 (first: without bpy, the module is skipped)
import numpy as np
import pytest
from test_blender import addon, empty_scene, ico_sphere  # noqa: F401 (fixtures)

import heatcore as hc
from heatcore import options


@pytest.fixture
def outputs(addon):  # noqa: F811 (fixture)
    return importlib.import_module("blender_addon.outputs")


def test_one_list_of_output_names(outputs):
    written = [name for name, p in inspect.signature(outputs.write_outputs).parameters.items()
               if p.kind is p.KEYWORD_ONLY]
    assert tuple(written) == outputs.OUTPUT_NAMES
    assert set(options.names("output")) <= set(outputs.OUTPUT_NAMES)  # every heatcore output option offered


def test_check_outputs_checks_heatcore_options_once_each(outputs):
    obj = ico_sphere(1)
    checked = outputs.check_outputs(obj, isolines=np.int64(3), weight_invert=np.True_, weight_radius=2)
    assert tuple(checked) == outputs.OUTPUT_NAMES
    assert type(checked["isolines"]) is int and checked["weight_invert"] is True and checked["weight_radius"] == 2.0
    with pytest.raises(outputs.AddonError, match="colormap"):
        outputs.check_outputs(obj, colormap="no such map")
    for bad in ({"isolines": -1}, {"weight_falloff": "WOBBLY"}, {"weight_radius": 0.0}):
        with pytest.raises(hc.InvalidOptionError):
            outputs.check_outputs(obj, **bad)
