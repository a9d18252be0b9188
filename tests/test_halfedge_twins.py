"""The one rule of half-edge twins (:func:`heatcore.domains.intrinsic.halfedge_twins`), against a plain loop."""

import numpy as np
import pytest

from heatcore.domains.intrinsic import NEXT, PREV, halfedge_twins


def plain_twins(F, oriented):
    """The rule written out: the two half-edges of an edge with exactly two, opposite when ``oriented``."""
    tail, head = F[:, NEXT].ravel(), F[:, PREV].ravel()
    by_edge = {}
    for h, (a, b) in enumerate(zip(tail, head)):
        by_edge.setdefault((min(a, b), max(a, b)), []).append(h)
    twin = np.full(tail.size, -1)
    for (a, b), hs in by_edge.items():
        if len(hs) == 2 and a != b and (not oriented or tail[hs[0]] != tail[hs[1]]):
            twin[hs[0]], twin[hs[1]] = hs[1], hs[0]
    return twin


@pytest.mark.parametrize("oriented", [True, False])
def test_non_manifold_misoriented_and_loops(oriented):
    F = np.array([[0, 1, 2], [0, 1, 3], [0, 1, 4], [2, 1, 5], [5, 1, 6], [6, 1, 7], [1, 7, 8], [8, 8, 7], [7, 8, 8]])
    rng = np.random.default_rng(0)
    for _ in range(50):
        G = rng.permutation(F)
        G = np.where(rng.random((len(G), 1)) < 0.5, G, G[:, [0, 2, 1]])
        assert np.array_equal(halfedge_twins(G, oriented=oriented), plain_twins(G, oriented))


def test_the_non_manifold_edge_has_no_twins_either_way():
    F = np.array([[0, 1, 2], [1, 0, 3], [0, 1, 4]])  # three faces on edge 0-1: half-edges 2, 5, 8
    for oriented in (True, False):
        assert (halfedge_twins(F, oriented=oriented)[[2, 5, 8]] == -1).all()


@pytest.mark.parametrize("oriented", [True, False])
def test_pairs_found_by_the_edge_sort_give_the_same_twins(oriented):
    """``unique_edges(F, with_pairs=True)``'s pairs (the sort midpoint subdivision makes anyway) stand for the side ids."""
    from heatcore.domains.refine import unique_edges

    F = np.array([[0, 1, 2], [0, 1, 3], [0, 1, 4], [2, 1, 5], [5, 1, 6], [6, 1, 7], [1, 7, 8], [8, 8, 7], [7, 8, 8]])
    rng = np.random.default_rng(1)
    for _ in range(50):
        G = rng.permutation(F)
        G = np.where(rng.random((len(G), 1)) < 0.5, G, G[:, [0, 2, 1]])
        _, side_edge, pairs = unique_edges(G, with_pairs=True)
        assert np.array_equal(halfedge_twins(G, pairs=pairs, oriented=oriented), plain_twins(G, oriented))
        assert np.array_equal(halfedge_twins(G, side_edge, oriented=oriented), plain_twins(G, oriented))
