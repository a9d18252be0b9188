"""Step 2 of the heat method: the unit field ``X = -grad f / |grad f|`` and its divergence.

``f`` is :func:`log_ratio` of the heat after the short and the long step
(:mod:`heatcore.steps.time_step`); the functions below take any field
decreasing away from the sources (the heat itself, too).

The right-hand side of the Poisson step is ``-div X = G^T (volumes * X)``
with ``G`` the domain's gradient operator; :func:`minus_divergence` computes
it for one heat field, :func:`minus_divergence_columns` for ``k`` heat fields
at once (in tiles of columns whose element arrays stay in the processor's
cache), each column with exactly the arithmetic of one.

Examples
--------
>>> import numpy as np, heatcore as hc
>>> mesh = hc.TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0)
>>> ops = mesh.operators
>>> b = minus_divergence(ops, ops.gradient.T, np.array([1.0, 0.5, 0.5]), 1.0)
>>> b.shape, bool(abs(b.sum()) < 1e-12)   # a divergence sums to zero
((3,), True)
"""

import numpy as np

#: A heat gradient smaller than this times ``u / h`` is rounding noise (an exact
#: saddle of the heat) and gets no direction in the unit field.
SADDLE_GRADIENT = 1e-9

#: The unit field of ``k`` heat fields is computed in tiles of columns whose
#: element arrays take about this many bytes: elementwise passes over arrays
#: that stay in the processor's cache (measured fastest on nefertiti and spot).
UNIT_FIELD_TILE_BYTES = 4 * 2**20


def log_ratio(u_short, u_long):
    """``log u_short - log u_long``: the field whose gradient gives the distance's direction.

    One backward Euler step of length ``s`` falls like ``exp(-d / sqrt(s))`` times a factor that,
    to first order, does not depend on ``s`` (the spreading of geodesics). The difference of the logs
    is then ``-d (1/sqrt(s_short) - 1/sqrt(s_long))`` up to a constant: linear in the distance, which
    elements interpolate exactly (the heat itself falls by a factor of about 3 per edge, and its
    linear interpolation bends the gradient), and free of the spreading factor (the log of one heat
    alone keeps it: on curved meshes its distances came out too long, spot 1.21% -> 1.54%). Where
    the short step's heat is 0 or negative (an unreached part, underflow) the result is not finite:
    its elements get no direction.

    Parameters
    ----------
    u_short, u_long : (n,) or (n, k) float arrays
        The heat after the short and the long step, from the same impulse.

    Returns
    -------
    float array shaped like ``u_short``

    Examples
    --------
    >>> d = np.array([0.0, 1.0, 2.0])
    >>> f = log_ratio(np.exp(-d / 1.0), 3 * np.exp(-d / 2.0))  # steps 1 and 4, any factor
    >>> np.diff(f).round(12).tolist()
    [-0.5, -0.5]
    """
    with np.errstate(divide="ignore", invalid="ignore"):
        f = np.log(u_short)
        f -= np.log(u_long)
    return f


def squared_norms(g):
    """``(g**2).sum(axis=0)`` for a few components, component by component (twice as fast as over rows).

    Examples
    --------
    >>> squared_norms(np.array([[3.0, 0.0], [4.0, 2.0]])).tolist()
    [25.0, 4.0]
    """
    norm2 = g[0] * g[0]
    square = np.empty_like(norm2) if len(g) > 1 else None  # one scratch array for every component
    for component in g[1:]:
        norm2 += np.multiply(component, component, out=square)
    return norm2


def scale_to_unit(g, u_first, weights, element_h):
    """Turn heat gradients into ``-weights * g / |g|`` in place (0 where they vanish or are noise).

    Parameters
    ----------
    g : (dim, m) or (dim, k, m) float array
        Gradient components axis first, for ``m`` elements (and ``k`` heat
        fields: each gets exactly the arithmetic of one).
    u_first : (m,) or (k, m) float array
        The heat at each element's first vertex.
    weights : float or (m,) float array
        Element volumes (for ``-div X``) or 1.
    element_h : float or (m,) float array
        Mean edge length of each element's part, in the operators' units.

    Returns
    -------
    float array shaped like ``g``
        ``g`` itself, or a new array where non-finite gradients were zeroed.

    Examples
    --------
    >>> scale_to_unit(np.array([[3.0], [4.0]]), np.array([1.0]), 1.0, 1.0).ravel().round(12).tolist()
    [-0.6, -0.8]
    """
    norm2 = squared_norms(g)
    if not np.isfinite(norm2.sum()):  # rare: a non-finite gradient gets no direction
        g = np.where(np.isfinite(g), g, 0.0)
        norm2 = squared_norms(g)
    # Far from the sources u (and so g) can be 1e-200, whose square
    # underflows: recompute those norms with hypot, which does not.
    tiny = np.nonzero(norm2 < 1e-280) if norm2.size and norm2.min() < 1e-280 else None
    norm = np.sqrt(norm2, out=norm2)
    if tiny is not None:
        redo = np.hypot(g[0][tiny], g[1][tiny])
        for axis in range(2, len(g)):
            redo = np.hypot(redo, g[axis][tiny])
        norm[tiny] = np.where(redo > 0, redo, np.inf)  # a zero gradient gets X = 0
    # A gradient below the rounding of u itself (an exact saddle of the heat, as at the far point
    # of a symmetric part: 2e-15 of u per edge length there, 5e-3 and more elsewhere) has no
    # direction: X = 0 there, not a direction made of rounding noise that any change of
    # elimination order (another part beside it) would turn elsewhere.
    scale = np.multiply(norm, element_h)  # a scratch array, then the scale
    np.putmask(norm, scale < SADDLE_GRADIENT * np.abs(u_first), np.inf)
    np.negative(np.divide(weights, norm, out=scale), out=scale)  # -(w / |g|) is (-w) / |g|, bit for bit
    for component in g:  # axis by axis: 3x faster than broadcasting over rows of 2 or 3
        component *= scale
    return g


def unit_field(ops, u, weights, element_h):
    """``weights * X`` per element, ``(m, dim)``, for one heat field ``u`` (see :func:`scale_to_unit`).

    Examples
    --------
    >>> import heatcore as hc
    >>> ops = hc.TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0).operators
    >>> X = unit_field(ops, np.array([1.0, 0.5, 0.5]), 1.0, 1.0)
    >>> X.shape, float(np.linalg.norm(X).round(12))
    ((1, 2), 1.0)
    """
    g = (ops.gradient @ u).reshape(-1, ops.dim)
    return scale_to_unit(g.T, u[ops.first_corners], weights, element_h).T


def minus_divergence(ops, gradient_transposed, u, element_h):
    """``-div X = G^T (volumes * X)`` for one heat field ``u`` (n,).

    Examples
    --------
    >>> import heatcore as hc
    >>> ops = hc.TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0).operators
    >>> minus_divergence(ops, ops.gradient.T, np.array([1.0, 0.5, 0.5]), 1.0).shape
    (3,)
    """
    return gradient_transposed @ unit_field(ops, u, ops.volumes, element_h).ravel()


def tile_columns(ops):
    """Heat fields per tile of :func:`minus_divergence_columns`: ``8 (dim + 5)`` bytes per element and column within ``UNIT_FIELD_TILE_BYTES``.

    Examples
    --------
    >>> import heatcore as hc
    >>> tile_columns(hc.TriangleMesh(*hc.io.load_demo_mesh()).operators) >= 1
    True
    """
    return max(1, int(UNIT_FIELD_TILE_BYTES // (8 * (ops.dim + 5) * ops.elements.shape[0])))


def minus_divergence_columns(ops, gradient_transposed, u, element_h):
    """:func:`minus_divergence` of the ``k`` columns of ``u`` (n, k): an ``(n, k)`` array, columns contiguous.

    The unit field is vectorized over tiles of columns (:func:`tile_columns`);
    the sparse products go column by column (scipy's one-column product is
    the faster one). Column ``j`` is bit for bit :func:`minus_divergence` of
    ``u[:, j]``.

    Examples
    --------
    >>> import heatcore as hc
    >>> ops = hc.TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0).operators
    >>> u = np.array([[1.0, 0.2], [0.5, 1.0], [0.5, 0.3]])
    >>> b = minus_divergence_columns(ops, ops.gradient.T, u, 1.0)
    >>> bool((b[:, 1] == minus_divergence(ops, ops.gradient.T, u[:, 1], 1.0)).all())
    True
    """
    n, k = u.shape
    gradient, first, dim = ops.gradient, ops.first_corners, ops.dim
    b = np.empty((n, k), order="F")
    width = tile_columns(ops)
    for start in range(0, k, width):
        tile = range(start, min(start + width, k))
        if len(tile) == 1:
            b[:, start] = minus_divergence(ops, gradient_transposed, u[:, start], element_h)
            continue
        g = np.empty((dim, len(tile), first.size))  # components first: contiguous passes over the tile
        u_first = np.empty((len(tile), first.size))
        for i, j in enumerate(tile):
            g[:, i, :] = (gradient @ u[:, j]).reshape(first.size, dim).T
            u_first[i] = u[:, j][first]
        g = scale_to_unit(g, u_first, ops.volumes, element_h)
        for i, j in enumerate(tile):
            b[:, j] = gradient_transposed @ g[:, i, :].T.ravel()  # element-major, as G's rows
    return b
