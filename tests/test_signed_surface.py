"""The signed heat method's curved refinement (heatcore/signed_heat/surface.py): PN triangles, creases kept."""

import numpy as np
import signed_cases as sc

import heatcore as hc
from heatcore.signed_heat.surface import curved_refinement


def _cube(n=4):
    """A cube of side 2 around 0, each face an n x n grid of squares split in two, outward faces: its
    vertices and a :class:`~heatcore.TriangleMesh` of it (not refined)."""
    t = np.linspace(-1, 1, n + 1)
    V, F = [], []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            a, b = [k for k in range(3) if k != axis]
            base = len(V)
            for i in range(n + 1):
                for j in range(n + 1):
                    p = np.zeros(3)
                    p[axis], p[a], p[b] = sign, t[i], t[j]
                    V.append(p)
            idx = base + np.arange((n + 1) ** 2).reshape(n + 1, n + 1)
            q = np.c_[idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()]
            tris = np.r_[q[:, [0, 1, 2]], q[:, [0, 2, 3]]]
            V_arr = np.array(V)
            normal = np.cross(V_arr[tris[:, 1]] - V_arr[tris[:, 0]], V_arr[tris[:, 2]] - V_arr[tris[:, 0]])[:, axis]
            tris[normal * sign < 0] = tris[normal * sign < 0][:, [0, 2, 1]]
            F += tris.tolist()
    mesh = hc.TriangleMesh(np.array(V), np.array(F), refine=0, weld=1e-9)  # the faces' shared border vertices as one
    return mesh.vertices, mesh


def test_a_flat_mesh_is_refined_as_before():
    V, F = sc.disc()
    mesh = hc.TriangleMesh(V, F)
    assert mesh.levels > 0 and curved_refinement(mesh) is mesh


def test_an_unrefined_mesh_is_itself():
    V, F = sc.uv_sphere()
    mesh = hc.TriangleMesh(V, F, refine=0)
    assert curved_refinement(mesh) is mesh


def test_a_sphere_is_refined_closer_to_itself():
    V, F = sc.uv_sphere()
    mesh = hc.TriangleMesh(V, F, refine=2)
    surface = curved_refinement(mesh)
    assert surface is not mesh and surface.levels == 0
    assert surface.operators.n_vertices == mesh.operators.n_vertices
    W = surface.vertices
    np.testing.assert_array_equal(W[: len(V)], V)  # the input vertices stay, first and in order
    flat = np.ldexp(mesh.subdivision.vertices, int(mesh.unit_exponent.max()))
    off_flat = np.abs(np.linalg.norm(flat, axis=1) - 1).max()
    off_curved = np.abs(np.linalg.norm(W, axis=1) - 1).max()
    assert off_curved < 0.1 * off_flat  # measured 0.0002 against 0.0024


def test_sharp_edges_stay_sharp():
    """A cube's vertex normals are 45 degrees or more from its faces' at its edges: every face stays flat."""
    V, mesh = _cube()
    refined = hc.TriangleMesh(V, mesh.faces, refine=1, weld=1e-9)
    assert curved_refinement(refined) is refined


def test_a_cube_loop_is_measured_on_the_cube():
    """The loop around a cube's middle (z = 0): the signed distance on the cube's faces is |z| up or down."""
    V, mesh = _cube()
    ring = np.flatnonzero(np.abs(V[:, 2]) < 1e-9)
    ring = ring[np.argsort(np.arctan2(V[ring, 1], V[ring, 0]))]
    loop = [int(v) for v in ring] + [int(ring[0])]
    phi = hc.SignedHeatSolver(hc.TriangleMesh(V, mesh.faces, weld=1e-9)).distance([loop])
    side = np.abs(V[:, 2]) < 1 - 1e-9  # on the four side faces the distance is |z| (the caps are further)
    assert np.abs(phi[side] - V[side, 2]).max() < 0.02


def test_a_shallow_fold_stays_a_fold():
    """A flat sheet folded by 20 degrees along a line of edges: its faces lie in at most two planes at every
    vertex, so it is refined flat and the distance to a line parallel to the fold is exact across it."""
    n = 21
    s = np.linspace(-1, 1, n)  # arc length across the fold (at s = 0)
    S, Y = np.meshgrid(s, np.linspace(0, 2, n), indexing="ij")
    a = np.radians(10)
    V = np.c_[(S * np.cos(a)).ravel(), Y.ravel(), (-np.abs(S) * np.sin(a)).ravel()]
    idx = np.arange(n * n).reshape(n, n)
    q0, q1, q2, q3 = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    F = np.r_[np.c_[q0, q1, q2], np.c_[q0, q2, q3]]
    mesh = hc.TriangleMesh(V, F)
    assert mesh.levels > 0 and curved_refinement(mesh) is mesh
    phi = hc.SignedHeatSolver(mesh).distance([[int(v) for v in idx[5]]])  # the line s = -0.5, along +y
    middle = (Y.ravel() > 0.4) & (Y.ravel() < 1.6)
    exact = np.abs(S.ravel() + 0.5)
    assert np.abs(np.abs(phi[middle]) - exact[middle]).max() < 1e-6
