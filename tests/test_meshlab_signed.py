"""The MeshLab signed filter: signed distance to the boundary of the selected faces, inside positive."""

import numpy as np
import pytest
import signed_cases as sc

import heatcore as hc
from heatcore.errors import InvalidOptionError, InvalidSourceError

pymeshlab = pytest.importorskip("pymeshlab")
from heatcore.apps.meshlab_signed import signed_distance_from_selection


def _meshset(V, F):
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(V, np.asarray(F, dtype=np.int32)))
    return ms


def test_disc_selection_inside_positive():
    V, F = sc.disc()
    centre = np.linalg.norm(V[F].mean(axis=1)[:, :2], axis=1)
    ms = _meshset(V, F)
    ms.compute_selection_by_condition_per_face(condselect="((x0+x1+x2)/3)^2 + ((y0+y1+y2)/3)^2 < 0.3025")
    stats = signed_distance_from_selection(ms, refine=0, isolines=3)
    mesh = ms.current_mesh()
    assert stats["curves"] == 1 and stats["faces_selected"] == int((centre < 0.55).sum())
    (loop,) = hc.region_boundary_curves(F, np.flatnonzero(mesh.face_selection_array()), mesh_boundary=False)
    expected = hc.SignedHeatSolver(hc.TriangleMesh(V, F, refine=0)).distance([[int(v) for v in loop]])
    np.testing.assert_allclose(stats["distance"], expected, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(mesh.vertex_scalar_array(), expected, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(mesh.vertex_custom_scalar_attribute_array("heat_signed_distance"), expected,
                               rtol=1e-9, atol=1e-12)
    r = np.linalg.norm(V[:, :2], axis=1)
    assert (expected[r < 0.4] > 0).all() and (expected[r > 0.7] < 0).all()  # inside the selection positive
    assert np.abs(expected - (0.55 - r)).mean() < 0.02  # a jagged loop of edges about the circle r = 0.55
    colors = mesh.vertex_color_matrix()
    inside, outside = np.argmin(r), np.argmax(r)
    assert colors[inside, 0] > colors[inside, 2] and colors[outside, 2] > colors[outside, 0]


def test_half_disc_selection_is_bounded_by_its_open_border():
    """Faces right of x = 0 selected: the border is the chain across the disc (the disc's rim is no curve)."""
    V, F = sc.disc()
    ms = _meshset(V, F)
    ms.compute_selection_by_condition_per_face(condselect="(x0+x1+x2)/3 > 0")
    stats = signed_distance_from_selection(ms, refine=0)
    assert stats["curves"] == 1
    d, x = stats["distance"], V[:, 0]
    far = np.abs(x) > 0.1
    assert (np.sign(d[far]) == np.sign(x[far])).all()
    assert np.abs(d - x).mean() < 0.03  # a zigzag of edges about x = 0


def test_no_selection_or_no_boundary_is_an_error_and_leaves_the_mesh():
    V, F = hc.io.load_demo_mesh()
    ms = _meshset(V, F)
    with pytest.raises(InvalidSourceError, match="no face is selected"):
        signed_distance_from_selection(ms, refine=0)
    ms.set_selection_all()
    with pytest.raises(InvalidSourceError, match="no boundary"):
        signed_distance_from_selection(ms, refine=0)
    with pytest.raises(InvalidOptionError, match="attribute"):
        signed_distance_from_selection(ms, attribute="not a name")
    assert np.allclose(ms.current_mesh().vertex_scalar_array(), 0.0)


def test_the_command_line_signed_flag(tmp_path, capsys):
    """``heatcore meshlab --signed --select-faces ...``: the border of the selected faces, written to a PLY."""
    from heatcore.apps.cli import main
    from heatcore.io.mesh import write_ply

    V, F = sc.disc()
    mesh = tmp_path / "disc.ply"
    write_ply(mesh, V, F, np.zeros(len(V)), np.zeros((len(V), 3), np.uint8))
    out = tmp_path / "signed.ply"
    condition = "((x0+x1+x2)/3)^2 + ((y0+y1+y2)/3)^2 < 0.3025"
    assert main(["meshlab", str(mesh), "--signed", "--select-faces", condition, "--refine", "0", "-o", str(out)]) == 0
    report = capsys.readouterr().out
    assert "1 curve(s) bordering" in report and "inside positive" in report
    quality = hc.io.read_mesh(out).vertex_data["quality"]
    r = np.linalg.norm(V[:, :2], axis=1)
    assert (quality[r < 0.4] > 0).all() and (quality[r > 0.7] < 0).all()
    assert main(["meshlab", str(mesh), "--signed", "-s", "0", "-o", str(out)]) == 2  # vertices are no region
    assert "border of selected faces" in capsys.readouterr().err
    assert main(["meshlab", str(mesh), "--signed", "--accuracy", "high", "--select-faces", condition,
                 "-o", str(out)]) == 2
    assert main(["meshlab", str(mesh), "--signed", "--select-faces", "(x0 > 5)", "-o", str(out)]) == 2
    assert "selects no face" in capsys.readouterr().err
