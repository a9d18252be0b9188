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

import numpy as np


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
    >>> _ = pytest.importorskip("gdist")  # the test and bench extras
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
    >>> exact_distance(V, np.array([[0, 1, 2], [1, 3, 2]], dtype=np.int32), [0]).round(4).tolist()
    [0.0, 1.0, 1.0, 1.4142]
    """
    import gdist

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
