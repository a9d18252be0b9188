"""The vector heat flow that keeps the curves' normals: the paper's "preserve source normals" option.

The flow ``(M + t L∇) Y = Y0`` is solved with the constraint that at every
point of a signed curve ``Y`` has no component along the curve: the
minimizer of the flow's energy ``½ Y^H A Y - Re(Y0^H Y)`` under the real
constraints ``Re(a_v^H Y) = 0`` (``a_v``: the curve's unit tangent at each vertex
carrying its points, in the vertex's frame) is
``Y = A^-1 (Y0 - Σ λ_v a_v)``, with ``λ`` from the ``k x k`` real system
``Re(a_w^H A^-1 a_v) λ_v = Re(a_w^H A^-1 Y0)``: one more flow per vertex, in
blocks of ``CONSTRAINT_COLUMNS``.

Examples
--------
>>> import numpy as np, heatcore as hc
>>> V, F = hc.io.load_demo_mesh()
>>> solver = hc.SignedHeatSolver(hc.TriangleMesh(V, F, refine=0))
>>> loop = [int(v) for v in hc.region_boundary_curves(F, range(50))[0]]
>>> bool(np.isfinite(solver.distance([loop], keep_normals=True)).all())
True
"""

import numpy as np
import scipy.sparse as sp

from .level_sets import CONSTRAINT_COLUMNS


def tangent_constraints(nodes, is_signed, basis, n):
    """The columns ``a_v`` (``(n, k)`` complex, sparse): one per vertex carrying a signed curve's points.

    A vertex's tangent is the sum of the curve's tangents at the points it
    carries, by hat weight, in its frame: one constraint per vertex, however
    many points lie around it (a point per refined vertex, or several per face).

    Examples
    --------
    >>> from heatcore.signed_heat.curves import CurveNodes
    >>> I = np.eye(3)
    >>> basis = (np.tile(I[2], (2, 1)), np.tile(I[0], (2, 1)), np.tile(I[1], (2, 1)))
    >>> carriers = [(np.array([0]), np.ones(1)), (np.array([1]), np.ones(1))]
    >>> nodes = CurveNodes(carriers, np.array([[0.0, 0, 0], [0, 3, 0]]), np.tile(I[2], (2, 1)), np.zeros(2, int))
    >>> tangent_constraints(nodes, [True], basis, 2).toarray().tolist()   # along +y: i in each frame
    [[1j, 0j], [0j, 1j]]
    """
    _, e1, e2 = basis
    tangent = np.zeros(n, dtype=complex)
    for c, signed in enumerate(is_signed):
        j = np.flatnonzero(nodes.curve == c)
        if not signed or j.size < 2:
            continue
        directions = np.gradient(nodes.positions[j], axis=0)  # central differences inside, one-sided at the ends
        for i, t in zip(j.tolist(), directions):
            vertices, weights = nodes.carriers[i]
            tangent[vertices] += weights * (e1[vertices] @ t + 1j * (e2[vertices] @ t))
    size = np.abs(tangent)
    rows = np.flatnonzero(size > 1e-12 * max(size.max(initial=0.0), 1e-300))
    columns = np.arange(rows.size)
    return sp.csc_matrix((tangent[rows] / size[rows], (rows, columns)), shape=(n, rows.size))


def flow_keeping_normals(vector_solver, rhs, nodes, is_signed, time_scale=1.0):
    """``Y``, the vector heat flow of ``rhs`` with no tangential part at the signed curves' points.

    Examples
    --------
    >>> import heatcore as hc
    >>> from heatcore.signed_heat.curves import curve_nodes, parse_curve
    >>> solver = hc.VectorHeatSolver(hc.TriangleMesh(*hc.io.load_demo_mesh(), refine=0))
    >>> nodes = curve_nodes([parse_curve([0, 1])], lambda v, p: solver.sources(v, points=p))
    >>> rhs = np.zeros(solver.operator_basis.e1.shape[0], dtype=complex)
    >>> rhs[[0, 1]] = 1.0
    >>> A = tangent_constraints(nodes, [True], solver.operator_basis, rhs.size)
    >>> Y = flow_keeping_normals(solver, rhs, nodes, [True])
    >>> bool(np.abs((A.conj().T @ Y).real).max() < 1e-9)   # no part along the curve at its vertices
    True
    """
    n = rhs.size
    A = tangent_constraints(nodes, is_signed, vector_solver.operator_basis, n)
    Y = vector_solver.diffuse(rhs, time_scale)
    k = A.shape[1]
    if k == 0:
        return Y
    system = np.empty((k, k))
    for start in range(0, k, CONSTRAINT_COLUMNS):
        block = vector_solver.diffuse(A[:, start:start + CONSTRAINT_COLUMNS].toarray(), time_scale)
        system[:, start:start + block.shape[1]] = (A.conj().T @ block).real
    lam = np.linalg.lstsq(system, (A.conj().T @ Y).real, rcond=None)[0]
    return vector_solver.diffuse(rhs - A @ lam, time_scale)
