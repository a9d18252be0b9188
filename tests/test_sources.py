"""One source vocabulary on every domain, the deprecated old keywords, and the written Domain interface."""

import warnings

import numpy as np
import pytest
from scipy.spatial import Delaunay
from shapes import grid

import heatcore as hc
from heatcore.domains.base import Domain, MeshDomain
from heatcore.domains.sources import DEPRECATED_SOURCE_KEYWORDS, SOURCE_KINDS, build_source_pins
from heatcore.errors import InvalidOptionError, InvalidSourceError


@pytest.fixture(scope="module")
def square():
    V, F = grid(9, 9)
    return V, F


@pytest.fixture(scope="module")
def domains(square):
    V, F = square
    quads = np.array([[i * 9 + j, i * 9 + j + 1, (i + 1) * 9 + j + 1, (i + 1) * 9 + j] for i in range(8) for j in range(8)])
    Vt = np.stack(np.meshgrid(*[np.linspace(0, 1, 4)] * 3, indexing="ij"), -1).reshape(-1, 3)
    Vt = Vt + np.random.default_rng(0).uniform(-0.05, 0.05, Vt.shape)
    T = Delaunay(Vt).simplices
    return {
        "triangle": hc.TriangleMesh(V, F, refine=1),
        "polygon": hc.PolygonMesh(V, quads),
        "tet": hc.TetMesh(Vt, T),
        "points": hc.PointCloud(np.random.default_rng(1).random((300, 3)) * [1, 1, 0.01]),
    }


def test_every_domain_implements_the_interface(domains):
    for name, domain in domains.items():
        assert isinstance(domain, Domain), name
        assert domain.source_kinds[0] == "vertices" and set(domain.source_kinds) <= set(SOURCE_KINDS), name
        assert domain.output_vertices.shape == (domain.n_input_vertices,), name
    assert all(isinstance(domains[k], MeshDomain) for k in ("triangle", "polygon", "tet"))
    assert [k for k, d in domains.items() if d.supports_high_accuracy] == ["triangle"]


def test_a_domain_that_misses_the_interface_cannot_be_built():
    class Incomplete(Domain):
        operators = None

    with pytest.raises(TypeError, match="abstract"):
        Incomplete()


@pytest.mark.parametrize(
    ("domain", "old", "new", "value"),
    [
        ("triangle", "face_points", "points", ([3], [[0.2, 0.3, 0.5]])),
        ("triangle", "faces", "region", [3, 4]),
        ("polygon", "faces", "region", [5]),
        ("tet", "tet_points", "points", ([0], [[0.25, 0.25, 0.25, 0.25]])),
    ],
)
def test_old_keywords_warn_and_mean_the_new_ones(domains, domain, old, new, value):
    solver = hc.HeatSolver(domains[domain])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        expected = solver.distance(**{new: value})
    with pytest.warns(DeprecationWarning, match=f"'{old}' is deprecated; use {new}=") as caught:
        d = solver.distance(**{old: value})
    assert caught[0].filename == __file__  # the warning points at the caller's line
    np.testing.assert_array_equal(d, expected)
    assert DEPRECATED_SOURCE_KEYWORDS[old] == new


def test_tet_boundary_faces_alias(domains):
    mesh = domains["tet"]
    region = mesh.boundary_faces[:2]
    with pytest.warns(DeprecationWarning, match="boundary_faces"):
        old = mesh.source_pins(boundary_faces=region)
    new = mesh.source_pins(region=region)
    np.testing.assert_array_equal(old.vertices, new.vertices)
    np.testing.assert_array_equal(old.heat, new.heat)


def test_same_kind_under_old_and_new_name_is_refused(domains):
    with pytest.raises(InvalidSourceError, match="region given twice"), pytest.warns(DeprecationWarning):
        domains["triangle"].source_pins(faces=[1], region=[2])


@pytest.mark.parametrize("name", ["face", "sources", "vertices_list", "boundary"])
def test_unknown_keywords_are_refused(domains, name):
    with pytest.raises(InvalidSourceError, match=f"unknown source keyword '{name}'"):
        hc.HeatSolver(domains["triangle"]).distance(**{name: [0]})


@pytest.mark.parametrize(
    ("domain", "kind", "value"),
    [
        ("points", "points", ([0], [[1.0, 0.0, 0.0]])),
        ("points", "region", [0]),
        ("polygon", "points", ([0], [[1.0, 0.0, 0.0]])),
        ("tet", "edges", [[0, 1]]),
    ],
)
def test_a_kind_the_domain_does_not_take_is_refused_by_name(domains, domain, kind, value):
    mesh = domains[domain]
    with pytest.raises(InvalidSourceError, match=f"a {mesh.domain_name} takes only .* as sources, not {kind}"):
        mesh.source_pins(**{kind: value})


def test_no_source_names_the_kinds_the_domain_takes(domains):
    with pytest.raises(InvalidSourceError, match="no source given: pass vertices, points, region"):
        domains["tet"].source_pins()
    with pytest.raises(InvalidSourceError, match="no source given: pass vertices \\(at least one\\)"):
        domains["points"].source_pins([])


def test_kinds_combine_into_one_set_of_pins(domains):
    mesh = domains["triangle"]
    both = build_source_pins(mesh, [0], region=[5])
    alone = [build_source_pins(mesh, [0]), build_source_pins(mesh, region=[5])]
    assert set(both.vertices) == set(alone[0].vertices) | set(alone[1].vertices)
    np.testing.assert_allclose(both.heat, alone[0].heat + alone[1].heat)


def test_polygon_heat_is_unit_once_per_source_vertex(domains):
    mesh = domains["polygon"]
    pins = mesh.source_pins([0, 0], region=[0])  # vertex 0 is named three times
    assert pins.heat[mesh.vertex_map[0]] == 1.0 and set(np.flatnonzero(pins.heat)) == set(pins.vertices)


def test_high_accuracy_is_a_declared_capability(domains):
    with pytest.raises(hc.errors.UnsupportedDomainError, match="accuracy='high' is available on triangle meshes"):
        hc.HeatSolver(domains["tet"], accuracy="high")
    faces, lengths = domains["triangle"].eikonal_triangles()
    assert all(f.shape == l.shape for f, l in zip(faces, lengths))
    with pytest.raises(NotImplementedError):
        domains["points"].eikonal_triangles()


def test_solver_factors_live_in_the_domain_cache_only(square):
    mesh = hc.TriangleMesh(*square, refine=0)
    solver = hc.HeatSolver(mesh)
    assert not any("factor" in name for name in vars(mesh))  # no attribute of their own: domain.derived holds them
    assert ("poisson", solver.factors.poisson_backend) in mesh.derived  # the domain's own cache, dropped with it
