"""Property-based tests (hypothesis) of the distance on random meshes and sources (issue 16, "How to test").

Over random small meshes (4-300 vertices: grids, tubes, perturbed icospheres,
tetrahedra, lifted Delaunay triangulations; several disjoint parts at any
scale; unreferenced vertices), vertex permutations, uniform scales, triangle
soups, duplicate vertices and every kind of source, the distance must be:

- finite and >= 0 on every part holding a source, ``inf`` exactly on the other
  parts and on unreferenced vertices, 0 at source vertices, never NaN;
- invariant under vertex permutation (the distance follows the vertex);
- scaled exactly with the mesh: ``d(s V) == s d(V)`` for every finite ``s > 0``;
- independent of the other parts: adding a disjoint part, of any size and
  scale, with or without sources, leaves a part's distances unchanged;
- the same on a triangle soup or a mesh with duplicated vertices as on the
  welded mesh (welding at exactly equal positions is the default);
- a typed :class:`~heatcore.HeatcoreError` (never a bare ``ValueError``,
  ``IndexError``, ``TypeError`` or a NaN result) on invalid input.

Profiles (registered in conftest.py): "ci" (the default: a few examples,
deterministic) and "local" (``HYPOTHESIS_PROFILE=local``: many more).
Comparisons are relative to the largest finite distance on the part compared.
"""

import dataclasses
import warnings

import numpy as np
import pytest
from hypothesis import given, note, settings
from hypothesis import strategies as st
from mesh_strategies import (
    INT_DTYPES,
    Sources,
    meshes,
    restrict,
    scale_values,
    soup,
    soup_sources,
    sources,
)

import heatcore as hc
from heatcore.errors import (
    HeatcoreError,
    InvalidMeshError,
    InvalidOptionError,
    InvalidSourceError,
)

#: Tests that run the default ``refine="auto"`` (each part refined to >= 11000 vertices: about a second
#: per solve) take few examples: one per parametrization in the "ci" profile.
FEW = settings(max_examples=max(1, settings.default.max_examples // 8))
#: Tests parametrized over many kinds of bad input take a couple of examples per kind.
PER_KIND = settings(max_examples=max(1, settings.default.max_examples // 4))
#: Vertex budget of the meshes in the ``refine="auto"`` tests.
SMALL = 40

PERMUTATION_RTOL = 1e-8
SCALE_RTOL = 1e-9
PART_RTOL = 1e-9
SOUP_RTOL = 1e-8


@pytest.fixture(autouse=True)
def _quiet_repairs():
    """Repairs (dropped degenerate or duplicate faces) warn; the properties do not depend on it."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", hc.HeatcoreWarning)
        yield


# --------------------------------------------------------------------------- helpers


def solve(V, F, src, *, refine=0, accuracy="smooth", **mesh_options):
    """Distance from ``src`` through ``HeatSolver(TriangleMesh(...))``."""
    solver = hc.HeatSolver(hc.TriangleMesh(V, F, refine=refine, **mesh_options), accuracy=accuracy)
    return src.query(solver)


def assert_close(actual, expected, rtol, groups=None, what="distance"):
    """Same ``inf`` pattern, no NaN; finite values within ``rtol`` of each group's largest distance."""
    actual, expected = np.asarray(actual, float), np.asarray(expected, float)
    assert actual.shape == expected.shape, f"{what}: shape {actual.shape}, expected {expected.shape}"
    assert not np.isnan(actual).any(), f"{what}: NaN at vertices {np.flatnonzero(np.isnan(actual))[:10].tolist()}"
    assert not np.isnan(expected).any(), f"reference {what}: NaN at {np.flatnonzero(np.isnan(expected))[:10].tolist()}"
    inf_a, inf_e = np.isinf(actual), np.isinf(expected)
    if (inf_a != inf_e).any():
        bad = np.flatnonzero(inf_a != inf_e)
        raise AssertionError(
            f"{what}: {bad.size} vertices differ in reachability, e.g. vertex {bad[0]}: "
            f"{actual[bad[0]]!r} vs expected {expected[bad[0]]!r}"
        )
    groups = np.zeros(actual.shape, int) if groups is None else np.asarray(groups)
    for g in np.unique(groups[~inf_e]):
        idx = np.flatnonzero((groups == g) & ~inf_e)
        scale = float(np.abs(expected[idx]).max())
        err = np.abs(actual[idx] - expected[idx])
        worst = int(np.argmax(err))
        if err[worst] > rtol * scale:
            v = idx[worst]
            raise AssertionError(
                f"{what} on part {g}: vertex {v} is {actual[v]!r}, expected {expected[v]!r} "
                f"(error {err[worst] / scale if scale else np.inf:.3g} of the part's largest distance {scale:.6g}; "
                f"allowed {rtol:g}; {int((err > rtol * scale).sum())} of {idx.size} vertices off)"
            )


def check_reachability(d, mesh, source_parts, src):
    """Finite and >= 0 on the source parts, ``inf`` exactly elsewhere, 0 at source vertices."""
    d = np.asarray(d)
    assert d.shape == (mesh.n,), f"result shape {d.shape}, expected ({mesh.n},)"
    assert d.dtype.kind == "f", d.dtype
    nan = np.flatnonzero(np.isnan(d))
    assert nan.size == 0, f"NaN at {nan.size} vertices, e.g. {nan[:10].tolist()} (parts {mesh.part[nan[:10]].tolist()})"
    reachable = np.isin(mesh.part, list(source_parts)) & (mesh.part >= 0)
    not_finite = np.flatnonzero(reachable & ~np.isfinite(d))
    assert not_finite.size == 0, (
        f"{not_finite.size} reachable vertices are not finite, e.g. vertex {not_finite[0]} "
        f"(part {mesh.part[not_finite[0]]}) = {d[not_finite[0]]!r}"
    )
    negative = np.flatnonzero(reachable & (d < 0))
    assert negative.size == 0, f"negative distance at vertex {negative[0]}: {d[negative[0]]!r}"
    not_inf = np.flatnonzero(~reachable & ~np.isposinf(d))
    assert not_inf.size == 0, (
        f"{not_inf.size} unreachable vertices are not inf, e.g. vertex {not_inf[0]} "
        f"(part {mesh.part[not_inf[0]]}, -1 = unreferenced) = {d[not_inf[0]]!r}"
    )
    if src.vertices is not None:
        at = np.asarray(src.vertices)
        assert (d[at] == 0).all(), f"source vertices {at.tolist()} have distances {d[at].tolist()}"


def permuted(mesh, perm):
    """``mesh`` with new vertex ``i`` = old vertex ``perm[i]``; returns (V, F, inverse)."""
    perm = np.asarray(perm, dtype=np.int64)
    inverse = np.argsort(perm)
    return mesh.V[perm], inverse[mesh.F], inverse


# --------------------------------------------------------------------------- reachability


@given(data=st.data())
def test_reachable_parts_finite_unreachable_parts_inf(data):
    mesh = data.draw(meshes(), label="mesh")
    src, parts = data.draw(sources(mesh), label="sources")
    accuracy = data.draw(st.sampled_from(["smooth", "high"]), label="accuracy")
    d = src.call(mesh.V, mesh.F, refine=0, accuracy=accuracy)
    check_reachability(d, mesh, parts, src)


@pytest.mark.parametrize("regime", ["tiny", "huge", "any"])
@given(data=st.data())
def test_reachability_with_parts_at_any_scale(regime, data):
    mesh = data.draw(meshes(scaled_parts=regime), label="mesh")
    src, parts = data.draw(sources(mesh), label="sources")
    d = solve(mesh.V, mesh.F, src, refine=0)
    check_reachability(d, mesh, parts, src)


@FEW
@given(data=st.data())
def test_reachability_refine_auto(data):
    mesh = data.draw(meshes(max_parts=2, max_vertices=SMALL, scaled_parts=True), label="mesh")
    src, parts = data.draw(sources(mesh), label="sources")
    check_reachability(src.call(mesh.V, mesh.F), mesh, parts, src)


@given(data=st.data())
def test_source_forms_give_identical_distances(data):
    """A vertex list, tuple, numpy array of any integer dtype, or one int: the same distances."""
    mesh = data.draw(meshes(max_parts=2), label="mesh")
    solver = hc.HeatSolver(hc.TriangleMesh(mesh.V, mesh.F, refine=0))
    referenced = np.flatnonzero(mesh.part >= 0)
    verts = data.draw(st.lists(st.sampled_from(referenced.tolist()), min_size=1, max_size=4), label="vertices")
    reference = solver.distance(list(verts))
    forms = [tuple(verts), np.asarray(verts)] + [np.asarray(verts, d) for d in INT_DTYPES if np.iinfo(d).max >= mesh.n]
    for form in forms:
        note(f"form {form!r}")
        np.testing.assert_array_equal(solver.distance(form), reference)
    one = verts[0]
    reference = solver.distance([one])
    for form in [one, np.int64(one), np.int32(one), np.uint16(one), np.array(one), np.array([one], np.uint8 if one < 256 else np.uint16)]:
        note(f"form {form!r}")
        np.testing.assert_array_equal(solver.distance(form), reference)


# --------------------------------------------------------------------------- invariances


@given(data=st.data())
def test_vertex_permutation_invariance(data):
    mesh = data.draw(meshes(), label="mesh")
    src, _ = data.draw(sources(mesh), label="sources")
    perm = data.draw(st.permutations(range(mesh.n)), label="permutation")
    V2, F2, inverse = permuted(mesh, perm)
    d = solve(mesh.V, mesh.F, src)
    d2 = solve(V2, F2, src.remap(inverse, np.arange(mesh.F.shape[0])))
    assert_close(d2, d[np.asarray(perm)], PERMUTATION_RTOL, groups=mesh.part[np.asarray(perm)], what="permuted")


@FEW
@given(data=st.data())
def test_vertex_permutation_invariance_refine_auto(data):
    mesh = data.draw(meshes(max_parts=2, max_vertices=SMALL), label="mesh")
    src, _ = data.draw(sources(mesh), label="sources")
    perm = data.draw(st.permutations(range(mesh.n)), label="permutation")
    V2, F2, inverse = permuted(mesh, perm)
    d = solve(mesh.V, mesh.F, src, refine="auto")
    d2 = solve(V2, F2, src.remap(inverse, np.arange(mesh.F.shape[0])), refine="auto")
    assert_close(d2, d[np.asarray(perm)], PERMUTATION_RTOL, groups=mesh.part[np.asarray(perm)], what="permuted")


@pytest.mark.parametrize("regime", ["tiny", "moderate", "huge"])
@given(data=st.data())
def test_uniform_scale(regime, data):
    mesh = data.draw(meshes(), label="mesh")
    src, _ = data.draw(sources(mesh), label="sources")
    s = data.draw(scale_values(regime), label="scale")
    d = solve(mesh.V, mesh.F, src)
    ds = solve(s * mesh.V, mesh.F, src)
    assert_close(ds, s * d, SCALE_RTOL, groups=mesh.part, what=f"distance at scale {s!r}")


@FEW
@given(data=st.data())
def test_uniform_scale_refine_auto(data):
    mesh = data.draw(meshes(max_parts=2, max_vertices=SMALL), label="mesh")
    src, _ = data.draw(sources(mesh), label="sources")
    s = data.draw(scale_values("tiny") | scale_values("huge"), label="scale")
    d = src.call(mesh.V, mesh.F)
    ds = src.call(s * mesh.V, mesh.F)
    assert_close(ds, s * d, SCALE_RTOL, groups=mesh.part, what=f"distance at scale {s!r}")


def _part_independence(data, max_vertices, refine, regime, max_parts=3):
    mesh = data.draw(meshes(2, max_parts, max_vertices=max_vertices, scaled_parts=regime), label="mesh")
    kept = data.draw(
        st.sets(st.integers(0, mesh.n_parts - 1), min_size=1, max_size=mesh.n_parts - 1), label="parts kept"
    )
    sub, keep_v, keep_f = restrict(mesh, kept)
    src_sub, _ = data.draw(sources(sub), label="sources on the kept parts")
    src = src_sub.remap(keep_v, keep_f)
    others = sorted(set(range(mesh.n_parts)) - set(kept))
    lit = data.draw(st.sets(st.sampled_from(others), max_size=len(others)), label="other parts with sources")
    if lit:
        src = src.union(data.draw(sources(mesh, parts=lit), label="sources on the other parts")[0])
    note(f"full-mesh sources: {src!r}")
    d_sub = solve(sub.V, sub.F, src_sub, refine=refine)
    d_full = solve(mesh.V, mesh.F, src, refine=refine)
    assert_close(d_full[keep_v], d_sub, PART_RTOL, groups=sub.part, what="distance with the other parts present")


@pytest.mark.parametrize("regime", [False, "any"])
@given(data=st.data())
def test_part_independence(regime, data):
    """Adding disjoint parts (any size, any scale, with or without sources) leaves a part's distances alone."""
    _part_independence(data, 300, 0, regime)


@FEW
@given(data=st.data())
def test_part_independence_refine_auto(data):
    """Two parts (the same shape, or not), each refined as if alone."""
    _part_independence(data, SMALL, "auto", False, max_parts=2)


# --------------------------------------------------------------------------- soups and duplicates


def _soup_matches_welded(data, max_vertices, refine, max_parts=3):
    mesh = data.draw(meshes(max_parts=max_parts, max_vertices=max_vertices, unreferenced=False), label="mesh")
    src, _ = data.draw(sources(mesh), label="sources")
    V2, F2, origin = soup(mesh)

    def choose(candidates):
        return candidates[data.draw(st.integers(0, len(candidates) - 1), label="copy")]

    src2 = soup_sources(src, mesh, choose)
    note(f"soup sources: {src2!r}")
    d = solve(mesh.V, mesh.F, src, refine=refine)
    d_soup = solve(V2, F2, src2, refine=refine)  # welding at exactly equal positions: the default
    assert_close(d_soup, d[origin], SOUP_RTOL, groups=mesh.part[origin], what="distance on the soup")


@given(data=st.data())
def test_soup_matches_welded_mesh(data):
    _soup_matches_welded(data, 300, refine=0)


@FEW
@given(data=st.data())
def test_soup_matches_welded_mesh_refine_auto(data):
    _soup_matches_welded(data, SMALL, refine="auto", max_parts=2)


@given(data=st.data())
def test_soup_without_welding_reaches_only_the_source_face(data):
    mesh = data.draw(meshes(max_parts=2, unreferenced=False), label="mesh")
    V2, F2, _ = soup(mesh)
    f = data.draw(st.integers(0, F2.shape[0] - 1), label="source face")
    kind = data.draw(st.sampled_from(["vertex", "face", "face_point"]), label="kind")
    if kind == "vertex":
        src = Sources(vertices=[int(F2[f, data.draw(st.integers(0, 2), label="corner")])])
    elif kind == "face":
        src = Sources(faces=[f])
    else:
        src = Sources(face_points=([f], [[0.2, 0.3, 0.5]]))
    d = solve(V2, F2, src, weld=None)
    on_face = np.zeros(V2.shape[0], bool)
    on_face[F2[f]] = True
    assert np.isfinite(d[on_face]).all() and (d[on_face] >= 0).all(), d[on_face]
    assert np.isposinf(d[~on_face]).all(), f"{int((~np.isposinf(d[~on_face])).sum())} vertices off the face reached"


@given(data=st.data())
def test_duplicate_vertices_match_welded_mesh(data):
    """Exact copies of vertex positions, referenced by some faces or by none: distances as without them."""
    mesh = data.draw(meshes(max_vertices=250), label="mesh")
    src, _ = data.draw(sources(mesh), label="sources")
    referenced = np.flatnonzero(mesh.part >= 0)
    picks = data.draw(st.lists(st.sampled_from(referenced.tolist()), min_size=1, max_size=6), label="copied vertices")
    V, F = mesh.V.copy(), mesh.F.copy()
    origin = list(range(mesh.n))  # the original vertex each vertex copies
    for v in picks:
        copy = V.shape[0]
        V = np.vstack([V, V[v]])
        origin.append(v)
        corners = np.argwhere(F == v)
        how = data.draw(st.sampled_from(["unreferenced", "some corners", "all corners"]), label=f"copy of {v}")
        if how != "unreferenced" and corners.size:
            take = corners if how == "all corners" else corners[: max(1, len(corners) // 2)]
            F[take[:, 0], take[:, 1]] = copy
    origin = np.asarray(origin)
    used = np.zeros(V.shape[0], bool)
    used[F.ravel()] = True
    # A source vertex whose every corner moved to a copy is unreferenced now: use the copy instead.
    if src.vertices is not None:
        moved = []
        for v in src.vertices:
            moved.append(int(v if used[v] else np.flatnonzero(used & (origin == v))[0]))
        src = Sources(moved, "list", src.edges, src.faces, src.face_points, src.edge_form)
    if src.edges is not None:  # an edge of the welded mesh, given by the vertices a face now uses
        edges = []
        for u, w in src.edges:
            for row in F:
                ou, ow = origin[row] == u, origin[row] == w
                if ou.any() and ow.any():
                    edges.append((int(row[ou][0]), int(row[ow][0])))
                    break
        src = Sources(src.vertices, src.form, edges, src.faces, src.face_points, src.edge_form)
    note(f"sources on the mesh with copies: {src!r}")
    d = solve(mesh.V, mesh.F, Sources(
        None if src.vertices is None else [int(origin[v]) for v in src.vertices], "list",
        None if src.edges is None else [(int(origin[u]), int(origin[w])) for u, w in src.edges],
        src.faces, src.face_points, src.edge_form))  # fmt: skip
    d2 = solve(V, F, src)
    expected = d[origin]
    assert not np.isnan(d2).any(), f"NaN at {np.flatnonzero(np.isnan(d2)).tolist()}"
    # Referenced vertices must match; an unreferenced exact copy of a referenced vertex may read inf or its value.
    loose = ~used & np.isinf(d2) & (mesh.part[origin] >= 0)
    assert_close(np.where(loose, expected, d2), expected, SOUP_RTOL, groups=mesh.part[origin], what="with copies")


# --------------------------------------------------------------------------- typed errors


BAD_MESH_KINDS = [
    "nan vertex", "inf vertex", "V 4 columns", "V 1 column", "V 1-D", "V 3-D", "V empty", "V strings",
    "F index n", "F index beyond", "F negative", "F int64 max", "F uint64 max", "F huge int",
    "F float", "F nan", "F 4 columns", "F 2 columns", "F 1-D", "F empty", "F ragged",
    "all faces degenerate", "all vertices coincide",
]  # fmt: skip


def _bad_mesh(kind, data, mesh):
    V, F = mesh.V.copy(), mesh.F.copy()
    n, m = V.shape[0], F.shape[0]
    r, c = data.draw(st.integers(0, m - 1), label="row"), data.draw(st.integers(0, 2), label="column")
    if kind == "nan vertex":
        V[F[r, c], c] = np.nan
    elif kind == "inf vertex":
        V[F[r, c], c] = -np.inf if r % 2 else np.inf
    elif kind == "V 4 columns":
        V = np.column_stack([V, V[:, 0]])
    elif kind == "V 1 column":
        V = V[:, :1]
    elif kind == "V 1-D":
        V = V.ravel()
    elif kind == "V 3-D":
        V = V[None]
    elif kind == "V empty":
        V = np.zeros((0, 3))
    elif kind == "V strings":
        V = [["a", "b", "c"]] * n
    elif kind == "F index n":
        F[r, c] = n
    elif kind == "F index beyond":
        F[r, c] = n + data.draw(st.integers(1, 10**9), label="beyond")
    elif kind == "F negative":
        F[r, c] = -data.draw(st.integers(1, 10**9), label="negative")
    elif kind == "F int64 max":
        F[r, c] = np.iinfo(np.int64).max
    elif kind == "F uint64 max":
        F = F.astype(np.uint64)
        F[r, c] = np.iinfo(np.uint64).max
    elif kind == "F huge int":
        F = F.tolist()
        F[r][c] = 10**20
    elif kind == "F float":
        F = F.astype(float)
        F[r, c] += 0.5
    elif kind == "F nan":
        F = F.astype(float)
        F[r, c] = np.nan
    elif kind == "F 4 columns":
        F = np.column_stack([F, F[:, 0]])
    elif kind == "F 2 columns":
        F = F[:, :2]
    elif kind == "F 1-D":
        F = F.ravel()
    elif kind == "F empty":
        F = np.zeros((0, 3), np.int64)
    elif kind == "F ragged":
        F = F.tolist()
        F[r] = F[r][:2]
    elif kind == "all faces degenerate":
        F[:, 1] = F[:, 0]
    elif kind == "all vertices coincide":
        V[:] = V[0]
    else:  # pragma: no cover
        raise AssertionError(kind)
    return V, F


@pytest.mark.parametrize("kind", BAD_MESH_KINDS)
@PER_KIND
@given(data=st.data())
def test_invalid_mesh_raises_invalid_mesh_error(kind, data):
    mesh = data.draw(meshes(max_parts=2, max_vertices=60), label="mesh")
    V, F = _bad_mesh(kind, data, mesh)
    with pytest.raises(HeatcoreError) as caught:
        d = hc.HeatSolver(hc.TriangleMesh(V, F, refine=0)).distance([int(mesh.F[0, 0])])
        note(f"result: {d!r}")
    assert isinstance(caught.value, InvalidMeshError), f"{kind}: {type(caught.value).__name__}: {caught.value}"


BAD_SOURCE_KINDS = [
    "no source", "empty list", "vertex n", "vertex -1", "vertex far beyond", "vertex int64 max",
    "vertex uint64 max", "vertex huge int", "scalar huge int", "vertex 0.5", "vertex nan", "vertex inf",
    "vertex string", "vertex string scalar", "nested vertices", "nested vertex pair", "2-D vertex array",
    "ragged vertices", "unreferenced vertex",
    "edge not in mesh", "edge loop", "edge 3 columns", "edge flat pair", "edge out of range", "edge negative",
    "edge nested deeper", "edge ragged", "edge on unreferenced vertex",
    "face m", "face -1", "face 0.5", "nested faces", "empty faces",
    "face point out of range", "face point bary sum", "face point bary negative", "face point bary nan",
    "face point count mismatch", "face point 2 weights", "face point 4 weights", "face point bary strings",
    "face points not a pair", "face points one-tuple", "face points triple", "face points string",
    "face point index 0.5", "face point nested index",
]  # fmt: skip


def _bad_source(kind, data, mesh):
    """A source specification that must be refused, as (args, kwargs)."""
    n, m = mesh.n, mesh.F.shape[0]
    referenced = np.flatnonzero(mesh.part >= 0)
    v = int(referenced[data.draw(st.integers(0, referenced.size - 1), label="vertex")])
    w = int(referenced[data.draw(st.integers(0, referenced.size - 1), label="other vertex")])
    f = data.draw(st.integers(0, m - 1), label="face")
    other_part = np.flatnonzero((mesh.part >= 0) & (mesh.part != mesh.part[v]))  # never adjacent to v
    far = int(other_part[0])
    u = int(np.flatnonzero(mesh.part < 0)[0])
    cases = {
        "no source": ((), {}),
        "empty list": (([],), {}),
        "vertex n": (([n],), {}),
        "vertex -1": (([-1],), {}),
        "vertex far beyond": (([n + 10**6],), {}),
        "vertex int64 max": (([np.iinfo(np.int64).max],), {}),
        "vertex uint64 max": ((np.array([np.iinfo(np.uint64).max], np.uint64),), {}),
        "vertex huge int": (([10**20],), {}),
        "scalar huge int": ((10**20,), {}),
        "vertex 0.5": (([v + 0.5],), {}),
        "vertex nan": (([np.nan],), {}),
        "vertex inf": (([np.inf],), {}),
        "vertex string": ((["a"],), {}),
        "vertex string scalar": (("0",), {}),
        "nested vertices": (([[v], [w]],), {}),
        "nested vertex pair": (([[v, w]],), {}),
        "2-D vertex array": ((np.array([[v], [w]]),), {}),
        "ragged vertices": (([[v, w], [v]],), {}),
        "unreferenced vertex": (([u],), {}),
        "edge not in mesh": ((), {"edges": [[v, far]]}),
        "edge loop": ((), {"edges": [[v, v]]}),
        "edge 3 columns": ((), {"edges": [[v, w, v]]}),
        "edge flat pair": ((), {"edges": [v, w]}),
        "edge out of range": ((), {"edges": [[v, n]]}),
        "edge negative": ((), {"edges": [[v, -1]]}),
        "edge nested deeper": ((), {"edges": [[[v, w]]]}),
        "edge ragged": ((), {"edges": [[v, w], [v]]}),
        "edge on unreferenced vertex": ((), {"edges": [[v, u]]}),
        "face m": ((), {"region": [m]}),
        "face -1": ((), {"region": [-1]}),
        "face 0.5": ((), {"region": [f + 0.5]}),
        "nested faces": ((), {"region": [[f], [0]]}),
        "empty faces": ((), {"region": []}),
        "face point out of range": ((), {"points": ([m], [[1.0, 0.0, 0.0]])}),
        "face point bary sum": ((), {"points": ([f], [[0.5, 0.6, 0.0]])}),
        "face point bary negative": ((), {"points": ([f], [[-0.5, 1.5, 0.0]])}),
        "face point bary nan": ((), {"points": ([f], [[np.nan, 0.5, 0.5]])}),
        "face point count mismatch": ((), {"points": ([f, 0], [[1.0, 0.0, 0.0]])}),
        "face point 2 weights": ((), {"points": ([f], [[0.5, 0.5]])}),
        "face point 4 weights": ((), {"points": ([f], [[0.25, 0.25, 0.25, 0.25]])}),
        "face point bary strings": ((), {"points": ([f], [["a", "b", "c"]])}),
        "face points not a pair": ((), {"points": [f]}),
        "face points one-tuple": ((), {"points": ([f],)}),
        "face points triple": ((), {"points": ([f], [[1.0, 0.0, 0.0]], 0)}),
        "face points string": ((), {"points": "abc"}),
        "face point index 0.5": ((), {"points": ([f + 0.5], [[1.0, 0.0, 0.0]])}),
        "face point nested index": ((), {"points": ([[f]], [[1.0, 0.0, 0.0]])}),
    }
    return cases[kind]


@pytest.mark.parametrize("kind", BAD_SOURCE_KINDS)
@PER_KIND
@given(data=st.data())
def test_invalid_sources_raise_invalid_source_error(kind, data):
    mesh = data.draw(meshes(min_parts=2, max_vertices=80), label="mesh")
    if not (mesh.part < 0).any():  # one unreferenced vertex at least, away from the parts
        mesh = dataclasses.replace(mesh, V=np.vstack([mesh.V, mesh.V.max(axis=0) + 1.0]), part=np.r_[mesh.part, -1])
    refine = data.draw(st.sampled_from([0, 1]), label="refine")
    solver = hc.HeatSolver(hc.TriangleMesh(mesh.V, mesh.F, refine=refine))
    args, kwargs = _bad_source(kind, data, mesh)
    with pytest.raises(HeatcoreError) as caught:
        d = solver.distance(*args, **kwargs)
        note(f"result: {d!r}")
    assert isinstance(caught.value, InvalidSourceError), f"{kind}: {type(caught.value).__name__}: {caught.value}"


@PER_KIND
@given(data=st.data())
def test_source_on_a_dropped_face_raises_invalid_source_error(data):
    """A face with a repeated vertex is ignored; its corners, used by no other face, cannot carry a source."""
    mesh = data.draw(meshes(max_parts=2, max_vertices=80, unreferenced=False), label="mesh")
    n = mesh.n
    V = np.vstack([mesh.V, mesh.V.max(axis=0) + 1.0, mesh.V.max(axis=0) + 2.0])
    F = np.vstack([mesh.F, [[n, n, n + 1]]])
    bad = F.shape[0] - 1
    kwargs = data.draw(
        st.sampled_from([{"region": [bad]}, {"points": ([bad], [[0.2, 0.3, 0.5]])}, {"points": ([bad], [[1.0, 0, 0]])}]),
        label="source",
    )
    solver = hc.HeatSolver(hc.TriangleMesh(V, F, refine=data.draw(st.sampled_from([0, 1]), label="refine")))
    with pytest.raises(HeatcoreError) as caught:
        d = solver.distance(**kwargs)
        note(f"result: {d!r}")
    assert isinstance(caught.value, InvalidSourceError), f"{type(caught.value).__name__}: {caught.value}"


BAD_OPTIONS = [
    ("refine", -1), ("refine", 9), ("refine", 1.5), ("refine", "x"), ("refine", True), ("refine", None),
    ("m", 0.0), ("m", -1.0), ("m", np.nan), ("m", np.inf), ("m", "1"), ("m", None),
    ("boundary", "x"), ("boundary", None), ("boundary", 1), ("accuracy", "x"), ("accuracy", None),
]  # fmt: skip


@pytest.mark.parametrize(("option", "value"), BAD_OPTIONS)
@PER_KIND
@given(data=st.data())
def test_invalid_options_raise_invalid_option_error(option, value, data):
    mesh = data.draw(meshes(max_parts=2, max_vertices=40), label="mesh")
    with pytest.raises(HeatcoreError) as caught:
        options = {"refine": 0, option: value}  # refine="auto" would build a large mesh before m is checked
        hc.geodesic_distance(mesh.V, mesh.F, [int(mesh.F[0, 0])], **options)
    assert isinstance(caught.value, InvalidOptionError), f"{type(caught.value).__name__}: {caught.value}"


@pytest.mark.parametrize("value", [-1.0, -1e-300, np.nan, "yes", [0.0]])
@PER_KIND
@given(data=st.data())
def test_invalid_weld_option_raises_invalid_option_error(value, data):
    mesh = data.draw(meshes(max_parts=2, max_vertices=40), label="mesh")
    with pytest.raises(HeatcoreError) as caught:
        hc.TriangleMesh(mesh.V, mesh.F, weld=value, refine=0)
    assert isinstance(caught.value, InvalidOptionError), f"{type(caught.value).__name__}: {caught.value}"


@pytest.mark.parametrize("value", [0.0, None, 1e-12])
@PER_KIND
@given(data=st.data())
def test_valid_weld_option_values(value, data):
    """``weld``: None (off) or a tolerance >= 0; a mesh with distinct positions is unchanged by any of them."""
    mesh = data.draw(meshes(max_parts=2, max_vertices=40), label="mesh")
    src, parts = data.draw(sources(mesh), label="sources")
    d = solve(mesh.V, mesh.F, src, weld=value)
    check_reachability(d, mesh, parts, src)
    assert_close(d, solve(mesh.V, mesh.F, src), SOUP_RTOL, groups=mesh.part, what=f"weld={value!r}")


@pytest.mark.parametrize("value", [2**63 - 1, 2**63, 2**64 - 1, "beyond"])
@pytest.mark.parametrize("where", ["face", "source"])
@PER_KIND
@given(data=st.data())
def test_out_of_range_index_message_shows_the_value_given(value, where, data):
    """Indices near int64 max or in uint64: the error message shows the value given, not a wrapped one."""
    mesh = data.draw(meshes(max_parts=1, max_vertices=40, unreferenced=False), label="mesh")
    if value == "beyond":
        value = data.draw(st.integers(mesh.n, 2**64 - 1), label="index")
    if where == "face":
        F = mesh.F.astype(np.uint64)
        F[0, 0] = value
        with pytest.raises(InvalidMeshError) as caught:
            hc.TriangleMesh(mesh.V, F, refine=0)
    else:
        solver = hc.HeatSolver(hc.TriangleMesh(mesh.V, mesh.F, refine=0))
        with pytest.raises(InvalidSourceError) as caught:
            solver.distance(np.array([value], dtype=np.uint64))
    assert str(value) in str(caught.value), str(caught.value)


@given(data=st.data())
def test_degenerate_geometry_gives_a_typed_error_or_clean_distances(data):
    """Collapsed or flattened faces: a HeatcoreError, or distances with no NaN and none negative."""
    mesh = data.draw(meshes(max_parts=2, max_vertices=120), label="mesh")
    V = mesh.V.copy()
    m = mesh.F.shape[0]
    for _ in range(data.draw(st.integers(1, 4), label="damaged faces")):
        f = mesh.F[data.draw(st.integers(0, m - 1), label="face")]
        how = data.draw(st.sampled_from(["collapse edge", "collapse face", "flatten", "sliver"]), label="how")
        a, b, c = f
        if how == "collapse edge":
            V[b] = V[a]
        elif how == "collapse face":
            V[b] = V[a]
            V[c] = V[a]
        elif how == "flatten":
            V[c] = 0.5 * (V[a] + V[b])
        else:
            V[c] = 0.5 * (V[a] + V[b]) + 1e-13 * (V[c] - V[a])
    referenced = np.flatnonzero(mesh.part >= 0)
    s = int(referenced[data.draw(st.integers(0, referenced.size - 1), label="source")])
    try:
        d = hc.HeatSolver(hc.TriangleMesh(V, mesh.F, refine=data.draw(st.sampled_from([0, 1]), label="refine"))).distance([s])
    except HeatcoreError:
        return
    assert not np.isnan(d).any(), f"NaN at {np.flatnonzero(np.isnan(d))[:10].tolist()}"
    assert (d >= 0).all()
    assert d[s] == 0
