"""Surfaces and curves with analytic signed distances, for the signed heat method's tests (issue 35).

- :func:`disc`: a flat unit disc, triangulated from jittered rings (Delaunay), faces up (+z);
- :func:`uv_sphere`: a unit sphere of latitude rings, the equator one of them;
- :func:`icosphere`: a subdivided icosahedron on the unit sphere (no vertex on the equator);
- :func:`torus`: a grid torus, and its vertex grid (a loop around the tube is a column);
- :func:`closed`, :func:`broken`: a closed curve, and the same in pieces with gaps;
- :func:`level_curve`: where a function of the vertices crosses 0 on the edges, as surface points
  ``(face, barycentric)`` in order, with the same points as potpourri3d's edge points.
"""

import numpy as np
import scipy.spatial as ss


def _faces_up(V, T):
    a = np.cross(V[T[:, 1]] - V[T[:, 0]], V[T[:, 2]] - V[T[:, 0]])[:, 2]
    T = T.copy()
    T[a < 0] = T[a < 0][:, [0, 2, 1]]
    return T


def disc(rings=30, seed=0):
    """A unit disc: jittered rings of vertices (the boundary ring kept round), Delaunay triangles facing +z."""
    rng = np.random.default_rng(seed)
    points = [[0.0, 0.0]]
    for r in np.linspace(1 / rings, 1, rings):
        k = max(6, round(2 * np.pi * r * rings))
        a = np.linspace(0, 2 * np.pi, k, endpoint=False) + rng.uniform(0, 2 * np.pi)
        points += list(np.c_[r * np.cos(a), r * np.sin(a)])
    P = np.array(points)
    inside = np.linalg.norm(P, axis=1) < 0.999
    P = P + rng.normal(scale=0.1 / rings, size=P.shape) * inside[:, None]
    V = np.c_[P, np.zeros(len(P))]
    return V, _faces_up(V, ss.Delaunay(P).simplices)


def uv_sphere(n_lon=64, n_lat=33):
    """A unit UV sphere with ``n_lat - 2`` latitude rings (odd ``n_lat``: the equator is one) and two poles."""
    lat = np.linspace(-np.pi / 2, np.pi / 2, n_lat)[1:-1]
    lon = np.linspace(0, 2 * np.pi, n_lon, endpoint=False)
    la, lo = np.meshgrid(lat, lon, indexing="ij")
    V = np.c_[(np.cos(la) * np.cos(lo)).ravel(), (np.cos(la) * np.sin(lo)).ravel(), np.sin(la).ravel()]
    V = np.r_[V, [[0, 0, -1], [0, 0, 1]]]
    south, north = len(V) - 2, len(V) - 1
    idx = np.arange(lat.size * n_lon).reshape(lat.size, n_lon)
    a, b = idx[:-1], np.roll(idx[:-1], -1, 1)
    c, d = np.roll(idx[1:], -1, 1), idx[1:]
    F = np.r_[np.c_[a.ravel(), b.ravel(), c.ravel()], np.c_[a.ravel(), c.ravel(), d.ravel()],
              np.c_[np.full(n_lon, south), np.roll(idx[0], -1), idx[0]],
              np.c_[np.full(n_lon, north), idx[-1], np.roll(idx[-1], -1)]]
    return V, F


def equator_loop(V):
    """The equator's vertices of :func:`uv_sphere`, eastwards (north on the left), closed."""
    ring = np.flatnonzero(np.abs(V[:, 2]) < 1e-9)
    ring = ring[np.argsort(np.arctan2(V[ring, 1], V[ring, 0]))]
    return [int(v) for v in ring] + [int(ring[0])]


def icosphere(subdivisions=4):
    """A unit icosphere (trimesh's), outward faces."""
    import trimesh

    mesh = trimesh.creation.icosphere(subdivisions)
    V = np.array(mesh.vertices)
    return V / np.linalg.norm(V, axis=1)[:, None], np.array(mesh.faces)


def torus(R=1.0, r=0.35, n=64, m=24):
    """A grid torus around +z, outward faces, and its ``(n, m)`` vertex grid (column 0: a loop around the tube)."""
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, n, endpoint=False), np.linspace(0, 2 * np.pi, m, endpoint=False),
                       indexing="ij")
    V = np.c_[((R + r * np.cos(v)) * np.cos(u)).ravel(), ((R + r * np.cos(v)) * np.sin(u)).ravel(),
              (r * np.sin(v)).ravel()]
    idx = np.arange(n * m).reshape(n, m)
    a, b = idx, np.roll(idx, -1, 0)
    c, d = np.roll(b, -1, 1), np.roll(idx, -1, 1)
    F = np.r_[np.c_[a.ravel(), b.ravel(), c.ravel()], np.c_[a.ravel(), c.ravel(), d.ravel()]]
    return V, F, idx


def level_curve(V, F, values, angle):
    """Where ``values`` (per vertex) crosses 0 on the edges, ordered by ``angle(points)``.

    Returns
    -------
    points : list of (face, barycentric)
        heatcore's surface points (on a face holding the edge).
    gc_points : list of (edge, [t])
        The same points as potpourri3d names them (its edge numbering: edges
        in the order the faces first list them, ``t`` from that first side's tail).
    """
    E = np.unique(np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1), axis=0)
    E = E[values[E[:, 0]] * values[E[:, 1]] < 0]
    t = values[E[:, 0]] / (values[E[:, 0]] - values[E[:, 1]])
    X = (1 - t)[:, None] * V[E[:, 0]] + t[:, None] * V[E[:, 1]]
    order = np.argsort(angle(X))
    E, t = E[order], t[order]
    index, tail = {}, {}
    for f in F:
        for c in range(3):
            a, b = int(f[c]), int(f[(c + 1) % 3])
            key = (min(a, b), max(a, b))
            if key not in index:
                index[key], tail[key] = len(index), a
    points, gc_points = [], []
    for (a, b), s in zip(E.tolist(), t.tolist()):
        face = int(np.flatnonzero(np.isin(F, [a, b]).sum(axis=1) == 2)[0])
        bary = np.zeros(3)
        bary[list(F[face]).index(a)], bary[list(F[face]).index(b)] = 1 - s, s
        points.append((face, bary))
        gc_points.append((index[a, b], [s if tail[a, b] == a else 1 - s]))
    return points, gc_points


def closed(points):
    """A closed curve of ``points``: the first repeated at the end."""
    return list(points) + [points[0]]


def broken(points, pieces=4, gap=0.1):
    """A closed curve of ``points`` broken into ``pieces``, leaving out ``gap`` of each piece's share at its end."""
    n = len(points)
    return [[points[i % n] for i in range(int(k * n / pieces), int((k + 1 - gap) * n / pieces) + 1)]
            for k in range(pieces)]


def mean_error(phi, exact, scale=1.0):
    """Mean absolute error over the vertices, relative to ``scale``."""
    return float(np.mean(np.abs(phi - exact)) / scale)


def sphere_cloud(n=3000, n_equator=96):
    """Points on the unit sphere: a Fibonacci lattice, and ``n_equator`` evenly spaced on the equator (the
    lattice's points nearer to it than half their spacing removed). Returns the points and the equator's
    indices eastwards (north on the left), closed."""
    i = np.arange(n) + 0.5
    z = 1 - 2 * i / n
    a = np.pi * (1 + 5**0.5) * i
    P = np.c_[np.sqrt(1 - z**2) * np.cos(a), np.sqrt(1 - z**2) * np.sin(a), z]
    spacing = np.sqrt(4 * np.pi / n)
    P = P[np.abs(P[:, 2]) > 0.5 * spacing]
    t = np.linspace(0, 2 * np.pi, n_equator, endpoint=False)
    P = np.r_[P, np.c_[np.cos(t), np.sin(t), np.zeros(n_equator)]]
    loop = list(range(len(P) - n_equator, len(P)))
    return P, loop + [loop[0]]


def disc_cloud(R=0.55, spacing=0.05):
    """Points on a flat unit disc in rings ``spacing`` apart, one of them at radius ``R``; and that ring's
    indices counter-clockwise (inside on the left, seen from +z), closed."""
    radii = np.r_[np.linspace(0, R, round(R / spacing) + 1)[1:], np.linspace(R, 1, round((1 - R) / spacing) + 1)[1:]]
    points, loop = [[0.0, 0.0, 0.0]], None
    for r in radii:
        k = round(2 * np.pi * r / spacing)
        a = np.linspace(0, 2 * np.pi, k, endpoint=False)
        if abs(r - R) < 1e-12:
            loop = list(range(len(points), len(points) + k))
        points += np.c_[r * np.cos(a), r * np.sin(a), np.zeros(k)].tolist()
    return np.array(points), loop + [loop[0]]
