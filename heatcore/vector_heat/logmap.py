"""The logarithmic map's pieces: two vector heat flows, the angle between them, polar to Cartesian.

The log map at ``y`` is ``r (cos θ, sin θ)`` in the source's tangent plane:

* ``θ``, the direction at the source of the geodesic towards ``y``, from the
  *affine* heat flow (Soliman and Sharp's affine heat method, geometry-central's
  ``AffineLocal`` strategy, which potpourri3d 1.4 uses by default): a point
  diffused with the affine connection, whose translation part moves it along
  each edge. Its homogeneous part is the scalar heat ``u`` (``(M + t L) u = δ``),
  and its vector part solves ``(M + t L∇) z = -t C u``
  (:func:`~heatcore.vector_heat.connection.translation_matrix`): ``z / u`` at
  ``y`` is the vector from the source to ``y``, carried to ``y``. The flow ``H``
  of the source's ``e1`` carries ``e1`` along the same geodesics, and angles
  are kept, so ``θ = arg(z / H)``. On a flat mesh both are exact whatever the
  time step. The paper's §5 construction (the flow of outward unit vectors
  around the source, ``R``) measured far worse on a flat grid: its direction
  follows the discrete heat kernel's gradient, 0.03 rad off on average on a
  60 x 60 Delaunay grid (0.46 rad with the one-ring as the ball), against
  1e-15 for the affine flow (docs/vector-heat.md);
* ``r``: the scalar geodesic distance of :class:`~heatcore.HeatSolver` (the
  smooth heat method, or ``accuracy="high"``), not ``|z / u|``, which is
  0.67% off on an icosphere of 10,242 vertices where the heat method is 0.50%
  off and the eikonal pass 0.08%.

Vertices that no geodesic reaches get ``(inf, inf)``.

Examples
--------
>>> import numpy as np
>>> log_coordinates(np.array([0.0, 2.0, np.inf]), np.array([0.0, np.pi / 2, 1.0])).round(12).tolist()
[[0.0, 0.0], [0.0, 2.0], [inf, inf]]
"""

import numpy as np


def frame_coordinates(vectors, e1, e2):
    """3D ``vectors`` (k, 3) as complex coordinates ``x + iy`` in the frames ``e1``, ``e2`` (k, 3).

    Examples
    --------
    >>> frame_coordinates(np.array([[1.0, 2.0, 3.0]]), np.eye(3)[[1]], np.eye(3)[[2]])
    array([2.+3.j])
    """
    return np.einsum("ij,ij->i", vectors, e1) + 1j * np.einsum("ij,ij->i", vectors, e2)


def source_impulse(basis, source, direction, n):
    """The vector heat flow's right-hand side for one tangent ``direction`` (3D) at ``source``.

    Each of the source's hat vertices gets its weight times the unit vector
    ``direction`` expressed in its own frame.

    Parameters
    ----------
    basis : (normal, e1, e2) of the operator vertices
    source : TangentSource
    direction : (3,) float array, in the source's tangent plane
    n : int
        Operator vertices.

    Returns
    -------
    (n,) complex array

    Examples
    --------
    >>> from heatcore.vector_heat.sources import TangentSource
    >>> I = np.eye(3)
    >>> basis = (np.tile(I[2], (2, 1)), np.tile(I[0], (2, 1)), np.tile(I[1], (2, 1)))
    >>> source = TangentSource(np.array([1]), np.ones(1), np.zeros(3), I[2], I[0], I[1], "vertex 1")
    >>> source_impulse(basis, source, np.array([0.0, 3.0, 0.0]), 2).tolist()
    [0j, 1j]
    """
    _, e1, e2 = basis
    k = source.vertices.size
    local = frame_coordinates(np.tile(direction, (k, 1)), e1[source.vertices], e2[source.vertices])
    rhs = np.zeros(n, dtype=complex)
    np.add.at(rhs, source.vertices, source.weights * local / np.maximum(np.abs(local), 1e-300))
    return rhs


def point_offsets(V, basis, source, n):
    """The affine flow's own right-hand side: each hat vertex's offset from the source point, in its frame.

    A point source on a face is spread on the corners ``x_k`` of its refined
    triangle with weights ``b_k``; the affine flow starts at each of them
    with the vector ``x_k - p`` (times ``b_k``), so that on a flat mesh it
    describes the point ``p`` exactly. Zero for a vertex source.

    Examples
    --------
    >>> from heatcore.vector_heat.sources import TangentSource
    >>> I = np.eye(3)
    >>> V = np.array([[0.0, 0, 0], [1, 0, 0]])
    >>> basis = (np.tile(I[2], (2, 1)), np.tile(I[0], (2, 1)), np.tile(I[1], (2, 1)))
    >>> source = TangentSource(np.array([0, 1]), np.array([0.75, 0.25]), np.array([0.25, 0, 0]), I[2], I[0], I[1], "face 0")
    >>> point_offsets(V, basis, source, 2).tolist()
    [(-0.1875+0j), (0.1875+0j)]
    """
    _, e1, e2 = basis
    k = source.vertices
    rhs = np.zeros(n, dtype=complex)
    np.add.at(rhs, k, source.weights * frame_coordinates(V[k] - source.position, e1[k], e2[k]))
    return rhs


def flow_angle(vector, horizontal):
    """Angle from the flow ``horizontal`` to the flow ``vector`` at each vertex (0 where either vanishes).

    Examples
    --------
    >>> (flow_angle(np.array([1j, 0j]), np.array([2.0 + 0j, 1.0])) / np.pi).tolist()
    [0.5, 0.0]
    """
    return np.angle(vector * horizontal.conj())


def log_coordinates(distance, angle):
    """``distance (cos angle, sin angle)`` as (n, 2); ``(inf, inf)`` where the distance is not finite.

    Examples
    --------
    >>> log_coordinates(np.array([1.0]), np.array([np.pi])).round(12).tolist()
    [[-1.0, 0.0]]
    """
    reached = np.isfinite(distance)
    out = np.full((distance.size, 2), np.inf)
    out[reached] = distance[reached, None] * np.column_stack([np.cos(angle[reached]), np.sin(angle[reached])])
    return out
