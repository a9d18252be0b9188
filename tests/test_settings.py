"""The one settings object (heatcore/settings.py): checked once, split once, handed over as it is."""

import numpy as np
import pytest
from shapes import grid

import heatcore as hc
from heatcore.options import OPTIONS, Option
from heatcore.settings import FRONT_END_OPTIONS, MeshSettings, Settings, SolverSettings


def test_every_front_end_offers_declared_options_and_every_option_is_offered():
    offered = {name for names in FRONT_END_OPTIONS.values() for name in names}
    assert offered <= set(OPTIONS)
    assert offered == set(OPTIONS), f"declared but offered by no front end: {set(OPTIONS) - offered}"


@pytest.mark.parametrize(
    ("front_end", "name"),
    [(end, name) for end, names in FRONT_END_OPTIONS.items() for name in OPTIONS if name not in names],
)
def test_a_front_end_refuses_an_option_it_does_not_offer(front_end, name):
    with pytest.raises(hc.InvalidOptionError, match=f"does not offer the option {name}"):
        Settings.of(front_end, **{name: OPTIONS[name].default})


@pytest.mark.parametrize("front_end", FRONT_END_OPTIONS)
def test_defaults_are_the_front_ends_own(front_end):
    s = Settings.of(front_end)
    for part in (s.mesh, s.solver, s.output):
        for name, value in part.keywords().items():
            assert value == OPTIONS[name].default_for(front_end), (front_end, name)
        assert part.given == frozenset()


def test_settings_are_frozen_and_replace_checks():
    s = SolverSettings(m=2)
    with pytest.raises(AttributeError, match="frozen"):
        s.m = 3
    assert s.replace(boundary="neumann").m == 2.0
    with pytest.raises(hc.InvalidOptionError, match="invalid time factor -1"):
        s.replace(m=-1)
    assert SolverSettings(m=2) == s and hash(SolverSettings(m=2)) == hash(s)
    assert SolverSettings(m=2, intent="one query") != s


def test_unknown_keywords_are_typed_errors():
    mesh = hc.TriangleMesh(*grid(5, 5), refine=0)
    with pytest.raises(hc.InvalidOptionError, match="unknown solver option 'mm'"):
        hc.HeatSolver(mesh, mm=2)
    with pytest.raises(hc.InvalidOptionError, match="unknown mesh option 'refin'"):
        hc.TriangleMesh(*grid(5, 5), refin=0)
    with pytest.raises(hc.InvalidOptionError, match="intent"):
        SolverSettings(intent="twice")


def test_geodesic_distance_checks_each_value_once(monkeypatch):
    """The walk of every option from the Python API: one check per value, none downstream."""
    calls = []
    check = Option.check
    monkeypatch.setattr(Option, "check", lambda self, value, extra=(): calls.append(self.name) or check(self, value, extra))
    V, F = grid(6, 6)
    hc.geodesic_distance(V, F, [0], m=2, boundary="neumann", accuracy="high", backend="superlu", refine=1, robust=True,
                         weld=None)
    assert sorted(calls) == sorted(FRONT_END_OPTIONS["api"])


def test_solver_from_settings_equals_solver_from_keywords():
    mesh = hc.TriangleMesh(*grid(9, 9))
    settings = Settings.of("cli", m=3, boundary="dirichlet")
    a = hc.HeatSolver(mesh, settings.solver).distance([4])
    b = hc.HeatSolver(mesh, m=3, boundary="dirichlet").distance([4])
    c = hc.HeatSolver(mesh, settings).distance([4])  # the whole object: the solver takes its part
    assert np.array_equal(a, b) and np.array_equal(a, c)
    assert hc.HeatSolver(mesh, settings.solver, m=1).m == 1.0  # keywords change given settings


def test_intent_decides_what_auto_stands_for():
    mesh = hc.TriangleMesh(*grid(9, 9))
    n = mesh.operators.n_vertices
    once = hc.HeatSolver(mesh, SolverSettings(intent="one query")).factors
    reuse = hc.HeatSolver(mesh).factors
    assert once.heat_backend == once.poisson_backend == hc.linalg.choose_backend(n, "factor")
    assert (reuse.heat_backend, reuse.poisson_backend) == (hc.linalg.choose_backend(n, "factor"),
                                                           hc.linalg.choose_backend(n, "solve"))
    named = hc.HeatSolver(mesh, SolverSettings(backend="superlu", intent="one query")).factors
    assert named.heat_backend == named.poisson_backend == "superlu"


def test_domains_refuse_options_they_do_not_take_only_when_given():
    V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)
    with pytest.raises(hc.InvalidOptionError, match="a polygon mesh does not take the option weld"):
        hc.PolygonMesh(V, [[0, 1, 2, 3]], weld=0.5)
    with pytest.raises(hc.InvalidOptionError, match="a point cloud does not take the options robust, weld"):
        hc.PointCloud(np.random.default_rng(0).random((30, 3)), robust=False, weld=None)
    blender = MeshSettings("blender")  # weld None is Blender's default, not given: no refusal
    assert hc.PolygonMesh(V, [[0, 1, 2, 3]], blender, refine=0).levels == 0
