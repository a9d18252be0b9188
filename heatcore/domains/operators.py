"""The operator bundle: what a domain hands to the heat solver.

A domain (triangle mesh, tetrahedral mesh, polygon mesh, point cloud) reduces
to the same five objects, and the heat method in :mod:`heatcore.heat` is
written once against them.
"""

import functools
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp


@dataclass
class Operators:
    """Discrete differential operators on ``n`` vertices and ``e`` elements.

    Attributes
    ----------
    laplacian : (n, n) sparse matrix
        Positive semi-definite stiffness (cotan) Laplacian ``L = G^T diag(V) G``.
    mass : (n,) float array
        Lumped (diagonal) mass, positive on every vertex.
    gradient : (e * dim, n) sparse matrix
        Per-element gradient; row ``e * dim + k`` is component ``k`` of element
        ``e``'s gradient, in a frame local to the element.
    volumes : (e,) float array
        Element areas (or volumes); the divergence is ``-gradient.T @ diag(volumes)``.
    dim : int
        Number of components of an element gradient.
    boundary : (n,) bool array
        Vertices on the domain boundary (where Dirichlet conditions apply).
    elements : (e, k) int array
        Vertex indices of each element; defines connected components.
    mean_edge_length : float or (n,) float array
        ``h`` in the time step ``t = m h^2``: one value, or per vertex the
        mean edge length of the vertex's connected part.
    unit_exponent : (n,) int array or 0
        Length unit of each vertex's part: the operators measure lengths in
        units of ``2**unit_exponent`` input units (see :mod:`heatcore.domains.parts`),
        so a distance ``d`` on them is ``np.ldexp(d, unit_exponent)`` in the
        input's units. 0 for domains built in the input's units.
    boundary_surface : BoundarySurface or None
        The boundary as outward-wound triangles, where the domain gives it
        (tet meshes): sources on it get Robin heat (:mod:`heatcore.steps.boundary_source`).
    parts : (count, (n,) int array) pair or None
        The connected parts of the vertices, numbered as
        :func:`~heatcore.domains.parts.vertex_components` numbers those of
        ``elements``, where the domain has them already (triangle meshes:
        the parts it found on its input faces); None: the solver finds them.

    Examples
    --------
    >>> from heatcore import TriangleMesh
    >>> ops = TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0).operators
    >>> ops.laplacian.shape, ops.mass.shape, ops.gradient.shape, ops.dim
    ((3, 3), (3,), (2, 3), 2)
    >>> ops.divergence(np.array([[1.0, 0.0]])).round(3).tolist()
    [0.612, -0.612, -0.0]
    """

    laplacian: sp.spmatrix
    mass: np.ndarray
    gradient: sp.spmatrix
    volumes: np.ndarray
    dim: int
    boundary: np.ndarray
    elements: np.ndarray
    mean_edge_length: object
    unit_exponent: object = 0
    boundary_surface: object = None
    parts: object = None

    @functools.cached_property
    def first_corners(self):
        """``elements[:, 0]`` as a contiguous array of its own: the unit field reads it every query.

        Examples
        --------
        >>> from heatcore import TriangleMesh
        >>> TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0).operators.first_corners.tolist()
        [0]
        """
        return np.ascontiguousarray(self.elements[:, 0])

    @property
    def n_vertices(self):
        """Number of vertices the operators act on."""
        return self.mass.shape[0]

    def divergence(self, field):
        """Integrated divergence at vertices of a per-element vector field.

        Parameters
        ----------
        field : (e, dim) float array

        Returns
        -------
        (n,) float array, equal to ``-G^T diag(volumes) field``.
        """
        weighted = (field * self.volumes[:, None]).ravel()
        return -(self.gradient.T @ weighted)


@dataclass
class BoundarySurface:
    """The boundary of a volume domain: triangles wound outward, on the operators' vertices.

    Attributes
    ----------
    positions : (n, 3) float array
        Positions of the operator vertices, in the operators' units.
    faces : (k, 3) int array
        Boundary triangles (operator vertex indices), normals pointing out of the domain.
    area_vectors : (k, 3) float array
        Outward normal times area of each triangle (computed).

    Examples
    --------
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    >>> BoundarySurface(V, np.array([[0, 2, 1]])).area_vectors.tolist()
    [[0.0, 0.0, -0.5]]
    """

    positions: np.ndarray
    faces: np.ndarray
    area_vectors: np.ndarray = None

    def __post_init__(self):
        P = self.positions[self.faces]
        self.area_vectors = 0.5 * np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0])


def laplacian_from_weights(a, b, w, n):
    """Symmetric Laplacian with ``-w`` at ``(a, b)`` and ``(b, a)``, rows summing to zero.

    Repeated pairs add up. Assembled in the upper triangle and mirrored, which is
    several times faster than one COO matrix of all four entries per pair.

    Parameters
    ----------
    a, b : (k,) int arrays
        Vertex pairs.
    w : (k,) float array
        Weight of each pair.
    n : int
        Number of vertices.

    Returns
    -------
    (n, n) scipy.sparse.csr_matrix

    Examples
    --------
    >>> laplacian_from_weights(np.array([0]), np.array([1]), np.array([2.0]), 2).toarray()
    array([[ 2., -2.],
           [-2.,  2.]])
    """
    upper = sp.csr_matrix((-w, (np.minimum(a, b), np.maximum(a, b))), shape=(n, n))
    diagonal = np.bincount(a, weights=w, minlength=n) + np.bincount(b, weights=w, minlength=n)
    return (upper + upper.T + sp.diags(diagonal)).tocsr()
