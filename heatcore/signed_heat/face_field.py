"""Vertex tangent vectors of the vector heat flow, read on the triangles and normalized: the signed heat method's field.

Each triangle of the intrinsic triangulation is laid out in the plane as the
gradient operator lays it out (:func:`heatcore.domains.cotan.triangle_operators`:
corner 0 at the origin, corner 1 on the +x axis, counter-clockwise). A vector
``z`` in the frame of the vertex at corner ``c`` (:mod:`heatcore.vector_heat.frames`)
is turned so that the corner's first side (towards corner ``c + 1``), at angle
``start`` in the vertex frame, lies at its angle in the layout; the triangle's
vector is the mean of its three corners' and is then scaled to length 1.

Examples
--------
>>> import numpy as np
>>> from heatcore.domains.intrinsic import IntrinsicTriangulation
>>> from heatcore.vector_heat.frames import vertex_frames
>>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
>>> tri = IntrinsicTriangulation.from_mesh(V, np.array([[0, 1, 2]]))
>>> frames = vertex_frames(tri, 3)
>>> Y = np.array([np.exp(1j * frames.start[0]), 0, 0])   # vertex 0: along its corner's first side, to vertex 1
>>> unit_face_field(tri, frames, Y).round(6).tolist()
[[1.0, 0.0]]
"""

import numpy as np

from ..vector_heat.frames import corner_angles


def first_side_angles(lengths):
    """Angle of each corner's first side (towards the next corner) in its triangle's layout, ``(m, 3)``.

    Examples
    --------
    >>> (first_side_angles(np.array([[1.0, 1.0, 1.0]])) / np.pi * 180).round(3).tolist()
    [[0.0, 120.0, 240.0]]
    """
    angle = corner_angles(lengths)
    return np.column_stack([np.zeros(len(lengths)), np.pi - angle[:, 1], np.pi + angle[:, 0]])


def unit_face_field(tri, frames, Y):
    """The unit vector of each triangle, ``(m, 2)`` in its layout, from vertex vectors ``Y`` (complex, per vertex).

    Rows of zeros where the three corners' vectors cancel or vanish.

    Examples
    --------
    >>> from heatcore.domains.intrinsic import IntrinsicTriangulation
    >>> from heatcore.vector_heat.frames import vertex_frames
    >>> tri = IntrinsicTriangulation.from_mesh(np.eye(3), np.array([[0, 1, 2]]))
    >>> unit_face_field(tri, vertex_frames(tri, 3), np.zeros(3, dtype=complex)).tolist()
    [[0.0, 0.0]]
    """
    faces = tri.faces
    turn = first_side_angles(tri.lengths) - frames.start.reshape(-1, 3)
    mean = (Y[faces] * np.exp(1j * turn)).mean(axis=1)
    size = np.abs(mean)
    unit = np.zeros_like(mean)
    ok = size > 1e-300
    unit[ok] = mean[ok] / size[ok]
    return np.column_stack([unit.real, unit.imag])

