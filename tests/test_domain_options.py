"""A domain refuses a mesh option it does not take when the user set it; defaults pass (issue 33)."""

import meshio
import numpy as np
import pytest
import scipy.spatial

import heatcore as hc
from heatcore import options
from heatcore.apps import cli
from heatcore.domains.pointcloud import PointCloud
from heatcore.errors import InvalidOptionError
from heatcore.io.domain import DomainFile

CLASSES = {"triangle": hc.TriangleMesh, "polygon": hc.PolygonMesh, "tet": hc.TetMesh, "points": PointCloud}
#: The mesh options each kind's domain declares it takes.
DOMAIN_OPTIONS = {kind: cls.mesh_options for kind, cls in CLASSES.items()}


def _files():
    """One small DomainFile of each kind."""
    P = np.random.default_rng(0).random((40, 3))
    square = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0.5, 0]], float)
    return {
        "triangle": DomainFile("triangle", square, None, np.array([[0, 1, 2], [0, 2, 3], [1, 4, 2]])),
        "polygon": DomainFile("polygon", square, None, [[0, 1, 2, 3], [1, 4, 2]]),
        "tet": DomainFile("tet", P, None, scipy.spatial.Delaunay(P).simplices),
        "points": DomainFile("points", P, None, None),
    }


REFUSED = [(kind, name, value) for kind in DOMAIN_OPTIONS for name in options.names("mesh")
           if name not in DOMAIN_OPTIONS[kind]
           for value in ((options.OPTIONS[name].default,) + ((None,) if name == "weld" else ()))]


def test_each_kind_refuses_something_but_triangles():
    assert {kind for kind, *_ in REFUSED} == {"polygon", "tet", "points"}


@pytest.mark.parametrize("kind, name, value", REFUSED)
def test_an_option_the_domain_does_not_take_is_refused(kind, name, value):
    with pytest.raises(InvalidOptionError) as error:
        _files()[kind].domain(**{name: value})
    message = str(error.value)
    assert f"does not take the option {name}" in message
    assert f"a {CLASSES[kind].domain_name} does not take" in message
    assert f"(it takes {', '.join(DOMAIN_OPTIONS[kind]) or 'no mesh option'})" in message


@pytest.mark.parametrize("kind", sorted(DOMAIN_OPTIONS))
def test_defaults_and_taken_options_build(kind):
    f = _files()
    assert isinstance(f[kind].domain(), CLASSES[kind])
    given = {name: options.OPTIONS[name].default for name in DOMAIN_OPTIONS[kind]}
    assert isinstance(f[kind].domain(**given), CLASSES[kind])


@pytest.mark.parametrize("kind", sorted(DOMAIN_OPTIONS))
def test_the_domains_take_declared_mesh_options(kind):
    assert set(DOMAIN_OPTIONS[kind]) <= set(options.names("mesh"))
    assert set(DOMAIN_OPTIONS[kind]) == {"triangle": {"robust", "refine", "weld"}, "polygon": {"refine"}, "tet": set(),
                                         "points": {"refine"}}[kind]


def test_refine_reaches_a_polygon_mesh():
    assert _files()["polygon"].domain(refine=0).levels == 0
    assert _files()["polygon"].domain().levels > 0


@pytest.fixture
def tet_file(tmp_path):
    P = np.random.default_rng(1).random((60, 3))
    path = tmp_path / "cube.vtu"
    meshio.write(path, meshio.Mesh(P, [("tetra", scipy.spatial.Delaunay(P).simplices)]))
    return path


def test_command_refuses_a_flag_set_for_a_tet_mesh(tet_file, tmp_path, capsys):
    out = tmp_path / "d.npy"
    assert cli.main(["distance", str(tet_file), "-s", "0", "-o", str(out), "-q"]) == 0  # defaults pass
    capsys.readouterr()
    assert cli.main(["distance", str(tet_file), "-s", "0", "-o", str(out), "-q", "--no-robust"]) != 0
    assert "a tet mesh does not take the option robust" in capsys.readouterr().err


def test_command_refuses_weld_for_a_point_cloud(tmp_path, capsys):
    path, out = tmp_path / "p.xyz", tmp_path / "d.npy"
    np.savetxt(path, np.random.default_rng(2).random((50, 3)))
    assert cli.main(["distance", str(path), "-s", "0", "-o", str(out), "-q", "--refine", "0"]) == 0
    capsys.readouterr()
    assert cli.main(["distance", str(path), "-s", "0", "-o", str(out), "-q", "--weld-tolerance", "0.1"]) != 0
    assert "a point cloud does not take the option weld (it takes refine)" in capsys.readouterr().err
