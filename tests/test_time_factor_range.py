"""The time factor ``m`` (t = m h^2) has a range that keeps the distance meaningful: (0, M_MAX], declared once.

Measured before the range existed (mean edge length h; "max" is the largest distance over the exact
largest distance, gdist; source vertex 0; default options unless said):

=================================  ======  ======  ======  ======  ======  ======
mesh (hop diameter)                m=1e6   1e8     1e9     1e10    1e12    1e15+
=================================  ======  ======  ======  ======  ======  ======
spot (130 hops, refined)           1.247   1.246   1.222   0.992   0.124   zeros
spot, refine=0 (70)                1.243   1.243   1.190   0.822   0.124   zeros
spot x 1e6, spot x 1e-6            1.247   1.246   1.222   0.992   0.124   noise
icosahedron, refine=0 (3)          0.982   0.982   0.612   0.612   0.612   0.612
icosphere(1), refine=0             0.974   0.974   0.660   0.347   0.347   0.347
icosphere(6), 41k vertices (192)   0.998   0.998   0.988   0.881   0.033
stanford-bunny, boundary (185)     1.154   1.154   1.154   1.106   0.077
spot + a small cheburashka         1.247   1.246   1.222   0.992   0.124   zeros
3 triangles, refine=0              0.997   0.997   0.997   0.997   0.997   1e20: SolverError
=================================  ======  ======  ======  ======  ======  ======

The smoothed distance (the paper's large-t limit) is reached by m = 1e5 on every mesh (spot 1.246 at
1e5, 1.247 at 1e6; mean relative error 15.0-15.1%, the limit's own), and from m = 1e9 the heat's
variation sinks into rounding. The cap 1e6 keeps 3 decades from the first failure. Tiny m (down to
5e-324) is harmless: the underflow guard raises it (spot: 0.0267), so there is no lower bound beyond 0.
"""

import numpy as np
import pytest

import heatcore as hc
from heatcore import heat
from heatcore.apps.cli import main
from heatcore.errors import InvalidOptionError
from heatcore.options import M_MAX, OPTIONS
from heatcore.steps.time_step import underflow_safe_m

ABOVE = [np.nextafter(M_MAX, np.inf), 1e7, 1e12, 1e15, 1e20, np.inf]


@pytest.fixture(scope="module")
def spot_exact():
    from conftest import exact_distance, load_shared_mesh

    V, F = load_shared_mesh("spot")
    return V, F, exact_distance(V, F.astype(np.int32), [0])


def assert_a_distance(d, exact, max_ratio=(0.95, 1.30), mean_error=0.20):
    """Still a distance: 0 at the source, its largest value about right, ordered as the exact distance."""
    assert d[0] == 0 and np.all(np.isfinite(d)) and np.all(d >= 0)
    low, high = max_ratio
    assert low < d.max() / exact.max() < high, d.max() / exact.max()
    far = exact > 0
    assert np.mean(np.abs(d[far] - exact[far]) / exact[far]) < mean_error
    rank = np.argsort(np.argsort(d)), np.argsort(np.argsort(exact))  # Spearman's rank correlation
    assert np.corrcoef(*rank)[0, 1] > 0.9


def test_cap_is_declared_once_and_shown_by_every_front_end():
    opt = OPTIONS["m"]
    assert opt.high == M_MAX == 1e6 and opt.low == 0 and opt.low_open
    assert "at most 1e+06" in opt.help_text("cli")
    assert opt.requirement() == "a positive number <= 1e+06"


def test_blender_property_max_is_the_declared_cap():
    pytest.importorskip("bpy")
    from blender_addon.properties import option_property

    assert option_property("m").keywords["max"] == M_MAX


@pytest.mark.parametrize("m", [M_MAX, 1e5])
def test_at_the_cap_the_smoothed_distance_is_still_a_distance(spot_exact, m):
    V, F, exact = spot_exact
    d = hc.HeatSolver(hc.TriangleMesh(V, F), m=m).distance([0])
    assert_a_distance(d, exact)  # measured: max 1.247 x exact, mean error 15.1%, ranks 0.927


def test_the_cap_is_the_smoothed_limit_with_all_its_digits(spot_exact):
    """Past 1e5 the distance no longer changes: the cap loses nothing a user could want, nor any precision."""
    V, F, _ = spot_exact
    mesh = hc.TriangleMesh(V, F)
    d5, d6 = (hc.HeatSolver(mesh, m=m).distance([0]) for m in (1e5, M_MAX))
    assert np.max(np.abs(d6 - d5)) < 0.01 * d5.max()


@pytest.mark.parametrize("scale", [1e-6, 1e6])
def test_the_cap_does_not_depend_on_the_scale(spot_exact, scale):
    V, F, _ = spot_exact
    d = hc.HeatSolver(hc.TriangleMesh(V, F), m=M_MAX).distance([0])
    scaled = hc.HeatSolver(hc.TriangleMesh(V * scale, F), m=M_MAX).distance([0]) / scale
    assert np.allclose(scaled, d, rtol=1e-6, atol=1e-9 * d.max())


@pytest.mark.parametrize("m", [1e-6, 1e-15, 1e-300, 5e-324])
def test_tiny_m_is_raised_by_the_guard_and_stays_a_distance(spot_exact, m):
    V, F, exact = spot_exact
    solver = hc.HeatSolver(hc.TriangleMesh(V, F), m=m)
    assert solver.m == m and solver.m_effective > 0.01  # the underflow guard's floor (0.0267 on spot)
    assert_a_distance(solver.distance([0]), exact, max_ratio=(0.9, 1.05), mean_error=0.10)


@pytest.mark.parametrize("m", ABOVE)
def test_above_the_cap_is_refused_with_the_reason(m):
    V, F = hc.io.load_demo_mesh()
    for call in (lambda: hc.HeatSolver(hc.TriangleMesh(V, F, refine=0), m=m),
                 lambda: hc.geodesic_distance(V, F, [0], m=m, refine=0)):
        with pytest.raises(InvalidOptionError, match=r"m must be a positive number <= 1e\+06: above 1e\+06 the "
                                                     r"heat step .* loses its digits"):
            call()


def test_below_zero_says_positive_without_the_cap_reason():
    with pytest.raises(InvalidOptionError) as caught:
        OPTIONS["m"].check(-1.0)
    assert str(caught.value) == "invalid time factor -1.0: m must be a positive number <= 1e+06"


def test_the_underflow_guard_may_raise_m_past_the_cap(spot_exact, monkeypatch):
    """The cap is on the user's m: the guard's own m (about (hops / 443)^2) is never refused."""
    assert underflow_safe_m(500_000) > M_MAX  # a mesh half a million hops across needs more than the cap
    V, F, exact = spot_exact
    monkeypatch.setattr(heat, "underflow_safe_m", lambda hops: np.full(np.shape(hops), 10 * M_MAX))
    solver = hc.HeatSolver(hc.TriangleMesh(V, F), m=1.0)
    assert solver.m == 1.0 and solver.m_effective == 10 * M_MAX
    assert_a_distance(solver.distance([0]), exact)


def test_cli_refuses_m_above_the_cap_and_accepts_the_cap(tmp_path, capsys):
    from heatcore.io import demo_mesh_path

    out = tmp_path / "d.npy"
    code = main(["distance", str(demo_mesh_path()), "-s", "0", "-o", str(out), "--m", "1e15"])
    err = capsys.readouterr().err
    assert code == 2 and not out.exists()
    assert "--m: must be a positive number <= 1e+06, got '1e15': above 1e+06" in err
    assert main(["distance", str(demo_mesh_path()), "-s", "0", "-o", str(out), "--m", "1e6", "--refine", "0"]) == 0
    d = np.load(out)
    assert d[0] == 0 and 1.5 < d.max() < 3.0  # spot's exact largest distance from vertex 0 is 2.016


def test_batch_refuses_m_above_the_cap_before_any_work(tmp_path):
    from heatcore.apps.batch import run_batch
    from heatcore.io import demo_mesh_path

    with pytest.raises(InvalidOptionError, match="above 1e"):
        run_batch([demo_mesh_path()], tmp_path / "out", "0", workers=0, progress=False, solver_options={"m": 1e9})
    assert not (tmp_path / "out").exists()
