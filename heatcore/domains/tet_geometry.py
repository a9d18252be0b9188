"""Tet geometry: signed volumes, faces, the boundary surface, the dihedral-angle cotan Laplacian and gradient.

The pieces :class:`~heatcore.domains.tet.TetMesh` builds its operators from,
as plain functions of vertex positions ``V`` (n, 3) and tets ``T`` (m, 4).
``L = G^T diag(vol) G`` holds between :func:`cotan_laplacian` and
:func:`tet_gradient` on positively oriented tets.

Examples
--------
>>> import numpy as np
>>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
>>> T = np.array([[0, 1, 2, 3]])
>>> L, G, vol = cotan_laplacian(V, T), tet_gradient(V, T), signed_volumes(V, T)
>>> import scipy.sparse as sp
>>> bool(np.allclose(L.toarray(), (G.T @ sp.diags(np.repeat(vol, 3)) @ G).toarray()))
True
"""

import numpy as np
import scipy.sparse as sp

from .operators import BoundarySurface, Operators, laplacian_from_weights
from .parts import part_means, vertex_components

#: Face opposite each corner of a positively oriented tet, wound so that its
#: normal points out of the tet.
TET_FACES = np.array([[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]])

#: The six edges (i, j) of a tet and, in the same order, the opposite edges (k, l).
TET_EDGES = np.array([[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]])
TET_OPPOSITE_EDGES = np.array([[2, 3], [1, 3], [1, 2], [0, 3], [0, 2], [0, 1]])

#: A tet whose volume is below this fraction of its longest edge cubed is
#: flat: ``6 |vol| <= FLAT_TET_TOLERANCE * l_max^3`` (a regular tet has
#: ``6 vol / l^3 = 0.71``).
FLAT_TET_TOLERANCE = 1e-9


def signed_volumes(V, T):
    """Signed volume of each tet, positive when ``det(v1 - v0, v2 - v0, v3 - v0) > 0``.

    Parameters
    ----------
    V : (n, 3) float array
    T : (m, 4) int array

    Returns
    -------
    (m,) float array

    Examples
    --------
    >>> import numpy as np
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    >>> signed_volumes(V, np.array([[0, 1, 2, 3], [0, 2, 1, 3]])).tolist()
    [0.16666666666666666, -0.16666666666666666]
    """
    P = V[T]
    e1, e2, e3 = P[:, 1] - P[:, 0], P[:, 2] - P[:, 0], P[:, 3] - P[:, 0]
    return np.einsum("ij,ij->i", e1, np.cross(e2, e3)) / 6.0


def tet_faces(T):
    """All four faces of every tet, outward-wound for positively oriented tets.

    Parameters
    ----------
    T : (m, 4) int array

    Returns
    -------
    (4 m, 3) int array; rows ``4 e .. 4 e + 3`` are the faces opposite corners 0..3 of tet ``e``.

    Examples
    --------
    >>> import numpy as np
    >>> tet_faces(np.array([[0, 1, 2, 3]])).tolist()
    [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]]
    """
    return T[:, TET_FACES].reshape(-1, 3)


def boundary_faces(T):
    """Faces that belong to exactly one tet, and the number of faces shared by more than two.

    Parameters
    ----------
    T : (m, 4) int array, positively oriented tets

    Returns
    -------
    faces : (k, 3) int array, outward-wound boundary faces
    n_overshared : int
        Faces used by three tets or more (the tets overlap there).

    Examples
    --------
    >>> import numpy as np
    >>> boundary_faces(np.array([[0, 1, 2, 3], [1, 2, 3, 4]]))[0].shape
    (6, 3)
    """
    faces = tet_faces(T)
    _, inverse, counts = np.unique(np.sort(faces, axis=1), axis=0, return_inverse=True, return_counts=True)
    inverse = inverse.ravel()
    return faces[counts[inverse] == 1], int((counts > 2).sum())


def cotan_laplacian(V, T):
    """Cotan Laplacian of a tet mesh from the dihedral angles.

    ``L_ij = -(1/6) sum l_kl cot(theta_kl)`` over the tets containing edge
    ``ij``, where ``kl`` is the opposite edge of the tet, ``l_kl`` its length and
    ``theta_kl`` the dihedral angle at it; ``L_ii = -sum_j L_ij``. It equals
    ``G^T diag(vol) G`` for the per-tet gradient ``G`` of :func:`tet_gradient`.

    Parameters
    ----------
    V : (n, 3) float array
    T : (m, 4) int array, positively oriented, non-flat tets

    Returns
    -------
    (n, n) scipy.sparse.csr_matrix, symmetric positive semi-definite on meshes
    whose dihedral angles are not too obtuse.

    Examples
    --------
    >>> import numpy as np
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    >>> L = cotan_laplacian(V, np.array([[0, 1, 2, 3]]))
    >>> np.allclose(L @ np.ones(4), 0)
    True
    """
    P = V[T]
    normals = _face_area_vectors(P)  # (m, 4, 3), outward, |N| = face area
    i, j = TET_EDGES.T
    k, l = TET_OPPOSITE_EDGES.T
    # The dihedral angle at edge kl is between the faces opposite i and j.
    Ni, Nj = normals[:, i], normals[:, j]
    cos_part = -np.einsum("etc,etc->et", Ni, Nj)  # = A_i A_j cos(theta)
    sin_part = np.linalg.norm(np.cross(Ni, Nj), axis=2)  # = A_i A_j sin(theta)
    cot = cos_part / sin_part
    length = np.linalg.norm(P[:, l] - P[:, k], axis=2)
    w = (length * cot / 6.0).ravel()
    a, b = T[:, i].ravel(), T[:, j].ravel()
    return laplacian_from_weights(a, b, w, V.shape[0])


def tet_gradient(V, T):
    """Gradient of the piecewise linear interpolant, one 3D vector per tet.

    Parameters
    ----------
    V : (n, 3) float array
    T : (m, 4) int array, positively oriented, non-flat tets

    Returns
    -------
    (3 m, n) scipy.sparse.csr_matrix; row ``3 e + k`` is component ``k`` (x, y, z) of tet ``e``.

    Examples
    --------
    >>> import numpy as np
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    >>> (tet_gradient(V, np.array([[0, 1, 2, 3]])) @ V[:, 0]).tolist()
    [1.0, 0.0, 0.0]
    """
    P = V[T]
    vol = signed_volumes(V, T)
    # grad of barycentric coordinate c = -(outward area vector of the opposite face) / (3 vol)
    grad_hat = -_face_area_vectors(P) / (3.0 * vol[:, None, None])  # (m, 4 corners, 3)
    m = T.shape[0]
    rows = np.broadcast_to(3 * np.arange(m)[:, None, None] + np.arange(3)[None, None, :], grad_hat.shape)
    cols = np.broadcast_to(T[:, :, None], grad_hat.shape)
    return sp.csr_matrix((grad_hat.ravel(), (rows.ravel(), cols.ravel())), shape=(3 * m, V.shape[0]))


def tet_operators(V, T, boundary, faces=None):
    """Operator bundle of a tet mesh.

    Parameters
    ----------
    V : (n, 3) float array
    T : (m, 4) int array, positively oriented, non-flat tets using every vertex
    boundary : (n,) bool array, vertices on the boundary surface
    faces : (k, 3) int array, optional
        The boundary surface, wound outward; kept as the bundle's
        ``boundary_surface`` (the Robin heat of sources on the boundary).

    Returns
    -------
    Operators
        ``dim = 3``, volumes = tet volumes, mass = a quarter of the incident tet volumes.

    Examples
    --------
    >>> import numpy as np
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    >>> ops = tet_operators(V, np.array([[0, 1, 2, 3]]), np.ones(4, bool))
    >>> ops.dim, ops.mass.round(4).tolist()
    (3, [0.0417, 0.0417, 0.0417, 0.0417])
    """
    n = V.shape[0]
    vol = signed_volumes(V, T)
    mass = np.bincount(T.ravel(), weights=np.repeat(vol / 4.0, 4), minlength=n)
    edges = np.unique(np.sort(T[:, TET_EDGES].reshape(-1, 2), axis=1), axis=0)
    count, part = vertex_components(T, n)
    lengths = np.linalg.norm(V[edges[:, 0]] - V[edges[:, 1]], axis=1)
    h = part_means(lengths, part[edges[:, 0]], count)[part]  # each part its own time step
    surface = None if faces is None else BoundarySurface(V, faces)
    return Operators(cotan_laplacian(V, T), mass, tet_gradient(V, T), vol, 3, boundary, T, h, 0, surface)


def _face_area_vectors(P):
    """Outward area vectors of the faces opposite each corner: (m, 4, 3) for corners (m, 4, 3)."""
    F = P[:, TET_FACES]  # (m, 4, 3 corners, 3)
    return 0.5 * np.cross(F[:, :, 1] - F[:, :, 0], F[:, :, 2] - F[:, :, 0])
