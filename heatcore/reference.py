"""Reference distances for tests and benchmarks: exact geodesics and the error metric.

Exact geodesics come from MMP (Mitchell, Mount, Papadimitriou) through the
``gdist`` package (the ``test``/``bench`` extras). gdist crashes on
non-manifold meshes: call it on manifold input, or in a child process.

Examples
--------
>>> import numpy as np
>>> round(mean_relative_error(np.array([0.0, 1.1, 2.0]), np.array([0.0, 1.0, 2.0])), 6)
0.05
"""

from typing import NamedTuple

import numpy as np


def import_gdist():
    """The ``gdist`` module, or an ImportError that says why it cannot be used.

    gdist 2.1.0's wheels are built against numpy 1: under numpy 2 its import
    fails with a ``ValueError`` ("numpy.dtype size changed"), turned here into
    the ImportError of a missing package (the ``test`` extra pins ``numpy<2``).

    Returns
    -------
    module

    Raises
    ------
    ImportError
        gdist is not installed, or cannot be imported with this numpy.

    Examples
    --------
    >>> try:
    ...     found = import_gdist().__name__
    ... except ImportError as missing:  # the message names the package
    ...     found = "gdist" if "gdist" in str(missing) else str(missing)
    >>> found
    'gdist'
    """
    try:
        import gdist
    except ValueError as exc:  # binary incompatibility with the installed numpy
        raise ImportError(f"gdist cannot be imported with numpy {np.__version__}: {exc} "
                          "(its wheels are built against numpy 1: install numpy<2)") from exc
    return gdist


def exact_distance(V, F, sources):
    """Exact geodesic distance from ``sources`` on the vertices used by ``F``; ``inf`` elsewhere.

    Parameters
    ----------
    V : (n, 3) float array
    F : (m, 3) int array, a manifold triangle mesh
    sources : int or sequence of int

    Returns
    -------
    (n,) float array

    Examples
    --------
    >>> import pytest
    >>> try:
    ...     _ = import_gdist()
    ... except ImportError as missing:  # not installed, or built against another numpy
    ...     pytest.skip(str(missing))
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
    >>> exact_distance(V, np.array([[0, 1, 2], [1, 3, 2]], dtype=np.int32), [0]).round(4).tolist()
    [0.0, 1.0, 1.0, 1.4142]
    """
    gdist = import_gdist()
    used = np.unique(F)
    vmap = np.full(len(V), -1)
    vmap[used] = np.arange(used.size)
    d = gdist.compute_gdist(
        np.ascontiguousarray(V[used], dtype=np.float64),
        np.ascontiguousarray(vmap[F], dtype=np.int32),
        np.asarray(vmap[np.atleast_1d(sources)], dtype=np.int32),
    )
    out = np.full(len(V), np.inf)
    out[used] = d
    return out


def mean_relative_error(d, exact):
    """Mean of ``|d - exact| / exact`` over vertices with finite exact distance > 0.

    Parameters
    ----------
    d : (n,) float array
        Distances to judge.
    exact : (n,) float array
        Reference distances; vertices where it is 0 (sources) or not finite are skipped.

    Returns
    -------
    float

    Examples
    --------
    >>> round(mean_relative_error(np.array([0.0, 1.1, 1.8, 5.0]), np.array([0.0, 1.0, 2.0, np.inf])), 6)
    0.1
    """
    mask = np.isfinite(exact) & (exact > 0)
    return float(np.mean(np.abs(d[mask] - exact[mask]) / exact[mask]))


class ExactDirections(NamedTuple):
    """Where the exact shortest paths from a source leave it (:func:`exact_directions`).

    Examples
    --------
    >>> found = ExactDirections(np.zeros(1), np.eye(3)[:1], np.ones(1), np.ones(1), np.ones(1, bool))
    >>> found.shortest.tolist()
    [True]
    """

    angle: np.ndarray  #: (k,) angle in the source's scaled frame; NaN where no corner of the source holds the path
    direction: np.ndarray  #: (k, 3) unit vector of each path's first segment
    length: np.ndarray  #: (k,) length of each edge-flip path
    distance: np.ndarray  #: (k,) exact (MMP) distance to each target
    shortest: np.ndarray  #: (k,) bool: the path's length is the exact distance (else it is only locally shortest)


def exact_directions(V, F, source, targets, tolerance=1e-12):
    """The initial direction of the shortest path from ``source`` to each target, as the log map measures it.

    Each path is potpourri3d's edge-flip geodesic (the ``test``/``bench``
    extras); its first segment leaves the source inside one of its corners
    (the nearest whose plane holds it and whose angle contains it), and its
    angle is that corner's start plus the angle from the corner's first side,
    times ``2π/Θ`` at a vertex of cone angle ``Θ``: the angle-scaled frame of
    :func:`heatcore.vector_heat.frames.vertex_frames`, which heatcore's and
    potpourri3d's log maps share up to a rotation. An edge-flip path is only
    locally shortest where its length exceeds MMP's distance (gdist) by more
    than ``tolerance`` (relative): ``shortest`` says which are not.

    Parameters
    ----------
    V : (n, 3) float array
    F : (m, 3) int array, a manifold triangle mesh
    source : int
    targets : (k,) int array, vertices other than ``source``
    tolerance : float, default 1e-12

    Returns
    -------
    ExactDirections

    Examples
    --------
    >>> import pytest
    >>> _ = pytest.importorskip("potpourri3d")
    >>> try:
    ...     _ = import_gdist()
    ... except ImportError as missing:  # not installed, or built against another numpy
    ...     pytest.skip(str(missing))
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
    >>> found = exact_directions(V, np.array([[0, 1, 2], [1, 3, 2]]), 0, np.array([1, 3, 2]))
    >>> np.round(np.degrees(found.angle)).tolist(), found.shortest.tolist()  # a boundary corner: unscaled
    ([0.0, 45.0, 90.0], [True, True, True])
    """
    import potpourri3d as pp3d

    from .domains.intrinsic import IntrinsicTriangulation
    from .vector_heat.frames import vertex_frames

    paths = pp3d.EdgeFlipGeodesicSolver(V, F)
    direction, length = np.zeros((len(targets), 3)), np.zeros(len(targets))
    for i, t in enumerate(targets):
        steps = np.diff(paths.find_geodesic_path(int(source), int(t)), axis=0)
        steps = steps[np.linalg.norm(steps, axis=1) > 0]
        direction[i], length[i] = steps[0] / np.linalg.norm(steps[0]), np.linalg.norm(steps, axis=1).sum()
    frames = vertex_frames(IntrinsicTriangulation.from_mesh(V, F), len(V))
    k = np.flatnonzero(frames.vertex == source)
    f, c = np.divmod(k, 3)
    a, b = V[F[f, (c + 1) % 3]] - V[source], V[F[f, (c + 2) % 3]] - V[source]
    normal = np.cross(a, b)
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    side = a / np.linalg.norm(a, axis=1)[:, None]
    off_plane = np.abs(direction @ normal.T)  # (targets, corners)
    psi = np.arctan2(direction @ np.cross(normal, side).T, direction @ side.T)
    inside = (psi >= -1e-6) & (psi <= frames.angle[k] + 1e-6) & (off_plane < 1e-3)
    best = np.argmin(np.where(inside, off_plane, np.inf), axis=1)
    rows = np.arange(len(targets))
    angle = np.where(inside[rows, best], frames.start[k][best] + frames.scale[source] * psi[rows, best], np.nan)
    distance = exact_distance(V, F, int(source))[targets]
    return ExactDirections(angle, direction, length, distance, length <= distance * (1 + tolerance))
