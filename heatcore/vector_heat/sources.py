"""Sources of the vector heat method: a vertex or a point on a face, with its tangent plane.

A source is where vectors start: its hat weights on the operator vertices
(one vertex; or, for a point on a face, the corners of the refined triangle
holding it, as :meth:`~heatcore.domains.triangle.TriangleMesh.source_pins`
gives them), its position, and the frame its vectors and log-map
coordinates are given in: the vertex's own tangent basis
(:meth:`~heatcore.vector_heat.VectorHeatSolver.tangent_basis`), or the
face's plane with ``e1`` along the face's first side (corner 0 to corner 1).
A vector given in 3D is projected on that plane; one with no tangent part
(zero, or along the normal) is refused with a typed error.

Examples
--------
>>> import numpy as np, heatcore as hc
>>> from heatcore.vector_heat import VectorHeatSolver
>>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
>>> solver = VectorHeatSolver(hc.TriangleMesh(V, [[0, 1, 2]], refine=0))
>>> source = solver.sources(points=([0], [[0.2, 0.3, 0.5]]))[0]
>>> source.position.round(3).tolist(), source.e1.tolist()
([0.3, 0.5, 0.0], [1.0, 0.0, 0.0])
"""

from dataclasses import dataclass

import numpy as np

from ..domains.sources import index_list
from ..errors import InvalidOptionError, InvalidSourceError

#: A vector whose tangent part is shorter than this fraction of its length has no direction on the surface.
TANGENT_TOLERANCE = 1e-9


@dataclass
class TangentSource:
    """One source point of the vector heat method.

    Attributes
    ----------
    vertices : (k,) int array
        Operator vertices carrying the source (its hat functions).
    weights : (k,) float array
        Their hat weights (sum 1).
    position : (3,) float array
        Where the source is (in the operators' length unit).
    normal, e1, e2 : (3,) float arrays
        The source's tangent frame.
    label : str
        "vertex 12" or "face 3": for messages.

    Examples
    --------
    >>> source = TangentSource(np.array([0]), np.ones(1), np.zeros(3), np.eye(3)[2], np.eye(3)[0], np.eye(3)[1], "vertex 0")
    >>> source.coordinates([2.0, 2.0, 5.0], "vector")
    (2+2j)
    """

    vertices: np.ndarray
    weights: np.ndarray
    position: np.ndarray
    normal: np.ndarray
    e1: np.ndarray
    e2: np.ndarray
    label: str

    def coordinates(self, vector, what, error=InvalidSourceError):
        """``vector`` (3D) projected on the source's tangent plane, as ``x + iy`` in its frame.

        Raises ``error`` (naming ``what``) for a vector that is not 3 finite
        numbers or has no tangent part at the source.
        """
        v = np.asarray(vector, dtype=float)
        if v.shape != (3,) or not np.isfinite(v).all():
            raise error(f"the {what} must be 3 finite numbers (a 3D vector), got {np.asarray(vector).tolist()!r}")
        z = complex(v @ self.e1, v @ self.e2)
        length = float(np.linalg.norm(v))
        if not abs(z) > TANGENT_TOLERANCE * length:
            why = "is zero" if length == 0 else "is normal to the surface"
            raise error(f"the {what} {v.tolist()} {why} at {self.label}: it has no direction in the tangent plane")
        return z


def tangent_sources(domain, basis, source=None, points=None):
    """The :class:`TangentSource` of each vertex in ``source`` and each point in ``points``, in that order.

    Parameters
    ----------
    domain : TriangleMesh
    basis : (normal, e1, e2)
        Operator vertices' frames, (n, 3) each.
    source : int or sequence of int, optional
        Input vertices.
    points : (face_indices, barycentric) pair, optional
        Points on input faces.

    Returns
    -------
    list of TangentSource

    Raises
    ------
    InvalidSourceError
        No source, an index out of range, a vertex no face uses, a face that was ignored, bad barycentric coordinates.

    Examples
    --------
    >>> import numpy as np, heatcore as hc
    >>> from heatcore.vector_heat import VectorHeatSolver
    >>> solver = VectorHeatSolver(hc.TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0))
    >>> [s.label for s in solver.sources([2, 0])]
    ['vertex 2', 'vertex 0']
    """
    normal, e1, e2 = basis
    out = []
    if source is not None:
        vertices = index_list(source, domain.n_input_vertices, "vertex")
        mapped = domain.output_vertices[vertices]
        if (mapped < 0).any():
            bad = int(vertices[mapped < 0][0])
            raise InvalidSourceError(f"vertex {bad} is not used by any face, so it cannot be a source")
        positions = domain.subdivision.vertices
        for v, o in zip(vertices.tolist(), mapped.tolist()):
            out.append(TangentSource(np.array([o]), np.ones(1), positions[o], normal[o], e1[o], e2[o], f"vertex {v}"))
    if points is not None:
        try:
            faces, bary = points
        except (TypeError, ValueError):
            raise InvalidSourceError("points must be a pair (face indices, barycentric coordinates)") from None
        faces = index_list(faces, domain.faces.shape[0], "face")
        bary = np.asarray(bary, dtype=float).reshape(faces.size, -1) if faces.size else np.zeros((0, 3))
        for f, b in zip(faces.tolist(), bary):
            out.append(_point_source(domain, f, b))
    if not out:
        raise InvalidSourceError("no source given: pass a vertex (source=) or a point on a face (points=)")
    return out


def single_source(domain, basis, source, points):
    """The one :class:`TangentSource` a log map starts from; a typed error for none or several.

    Examples
    --------
    >>> import numpy as np, heatcore as hc
    >>> from heatcore.vector_heat import VectorHeatSolver
    >>> solver = VectorHeatSolver(hc.TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0))
    >>> solver.log_map([0, 1])
    Traceback (most recent call last):
    ...
    heatcore.errors.InvalidSourceError: a log map has one source (a vertex or a point on a face), got 2
    """
    if source is not None and np.ndim(source) == 0:
        source = [source]
    found = tangent_sources(domain, basis, source, points)
    if len(found) != 1:
        raise InvalidSourceError(f"a log map has one source (a vertex or a point on a face), got {len(found)}")
    return found[0]


def reference_angle(source, reference):
    """Angle of ``reference`` (3D) in the source's frame (0 when None); a typed error for a zero or normal one.

    Examples
    --------
    >>> source = TangentSource(np.array([0]), np.ones(1), np.zeros(3), np.eye(3)[2], np.eye(3)[0], np.eye(3)[1], "vertex 0")
    >>> round(reference_angle(source, [0.0, 1.0, 0.0]) / np.pi, 3)
    0.5
    >>> reference_angle(source, [0.0, 0.0, 1.0])
    Traceback (most recent call last):
    ...
    heatcore.errors.InvalidOptionError: the reference direction [0.0, 0.0, 1.0] is normal to the surface at vertex 0: it has no direction in the tangent plane
    """
    if reference is None:
        return 0.0
    return float(np.angle(source.coordinates(reference, "reference direction", InvalidOptionError)))


def _point_source(domain, face, bary):
    """The source at barycentric ``bary`` of input face ``face``."""
    pins = domain.source_pins(points=([face], [bary]))  # checks the face and the coordinates
    vertices = np.flatnonzero(pins.heat)
    weights = pins.heat[vertices]
    corners = domain.subdivision.vertices[domain.vertex_map[domain.faces[face]]]
    b = np.asarray(bary, dtype=float)
    position = b @ corners
    u = corners[1] - corners[0]
    normal = np.cross(u, corners[2] - corners[0])
    if not np.linalg.norm(normal) > 0:
        raise InvalidSourceError(f"face {face} has no area (its corners are on one line): it has no tangent plane")
    normal /= np.linalg.norm(normal)
    e1 = u / np.linalg.norm(u)
    return TangentSource(vertices, weights / weights.sum(), position, normal, e1, np.cross(normal, e1), f"face {face}")
