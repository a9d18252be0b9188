"""Curves made of mesh edges, oriented by the faces' winding: what a user selects becomes signed-distance curves.

A curve is an ordered array of vertex indices; a closed one repeats its first
vertex at the end. Orientation follows the signed heat method's convention:
the side on the *left* of the curve, looking along the surface normal, is
positive. A directed edge ``a -> b`` that a triangle lists in its own (counter-
clockwise) order has that triangle on its left.

- :func:`region_boundary_curves`: the boundary of a set of faces (a selection),
  oriented so that the faces are on the left: inside positive.
- :func:`edge_curves`: selected edges, cut into chains at their ends and
  junctions, and closed loops. A loop that splits its part of the surface in
  two is oriented so that the *inside* is on its left: the side holding more
  of the ``inside`` faces where given, else the side of smaller area (a loop
  around a character's arm: the hand's side). A chain (open), or a loop that
  does not split the surface (around a torus's tube), runs from its
  lower-numbered end, and its left is wherever the faces' winding puts it.

Examples
--------
>>> import numpy as np
>>> F = np.array([[0, 1, 2], [0, 2, 3]])        # a square, counter-clockwise seen from +z
>>> [c.tolist() for c in region_boundary_curves(F, [0, 1])]
[[0, 1, 2, 3, 0]]
>>> [c.tolist() for c in edge_curves(F, [[2, 1], [0, 1]])]
[[0, 1, 2]]
"""

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components

from .intrinsic import face_areas
from .sources import edge_list, index_list


def region_boundary_curves(faces, region, mesh_boundary=True):
    """The boundary of a set of faces, as curves oriented with the faces on their left.

    Parameters
    ----------
    faces : (m, 3) int array
        Triangles, counter-clockwise seen from their normal.
    region : sequence of int
        Face indices.
    mesh_boundary : bool, default True
        Keep the region's sides on the mesh's own boundary. False: only the
        sides it shares with faces outside it (a selection that reaches the
        border of an open mesh is then bounded by open chains).

    Returns
    -------
    list of int arrays
        Curves: closed loops (first vertex repeated at the end) and, with
        ``mesh_boundary=False``, open chains from border to border.

    Examples
    --------
    >>> F = np.array([[0, 1, 2], [0, 2, 3], [0, 3, 4]])
    >>> [c.tolist() for c in region_boundary_curves(F, [1])]
    [[0, 2, 3, 0]]
    >>> [c.tolist() for c in region_boundary_curves(F, [1], mesh_boundary=False)]   # sides 0-2 and 3-0 only
    [[3, 0, 2]]
    """
    faces = np.asarray(faces, dtype=np.int64)
    inside = faces[index_list(region, len(faces), "face")]
    half = np.stack([inside, np.roll(inside, -1, axis=1)], axis=2).reshape(-1, 2)
    keys = {(int(a), int(b)) for a, b in half}
    every = keys if mesh_boundary else {(int(a), int(b)) for a, b in
                                        np.stack([faces, np.roll(faces, -1, axis=1)], axis=2).reshape(-1, 2)}
    boundary = [(a, b) for a, b in keys if (b, a) not in keys and (mesh_boundary or (b, a) in every)]
    return _walk(boundary)


def edge_curves(faces, edges, inside=None, positions=None):
    """Mesh edges as oriented curves: chains between ends and junctions, and closed loops.

    Parameters
    ----------
    faces : (m, 3) int array
        Triangles, counter-clockwise seen from their normal.
    edges : (k, 2) array_like of int
        Undirected edges (each once); edges no face has are kept, unoriented.
    inside : sequence of int, optional
        Faces on the positive side of the loops (a user's face selection).
    positions : (n, 3) array_like of float, optional
        Vertex positions: without ``inside``, a loop's inside is its side of
        smaller area (without positions, of fewer faces).

    Returns
    -------
    list of int arrays
        Each a curve (a loop repeats its first vertex at the end).

    Examples
    --------
    >>> F = np.array([[0, 1, 2], [0, 2, 3], [0, 3, 1], [1, 3, 2]])   # a tetrahedron, outward normals
    >>> [c.tolist() for c in edge_curves(F, [[0, 1], [1, 2], [2, 0]])]   # face 0's loop, face 0 inside
    [[0, 1, 2, 0]]
    """
    faces = np.asarray(faces, dtype=np.int64)
    n = int(faces.max(initial=-1)) + 1
    e = edge_list(edges, max(n, int(np.max(edges, initial=-1)) + 1))
    curves = _chains(e)
    area = face_areas_of(faces, positions)
    owner = _HalfEdges(faces)
    weight = np.zeros(len(faces)) if inside is None else np.bincount(
        index_list(inside, len(faces), "face"), minlength=len(faces)).astype(float)
    return [_oriented(c, faces, owner, area, weight) for c in curves]


def face_areas_of(faces, positions=None):
    """Face weights for choosing a loop's inside: the areas where ``positions`` are given, else 1 per face.

    Examples
    --------
    >>> face_areas_of(np.array([[0, 1, 2]])).tolist(), face_areas_of(np.array([[0, 1, 2]]), np.eye(3)).round(3).tolist()
    ([1.0], [0.866])
    """
    if positions is None:
        return np.ones(len(faces))
    X = np.asarray(positions, dtype=float)
    return face_areas(np.linalg.norm(X[np.roll(faces, -1, axis=1)] - X[faces], axis=2))


class _HalfEdges:
    """The face of each directed side ``a -> b`` of the faces, looked up by sorted integer keys."""

    def __init__(self, faces):
        self.base = int(faces.max(initial=0)) + 1
        half = np.stack([faces, np.roll(faces, -1, axis=1)], axis=2).reshape(-1, 2)
        key = half[:, 0] * self.base + half[:, 1]
        order = np.argsort(key, kind="stable")
        self.keys, self.faces = key[order], np.repeat(np.arange(len(faces)), 3)[order]

    def faces_of(self, a, b):
        """Faces holding the directed sides ``a[i] -> b[i]`` (those that exist)."""
        a, b = np.asarray(a, dtype=np.int64), np.asarray(b, dtype=np.int64)
        inside = (a < self.base) & (b < self.base)
        key = a[inside] * self.base + b[inside]
        pos = np.clip(np.searchsorted(self.keys, key), 0, max(self.keys.size - 1, 0))
        found = self.keys[pos] == key if self.keys.size else np.zeros(key.size, bool)
        return self.faces[pos[found]]


def _chains(edges):
    """Undirected edges cut into vertex chains at every vertex not of degree 2, then the loops left."""
    neighbours = {}
    for a, b in edges.tolist():
        neighbours.setdefault(a, []).append(b)
        neighbours.setdefault(b, []).append(a)
    used = set()
    curves = []

    def walk(start, nxt):
        chain = [start, nxt]
        used.add(frozenset((start, nxt)))
        while len(neighbours[chain[-1]]) == 2 and chain[-1] != start:
            step = next((w for w in neighbours[chain[-1]] if frozenset((chain[-1], w)) not in used), None)
            if step is None:
                break
            used.add(frozenset((chain[-1], step)))
            chain.append(step)
        return chain

    for v in sorted(neighbours):
        if len(neighbours[v]) != 2:
            curves += [walk(v, w) for w in sorted(neighbours[v]) if frozenset((v, w)) not in used]
    for v in sorted(neighbours):
        for w in sorted(neighbours[v]):
            if frozenset((v, w)) not in used:
                curves.append(walk(v, w))
    return [np.array(c if c[0] == c[-1] or c[0] < c[-1] else c[::-1], dtype=np.int64) for c in curves]


def _walk(half_edges):
    """Directed edges chained head to tail: open chains from the vertices with more ways out than in, then
    closed loops (at a vertex with several ways on, any)."""
    out, surplus = {}, {}
    for a, b in sorted(half_edges):
        out.setdefault(a, []).append(b)
        surplus[a] = surplus.get(a, 0) + 1
        surplus[b] = surplus.get(b, 0) - 1
    curves = []
    for start in [v for v in sorted(out) if surplus[v] > 0] + sorted(out):
        while out.get(start) and (surplus[start] > 0 or all(surplus[v] <= 0 for v in out)):
            curve = [start]
            while out.get(curve[-1]):
                curve.append(out[curve[-1]].pop())
                if curve[-1] == start:
                    break
            surplus[start] -= 1
            surplus[curve[-1]] += 1
            curves.append(np.array(curve, dtype=np.int64))
    return curves


def _oriented(curve, faces, owner, area, weight):
    """``curve`` reversed where its inside (see :func:`edge_curves`) is on its right."""
    if curve[0] != curve[-1]:
        return curve
    pairs = list(zip(curve[:-1].tolist(), curve[1:].tolist()))
    left, right = owner.faces_of(curve[:-1], curve[1:]), owner.faces_of(curve[1:], curve[:-1])
    if not left.size or not right.size:
        return curve
    side = _sides(faces, pairs)
    left_parts, right_parts = set(side[left]), set(side[right])
    if left_parts & right_parts:  # the loop does not split the surface: no inside
        return curve
    on_left, on_right = np.isin(side, list(left_parts)), np.isin(side, list(right_parts))
    if weight[on_left].sum() != weight[on_right].sum():
        left_is_inside = weight[on_left].sum() > weight[on_right].sum()
    else:
        left_is_inside = area[on_left].sum() <= area[on_right].sum()
    return curve if left_is_inside else curve[::-1]


def _sides(faces, cut):
    """Connected component of each face when faces meet across every side except the ``cut`` edges."""
    half = np.stack([faces, np.roll(faces, -1, axis=1)], axis=2).reshape(-1, 2)
    owner = np.repeat(np.arange(len(faces)), 3)
    key = np.minimum(half[:, 0], half[:, 1]) * (faces.max() + 1) + np.maximum(half[:, 0], half[:, 1])
    blocked = {min(a, b) * (faces.max() + 1) + max(a, b) for a, b in cut}
    keep = ~np.isin(key, list(blocked))
    order = np.argsort(key[keep], kind="stable")
    k, f = key[keep][order], owner[keep][order]
    same = k[1:] == k[:-1]
    graph = sp.coo_matrix((np.ones(int(same.sum())), (f[:-1][same], f[1:][same])), shape=(len(faces),) * 2)
    return connected_components(graph, directed=False)[1]
