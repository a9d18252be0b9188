"""Each vertex's intrinsic frame placed in 3D: a unit normal and the directions ``e1``, ``e2``.

The frames of :mod:`heatcore.vector_heat.frames` live on the intrinsic
triangulation, whose flipped edges are not segments of the mesh. To give
results in 3D, each vertex gets the angle-weighted normal of the mesh's own
(possibly refined) triangles, and ``e1`` is the tangent direction at angle 0
of its frame: the rotation about the normal that best matches the frame
angles of the vertex's intrinsic edges to their chords projected on the
tangent plane (the circular mean of the differences). On a flat mesh and on
every unflipped edge the chord is the edge itself, so the fit is exact; a
flipped edge's chord bends with the surface by a fraction of the dihedral
angles it crosses. ``e2 = normal x e1``: coordinates ``(x, y)`` in the frame
are the 3D vector ``x e1 + y e2``.

Examples
--------
>>> import numpy as np
>>> from heatcore.domains.intrinsic import IntrinsicTriangulation
>>> from heatcore.vector_heat.frames import vertex_frames
>>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
>>> F = np.array([[0, 1, 2], [1, 3, 2]])
>>> tri = IntrinsicTriangulation.from_mesh(V, F)
>>> normal, e1, e2 = tangent_frames(V, F, tri, vertex_frames(tri, 4))
>>> normal[0].tolist(), e1[0].round(6).tolist(), e1[1].round(6).tolist()
([0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [-0.0, 1.0, 0.0])
"""

import numpy as np

from ..domains.intrinsic import NEXT, face_edge_lengths
from .frames import corner_angles


def vertex_normals(V, F):
    """Angle-weighted unit vertex normals of a triangle mesh (``+z`` where a vertex has no area).

    Examples
    --------
    >>> vertex_normals(np.eye(3), np.array([[0, 1, 2]])).round(4).tolist()[0]
    [0.5774, 0.5774, 0.5774]
    """
    P = V[F]
    face_normal = np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0])
    length = np.linalg.norm(face_normal, axis=1)
    face_normal /= np.where(length > 0, length, 1.0)[:, None]
    weights = corner_angles(face_edge_lengths(V, F))
    normal = np.zeros(V.shape)
    for c in range(3):
        np.add.at(normal, F[:, c], weights[:, c, None] * face_normal)
    length = np.linalg.norm(normal, axis=1)
    flat = ~(length > 0)
    normal[flat] = [0.0, 0.0, 1.0]
    length[flat] = 1.0
    return normal / length[:, None]


def tangent_frames(V, F, tri, frames):
    """Normal, ``e1`` and ``e2`` of every vertex, matched to its intrinsic frame.

    Parameters
    ----------
    V : (n, 3) float array
        Vertex positions (the operator vertices).
    F : (m, 3) int array
        The mesh's own triangles (normals come from them).
    tri : IntrinsicTriangulation
        The triangulation the frames were built on (same vertices).
    frames : VertexFrames

    Returns
    -------
    normal, e1, e2 : (n, 3) float arrays
        Orthonormal at each vertex, ``e2 = normal x e1``.

    Examples
    --------
    >>> from heatcore.domains.intrinsic import IntrinsicTriangulation
    >>> from heatcore.vector_heat.frames import vertex_frames
    >>> V = np.array([[0, 0, 0], [0, 0, 1], [0, 1, 0]], float)
    >>> tri = IntrinsicTriangulation.from_mesh(V, np.array([[0, 1, 2]]))
    >>> normal, e1, e2 = tangent_frames(V, np.array([[0, 1, 2]]), tri, vertex_frames(tri, 3))
    >>> normal[0].tolist(), e1[0].round(12).tolist(), e2[0].round(12).tolist()   # e1 along the first edge, 0 -> 1
    ([-1.0, 0.0, 0.0], [-0.0, -0.0, 1.0], [0.0, 1.0, 0.0])
    """
    normal = vertex_normals(V, F)
    n = V.shape[0]
    b1 = np.cross(normal, np.eye(3)[np.argmin(np.abs(normal), axis=1)])  # any tangent direction
    b1 /= np.linalg.norm(b1, axis=1)[:, None]
    b2 = np.cross(normal, b1)
    faces = tri.faces
    corner_vertex = frames.vertex
    towards = faces[np.arange(faces.shape[0])[:, None], NEXT[None, :]].ravel()  # each corner's first side
    chord = V[towards] - V[corner_vertex]
    x = np.einsum("ij,ij->i", chord, b1[corner_vertex])
    y = np.einsum("ij,ij->i", chord, b2[corner_vertex])
    length = np.hypot(x, y)
    phase = np.where(length > 0, (x + 1j * y) / np.where(length > 0, length, 1.0), 0.0)
    phase = phase * np.exp(-1j * frames.start)
    mean = np.bincount(corner_vertex, weights=phase.real, minlength=n) + 1j * np.bincount(
        corner_vertex, weights=phase.imag, minlength=n
    )
    offset = np.angle(mean)
    e1 = np.cos(offset)[:, None] * b1 + np.sin(offset)[:, None] * b2
    e2 = np.cross(normal, e1)
    return normal, e1, e2
