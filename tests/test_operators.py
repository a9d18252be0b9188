"""Triangle operators, intrinsic Delaunay flips and midpoint subdivision."""

import numpy as np
import scipy.sparse as sp
from conftest import load_shared_mesh

import heatcore as hc
from heatcore.domains.intrinsic import (
    NEXT,
    PREV,
    IntrinsicTriangulation,
    corner_cotangents,
    face_areas,
)
from heatcore.domains.refine import midpoint_subdivide


def test_flips_reach_delaunay_and_keep_the_surface():
    V, F = load_shared_mesh("homer")
    tri = IntrinsicTriangulation.from_mesh(V, F)
    area_before = face_areas(tri.lengths).sum()
    cot_before = corner_cotangents(tri.lengths).ravel()
    n_flips = tri.flip_to_delaunay()
    assert n_flips > 1000
    cot = corner_cotangents(tri.lengths).ravel()
    h = np.flatnonzero(tri.twin >= 0)
    assert (cot[h] + cot[tri.twin[h]]).min() > -1e-9  # every interior edge is Delaunay
    h0 = np.flatnonzero(tri.twin >= 0)
    assert (cot_before[h0] + cot_before[tri.twin[h0]]).min() < -1  # it was far from it
    assert np.isclose(face_areas(tri.lengths).sum(), area_before, rtol=1e-9)
    # twins are consistent: same edge, opposite direction
    tails, heads = tri.faces[:, NEXT].ravel(), tri.faces[:, PREV].ravel()
    assert np.all(tri.twin[tri.twin[h]] == h)
    assert np.all(tails[h] == heads[tri.twin[h]]) and np.all(heads[h] == tails[tri.twin[h]])


def test_operators_are_consistent():
    V, F = load_shared_mesh("spot")
    ops = hc.TriangleMesh(V, F, refine=0).operators
    L, G = ops.laplacian, ops.gradient
    A = sp.diags(np.repeat(ops.volumes, ops.dim))
    assert abs(L - G.T @ A @ G).max() < 1e-9 * abs(L).max()
    assert np.allclose(L @ np.ones(L.shape[0]), 0, atol=1e-10)
    assert np.isclose(ops.mass.sum(), ops.volumes.sum())
    # intrinsic Delaunay: no negative off-diagonal weight (an M-matrix)
    off = sp.triu(L, 1)
    assert off.data.max() <= 1e-12
    # on the extrinsic triangles, grad x is the projection of e_x onto each face plane
    plain = hc.TriangleMesh(V, F, refine=0, robust=False).operators
    g = np.linalg.norm((plain.gradient @ V[:, 0]).reshape(-1, 2), axis=1)
    P = V[F]
    n = np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0])
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    assert np.allclose(g, np.sqrt(1 - n[:, 0] ** 2), atol=1e-9)
    X = np.random.default_rng(0).normal(size=(len(ops.volumes), 2))
    assert np.allclose(ops.divergence(X), -(G.T @ (A @ X.ravel())))


def test_gradient_is_exact_on_a_plane():
    V = np.array([[0, 0, 0], [2, 0, 0], [0.5, 1.5, 0], [2, 2, 0]], float)
    ops = hc.TriangleMesh(V, [[0, 1, 2], [1, 3, 2]], refine=0, robust=False).operators
    g = (ops.gradient @ (3 * V[:, 0] + 4 * V[:, 1])).reshape(-1, 2)
    assert np.allclose(np.linalg.norm(g, axis=1), 5.0)


def test_midpoint_subdivision_tracks_origins():
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], float)
    F = np.array([[0, 1, 2], [1, 3, 2]])
    sub = midpoint_subdivide(V, F, 2)
    assert sub.faces.shape == (32, 3) and sub.vertices.shape == (25, 3)
    assert np.array_equal(sub.vertices[:4], V)
    # vertices on input edge (0, 1) lie on y = 0; interior ones of face 0 below the diagonal
    e01 = np.flatnonzero((sub.edges == [0, 1]).all(axis=1))[0]
    on_edge = sub.vertex_edge == e01
    assert on_edge.sum() == 3 and np.allclose(sub.vertices[on_edge, 1], 0)
    inside0 = sub.vertex_face == 0
    assert inside0.sum() == 3 and np.all(sub.vertices[inside0].sum(axis=1) < 1)
    assert np.all((sub.vertex_edge >= 0) | (sub.vertex_face >= 0) | (np.arange(25) < 4))
    assert np.isclose(face_areas(np.linalg.norm(sub.vertices[sub.faces][:, [1, 2, 0]] - sub.vertices[sub.faces][:, [2, 0, 1]], axis=2)).sum(), 1.0)


def test_auto_refinement_levels():
    from heatcore.domains.triangle import auto_refine_levels

    assert auto_refine_levels(3) >= 6
    assert auto_refine_levels(2930) == 1
    assert auto_refine_levels(50000) == 0
