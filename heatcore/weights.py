"""Distance to weights in [0, 1] for modifiers: 1 at the sources, falling to 0 at a radius.

The mapping is Blender's VertexWeightProximity modifier with *Lowest* = the
radius and *Highest* = 0, measured along the surface instead of straight
through space: the distance ``d`` becomes ``t = clip(1 - d / radius, 0, 1)``
(1 at the sources, 0 at and beyond the radius), a falloff curve with
Blender's name shapes ``t`` (``weightvg_do_map`` in Blender's
``MOD_weightvg_util.cc``), and *invert* takes ``1 - weight``. Vertices that
no source reaches (distance ``inf``) get weight 0 whatever the options.

Examples
--------
>>> distance_weights([0.0, 0.5, 1.0, 2.0, float("inf")]).tolist()
[1.0, 0.75, 0.5, 0.0, 0.0]
>>> distance_weights([0.0, 0.5, 1.0, 2.0], radius=1.0, falloff="SHARP").tolist()
[1.0, 0.25, 0.0, 0.0]
"""

import numpy as np

from .options import check

#: Falloff curves (Blender's names), each applied to ``t`` in [0, 1].
FALLOFFS = {
    "LINEAR": lambda t: t,
    "SMOOTH": lambda t: t * t * (3.0 - 2.0 * t),
    "SHARP": lambda t: t * t,
    "ROOT": np.sqrt,
}


def distance_weights(distance, radius=None, falloff="LINEAR", invert=False):
    """Weights in [0, 1]: 1 at the sources, falling to 0 at geodesic distance ``radius``.

    With ``t = clip(1 - distance / radius, 0, 1)`` the weight is ``f(t)``
    (``1 - f(t)`` with ``invert``), ``f`` the falloff curve. These are the
    curves of Blender's VertexWeightProximity and VertexWeightEdit modifiers
    (``weightvg_do_map``), so a weight here equals that modifier's weight with
    *Lowest* = ``radius``, *Highest* = 0 and the same *Falloff Type* and
    *Invert Falloff*, the distance being geodesic:

    - ``"LINEAR"``: ``f(t) = t``, a cone: the weight falls evenly with distance;
    - ``"SMOOTH"``: ``f(t) = 3t² - 2t³`` (smoothstep), flat at the sources and
      at the radius;
    - ``"SHARP"``: ``f(t) = t²``, a spike: the weight drops fast near the
      sources and fades out slowly;
    - ``"ROOT"``: ``f(t) = √t``, a dome: the weight stays high and drops
      steeply at the radius.

    Parameters
    ----------
    distance : (n,) array_like
        Geodesic distances (>= 0; ``inf`` where no source reaches). Negative
        values count as 0; ``inf`` and NaN entries get weight 0.
    radius : float, optional
        Distance at which the weight reaches 0 (a positive, finite number).
        None: the largest finite distance (when that is 0, only the vertices
        at distance 0 get ``f(1)``).
    falloff : {"LINEAR", "SMOOTH", "SHARP", "ROOT"}
        The curve from the sources to the radius (Blender's names).
    invert : bool
        Blender's *Invert Falloff*: weight ``1 - f(t)``, 0 at the sources and 1
        at and beyond the radius. Unreachable vertices stay 0.

    Returns
    -------
    (n,) float64 array
        Weights in [0, 1].

    Raises
    ------
    heatcore.errors.InvalidOptionError
        A radius that is not a positive finite number (or None), an unknown
        falloff, or an invert that is not a bool (``heatcore.options``:
        ``weight_radius``, ``weight_falloff``, ``weight_invert``).

    Examples
    --------
    >>> d = [0.0, 0.25, 0.5, 1.0, float("inf")]
    >>> distance_weights(d, radius=1.0, falloff="SMOOTH").tolist()
    [1.0, 0.84375, 0.5, 0.0, 0.0]
    >>> distance_weights(d, radius=1.0, falloff="ROOT", invert=True).tolist()
    [0.0, 0.1339745962155614, 0.2928932188134524, 1.0, 0.0]
    >>> distance_weights(d, radius=0.0)
    Traceback (most recent call last):
    ...
    heatcore.errors.InvalidOptionError: invalid weight radius 0.0: weight_radius must be a positive number or None (the largest distance)
    """
    radius = check("weight_radius", radius)
    curve = FALLOFFS[check("weight_falloff", falloff)]
    invert = check("weight_invert", invert)
    d = np.asarray(distance, dtype=np.float64)
    reached = np.isfinite(d)
    if radius is None:
        radius = float(d[reached].max()) if reached.any() else 0.0
    if radius > 0:
        t = np.clip(1.0 - np.where(reached, d, radius) / radius, 0.0, 1.0)
    else:  # every reached distance is 0 (or below): those vertices are the sources
        t = (reached & (d <= 0)).astype(np.float64)
    weights = curve(t)
    if invert:
        weights = 1.0 - weights
    return np.where(reached, weights, 0.0)


def signed_weights(d, band=0.0):
    """Vertex weights of a signed field: 1 inside (``d > 0``), 0 outside, linear across a band ``band`` wide.

    Blender's *Signed Distance from Edges* writes them as a vertex group (a mask for modifiers); vertices
    no curve reaches (``inf``) get 0.

    Examples
    --------
    >>> signed_weights(np.array([-1.0, 0.0, 0.05, 1.0, np.inf]), band=0.2).tolist()
    [0.0, 0.5, 0.75, 1.0, 0.0]
    """
    d = np.asarray(d, dtype=np.float64)
    finite = np.isfinite(d)
    if band > 0:
        w = np.clip(0.5 + np.where(finite, d, -np.inf) / band, 0.0, 1.0)
    else:
        w = (np.where(finite, d, -1.0) > 0).astype(np.float64)
    return np.where(finite, w, 0.0)
