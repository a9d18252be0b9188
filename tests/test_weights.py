"""heatcore.weights.distance_weights: exact values of every falloff, Blender's mapping, typed errors."""

import math

import numpy as np
import pytest

from heatcore.errors import InvalidOptionError
from heatcore.options import OPTIONS
from heatcore.weights import FALLOFFS, distance_weights

INF = math.inf
D = [0.0, 0.25, 0.5, 0.75, 1.0, 1.5, INF]

#: Weights of D at radius 1, worked out by hand: t = 1 - d (clipped to [0, 1]), then the curve.
EXACT = {
    "LINEAR": [1.0, 0.75, 0.5, 0.25, 0.0, 0.0, 0.0],
    "SMOOTH": [1.0, 0.84375, 0.5, 0.15625, 0.0, 0.0, 0.0],  # 3t^2 - 2t^3
    "SHARP": [1.0, 0.5625, 0.25, 0.0625, 0.0, 0.0, 0.0],  # t^2
    "ROOT": [1.0, math.sqrt(0.75), math.sqrt(0.5), 0.5, 0.0, 0.0, 0.0],  # sqrt(t)
}


@pytest.mark.parametrize("falloff", list(EXACT))
def test_each_falloff_exact_values(falloff):
    w = distance_weights(D, radius=1.0, falloff=falloff)
    assert w.dtype == np.float64 and w.shape == (len(D),)
    np.testing.assert_allclose(w, EXACT[falloff], rtol=0, atol=1e-15)


@pytest.mark.parametrize("falloff", list(EXACT))
def test_invert_is_one_minus_the_falloff_and_unreachable_stays_zero(falloff):
    w = distance_weights(D, radius=1.0, falloff=falloff, invert=True)
    expected = [1.0 - x for x in EXACT[falloff][:-1]] + [0.0]  # the last distance is inf
    np.testing.assert_allclose(w, expected, rtol=0, atol=1e-15)


def _blender_proximity(d, lowest, highest, falloff, invert):
    """Blender's VertexWeightProximity mapping, transcribed: ``do_map`` (its lowest > highest branch)
    then ``weightvg_do_map`` (MOD_weightvgproximity.cc, MOD_weightvg_util.cc)."""
    if d <= highest:
        fac = 1.0
    elif d >= lowest:
        fac = 0.0
    else:
        fac = (d - lowest) * (1.0 / (highest - lowest))
    fac = {"LINEAR": fac, "SHARP": fac * fac, "SMOOTH": 3.0 * fac * fac - 2.0 * fac * fac * fac,
           "ROOT": math.sqrt(fac)}[falloff]
    return 1.0 - fac if invert else fac


@pytest.mark.parametrize("invert", [False, True])
@pytest.mark.parametrize("falloff", list(EXACT))
def test_matches_blender_proximity_modifier_with_lowest_radius_highest_zero(falloff, invert):
    rng = np.random.default_rng(7)
    radius = 2.5
    d = np.concatenate([[0.0, radius, 2 * radius], rng.uniform(0.0, 1.5 * radius, 200)])
    expected = [_blender_proximity(x, radius, 0.0, falloff, invert) for x in d]
    np.testing.assert_allclose(distance_weights(d, radius, falloff, invert), expected, rtol=0, atol=1e-14)


def test_default_radius_is_the_largest_finite_distance():
    d = np.array([0.0, 1.0, 2.0, 4.0, INF])
    np.testing.assert_array_equal(distance_weights(d), [1.0, 0.75, 0.5, 0.0, 0.0])
    np.testing.assert_array_equal(distance_weights(d, radius=None, falloff="SHARP"), [1.0, 0.5625, 0.25, 0.0, 0.0])
    np.testing.assert_array_equal(distance_weights(d), distance_weights(d, radius=4.0))


def test_scaling_distance_and_radius_together_leaves_weights_unchanged():
    d = np.random.default_rng(3).uniform(0.0, 3.0, 50)
    for falloff in FALLOFFS:
        np.testing.assert_allclose(distance_weights(1e-3 * d, 1e-3 * 2.0, falloff),
                                   distance_weights(d, 2.0, falloff), rtol=0, atol=1e-12)


def test_weights_fall_monotonically_from_one_to_zero():
    d = np.linspace(0.0, 3.0, 301)
    for falloff in FALLOFFS:
        w = distance_weights(d, radius=2.0, falloff=falloff)
        assert w[0] == 1.0 and (w[d >= 2.0] == 0.0).all() and (np.diff(w) <= 0).all(), falloff
        assert ((w > 0) & (w < 1))[(d > 0) & (d < 2.0)].all(), falloff


def test_only_unreachable_or_all_zero_distances():
    np.testing.assert_array_equal(distance_weights([INF, INF]), [0.0, 0.0])
    np.testing.assert_array_equal(distance_weights([INF, INF], invert=True), [0.0, 0.0])
    # every reached vertex is a source (largest distance 0): sources 1, inverted 0, unreachable 0
    np.testing.assert_array_equal(distance_weights([0.0, 0.0, INF]), [1.0, 1.0, 0.0])
    np.testing.assert_array_equal(distance_weights([0.0, 0.0, INF], invert=True), [0.0, 0.0, 0.0])
    # NaN counts as unreachable; a negative distance as a source
    np.testing.assert_array_equal(distance_weights([np.nan, -0.5, 0.5], radius=1.0), [0.0, 1.0, 0.5])
    assert distance_weights([]).shape == (0,)


@pytest.mark.parametrize(("name", "keyword", "value"), [
    ("weight_radius", "radius", 0.0), ("weight_radius", "radius", -1.0), ("weight_radius", "radius", INF),
    ("weight_radius", "radius", np.nan), ("weight_radius", "radius", "far"), ("weight_radius", "radius", True),
    ("weight_falloff", "falloff", "linear"), ("weight_falloff", "falloff", "SPHERE"), ("weight_falloff", "falloff", None),
    ("weight_invert", "invert", "yes"), ("weight_invert", "invert", 2),
])
def test_bad_options_raise_the_declared_error(name, keyword, value):
    with pytest.raises(InvalidOptionError) as caught:
        distance_weights([0.0, 1.0], **{keyword: value})
    assert str(caught.value) == str(OPTIONS[name].error(value))


def test_declared_choices_are_the_implemented_falloffs():
    assert OPTIONS["weight_falloff"].choices == tuple(FALLOFFS) == ("LINEAR", "SMOOTH", "SHARP", "ROOT")
    assert OPTIONS["weight_radius"].default is None and OPTIONS["weight_radius"].default_for("blender") == 0.0
    assert OPTIONS["weight_invert"].default is False
    assert all(OPTIONS[n].target == "output" and OPTIONS[n].flag is None
               for n in ("weight_radius", "weight_falloff", "weight_invert"))
