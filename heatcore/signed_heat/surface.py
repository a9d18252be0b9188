"""The surface the signed heat method refines onto: the mesh's refined vertices moved onto curved triangles.

Midpoint refinement (``refine``) keeps the mesh's polyhedron: every new
vertex lies on a flat input face. On a curved surface that polyhedron's own
distances are off the surface's (the UV sphere of tests/signed_cases.py: its
exact polyhedral distance to the equator is 0.057% of the radius from the
sphere's), and the signed heat method converges to the polyhedron's field
as the mesh is refined: 0.061%, 0.066%, 0.071% with 0, 1 and 2 levels (0.012% and 0.0027%
with 1 and 2 levels here).
Here each refined vertex is moved onto its input face's curved PN triangle
(Vlachos, Peters, Boyd and Mitchell, "Curved PN Triangles", I3D 2001): the
cubic Bézier triangle through the face's corners, tangent there to the
corners' normals (area-weighted means of the face normals). An edge's
curve depends only on its two ends, so neighbouring patches meet; a flat
part stays flat (every normal is the face's), so a disc is refined as
before. A corner whose normal is more than ``CREASE_DEGREES`` from the
face's own normal takes the face's normal in that face, which keeps sharp
edges and corners (a cube's faces stay flat), and so does every corner at a
vertex whose faces lie in at most ``POLYHEDRAL_PLANES`` planes (a shallow
fold of a flat sheet stays a fold). The input vertices do not move.

Examples
--------
>>> import numpy as np, heatcore as hc
>>> V, F = hc.io.load_demo_mesh()
>>> surface = curved_refinement(hc.TriangleMesh(V, F, refine=1))
>>> surface.n_input_vertices > V.shape[0]          # the refined vertices are the new mesh's own
True
"""

import numpy as np

from ..domains.refine import unique_edges
from ..domains.triangle import TriangleMesh

#: A corner keeps the face's own normal where the vertex normal is further than this from it: an edge
#: or corner sharper than this stays sharp (a cube's 45 degrees), a tessellated curve is smoothed
#: (the UV sphere of 64 x 33 vertices: at most 2.8 degrees; spot: 95% of corners within 12).
CREASE_DEGREES = 30.0

#: A vertex whose faces lie in at most this many planes is a fold or a corner of a polyhedron (a folded
#: sheet, a box), not a sample of a curved surface (around a vertex of a UV sphere, a torus or an
#: icosphere its faces lie in 4 to 64 planes): its corners keep their faces' normals. Without it a sheet
#: folded by 20 degrees along a line of edges was measured 0.007% off its exact distance, potpourri3d 0.
POLYHEDRAL_PLANES = 3


def pn_triangle_points(P, N, bary):
    """Points of cubic PN triangles: corners ``P`` (m, 3, 3), their unit normals ``N`` (m, 3, 3), at ``bary`` (m, 3).

    Examples
    --------
    >>> P = np.array([[[1.0, 0, 0], [0, 1, 0], [0, 0, 1]]])
    >>> pn_triangle_points(P, P, np.full((1, 3), 1 / 3)).round(4).tolist()   # a sphere's octant: bulges out
    [[0.4444, 0.4444, 0.4444]]
    """
    def side(i, j):  # the control point next to corner i on the side towards j
        w = np.einsum("mk,mk->m", P[:, j] - P[:, i], N[:, i])
        return (2 * P[:, i] + P[:, j] - w[:, None] * N[:, i]) / 3

    b = {(i, j): side(i, j) for i in range(3) for j in range(3) if i != j}
    E = sum(b.values()) / 6
    center = E + (E - P.mean(axis=1)) / 2
    u = [bary[:, c:c + 1] for c in range(3)]
    out = sum(P[:, c] * u[c] ** 3 for c in range(3))
    out = out + sum(3 * b[i, j] * u[i] ** 2 * u[j] for (i, j) in b)
    return out + 6 * center * u[0] * u[1] * u[2]


def corner_normals(V, F, crease_degrees=CREASE_DEGREES):
    """Each face corner's normal (m, 3, 3): the vertex's area-weighted normal, or the face's at a sharp corner.

    Examples
    --------
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]])
    >>> corner_normals(V, np.array([[0, 2, 1], [0, 1, 3]]))[0].round(3).tolist()   # a right angle: kept sharp
    [[0.0, 0.0, -1.0], [0.0, 0.0, -1.0], [0.0, 0.0, -1.0]]
    """
    face = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    vertex = np.zeros_like(V)
    for c in range(3):
        np.add.at(vertex, F[:, c], face)
    face = face / np.maximum(np.linalg.norm(face, axis=1), 1e-300)[:, None]
    vertex = vertex / np.maximum(np.linalg.norm(vertex, axis=1), 1e-300)[:, None]
    corner = vertex[F]
    sharp = np.einsum("mck,mk->mc", corner, face) < np.cos(np.radians(crease_degrees))
    sharp |= (plane_counts(face, F, V.shape[0]) <= POLYHEDRAL_PLANES)[F]
    return np.where(sharp[:, :, None], face[:, None, :], corner)


def plane_counts(face_normals, F, n):
    """How many distinct planes (unit normals equal to 1e-7) the faces around each vertex lie in, ``(n,)``.

    Examples
    --------
    >>> normals = np.array([[0, 0, 1.0], [0, 0, 1.0], [0, 1.0, 0]])
    >>> plane_counts(normals, np.array([[0, 1, 2], [0, 2, 3], [0, 3, 4]]), 5).tolist()
    [2, 1, 1, 2, 1]
    """
    key = np.round(face_normals / 1e-7).astype(np.int64)
    rows = np.column_stack([F.ravel(), np.repeat(key, 3, axis=0)])
    vertices = np.unique(rows, axis=0)[:, 0]
    return np.bincount(vertices, minlength=n)


def curved_positions(V, F, sub):
    """The refined vertices of ``sub`` (a midpoint subdivision of ``V, F``) moved onto the faces' PN triangles.

    ``V`` in any length unit (the result's); ``sub.vertices`` give each refined
    vertex's place on its input edge or face. None where nothing moves (a
    flat mesh) or ``sub`` is not the subdivision of ``F``.

    Examples
    --------
    >>> import heatcore as hc
    >>> from heatcore.domains.refine import midpoint_subdivide
    >>> V, F = hc.io.load_demo_mesh()
    >>> sub = midpoint_subdivide(V, F, 1)
    >>> W = curved_positions(V, F, sub)
    >>> float(np.abs(W[:len(V)] - V).max()), bool(np.abs(W - sub.vertices).max() > 0)   # new vertices move
    (0.0, True)
    """
    n = V.shape[0]
    X = sub.vertices
    out = np.empty((X.shape[0], 3))
    out[:n] = V
    normals = corner_normals(V, F)
    edges, side_edge = unique_edges(F)
    if not np.array_equal(edges, sub.edges):  # not the subdivision of these faces: leave it flat
        return None
    face_of_edge = np.empty(edges.shape[0], dtype=np.int64)
    corner_of_edge = np.empty(edges.shape[0], dtype=np.int64)
    face_of_edge[side_edge.ravel()] = np.arange(side_edge.size) // 3
    corner_of_edge[side_edge.ravel()] = np.arange(side_edge.size) % 3
    new = np.arange(n, X.shape[0])
    on_edge, in_face = sub.vertex_edge[new], sub.vertex_face[new]
    face = np.where(on_edge >= 0, face_of_edge[np.maximum(on_edge, 0)], in_face)
    corners = sub.vertices[F[face]]
    bary = _barycentric(corners, X[new])
    side = on_edge >= 0
    bary[side, corner_of_edge[on_edge[side]]] = 0.0  # exactly on the edge: the patch's side curve
    bary /= bary.sum(axis=1)[:, None]
    out[new] = pn_triangle_points(V[F[face]], normals[face], bary)
    linear = np.einsum("kc,kcd->kd", bary, V[F[face]])
    if not np.abs(out[new] - linear).max(initial=0.0) > 1e-12 * np.abs(V).max(initial=0.0):
        return None  # flat: nothing moves
    return out


def _barycentric(corners, points):
    """Barycentric coordinates of ``points`` (k, 3) in the triangles ``corners`` (k, 3, 3)."""
    u, v, w = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0], points - corners[:, 0]
    uu, uv, vv = (u * u).sum(1), (u * v).sum(1), (v * v).sum(1)
    wu, wv = (w * u).sum(1), (w * v).sum(1)
    det = np.maximum(uu * vv - uv * uv, 1e-300)
    b1, b2 = (vv * wu - uv * wv) / det, (uu * wv - uv * wu) / det
    return np.clip(np.column_stack([1 - b1 - b2, b1, b2]), 0.0, 1.0)


def curved_refinement(domain):
    """The :class:`~heatcore.TriangleMesh` of ``domain``'s refined mesh with its new vertices on PN triangles.

    The domain itself where it is not refined or nothing moves (a flat
    mesh). Otherwise a mesh whose vertices are the domain's operator
    vertices, in their order (so the domain's carriers of surface points
    index it), not refined again, with the domain's ``robust``.

    Examples
    --------
    >>> import numpy as np, heatcore as hc
    >>> flat = hc.TriangleMesh(np.eye(3) * [1, 1, 0], [[0, 1, 2]], refine=1)
    >>> curved_refinement(flat) is flat
    True
    """
    sub = domain.subdivision
    if domain.levels == 0:
        return domain
    kept = domain.face_map >= 0
    F = np.empty((int(kept.sum()), 3), dtype=np.int64)
    F[domain.face_map[kept]] = domain.vertex_map[domain.faces[kept]]
    n = int(domain.vertex_map.max()) + 1
    V = np.empty((n, 3))
    used = domain.vertex_map >= 0
    V[domain.vertex_map[used]] = domain.vertices[used]
    W = curved_positions(V, F, sub)
    if W is None:
        return domain
    return TriangleMesh(W, sub.faces, refine=0, robust=domain.robust, weld=None)
