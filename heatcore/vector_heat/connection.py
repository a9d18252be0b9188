"""The connection Laplacian: the cotan Laplacian of tangent vectors, with the rotation along each edge.

With vertex frames (:mod:`heatcore.vector_heat.frames`), transporting a
vector from vertex ``i`` to vertex ``j`` along their edge rotates its
coordinate by ``ρ_ij`` (the edge's direction at ``j``, turned by ``π``, minus
its direction at ``i``): the discrete Levi-Civita connection. The connection
Laplacian is the Hermitian matrix of the energy ``Σ w_ij |z_j - e^{iρ_ij} z_i|²``
with the cotan weights ``w_ij`` of the same triangles, assembled per face
side like :func:`heatcore.domains.operators.laplacian_from_weights`, so
repeated edges and faces with a repeated vertex (a Δ-complex) need nothing
special. With every ``ρ = 0`` it is the cotan Laplacian.

Examples
--------
>>> import numpy as np
>>> from heatcore.domains.intrinsic import IntrinsicTriangulation
>>> from heatcore.vector_heat.basis import tangent_frames
>>> from heatcore.vector_heat.frames import vertex_frames
>>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
>>> F = np.array([[0, 1, 2], [1, 3, 2]])
>>> tri = IntrinsicTriangulation.from_mesh(V, F)
>>> frames = vertex_frames(tri, 4)
>>> L = connection_laplacian(tri, frames)
>>> bool(np.allclose(L.toarray(), L.toarray().conj().T))   # Hermitian
True
>>> _, e1, e2 = tangent_frames(V, F, tri, frames)
>>> z = e1[:, 0] + 1j * e2[:, 0]   # the constant field (1, 0, 0), in each vertex's frame
>>> bool(abs(L @ z).max() < 1e-12)   # a flat mesh: it is parallel
True
"""

import numpy as np
import scipy.sparse as sp

from ..domains.intrinsic import NEXT, PREV, corner_cotangents


def connection_laplacian(tri, frames):
    """The (n, n) complex Hermitian connection Laplacian of an intrinsic triangulation.

    Parameters
    ----------
    tri : IntrinsicTriangulation
    frames : VertexFrames
        Of the same triangulation.

    Returns
    -------
    (n, n) complex scipy.sparse.csr_matrix
        Positive semi-definite where the cotan weights are non-negative
        (an intrinsic Delaunay triangulation).

    Examples
    --------
    >>> from heatcore.domains.intrinsic import IntrinsicTriangulation
    >>> from heatcore.vector_heat.frames import vertex_frames
    >>> V = np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1], [0, 0, 0]], float)   # a tetrahedron: curved
    >>> tri = IntrinsicTriangulation.from_mesh(V, np.array([[0, 1, 2], [0, 3, 1], [1, 3, 2], [0, 2, 3]]))
    >>> L = connection_laplacian(tri, vertex_frames(tri, 4))
    >>> bool(np.linalg.eigvalsh(L.toarray()).min() > 1e-3)   # no parallel field: definite
    True
    """
    faces = tri.faces
    m = faces.shape[0]
    n = frames.scale.size
    h = np.arange(3 * m)
    weight = 0.5 * corner_cotangents(tri.lengths).ravel()
    tail = faces[:, NEXT].ravel()
    head = faces[:, PREV].ravel()
    rotation = np.exp(1j * frames.transport(h))
    rows = np.concatenate([tail, head, tail, head])
    cols = np.concatenate([tail, head, head, tail])
    data = np.concatenate([weight, weight, -weight * rotation.conj(), -weight * rotation]).astype(np.complex128)
    return sp.csr_matrix((data, (rows, cols)), shape=(n, n))


def translation_matrix(tri, frames):
    """The translation part of the affine connection: ``(C w)_i = Σ_j w_ij e_ij w_j``.

    ``e_ij`` is the edge from ``i`` to ``j`` as a vector of ``i``'s frame
    (its length, at its scaled direction) and ``w_ij`` the cotan weight, per
    face side as in :func:`connection_laplacian`. With it the affine heat flow
    of a point (Soliman and Sharp's affine heat method) splits into a scalar
    heat flow ``u`` and a vector one: ``(M + t L∇) z = -t C u``, and ``z / u`` at
    ``i`` is the vector from the source to ``i``, carried to ``i``'s frame
    (exactly, on a flat mesh).

    Returns
    -------
    (n, n) complex scipy.sparse.csr_matrix

    Examples
    --------
    >>> from heatcore.domains.intrinsic import IntrinsicTriangulation
    >>> from heatcore.vector_heat.frames import vertex_frames
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0]], float)
    >>> tri = IntrinsicTriangulation.from_mesh(V, np.array([[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 1]]))
    >>> C = translation_matrix(tri, vertex_frames(tri, 5))
    >>> bool(abs((C @ np.ones(5))[0]) < 1e-12)   # a flat interior vertex: the edge vectors balance
    True
    """
    faces = tri.faces
    n = frames.scale.size
    h = np.arange(3 * faces.shape[0])
    weight = 0.5 * corner_cotangents(tri.lengths).ravel() * tri.lengths.ravel()
    tail = faces[:, NEXT].ravel()
    head = faces[:, PREV].ravel()
    rows = np.concatenate([tail, head])
    cols = np.concatenate([head, tail])
    data = np.concatenate([weight * np.exp(1j * frames.tail_direction(h)), weight * np.exp(1j * frames.head_direction(h))])
    return sp.csr_matrix((data, (rows, cols)), shape=(n, n))
