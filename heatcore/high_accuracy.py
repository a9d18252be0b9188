"""accuracy="high": which eikonal pass runs, and the compiled pass's corners (kept in the domain's cache).

Where numba is installed (the ``fast`` extra) the distance comes from the
compiled fast marching of :mod:`heatcore.fast_marching`, run from the
sources alone: no heat flow is solved. Without numba, the vectorized pass of
:func:`heatcore.eikonal.refine_distance` takes the heat distance as its order.
Both use the same triangle update over the same corners (docs/accuracy-high.md).

Examples
--------
>>> import numpy as np, heatcore as hc
>>> domain = hc.TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0)
>>> d = high_accuracy_distance(domain, domain.source_pins([0]), lambda: hc.HeatSolver(domain).distance([0]))
>>> d.round(6).tolist()
[0.0, 1.414214, 1.414214]
"""

import numpy as np

from .eikonal import TOL, refine_distance
from .options import AUTO_HIGH_VERTICES


def high_accuracy_distance(domain, pins, heat_distance, tol=TOL):
    """The ``accuracy="high"`` distance from ``pins``, in the input's units.

    With numba (:mod:`heatcore.fast_marching`) the pass runs from the pins
    alone and ``heat_distance`` is not called; without it, the vectorized
    pass of :func:`refine_distance` takes ``heat_distance()`` as its order.

    Parameters
    ----------
    domain : Domain with ``supports_high_accuracy``
    pins : SourcePins
    heat_distance : callable
        Returns the heat method's distance from ``pins`` (as :func:`refine_distance`'s ``phi``).
    tol : float

    Examples
    --------
    >>> import numpy as np, heatcore as hc
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
    >>> domain = hc.TriangleMesh(V, [[0, 1, 2], [1, 3, 2]])
    >>> smooth = hc.HeatSolver(domain)
    >>> pins = domain.source_pins([0])
    >>> d = high_accuracy_distance(domain, pins, lambda: smooth.distance_from_pins(pins))
    >>> round(float(d[3]), 6)
    1.414214
    """
    if high_accuracy_needs_heat():
        return refine_distance(domain, heat_distance(), pins, tol=tol)
    return march_from_pins(domain, pins, tol)


def resolve_accuracy(settings, domain):
    """``settings`` (:class:`~heatcore.settings.SolverSettings`) with ``accuracy="auto"`` resolved for ``domain``.

    "high" for one query (the settings' ``intent``) on a domain that takes it
    (triangle meshes) of at least ``AUTO_HIGH_VERTICES`` operator vertices,
    where the compiled march is installed: it solves no heat, and is then
    faster than the heat method; "smooth" otherwise (every other intent: a
    solver kept for reuse, Blender's interactive one).

    Examples
    --------
    >>> import numpy as np, heatcore as hc
    >>> small = hc.TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0)
    >>> one = hc.SolverSettings(intent="one query")
    >>> one.accuracy, resolve_accuracy(one, small).accuracy, resolve_accuracy(one.replace(accuracy="high"), small).accuracy
    ('auto', 'smooth', 'high')
    """
    if settings.accuracy != "auto":
        return settings
    high = (settings.intent == "one query" and domain.supports_high_accuracy
            and domain.n_vertices >= AUTO_HIGH_VERTICES and not high_accuracy_needs_heat())
    return settings.replace(accuracy="high" if high else "smooth")


def high_accuracy_needs_heat():
    """Whether the ``accuracy="high"`` pass needs the heat distance: without numba, as the vectorized pass's order.

    Examples
    --------
    >>> from heatcore import fast_marching
    >>> high_accuracy_needs_heat() == (not fast_marching.available())
    True
    """
    from . import fast_marching  # numba, imported on first use

    return not fast_marching.available()


def march_from_pins(domain, pins, tol=TOL):
    """Compiled fast marching from ``pins`` over the domain's eikonal triangles, in the input's units (needs numba).

    ``inf`` where no pin can be reached.

    Examples
    --------
    >>> import numpy as np, heatcore as hc
    >>> domain = hc.TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0)
    >>> from heatcore import fast_marching
    >>> if fast_marching.available():
    ...     print(march_from_pins(domain, domain.source_pins([0])).round(6).tolist())
    ... else:
    ...     print([0.0, 1.414214, 1.414214])
    [0.0, 1.414214, 1.414214]
    """
    from . import fast_marching

    d = np.full(domain.n_vertices, np.inf)
    d[pins.vertices] = pins.values
    readers = domain.derived.get_or_build(  # kept in the domain's cache
        ("fast marching", None),
        lambda: fast_marching.Readers.of_triangles(domain.n_vertices, *domain.eikonal_triangles()),
    )
    fast_marching.march(readers, d, pins.vertices, tol)
    return np.ldexp(d, domain.vertex_unit_exponent)
