"""Each domain owns one cache of what is derived from it (heatcore/domains/derived.py), dropped with it."""

import ast
import gc
import pathlib
import weakref

import numpy as np
import pytest

import heatcore as hc
from heatcore.domains.derived import KINDS, DerivedCache

ROOT = pathlib.Path(__file__).resolve().parents[1]

#: Module-level dicts filled at run time that are keyed by something else than a domain or a solver.
NOT_BY_DOMAIN = {
    "heatcore/apps/cli.py COMMANDS": "subcommands, by name",
    "heatcore/linalg/libraries.py _modules": "optional libraries, by module name",
    "heatcore/linalg/supernodal.py _threads": "the background factorization's thread pool, by role (cleared in a forked child)",
    "blender_addon/undo.py _BEFORE_RUN": "a Blender mesh's active colour before a run, by the mesh's name",
}


@pytest.fixture(scope="module")
def square():
    V = np.array([[x, y, 0.0] for y in range(4) for x in range(4)], float)
    F = [[i + 4 * j, i + 1 + 4 * j, i + 4 * (j + 1)] for j in range(3) for i in range(3)]
    F += [[i + 1 + 4 * j, i + 1 + 4 * (j + 1), i + 4 * (j + 1)] for j in range(3) for i in range(3)]
    return V, np.array(F)


def test_every_domain_kind_has_its_own_cache_created_on_first_use(square):
    V, F = square
    domains = [hc.TriangleMesh(V, F, refine=0), hc.TriangleMesh(V, F, refine=0), hc.PointCloud(V),
               hc.PolygonMesh(V, [list(f) for f in F])]
    for domain in domains:
        assert "_derived" not in vars(domain)
        assert isinstance(domain.derived, DerivedCache) and domain.derived is domain.derived
    assert domains[0].derived is not domains[1].derived  # equal meshes share nothing


def test_what_the_solvers_derive_is_kept_in_the_domain_cache(square):
    mesh = hc.TriangleMesh(*square)
    solver = hc.HeatSolver(mesh, accuracy="high")
    solver.distance([0])
    solver.geodesic_path(0, 3)
    hc.HeatSolver(mesh).distance([0])  # the heat method's factors (accuracy="high" with numba needs none)
    hc.VectorHeatSolver(mesh).log_map(0)  # its factors are built on first use
    kinds = {kind for kind, _ in mesh.derived}
    # refined: the distance takes two heat steps, the vector heat method's flows factor their own (vector scalar heat)
    assert {"ordering", "poisson", "path mesh", "vector frames", "vector heat", "vector scalar heat"} <= kinds
    assert kinds & {"eikonal corners", "fast marching"}  # the accuracy='high' pass: either one
    assert kinds <= set(KINDS)
    assert hc.linalg.factor.__module__ == "heatcore.linalg.factor"
    assert ("poisson", solver.factors.poisson_backend) in mesh.derived


def test_the_cache_goes_with_the_domain(square):
    mesh = hc.TriangleMesh(*square)
    solver = hc.HeatSolver(mesh, accuracy="high")
    solver.geodesic_path(0, 3)
    kept = [weakref.ref(mesh.derived), weakref.ref(mesh.derived["path mesh", None])]
    del mesh, solver
    gc.collect()
    assert [ref() for ref in kept] == [None, None]


def test_clear_drops_everything_and_solvers_rebuild_the_same(square):
    mesh = hc.TriangleMesh(*square)
    before = hc.HeatSolver(mesh).distance([0])
    mesh.derived.clear()
    assert len(mesh.derived) == 0
    assert np.array_equal(hc.HeatSolver(mesh).distance([0]), before)


def test_keys_are_documented_kind_variant_pairs():
    cache = DerivedCache()
    assert cache.get_or_build(("ordering", "qdldl"), lambda: 1) == 1
    for key in ("ordering", ("colour", None), ("ordering", "qdldl", 2)):
        with pytest.raises(KeyError, match="kind one of"):
            cache[key] = 0


def _module_level_caches(path):
    """Module-level names bound to a dict, WeakKeyDictionary or WeakValueDictionary that the module mutates."""
    tree = ast.parse(path.read_text())
    found = []
    for node in tree.body:
        if not isinstance(node, (ast.Assign, ast.AnnAssign)) or node.value is None:
            continue
        value = node.value
        weak = isinstance(value, ast.Call) and getattr(value.func, "attr", getattr(value.func, "id", "")) in (
            "WeakKeyDictionary", "WeakValueDictionary")
        empty = isinstance(value, ast.Dict) and not value.keys
        if weak or empty:
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            found += [f"{path.relative_to(ROOT).as_posix()} {ast.unparse(t)}" for t in targets]
    return found


def test_no_module_level_table_keyed_by_domain_or_solver():
    """No module-level weak dictionary, and no empty dict filled at run time but by names: derived data lives with
    its owner (the domain's cache, the solver's path fields)."""
    files = sorted((ROOT / "heatcore").rglob("*.py")) + sorted((ROOT / "blender_addon").rglob("*.py"))
    found = {hit for path in files for hit in _module_level_caches(path)}
    assert found <= set(NOT_BY_DOMAIN)
    sources = "".join(path.read_text() for path in files)
    assert "WeakKeyDictionary" not in sources and "__dict__.setdefault(\"_path" not in sources
