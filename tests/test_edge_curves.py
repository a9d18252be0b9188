"""Selected edges and face regions as oriented curves (heatcore.domains.edge_curves): the signed method's input."""

import itertools

import numpy as np
import pytest
from shapes import grid

from heatcore.domains.edge_curves import edge_curves, region_boundary_curves
from heatcore.errors import InvalidSourceError


def signed_area(V, curve):
    """Twice the signed area (xy plane) of a closed curve: > 0 counter-clockwise seen from +z."""
    x, y = V[curve, 0], V[curve, 1]
    return float(np.sum(x[:-1] * y[1:] - x[1:] * y[:-1]))


@pytest.fixture
def plane():
    V, F = grid(9, 9, size=8.0)  # vertices at integer x and y, faces counter-clockwise seen from +z
    assert np.cross(V[F[0, 1]] - V[F[0, 0]], V[F[0, 2]] - V[F[0, 0]])[2] > 0
    return V, F


def loop_edges(V, F, lo, hi):
    """The mesh edges along the square [lo, hi]^2's sides."""
    E = np.unique(np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1), axis=0)
    a, b = V[E[:, 0], :2], V[E[:, 1], :2]
    inside = ((a >= lo) & (a <= hi)).all(axis=1) & ((b >= lo) & (b <= hi)).all(axis=1)
    along = ((a[:, 0] == b[:, 0]) & np.isin(a[:, 0], (lo, hi))) | ((a[:, 1] == b[:, 1]) & np.isin(a[:, 1], (lo, hi)))
    return E[inside & along]


def torus(n_major, n_minor, R=1.0, r=0.4):
    """A torus of quads split in two, outward normals; vertex (i, j) at i * n_minor + j."""
    u, v = np.meshgrid(2 * np.pi * np.arange(n_major) / n_major, 2 * np.pi * np.arange(n_minor) / n_minor,
                       indexing="ij")
    V = np.column_stack([((R + r * np.cos(v)) * np.cos(u)).ravel(), ((R + r * np.cos(v)) * np.sin(u)).ravel(),
                         (r * np.sin(v)).ravel()])
    i, j = np.meshgrid(np.arange(n_major), np.arange(n_minor), indexing="ij")
    a = (i * n_minor + j).ravel()
    b = (((i + 1) % n_major) * n_minor + j).ravel()
    c = (((i + 1) % n_major) * n_minor + (j + 1) % n_minor).ravel()
    d = (i * n_minor + (j + 1) % n_minor).ravel()
    return V, np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])


def test_a_loop_is_oriented_with_its_smaller_side_on_the_left(plane):
    V, F = plane
    edges = loop_edges(V, F, 2, 5)
    (curve,) = edge_curves(F, edges, positions=V)
    assert curve[0] == curve[-1] and len(curve) == 13  # 12 edges, closed
    assert signed_area(V, curve) == pytest.approx(2 * 9.0)  # counter-clockwise: the 3x3 inside on the left
    (again,) = edge_curves(F, edges[::-1, ::-1], positions=V)  # the same edges listed otherwise
    assert signed_area(V, again) == pytest.approx(2 * 9.0)


def test_inside_faces_choose_the_side(plane):
    V, F = plane
    centroids = V[F].mean(axis=1)
    outside = np.flatnonzero((centroids[:, 0] < 2) | (centroids[:, 0] > 5))
    (curve,) = edge_curves(F, loop_edges(V, F, 2, 5), inside=outside, positions=V)
    assert signed_area(V, curve) == pytest.approx(-2 * 9.0)  # the outside on the left


def test_chains_run_from_their_lower_end_and_split_at_junctions(plane):
    V, F = plane
    index = {(round(x), round(y)): k for k, (x, y, _) in enumerate(V)}
    row = [index[(x, 4)] for x in range(1, 8)]
    column = [index[(4, y)] for y in range(4, 8)]
    edges = list(itertools.pairwise(row)) + list(itertools.pairwise(column))
    curves = edge_curves(F, edges)
    assert sorted(len(c) for c in curves) == [4, 4, 4]  # three arms meet at (4, 4)
    assert all(c[0] < c[-1] or c[0] == index[(4, 4)] or c[-1] == index[(4, 4)] for c in curves)
    assert sum(len(c) - 1 for c in curves) == len(edges)


def test_region_boundary_has_the_region_on_its_left(plane):
    V, F = plane
    centroids = V[F].mean(axis=1)
    ring = np.flatnonzero((np.abs(centroids[:, 0] - 4) < 3) & (np.abs(centroids[:, 1] - 4) < 3)
                          & ~((np.abs(centroids[:, 0] - 4) < 1) & (np.abs(centroids[:, 1] - 4) < 1)))
    loops = region_boundary_curves(F, ring)
    areas = sorted(signed_area(V, c) for c in loops)
    assert areas == pytest.approx([-2 * 4.0, 2 * 36.0])  # the hole clockwise, the outer side counter-clockwise


def test_a_loop_that_splits_nothing_keeps_its_order():
    """Around a torus's tube: no inside; the loop as walked, from its lowest vertex."""
    V, F = torus(12, 8)
    order = np.arange(8)  # the cross-section at u = 0, in the tube's order
    edges = np.column_stack([order, np.roll(order, -1)])
    (curve,) = edge_curves(F, edges, positions=V)
    assert curve[0] == curve[-1] == order.min() and len(curve) == len(order) + 1


def test_bad_edges_are_typed_errors():
    F = np.array([[0, 1, 2]])
    with pytest.raises(InvalidSourceError):
        edge_curves(F, [[0, 1, 2]])
    with pytest.raises(InvalidSourceError):
        region_boundary_curves(F, [3])
