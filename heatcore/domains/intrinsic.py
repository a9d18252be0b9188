"""Intrinsic triangulations: edge lengths, mollification and Delaunay edge flips.

An intrinsic triangulation keeps the surface's metric (its edge lengths) but
lets the connectivity change: flipping an edge replaces the diagonal of the
flat quadrilateral formed by its two triangles with the other diagonal, whose
length is measured in that quadrilateral's planar layout. Flipping every edge
whose opposite angles sum to more than pi yields an intrinsic Delaunay
triangulation, whose cotan Laplacian has non-negative weights (Bobenko and
Springborn 2007; Sharp, Soliman and Crane 2019).

The triangulation is stored as half-edges: half-edge ``h = 3 * f + c`` is the
edge of face ``f`` opposite its corner ``c``, running from corner ``c + 1`` to
corner ``c + 2``. ``twin[h]`` is the half-edge on the other side, or ``-1`` on
boundary edges and on non-manifold or inconsistently oriented edges (which are
never flipped). Repeated vertices in a face and repeated edges between a
vertex pair are allowed, as in any intrinsic triangulation (a Delta-complex).

Examples
--------
>>> import numpy as np
>>> V = np.array([[0, 0, 0], [1, 0, 0], [1, 0.1, 0], [0, 0.1, 0.5]], float)
>>> tri = IntrinsicTriangulation.from_mesh(V, np.array([[0, 1, 2], [0, 2, 3]]))
>>> n_flips = tri.flip_to_delaunay()
"""

from dataclasses import dataclass

import numpy as np

from ..compiled import use_build_kernels
from .parts import part_extremes, part_means, row_reduce
from .refine import unique_edges

NEXT = np.array([1, 2, 0])
PREV = np.array([2, 0, 1])


def face_edge_lengths(V, F):
    """Lengths of the edges of each face, column ``c`` opposite corner ``c``.

    Parameters
    ----------
    V : (n, 3) float array
    F : (m, 3) int array

    Returns
    -------
    (m, 3) float array

    Examples
    --------
    >>> V = np.array([[0, 0, 0], [3, 0, 0], [0, 4, 0]], float)
    >>> face_edge_lengths(V, np.array([[0, 1, 2]])).tolist()
    [[5.0, 4.0, 3.0]]
    """
    lengths = np.empty(F.shape)
    for corner in range(3):  # a column at a time: 3-4x faster than norms of (m, 3, 3) gathers, the same bits
        side = V[F[:, PREV[corner]]] - V[F[:, NEXT[corner]]]
        side *= side
        np.sqrt(side.sum(axis=1), out=lengths[:, corner])
    return lengths


def face_areas(lengths):
    """Triangle areas from edge lengths (Kahan's numerically stable Heron formula).

    Parameters
    ----------
    lengths : (m, 3) float array

    Returns
    -------
    (m,) float array; 0 where the lengths violate the triangle inequality.

    Examples
    --------
    >>> face_areas(np.array([[5.0, 4.0, 3.0], [1.0, 1.0, 3.0]])).tolist()
    [6.0, 0.0]
    """
    x, y, z = lengths[:, 0], lengths[:, 1], lengths[:, 2]
    lo_xy, hi_xy = np.minimum(x, y), np.maximum(x, y)
    a = np.maximum(hi_xy, z)  # sorted without arithmetic: a >= b >= c
    c = np.minimum(lo_xy, z)
    b = np.maximum(lo_xy, np.minimum(hi_xy, z))
    q = (a + (b + c)) * (c - (a - b)) * (c + (a - b)) * (a + (b - c))
    return 0.25 * np.sqrt(np.maximum(q, 0.0))


def corner_cotangents(lengths, areas=None):
    """Cotangent of each corner angle, column ``c`` for corner ``c``.

    Parameters
    ----------
    lengths : (m, 3) float array
        Edge lengths, column ``c`` opposite corner ``c``.
    areas : (m,) float array, optional
        Precomputed :func:`face_areas`.

    Returns
    -------
    (m, 3) float array

    Examples
    --------
    >>> corner_cotangents(np.array([[5.0, 4.0, 3.0]])).round(4).tolist()
    [[0.0, 0.75, 1.3333]]
    """
    if areas is None:
        areas = face_areas(lengths)
    sq = lengths**2
    return (sq[:, NEXT] + sq[:, PREV] - sq) / (4.0 * areas[:, None])


def mollify(lengths, relative_delta=1e-6, part=None, n_parts=1):
    """Add one small constant to every length so each triangle is strictly valid.

    Implements the mollification of Sharp and Crane ("A Laplacian for
    nonmanifold triangle meshes", 2020): with ``delta = relative_delta *
    mean length``, the smallest ``eps >= 0`` such that ``l_a + l_b - l_c >=
    delta`` holds in every triangle is added to all lengths. Given ``part``,
    each connected part gets its own ``delta`` and ``eps``, so a bad triangle in
    one part leaves the others as they are.

    Parameters
    ----------
    lengths : (m, 3) float array
    relative_delta : float, or (n_parts,) float array with ``part``
    part : (m,) int array, optional
        Part of each face.
    n_parts : int
        Number of parts (with ``part``).

    Returns
    -------
    mollified : (m, 3) float array
    eps : float, or (n_parts,) float array with ``part``
        The constant added (0 for a mesh or part that needs none).

    Examples
    --------
    >>> L = np.array([[1.0, 1.0, 2.0], [1.0, 1.0, 1.0]])
    >>> mollified, eps = mollify(L, 0.1, part=np.array([0, 1]), n_parts=2)
    >>> eps.round(3).tolist()
    [0.133, 0.0]
    """
    slack = triangle_slack(lengths)
    if part is None:
        delta = relative_delta * float(np.mean(lengths))
        eps = max(0.0, float(delta - slack.min()))
        return lengths + eps, eps
    delta = relative_delta * part_means(lengths.ravel(), np.repeat(part, 3), n_parts)
    least = part_extremes(row_reduce(np.minimum, slack), part, n_parts)
    eps = np.maximum(0.0, np.where(np.isfinite(least), delta - least, 0.0))
    return lengths + eps[part][:, None], eps


def triangle_slack(lengths):
    """``l_a + l_b - l_c`` for each side ``c`` of each face: how far from degenerate the triangle is.

    Examples
    --------
    >>> triangle_slack(np.array([[1.0, 1.0, 1.5]])).tolist()
    [[1.5, 1.5, 0.5]]
    """
    slack = np.empty_like(lengths)
    for c in range(3):  # a column at a time: no (m, 3) gathers, the same numbers
        np.add(lengths[:, NEXT[c]], lengths[:, PREV[c]], out=slack[:, c])
        slack[:, c] -= lengths[:, c]
    return slack


@dataclass
class IntrinsicTriangulation:
    """Faces with per-face edge lengths and half-edge twins; see the module docstring.

    Attributes
    ----------
    faces : (m, 3) int array
    lengths : (m, 3) float array, column ``c`` opposite corner ``c``
    twin : (3 m,) int array

    Examples
    --------
    Two flat triangles on a long shared edge (0-1) whose opposite angles are obtuse:

    >>> V = np.array([[-1, 0, 0], [1, 0, 0], [0, 0.2, 0], [0, -0.2, 0]], float)
    >>> tri = IntrinsicTriangulation.from_mesh(V, np.array([[0, 1, 2], [1, 0, 3]]))
    >>> tri.twin.tolist()
    [-1, -1, 5, -1, -1, 2]
    >>> tri.flip_to_delaunay(), tri.faces.tolist()
    (1, [[3, 1, 2], [2, 0, 3]])
    >>> tri.lengths[0].round(3).tolist()   # the new edge 2-3 is 0.4 long
    [1.02, 0.4, 1.02]
    """

    faces: np.ndarray
    lengths: np.ndarray
    twin: np.ndarray

    @classmethod
    def from_mesh(cls, V, F, lengths=None, side_edge=None, side_pairs=None):
        """Build from vertex positions (or given lengths) and faces.

        Parameters
        ----------
        V : (n, 3) float array
        F : (m, 3) int array
        lengths : (m, 3) float array, optional
            Edge lengths to use instead of those measured from ``V``.
        side_edge : (m, 3) int array, optional
            Undirected edge ids of the face sides, if already known.
        side_pairs : (p, 2) int array, optional
            The two sides of each edge with exactly two, if already known
            (:func:`~heatcore.domains.refine.unique_edges` with ``with_pairs``).
        """
        F = np.ascontiguousarray(F, dtype=np.int64)
        if lengths is None:
            lengths = face_edge_lengths(V, F)
        return cls(F.copy(), np.array(lengths, dtype=float), halfedge_twins(F, side_edge, pairs=side_pairs))

    def flip_to_delaunay(self, max_rounds=10_000, flippable=None):
        """Flip non-Delaunay edges in independent batches until none is left.

        Each round finds every interior manifold edge whose opposite angles sum
        to more than pi, keeps a set of them that share no face (the most
        violating edge of each face wins), and flips that set at once.

        Parameters
        ----------
        max_rounds : int
        flippable : (n_faces,) bool array, optional
            Only edges between two of these faces are flipped (a flip keeps
            its two faces' indices); default all.

        Returns
        -------
        int
            Total number of flips.
        """
        total = 0
        tol = 1e-12
        kernels = None
        if use_build_kernels(self.faces.shape[0]):  # a large mesh: compiled tests and flips, the same numbers
            from . import build_kernels

            kernels = build_kernels if build_kernels.fits(self.faces, self.lengths, self.twin) else None
        renamed = np.full(self.twin.size, -1, dtype=np.int64) if kernels is None else None  # scratch for _flip
        allowed = None if flippable is None else np.asarray(flippable, bool)
        candidates = np.flatnonzero(self.twin > np.arange(self.twin.size))
        cotangents = None  # every corner's, once many edges are asked about; then kept up to date
        for _ in range(max_rounds):
            if allowed is not None:
                candidates = candidates[allowed[candidates // 3] & allowed[self.twin[candidates] // 3]]
            h, t = candidates, self.twin[candidates]
            if kernels is None and cotangents is None and 2 * h.size > self.lengths.shape[0]:  # many: all at once
                cotangents = corner_cotangents(self.lengths).ravel()
            if kernels is not None:
                cot_sum = kernels.cotangent_sums(self.lengths, h, t)
            elif cotangents is None:
                cot_sum = _corner_cotangent(self.lengths, h) + _corner_cotangent(self.lengths, t)
            else:
                cot_sum = cotangents[h] + cotangents[t]
            f0, f1 = h // 3, t // 3
            # The tolerance follows the rounding of the cotangents, (a^2 + b^2 - c^2) / 4A: on needle
            # triangles it is large, and two cocircular configurations would otherwise flip forever.
            bad = (cot_sum < -tol) & (f0 != f1)  # the rounding scale is >= sqrt(3): only these can pass
            bad[bad] = cot_sum[bad] < -tol * (
                _cotangent_rounding(self.lengths, f0[bad]) + _cotangent_rounding(self.lengths, f1[bad])
            )
            if not bad.any():
                break
            h, t, f0, f1, score = h[bad], t[bad], f0[bad], f1[bad], cot_sum[bad]
            chosen = _independent_edges(f0, f1, score, self.faces.shape[0])
            if kernels is None:
                self._flip(h[chosen], t[chosen], renamed)
            else:
                kernels.flip_pairs(self.faces, self.lengths, self.twin, h[chosen], t[chosen])
            total += int(chosen.sum())
            # Only edges of the flipped faces, and bad edges left for later, can be non-Delaunay now.
            touched = np.concatenate([f0[chosen], f1[chosen]])
            if cotangents is not None:  # a face's cotangents depend on its lengths alone: the same numbers
                cotangents.reshape(-1, 3)[touched] = corner_cotangents(self.lengths[touched])
            sides = np.concatenate([(3 * touched[:, None] + np.arange(3)).ravel(), h[~chosen]])
            twins = self.twin[sides]
            inner = twins >= 0
            candidates = _sorted_unique(np.minimum(sides[inner], twins[inner]), self.twin.size)
        return total

    def _flip(self, h0, h1, renamed):
        """Flip the edges given by half-edge pairs ``(h0, h1)`` (no shared faces).

        ``renamed`` is a scratch array of -1 per half-edge, left as it was found.
        """
        F, Lf, twin = self.faces, self.lengths, self.twin
        f0, c0 = h0 // 3, h0 % 3
        f1, c1 = h1 // 3, h1 % 3
        k = F[f0, c0]
        i = F[f0, NEXT[c0]]
        j = F[f0, PREV[c0]]
        l = F[f1, c1]
        l_ij = Lf[f0, c0]
        l_jk = Lf[f0, NEXT[c0]]
        l_ki = Lf[f0, PREV[c0]]
        l_il = Lf[f1, NEXT[c1]]
        l_lj = Lf[f1, PREV[c1]]
        l_kl = _flipped_diagonal(l_ij, l_jk, l_ki, l_il, l_lj)

        # Old half-edge ids of the four outer edges, and the ids they get.
        old_jk, old_ki = 3 * f0 + NEXT[c0], 3 * f0 + PREV[c0]
        old_il, old_lj = 3 * f1 + NEXT[c1], 3 * f1 + PREV[c1]
        # New faces: f0 = (l, j, k), f1 = (k, i, l).
        new_jk, new_lj = 3 * f0 + 0, 3 * f0 + 2
        new_il, new_ki = 3 * f1 + 0, 3 * f1 + 2
        diag0, diag1 = 3 * f0 + 1, 3 * f1 + 1

        old = np.concatenate([old_jk, old_ki, old_il, old_lj])
        new = np.concatenate([new_jk, new_ki, new_il, new_lj])
        # The outer edges' twins, renamed where a twin is itself an outer edge that moves.
        outside = twin[old]
        renamed[old] = new
        moves = outside >= 0
        moves[moves] = renamed[outside[moves]] >= 0
        outside[moves] = renamed[outside[moves]]
        renamed[old] = -1
        twin[new] = outside
        linked = outside >= 0
        twin[outside[linked]] = new[linked]
        twin[diag0] = diag1
        twin[diag1] = diag0

        F[f0] = np.stack([l, j, k], axis=1)
        F[f1] = np.stack([k, i, l], axis=1)
        Lf[f0] = np.stack([l_jk, l_kl, l_lj], axis=1)
        Lf[f1] = np.stack([l_il, l_kl, l_ki], axis=1)


def halfedge_twins(F, side_edge=None, oriented=True, pairs=None):
    """Twin of each half-edge: the other half-edge of its edge, or ``-1``.

    The rule: two half-edges are twins when they are the only two on their
    edge (the same two vertices). An edge of one face (a boundary edge) or of
    three faces or more (a non-manifold edge) has no twins; nor does a loop
    (a face with a repeated vertex). With ``oriented`` (an intrinsic
    triangulation, whose flips need a consistent orientation) the two must also
    run in opposite directions, so an edge where two faces disagree on the
    orientation has none either; without it (crossing from face to face, as
    geodesic paths do) they are paired whatever their directions.

    Parameters
    ----------
    F : (m, 3) int array
    side_edge : (m, 3) int array, optional
        Undirected edge id of each half-edge (as from
        :func:`heatcore.domains.refine.unique_edges`); computed when not given.
    oriented : bool, default True
        Pair only half-edges of opposite directions.
    pairs : (p, 2) int array, optional
        The two half-edges of each edge with exactly two, where already found
        (:func:`heatcore.domains.refine.unique_edges` with ``with_pairs``); then
        ``side_edge`` is not read.

    Returns
    -------
    (3 m,) int array
        Half-edge ``3 f + c`` is face ``f``'s side opposite corner ``c``
        (from corner ``c + 1`` to corner ``c + 2``).

    Examples
    --------
    >>> halfedge_twins(np.array([[0, 1, 2], [0, 2, 3]])).tolist()   # edge 0-2: half-edges 1 and 5
    [-1, 5, -1, -1, -1, 1]
    >>> flipped = np.array([[0, 1, 2], [0, 3, 2]])  # the second face turned over: edge 0-2 runs 0->2 twice
    >>> halfedge_twins(flipped).tolist(), halfedge_twins(flipped, oriented=False).tolist()
    ([-1, -1, -1, -1, -1, -1], [-1, 4, -1, -1, 1, -1])
    """
    if pairs is None:
        a, b = _pairs(F, side_edge)
    elif use_build_kernels(F.shape[0]):  # a large mesh: the same twins, compiled
        from .build_kernels import twins_of_pairs

        return twins_of_pairs(F, pairs, oriented)
    else:
        a, b = pairs[:, 0], pairs[:, 1]
    tail = F[:, NEXT].ravel()
    head = F[:, PREV].ravel()
    forward = tail < head
    # Both join the same two vertices (a loop joins one: neither runs forward).
    keep = forward[a] != forward[b] if oriented else (tail[a] != head[a])
    a, b = a[keep], b[keep]
    twin = np.full(F.size, -1, dtype=np.int64)
    twin[a] = b
    twin[b] = a
    return twin


def _pairs(F, side_edge=None):
    """The two half-edges of each edge with exactly two, by edge id, the smaller first."""
    if side_edge is None:
        side_edge = unique_edges(F)[1]
    key = side_edge.ravel()
    n_edges = int(key.max()) + 1 if key.size else 0
    halfedges = np.arange(key.size)
    # An edge with exactly two half-edges: its first and last half-edge are the pair.
    first = np.full(n_edges, key.size, dtype=np.int64)
    last = np.full(n_edges, -1, dtype=np.int64)
    np.minimum.at(first, key, halfedges)
    np.maximum.at(last, key, halfedges)
    paired = np.bincount(key, minlength=n_edges) == 2
    return first[paired], last[paired]


def _independent_edges(f0, f1, score, n_faces):
    """Pick candidate flips that share no face: each face keeps its lowest score."""
    rank = np.empty(score.size, dtype=np.int64)
    rank[np.argsort(score, kind="stable")] = np.arange(score.size)
    best = np.full(n_faces, score.size, dtype=np.int64)
    np.minimum.at(best, f0, rank)
    np.minimum.at(best, f1, rank)
    return (best[f0] == rank) & (best[f1] == rank)


def _sorted_unique(values, bound):
    """``np.unique(values)`` of integers in ``0 .. bound - 1``: a mask where there are many, a sort where few."""
    if 16 * values.size < bound:
        return np.unique(values)
    seen = np.zeros(bound, dtype=bool)
    seen[values] = True
    return np.flatnonzero(seen)


def _corner_cotangent(lengths, h):
    """Cotangent of the corner opposite each half-edge ``h``."""
    f, c = h // 3, h % 3
    sides = lengths[f]
    rows = np.arange(f.size)
    sq = sides**2
    return (sq[rows, NEXT[c]] + sq[rows, PREV[c]] - sq[rows, c]) / (4.0 * face_areas(sides))


def _cotangent_rounding(lengths, f):
    """``(a^2 + b^2 + c^2) / 4A`` of faces ``f``: the scale of the rounding error of their cotangents."""
    sides = lengths[f]
    return (sides**2).sum(axis=1) / (4.0 * face_areas(sides))


def _flipped_diagonal(l_ij, l_jk, l_ki, l_il, l_lj):
    """Length of diagonal k-l of the quad (i, l, j, k) laid out flat across edge i-j."""
    area_k = face_areas(np.stack([l_ij, l_jk, l_ki], axis=1))
    area_l = face_areas(np.stack([l_ij, l_lj, l_il], axis=1))
    x_k = (l_ij**2 + l_ki**2 - l_jk**2) / (2.0 * l_ij)
    x_l = (l_ij**2 + l_il**2 - l_lj**2) / (2.0 * l_ij)
    y_k = 2.0 * area_k / l_ij
    y_l = -2.0 * area_l / l_ij
    return np.hypot(x_k - x_l, y_k - y_l)
