"""The time step ``t = m h^2`` of each vertex, and its guard: heat that would underflow far from the sources.

:func:`vertex_time_steps` is the one definition of the step, shared by the
heat method and the vector heat method. On refined parts the distance is read
from two heat steps, a short one ``SHORT_STEP t`` and a long one ``LONG_STEP t``
(:mod:`heatcore.steps.unit_field`).

With ``t = m h^2`` the heat of one backward-Euler step falls by a constant
factor per edge hop, so on a mesh hundreds of hops across it underflows and
its gradient is noise there. :func:`underflow_safe_m` gives the smallest time
factor that keeps it representable; :class:`~heatcore.HeatSolver` raises
``m`` per component to it where needed.

Examples
--------
>>> round(float(underflow_safe_m(700)), 2)
3.03
>>> vertex_time_steps(np.array([1.0, 2.0]), np.array([0, 0, 1]), 0.5).tolist()
[0.25, 0.25, 0.5]
"""

import numpy as np

#: Decimal orders of magnitude the heat may fall over the mesh: double
#: precision underflows near 1e-308, and the heat must stay well above it.
HEAT_DECADES_BUDGET = 250.0
#: Decimal orders of magnitude the heat falls per edge hop, relative to the 1D
#: backward-Euler rate; measured on intrinsic Delaunay meshes (0.55 decades per
#: hop at m = 1, where the 1D rate is 0.42), with hops counted on a star per
#: triangle (1.3). Hops are now counted along every side
#: (:func:`heatcore.domains.parts.edge_graph`), 0-20% fewer (spot 1.20x fewer, homer
#: 1.06x, bunny 1.0x, letters of text 1.0-1.15x), hence 1.45: on the text of
#: tests/test_polygon_concave.py, 1.3 let a letter's far end underflow (1.24% -> 1.58%).
HOP_DECAY_FACTOR = 1.45

#: The heat method's two steps on refined parts (``Domain.two_step_vertices``), in multiples of ``t = m h^2``.
#: One backward Euler step of length ``s`` falls like ``exp(-d / sqrt(s))`` times a factor that does not
#: depend on ``s`` to first order (the spreading of geodesics, the surface's curvature), so
#: ``log u_short - log u_long`` is ``-d (1/sqrt(s_short) - 1/sqrt(s_long))`` up to a constant: linear in the
#: distance, which a piecewise-linear field interpolates exactly, and free of that factor. With one step,
#: the gradient's direction error repeats at every refinement level, so refining did not converge
#: (docs/polygon.md). Steps 2t and 8t (sqrt(s) doubled) measured best on issue 32's meshes and on the
#: shared ones: spot 1.20% -> 0.88%, cheburashka 1.18% -> 0.91%, homer 1.48% -> 1.16%; longer steps err
#: more from a source beside a boundary (a jittered grid refined: 2.5t and 10t 1.10 times its unrefined
#: error), shorter ones on curved meshes (t and 4t: suzanne 2.25% -> 2.95%). On coarse parts left
#: unrefined one step is better (the 20 meshes of docs/polygon.md at refine=0: two steps 1.03-1.32
#: times the error on 16), and on large ones it costs less (a query 1.3-1.5 times as long with two).
SHORT_STEP = 2.0
LONG_STEP = 8.0


def heat_decay_per_hop(m):
    """Decimal orders of magnitude one backward-Euler heat step of ``t = m h^2`` falls per hop (1D).

    Parameters
    ----------
    m : float or float array
        Time factor (unitless).

    Returns
    -------
    float or float array
        ``-log10`` of the heat's ratio between neighbouring vertices of a 1D grid.

    Examples
    --------
    >>> round(float(heat_decay_per_hop(1.0)), 3)
    0.418
    >>> bool(heat_decay_per_hop(10.0) < heat_decay_per_hop(1.0))  # a longer step spreads the heat further
    True
    """
    ratio = 2 * m / ((1 + 2 * m) + np.sqrt(1 + 4 * m))  # root of m r^2 - (1 + 2m) r + m = 0
    return -np.log10(ratio)


def underflow_safe_m(hop_diameter, budget=HEAT_DECADES_BUDGET):
    """Smallest time factor keeping the heat representable across ``hop_diameter`` hops.

    With ``t = m h^2`` the heat falls by a constant factor per edge hop (about
    0.38 in 1D at m = 1), so on a mesh hundreds of hops across it underflows
    double precision and its gradient is noise. This returns the smallest
    ``m`` whose decay over the diameter stays within ``budget`` decades, in
    closed form (the per-hop ratio ``r`` of :func:`heat_decay_per_hop` gives
    ``m = r / (1 - r)^2``).

    Parameters
    ----------
    hop_diameter : int or array of int
        Edge hops across (one value per component).
    budget : float
        Decimal orders of magnitude the heat may fall.

    Returns
    -------
    float, or a float array of the shape of ``hop_diameter``

    Examples
    --------
    >>> bool(underflow_safe_m(300) < 1.0)
    True
    >>> round(float(underflow_safe_m(700)), 2)
    3.03
    >>> underflow_safe_m(np.array([300, 700])).round(2).tolist()
    [0.49, 3.03]
    >>> m = underflow_safe_m(700)
    >>> round(float(700 * HOP_DECAY_FACTOR * heat_decay_per_hop(m)), 9)  # spends the budget exactly
    250.0
    >>> underflow_safe_m(0)
    0.0
    """
    hops = np.asarray(hop_diameter, dtype=float)
    with np.errstate(divide="ignore"):  # no hops: no decay to guard, m = 0
        ratio = 10.0 ** -(budget / (HOP_DECAY_FACTOR * hops))  # the heat ratio per hop that spends the budget
    m = ratio / (1.0 - ratio) ** 2  # inverts heat_decay_per_hop: m r^2 - (1 + 2m) r + m = 0 for m
    return float(m) if m.ndim == 0 else m


def vertex_time_steps(part_m, component, mean_edge_length):
    """The heat time step ``t = m h^2`` of each vertex: its component's time factor and mean edge length.

    Parameters
    ----------
    part_m : (n_components,) float array
        The time factor of each connected component (``m``, raised by
        :func:`underflow_safe_m` where needed).
    component : (n,) int array
        The component of each vertex.
    mean_edge_length : float or (n,) float array
        ``h``: one value, or each vertex's (its component's, in its unit).

    Returns
    -------
    (n,) float array
        ``part_m[component] * h * h``, constant on each component.

    Examples
    --------
    >>> vertex_time_steps(np.array([1.0]), np.zeros(3, dtype=int), 0.1).round(12).tolist()
    [0.01, 0.01, 0.01]
    >>> vertex_time_steps(np.array([1.0, 4.0]), np.array([0, 1]), np.array([2.0, 0.5])).tolist()
    [4.0, 1.0]
    """
    h = np.broadcast_to(mean_edge_length, component.shape)
    return part_m[component] * h * h
