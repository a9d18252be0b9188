"""Perceptual colormaps and isoline stripes for distance fields, in pure numpy.

The tables are 33 samples of matplotlib's perceptually uniform colormaps
(viridis, magma, inferno, plasma, cividis; released to the public domain
under CC0), interpolated linearly. Pure numpy so that front ends without
matplotlib (Blender) color the same way.

Examples
--------
>>> import numpy as np
>>> colorize(np.array([0.0, 0.5, 1.0])).shape
(3, 3)
"""

import numpy as np

from ..options import check

# fmt: off
COLORMAPS = {
    "viridis": np.array([
        (0.2670, 0.0049, 0.3294),
        (0.2770, 0.0503, 0.3757),
        (0.2823, 0.0950, 0.4173),
        (0.2829, 0.1359, 0.4534),
        (0.2788, 0.1755, 0.4834),
        (0.2706, 0.2141, 0.5071),
        (0.2590, 0.2515, 0.5247),
        (0.2450, 0.2877, 0.5373),
        (0.2297, 0.3224, 0.5457),
        (0.2143, 0.3556, 0.5512),
        (0.1994, 0.3876, 0.5546),
        (0.1856, 0.4186, 0.5568),
        (0.1727, 0.4488, 0.5579),
        (0.1607, 0.4785, 0.5581),
        (0.1490, 0.5081, 0.5573),
        (0.1378, 0.5375, 0.5549),
        (0.1276, 0.5669, 0.5506),
        (0.1206, 0.5964, 0.5436),
        (0.1206, 0.6258, 0.5335),
        (0.1323, 0.6550, 0.5197),
        (0.1579, 0.6838, 0.5017),
        (0.1966, 0.7118, 0.4792),
        (0.2461, 0.7389, 0.4520),
        (0.3041, 0.7647, 0.4199),
        (0.3692, 0.7889, 0.3829),
        (0.4401, 0.8111, 0.3410),
        (0.5160, 0.8312, 0.2943),
        (0.5958, 0.8487, 0.2433),
        (0.6785, 0.8637, 0.1895),
        (0.7624, 0.8764, 0.1371),
        (0.8456, 0.8873, 0.0997),
        (0.9261, 0.8973, 0.1041),
        (0.9932, 0.9062, 0.1439),
    ]),
    "magma": np.array([
        (0.0015, 0.0005, 0.0139),
        (0.0137, 0.0118, 0.0687),
        (0.0396, 0.0311, 0.1335),
        (0.0743, 0.0520, 0.2027),
        (0.1131, 0.0655, 0.2768),
        (0.1590, 0.0684, 0.3527),
        (0.2117, 0.0620, 0.4186),
        (0.2654, 0.0602, 0.4618),
        (0.3167, 0.0717, 0.4854),
        (0.3660, 0.0903, 0.4980),
        (0.4147, 0.1104, 0.5047),
        (0.4635, 0.1299, 0.5077),
        (0.5128, 0.1482, 0.5076),
        (0.5629, 0.1654, 0.5047),
        (0.6136, 0.1818, 0.4985),
        (0.6649, 0.1981, 0.4888),
        (0.7164, 0.2150, 0.4753),
        (0.7674, 0.2337, 0.4578),
        (0.8169, 0.2559, 0.4365),
        (0.8633, 0.2837, 0.4124),
        (0.9043, 0.3196, 0.3881),
        (0.9372, 0.3649, 0.3686),
        (0.9609, 0.4183, 0.3596),
        (0.9767, 0.4762, 0.3645),
        (0.9867, 0.5356, 0.3822),
        (0.9928, 0.5949, 0.4103),
        (0.9961, 0.6537, 0.4462),
        (0.9973, 0.7118, 0.4882),
        (0.9969, 0.7696, 0.5349),
        (0.9951, 0.8271, 0.5857),
        (0.9924, 0.8843, 0.6401),
        (0.9894, 0.9415, 0.6975),
        (0.9871, 0.9914, 0.7495),
    ]),
    "inferno": np.array([
        (0.0015, 0.0005, 0.0139),
        (0.0140, 0.0112, 0.0719),
        (0.0423, 0.0281, 0.1411),
        (0.0820, 0.0433, 0.2153),
        (0.1293, 0.0473, 0.2908),
        (0.1834, 0.0403, 0.3550),
        (0.2383, 0.0366, 0.3964),
        (0.2908, 0.0456, 0.4186),
        (0.3415, 0.0623, 0.4294),
        (0.3915, 0.0809, 0.4331),
        (0.4412, 0.0993, 0.4316),
        (0.4910, 0.1172, 0.4256),
        (0.5409, 0.1347, 0.4151),
        (0.5907, 0.1526, 0.4003),
        (0.6401, 0.1714, 0.3811),
        (0.6887, 0.1922, 0.3576),
        (0.7357, 0.2159, 0.3302),
        (0.7805, 0.2433, 0.2995),
        (0.8224, 0.2752, 0.2661),
        (0.8605, 0.3119, 0.2306),
        (0.8943, 0.3534, 0.1936),
        (0.9232, 0.3994, 0.1552),
        (0.9470, 0.4492, 0.1153),
        (0.9654, 0.5022, 0.0739),
        (0.9784, 0.5579, 0.0349),
        (0.9860, 0.6158, 0.0256),
        (0.9879, 0.6753, 0.0653),
        (0.9841, 0.7361, 0.1295),
        (0.9746, 0.7977, 0.2063),
        (0.9606, 0.8591, 0.2980),
        (0.9476, 0.9174, 0.4107),
        (0.9545, 0.9659, 0.5404),
        (0.9884, 0.9984, 0.6449),
    ]),
    "plasma": np.array([
        (0.0504, 0.0298, 0.5280),
        (0.1324, 0.0223, 0.5633),
        (0.1934, 0.0184, 0.5903),
        (0.2480, 0.0144, 0.6129),
        (0.2999, 0.0096, 0.6316),
        (0.3502, 0.0044, 0.6463),
        (0.3994, 0.0009, 0.6561),
        (0.4477, 0.0021, 0.6602),
        (0.4949, 0.0120, 0.6579),
        (0.5406, 0.0350, 0.6486),
        (0.5844, 0.0686, 0.6328),
        (0.6260, 0.1033, 0.6113),
        (0.6651, 0.1386, 0.5856),
        (0.7018, 0.1740, 0.5573),
        (0.7360, 0.2094, 0.5279),
        (0.7681, 0.2448, 0.4985),
        (0.7982, 0.2802, 0.4695),
        (0.8266, 0.3157, 0.4413),
        (0.8533, 0.3516, 0.4137),
        (0.8784, 0.3879, 0.3866),
        (0.9018, 0.4251, 0.3597),
        (0.9233, 0.4633, 0.3328),
        (0.9426, 0.5026, 0.3058),
        (0.9594, 0.5434, 0.2787),
        (0.9734, 0.5858, 0.2515),
        (0.9842, 0.6297, 0.2246),
        (0.9914, 0.6754, 0.1985),
        (0.9945, 0.7227, 0.1744),
        (0.9930, 0.7717, 0.1548),
        (0.9865, 0.8224, 0.1436),
        (0.9744, 0.8746, 0.1441),
        (0.9568, 0.9282, 0.1524),
        (0.9400, 0.9752, 0.1313),
    ]),
    "cividis": np.array([
        (0.0000, 0.1351, 0.3048),
        (0.0000, 0.1579, 0.3575),
        (0.0000, 0.1788, 0.4148),
        (0.0179, 0.1985, 0.4412),
        (0.1034, 0.2204, 0.4358),
        (0.1543, 0.2425, 0.4301),
        (0.1951, 0.2644, 0.4259),
        (0.2309, 0.2861, 0.4235),
        (0.2637, 0.3078, 0.4228),
        (0.2947, 0.3295, 0.4237),
        (0.3242, 0.3513, 0.4263),
        (0.3529, 0.3732, 0.4302),
        (0.3808, 0.3952, 0.4357),
        (0.4082, 0.4174, 0.4426),
        (0.4352, 0.4398, 0.4511),
        (0.4616, 0.4624, 0.4620),
        (0.4887, 0.4853, 0.4710),
        (0.5179, 0.5085, 0.4727),
        (0.5478, 0.5319, 0.4717),
        (0.5782, 0.5557, 0.4687),
        (0.6091, 0.5798, 0.4636),
        (0.6404, 0.6044, 0.4568),
        (0.6720, 0.6293, 0.4480),
        (0.7040, 0.6547, 0.4371),
        (0.7365, 0.6806, 0.4240),
        (0.7694, 0.7070, 0.4085),
        (0.8027, 0.7340, 0.3902),
        (0.8364, 0.7615, 0.3687),
        (0.8707, 0.7896, 0.3433),
        (0.9056, 0.8183, 0.3129),
        (0.9411, 0.8475, 0.2758),
        (0.9778, 0.8773, 0.2280),
        (0.9957, 0.9093, 0.2178),
    ]),
}
# fmt: on

#: The diverging map of signed distances: blue (negative) through light gray (0) to red (positive), between
#: the end colors of Moreland's "cool to warm" map ("Diverging Color Maps for Scientific Visualization", 2009),
#: interpolated in RGB through a neutral middle.
DIVERGING = np.array([(0.230, 0.299, 0.754), (0.552, 0.690, 0.996), (0.866, 0.866, 0.866),
                      (0.956, 0.604, 0.482), (0.706, 0.016, 0.150)])

#: Color of vertices no source reaches (distance ``inf``).
UNREACHABLE_COLOR = (0.5, 0.5, 0.5)


def colorize(distance, colormap="viridis", isolines=0, vmax=None, stripe_width=0.08):
    """Map distances to RGB colors in [0, 1], with optional dark isoline stripes.

    Parameters
    ----------
    distance : (n,) float array
        Distances; ``inf`` entries get :data:`UNREACHABLE_COLOR`.
    colormap : str
        One of ``COLORMAPS``.
    isolines : int
        Number of dark stripes, at ``vmax * j / (isolines + 1)`` for ``j = 1..isolines``
        (the levels of :func:`heatcore.isolines` with an int count; 0 for none).
    vmax : float, optional
        Distance mapped to the top of the colormap (default: largest finite distance).
    stripe_width : float
        Stripe width as a fraction of the isoline spacing.

    Returns
    -------
    (n, 3) float array

    Examples
    --------
    >>> colorize(np.array([0.0, 1.0, np.inf])).round(3).tolist()
    [[0.267, 0.005, 0.329], [0.993, 0.906, 0.144], [0.5, 0.5, 0.5]]
    """
    colormap, isolines = check("colormap", colormap), check("isolines", isolines)
    d = np.asarray(distance, dtype=float)
    finite = np.isfinite(d)
    if vmax is None:
        vmax = float(d[finite].max()) if finite.any() else 1.0
    vmax = vmax if vmax > 0 else 1.0
    x = np.clip(np.where(finite, d, 0.0) / vmax, 0.0, 1.0)
    rgb = _sample(COLORMAPS[colormap], x)
    if isolines:
        phase = (x * (isolines + 1)) % 1.0
        near = np.minimum(phase, 1.0 - phase) < 0.5 * stripe_width
        rgb[near & (x > 0)] *= 0.25
    rgb[~finite] = UNREACHABLE_COLOR
    return rgb


def colorize_signed(values, isolines=0, vmin=None, vmax=None, stripe_width=0.08):
    """Map signed distances to RGB colors in [0, 1] (:data:`DIVERGING`: 0 is the neutral middle), with stripes.

    Each side is scaled by its own extreme, so that a small inside (a mask on a large mesh) is as red as the
    outside is blue: ``[0, vmax]`` goes to the red half, ``[vmin, 0]`` to the blue half.

    Parameters
    ----------
    values : (n,) float array
        Signed distances; non-finite entries get :data:`UNREACHABLE_COLOR`.
    isolines : int
        Dark stripes at 0 and every ``max(vmax, -vmin) / (isolines + 1)`` on either side: the levels of
        :func:`heatcore.contours.signed_levels`.
    vmin, vmax : float, optional
        The values at the blue and the red end (default: the smallest and the largest finite value).
    stripe_width : float
        Stripe width as a fraction of the level spacing.

    Returns
    -------
    (n, 3) float array

    Examples
    --------
    >>> colorize_signed(np.array([-4.0, 0.0, 1.0, np.nan])).round(3).tolist()   # each side to its end
    [[0.23, 0.299, 0.754], [0.866, 0.866, 0.866], [0.706, 0.016, 0.15], [0.5, 0.5, 0.5]]
    >>> colorize_signed(np.array([-4.0, 1.0]), vmax=4.0).round(3).tolist()[1]   # 1 is a quarter of the way up
    [0.911, 0.735, 0.674]
    """
    isolines = check("isolines", isolines)
    v = np.asarray(values, dtype=float)
    finite = np.isfinite(v)
    w = np.where(finite, v, 0.0)
    top = float(w.max(initial=0.0)) if vmax is None else float(vmax)
    bottom = float(-w.min(initial=0.0)) if vmin is None else float(-vmin)
    scale = np.where(w >= 0, top if top > 0 else 1.0, bottom if bottom > 0 else 1.0)
    rgb = _sample(DIVERGING, np.clip(0.5 + 0.5 * w / scale, 0.0, 1.0))
    if isolines:
        spacing = max(top, bottom) / (isolines + 1) if max(top, bottom) > 0 else 1.0
        phase = (np.abs(w) / spacing) % 1.0
        rgb[np.minimum(phase, 1.0 - phase) < 0.5 * stripe_width] *= 0.25
    rgb[~finite] = UNREACHABLE_COLOR
    return rgb


def _sample(table, x):
    """Colors of ``table`` (evenly spaced samples) at positions ``x`` in [0, 1], interpolated linearly."""
    pos = x * (len(table) - 1)
    lo = np.minimum(pos.astype(int), len(table) - 2)
    frac = (pos - lo)[:, None]
    return (1 - frac) * table[lo] + frac * table[lo + 1]


def to_uint8(rgb):
    """Colors in [0, 1] as 8-bit values.

    Parameters
    ----------
    rgb : (n, 3) float array
        Colors; values outside [0, 1] are clipped.

    Returns
    -------
    (n, 3) uint8 array

    Examples
    --------
    >>> to_uint8(np.array([[0.0, 0.5, 1.2]])).tolist()
    [[0, 128, 255]]
    """
    return np.round(np.clip(rgb, 0.0, 1.0) * 255).astype(np.uint8)
