"""Polygons read as triangles are heatcore's triangulation, not the readers' fans (issue 32).

trimesh (OBJ, OFF) and heatcore's own meshio path (PLY) fanned every polygon
from its first corner: on a concave polygon that fan folds outside it (the L
below came back as 4 triangles of total |area| 4, one flipped), a different
surface, silently. Each test here failed before the fix.
"""

import numpy as np
import pytest

import heatcore as hc
from heatcore.apps import cli
from heatcore.domains.polygon import triangulate_polygons
from heatcore.io import read_mesh
from heatcore.io.domain import read_domain

# An L of area 3 in the plane z = 0, counterclockwise, listed from the corner whose fan folds.
L_V = np.array([[0, 0, 0], [2, 0, 0], [2, 1, 0], [1, 1, 0], [1, 2, 0], [0, 2, 0], [3, 0, 0]], float)
L_POLY = [2, 3, 4, 5, 0, 1]
TRIANGLE = [1, 6, 2]  # a triangle next to the L (vertex 6 is used by nothing else)


def write_obj(path, V, polygons, uv=False, materials=False, relative=False):
    lines = ["mtllib m.mtl"] if materials else []
    lines += [f"v {x:.17g} {y:.17g} {z:.17g}" for x, y, z in V]
    if uv:
        lines += [f"vt {x / 3:.6g} {y / 3:.6g}" for x, y, _ in V] + ["vt 0.5 0.5", "vn 0 0 1"]
    for p, poly in enumerate(polygons):
        if materials:
            lines.append(f"usemtl {'ab'[p % 2]}")
        if relative:
            corners = [str(i - len(V)) for i in poly]
        elif uv:  # the first corner takes another texture coordinate: a UV seam there
            corners = [f"{i + 1}/{len(V) + 1 if k == 0 else i + 1}/1" for k, i in enumerate(poly)]
        else:
            corners = [str(i + 1) for i in poly]
        lines.append("f " + " ".join(corners))
    path.write_text("\n".join(lines) + "\n")
    if materials:
        (path.parent / "m.mtl").write_text("newmtl a\nKd 1 0 0\nnewmtl b\nKd 0 1 0\n")
    return path


def write_off(path, V, polygons):
    lines = ["OFF", f"{len(V)} {len(polygons)} 0"] + [f"{x:.17g} {y:.17g} {z:.17g}" for x, y, z in V]
    lines += [f"{len(p)} " + " ".join(map(str, p)) for p in polygons]
    path.write_text("\n".join(lines) + "\n")
    return path


def write_ply(path, V, polygons, binary=False):
    fmt = "binary_little_endian" if binary else "ascii"
    header = (f"ply\nformat {fmt} 1.0\nelement vertex {len(V)}\nproperty double x\nproperty double y\n"
              f"property double z\nelement face {len(polygons)}\nproperty list uchar int vertex_indices\n"
              "end_header\n").encode()
    if binary:
        body = np.asarray(V, "<f8").tobytes() + b"".join(
            np.uint8(len(p)).tobytes() + np.asarray(p, "<i4").tobytes() for p in polygons)
    else:
        body = ("\n".join(" ".join(f"{c:.17g}" for c in v) for v in V) + "\n"
                + "\n".join(f"{len(p)} " + " ".join(map(str, p)) for p in polygons) + "\n").encode()
    path.write_bytes(header + body)
    return path


WRITERS = {
    "obj": lambda p, V, P: write_obj(p.with_suffix(".obj"), V, P),
    "obj-uv-seam": lambda p, V, P: write_obj(p.with_suffix(".obj"), V, P, uv=True),
    "obj-materials": lambda p, V, P: write_obj(p.with_suffix(".obj"), V, P, materials=True),
    "obj-relative": lambda p, V, P: write_obj(p.with_suffix(".obj"), V, P, relative=True),
    "off": lambda p, V, P: write_off(p.with_suffix(".off"), V, P),
    "ply-ascii": lambda p, V, P: write_ply(p.with_suffix(".ply"), V, P),
    "ply-binary": lambda p, V, P: write_ply(p.with_suffix(".ply"), V, P, binary=True),
}


def signed_areas(V, F):
    """Areas of the triangles along +z (the polygons' normal here)."""
    return np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])[:, 2] / 2


def assert_covers_the_L(V, F):
    """``F``'s triangles of the L (those without vertex 6) tile it: area 3, none flipped, none outside."""
    assert V.shape == L_V.shape and np.array_equal(V, L_V)  # the file's vertices, in its numbering
    L = F[~(F == 6).any(axis=1)]
    assert len(L) == len(L_POLY) - 2
    assert sorted(np.unique(L).tolist()) == sorted(L_POLY)
    area = signed_areas(V, L)
    assert (area > 1e-12).all(), f"flipped or flat triangles: {area.tolist()}"
    assert area.sum() == pytest.approx(3.0)
    centroid = V[L].mean(axis=1)
    assert not ((centroid[:, 0] > 1) & (centroid[:, 1] > 1)).any()  # nothing in the L's missing square


@pytest.mark.parametrize("fmt", list(WRITERS))
def test_a_concave_polygon_is_read_as_triangles_inside_it(fmt, tmp_path):
    path = WRITERS[fmt](tmp_path / "L", L_V, [L_POLY, TRIANGLE])
    mesh = read_mesh(path)
    assert_covers_the_L(mesh.vertices, mesh.faces)
    assert [1, 6, 2] in mesh.faces.tolist()  # triangles stay as the file gives them


@pytest.mark.parametrize("kind", ["auto", "triangle", "polygon"])
@pytest.mark.parametrize("fmt", ["obj", "off", "ply-ascii", "ply-binary"])
def test_read_domain_triangles_of_a_polygon_file(fmt, kind, tmp_path):
    path = WRITERS[fmt](tmp_path / "L", L_V, [L_POLY, TRIANGLE])
    f = read_domain(path, kind)
    assert_covers_the_L(f.vertices, np.asarray(f.surface))
    if kind != "polygon":
        assert np.array_equal(f.cells, f.surface)


def dissolved_grid(blocks=8):
    """A flat square of side 1 tiled by L-shaped octagons and squares, as Dissolve Edges leaves a grid.

    Each 2 x 2 block of cells is an L (three cells, 8 corners: a reflex one and two straight ones,
    listed from the corner whose fan folds) and a square.
    """
    n = 2 * blocks + 1
    x, y = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    V = np.column_stack([x.ravel(), y.ravel(), np.zeros(n * n)]) / (n - 1)
    L = [(2, 1), (1, 1), (1, 2), (0, 2), (0, 1), (0, 0), (1, 0), (2, 0)]
    square = [(1, 1), (2, 1), (2, 2), (1, 2)]
    polygons = []
    for a in range(0, n - 1, 2):
        for b in range(0, n - 1, 2):
            polygons += [[(a + i) * n + b + j for i, j in L], [(a + i) * n + b + j for i, j in square]]
    return V, polygons


def test_the_grid_fans_fold():  # the meshes of the test below are ones the readers' fans got wrong
    V, polygons = dissolved_grid()
    fan = np.array([[p[0], p[k], p[k + 1]] for p in polygons for k in range(1, len(p) - 1)])
    assert (signed_areas(V, fan) < 0).sum() == 64 and abs(signed_areas(V, fan)).sum() > 1.1


@pytest.mark.parametrize("fmt", ["obj", "off", "ply-binary"])
def test_cli_distance_on_a_dissolved_grid_is_the_straight_line(fmt, tmp_path, capsys):
    V, polygons = dissolved_grid()
    path = WRITERS[fmt](tmp_path / "grid", V, polygons)
    source = len(V) // 2  # the centre
    out = tmp_path / "d.npy"
    assert cli.main(["distance", str(path), "-s", str(source), "-o", str(out), "--refine", "1", "-q"]) == 0
    capsys.readouterr()
    d = np.load(out)
    exact = np.linalg.norm(V - V[source], axis=1)
    offsets = np.r_[0, np.cumsum([len(p) for p in polygons])]
    F, _ = triangulate_polygons(V, offsets, np.concatenate(polygons))
    reference = hc.geodesic_distance(V, F, sources=[source], refine=1)
    far = exact > 0
    error = np.abs(d - exact)[far].mean() / exact[far].mean()
    ref_error = np.abs(reference - exact)[far].mean() / exact[far].mean()
    assert d.shape == (len(V),)
    assert error <= 1.02 * ref_error + 1e-9, (error, ref_error)


def test_an_obj_of_several_materials_keeps_the_files_vertices(tmp_path):
    # trimesh splits an OBJ at each usemtl, each part with its own copy of the vertices: 14 for these 7
    path = write_obj(tmp_path / "m.obj", L_V, [[0, 1, 3], [1, 2, 3], TRIANGLE], materials=True)
    mesh = read_mesh(path)
    assert np.array_equal(mesh.vertices, L_V)
    assert mesh.faces.tolist() == [[0, 1, 3], [1, 2, 3], TRIANGLE]


def test_a_quad_whose_fan_is_right_keeps_it(tmp_path):  # not a regression test: held before the fix too
    V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0.3], [0, 1, 0]], float)  # bent: the diagonal matters
    for fmt in ("obj", "off", "ply-binary"):
        F = read_mesh(WRITERS[fmt](tmp_path / "q", V, [[0, 1, 2, 3]])).faces
        F = np.array([np.roll(f, -np.argmin(f)) for f in F])  # each triangle from its smallest index
        assert F.tolist() == [[0, 1, 2], [0, 2, 3]]
