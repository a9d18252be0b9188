"""Point clouds: accuracy against exact geodesics and potpourri3d, robustness, bad input, reader.

The clouds are the vertices of shared test meshes; the reference is the exact
(MMP, gdist) distance on the mesh (scenarios as in scripts/bench_pointcloud.py).
"""

import sys
from pathlib import Path

import numpy as np
import pytest
from conftest import load_shared_mesh, mean_relative_error

import heatcore as hc
from heatcore.domains.pointcloud import PointCloud
from heatcore.errors import InvalidMeshError, InvalidOptionError, InvalidSourceError
from heatcore.io.pointcloud import read_point_cloud

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "scripts"))
from bench_pointcloud import potpourri_errors, scenario

# Measured (docs/pointcloud.md): spot clean 1.46%, cheburashka clean 2.59%;
# potpourri3d on the same points 2.18% and 4.24%. The clean thresholds sit
# ~0.3 points above ours and below potpourri3d; the tests also compare with
# potpourri3d in the same run.
CLEAN_THRESHOLDS = {"spot": 0.018, "cheburashka": 0.031}

# Robustness on spot, measured: hole 0.90%, nonuniform 1.67%, noise 1.97%
# (potpourri3d: 2.12%, 2.41%, 2.31%). Thresholds: the clean threshold (1.8%)
# for the hole, which removes points but not resolution; +0.7 points for a
# 5x density change (the sparse end has sqrt(5) times the spacing, and the
# heat method's error grows with h); +0.7 points for noise of 0.1 h, whose
# tangential jitter alone perturbs short distances by ~10% of h.
# Heavy noise (0.5% of the bounding-box diagonal, issue 22): measured 6.66% (potpourri3d 7.25%); it
# used to leave a point in no triangle (inf: an infinite mean error).
ROBUST_THRESHOLDS = {"hole": 0.018, "nonuniform": 0.025, "noise": 0.025, "heavy noise": 0.07}


def heatcore_error(P, sources, exact, **kw):
    solver = hc.HeatSolver(PointCloud(P, **kw))
    errors = []
    for s, e in zip(sources, exact):
        d = solver.distance([s])
        assert not np.isnan(d).any()
        errors.append(mean_relative_error(d, e))
    return float(np.mean(errors))


@pytest.mark.parametrize("name", sorted(CLEAN_THRESHOLDS))
def test_mesh_vertices_against_exact_and_potpourri(name):
    V, F = load_shared_mesh(name)
    P, sources, exact = scenario(V, F, "clean")
    ours = heatcore_error(P, sources, exact)
    peer = float(np.mean(potpourri_errors(P, sources, exact)[0]))
    assert ours <= CLEAN_THRESHOLDS[name]
    assert ours <= peer


@pytest.mark.parametrize("kind", sorted(ROBUST_THRESHOLDS))
def test_robustness_on_spot(kind):
    V, F = load_shared_mesh("spot")
    P, sources, exact = scenario(V, F, kind)
    ours = heatcore_error(P, sources, exact)
    peer = float(np.mean(potpourri_errors(P, sources, exact)[0]))
    assert ours <= ROBUST_THRESHOLDS[kind]
    assert ours <= peer


def test_homer_with_a_hole_against_potpourri():
    """Issue 22: holed clouds at least as close as potpourri3d's; homer's hole is the hardest (slits
    in the reference): measured 7.21% against 7.25% (7.91% before neighbors were limited to 2 spacings)."""
    V, F = load_shared_mesh("homer")
    P, sources, exact = scenario(V, F, "hole")
    ours = heatcore_error(P, sources, exact)
    assert ours <= 0.0725
    assert ours <= float(np.mean(potpourri_errors(P, sources, exact)[0]))


def test_given_normals_match_pca_normals(spot):
    import trimesh

    V, F = spot
    normals = trimesh.Trimesh(V, F, process=False).vertex_normals
    flipped = normals * np.where(np.arange(len(V)) % 2, 1.0, -1.0)[:, None]  # sign does not matter
    P, sources, exact = scenario(V, F, "clean")
    assert heatcore_error(P, sources, exact, normals=flipped) <= CLEAN_THRESHOLDS["spot"]


def test_plane_gives_euclidean_distance():
    rng = np.random.default_rng(1)
    Q = rng.random((400, 2))
    d = hc.HeatSolver(PointCloud(Q)).distance([0])
    e = np.linalg.norm(Q - Q[0], axis=1)
    assert np.mean(np.abs(d - e)[1:] / e[1:]) < 0.02


def test_duplicates_are_merged(spot):
    V, _ = spot
    n = len(V)
    P = np.vstack([V, V[:300], V[:300] + 1e-13])
    cloud = PointCloud(P)
    assert cloud.n_duplicates == 600
    d0 = hc.HeatSolver(PointCloud(V)).distance([5])
    d = hc.HeatSolver(cloud).distance([n + 5])  # a copy of point 5 as the source
    assert not np.isnan(d).any()
    np.testing.assert_allclose(d[:n], d0, atol=1e-9)
    np.testing.assert_allclose(d[n : n + 300], d0[:300], atol=1e-9)


def test_separate_clusters_get_inf(spot):
    V, _ = spot
    n = len(V)
    P = np.vstack([V, V + [5.0, 0.0, 0.0], [[20.0, 20.0, 20.0]]])
    solver = hc.HeatSolver(PointCloud(P))
    assert solver.n_components == 2
    d = solver.distance([0])
    assert np.isfinite(d[:n]).all() and np.isinf(d[n:]).all()
    both = solver.distance([0, n + 7])
    assert np.isfinite(both[:-1]).all() and np.isinf(both[-1])  # the lone point is reached by nothing
    with pytest.raises(InvalidSourceError, match="isolated"):
        solver.distance([2 * n])


@pytest.mark.parametrize(
    "points, match",
    [
        (np.zeros((10, 4)), "shape"),
        (np.zeros(10), "shape"),
        (np.zeros((0, 3)), "empty"),
        ([[0, 0, 0], [1, 0, 0]], "at least 3 distinct"),
        (np.ones((50, 3)), "at least 3 distinct"),
        (np.c_[np.arange(30.0), np.zeros(30), np.zeros(30)], "no triangles"),
        ("abc", "numeric"),
    ],
)
def test_bad_points(points, match):
    with pytest.raises(InvalidMeshError, match=match):
        PointCloud(points)


def test_nan_point(spot):
    P = spot[0].copy()
    P[7, 1] = np.nan
    with pytest.raises(InvalidMeshError, match="vertex 7"):
        PointCloud(P)


@pytest.mark.parametrize("k, match", [(3, "between"), (1000, "between"), (10.5, "integer"), (True, "integer")])
def test_bad_k(spot, k, match):
    with pytest.raises(InvalidOptionError, match=match):
        PointCloud(spot[0], k=k)


def test_k_larger_than_cloud():
    P = np.random.default_rng(0).random((20, 3))
    with pytest.raises(InvalidOptionError, match="only 20"):
        PointCloud(P, k=30)
    assert PointCloud(P).k == 19  # the default shrinks to fit


@pytest.mark.parametrize("normals, match", [(np.ones((3, 3)), "shape"), (None, "zero")])
def test_bad_normals(spot, normals, match):
    V = spot[0]
    with pytest.raises(InvalidMeshError, match=match):
        PointCloud(V, normals=np.zeros_like(V) if normals is None else normals)


def test_bad_sources(spot):
    solver = hc.HeatSolver(PointCloud(spot[0]))
    with pytest.raises(InvalidSourceError, match="out of range"):
        solver.distance([10**6])
    with pytest.raises(InvalidSourceError, match="no source"):
        solver.distance()
    with pytest.raises(InvalidSourceError, match="only"):
        solver.distance(points=([0], [[1.0, 0.0, 0.0]]))
    with pytest.raises(hc.errors.UnsupportedDomainError):
        hc.HeatSolver(PointCloud(spot[0]), accuracy="high")


def test_read_point_cloud_formats(tmp_path):
    import meshio

    rng = np.random.default_rng(0)
    P = rng.random((40, 3))
    N = P / np.linalg.norm(P, axis=1, keepdims=True)
    ply = tmp_path / "a.ply"
    meshio.write(str(ply), meshio.Mesh(P, [], point_data={"nx": N[:, 0], "ny": N[:, 1], "nz": N[:, 2]}))
    cloud = read_point_cloud(ply)
    np.testing.assert_allclose(cloud.points, P)
    np.testing.assert_allclose(cloud.normals, N)
    obj = tmp_path / "b.obj"
    obj.write_text("".join(f"v {x} {y} {z}\n" for x, y, z in P))
    np.testing.assert_allclose(read_point_cloud(obj).points, P)
    xyz = tmp_path / "c.xyz"
    np.savetxt(xyz, np.c_[P, N])
    cloud = read_point_cloud(xyz)
    np.testing.assert_allclose(cloud.points, P)
    np.testing.assert_allclose(cloud.normals, N)
    csv = tmp_path / "d.csv"
    np.savetxt(csv, P, delimiter=",")
    np.testing.assert_allclose(read_point_cloud(csv).points, P)


def test_read_point_cloud_errors(tmp_path):
    with pytest.raises(InvalidMeshError, match="not found"):
        read_point_cloud(tmp_path / "missing.ply")
    bad = tmp_path / "a.stl"
    bad.write_text("solid")
    with pytest.raises(InvalidMeshError, match="point clouds are read from"):
        read_point_cloud(bad)
    cols = tmp_path / "b.xyz"
    cols.write_text("1 2 3 4\n5 6 7 8\n")
    with pytest.raises(InvalidMeshError, match="columns"):
        read_point_cloud(cols)
    garbage = tmp_path / "c.ply"
    garbage.write_text("not a ply file")
    with pytest.raises(InvalidMeshError, match="cannot read"):
        read_point_cloud(garbage)
