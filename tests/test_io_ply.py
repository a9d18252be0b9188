"""PLY files the readers used to fail on: triangle strips, empty files, malformed files.

Triangle strips (``element tristrips``, ``property list int int
vertex_indices``, strips separated by ``-1``) are how the Stanford scans such
as igea.ply are stored; meshio does not read them, pymeshlab does. Before
issue 16 the command said ``cannot read mesh file igea.ply: 1``.
"""

import struct

import numpy as np
import pytest
from test_cli import run

import heatcore as hc
from heatcore.io import read_mesh

#: A 3 x 5 grid of vertices (z = 0) and one extra vertex used by no strip.
GRID = np.array([[x, y, 0.0] for y in range(3) for x in range(5)] + [[9.0, 9.0, 9.0]])
#: Two strips along the two rows of quads, as in a scanner's PLY: -1 between strips.
STRIPS = [[0, 5, 1, 6, 2, 7, 3, 8, 4, 9], [5, 10, 6, 11, 7, 12, 8, 13, 9, 14]]


def strip_triangles(strips):
    """Triangles of triangle strips, every other one flipped to keep the orientation."""
    F = []
    for s in strips:
        for i in range(len(s) - 2):
            F.append([s[i], s[i + 1], s[i + 2]] if i % 2 == 0 else [s[i + 1], s[i], s[i + 2]])
    return np.array(F)


def write_strips_ply(path, V, rows, binary, flags=None):
    """A PLY like igea.ply: float x y z (and int flags), one tristrips row per entry of ``rows``."""
    header = (
        f"ply\nformat {'binary_little_endian' if binary else 'ascii'} 1.0\ncomment tristrips test\n"
        f"element vertex {len(V)}\nproperty float x\nproperty float y\nproperty float z\n"
        + ("property int flags\n" if flags is not None else "")
        + f"element tristrips {len(rows)}\nproperty list int int vertex_indices\nend_header\n"
    )
    flags = np.zeros(len(V), int) if flags is None else np.asarray(flags)
    with_flags = "flags" in header
    if binary:
        body = b"".join(struct.pack("<3f", *v) + (struct.pack("<i", f) if with_flags else b"") for v, f in zip(V, flags))
        body += b"".join(struct.pack(f"<i{len(r)}i", len(r), *r) for r in rows)
        path.write_bytes(header.encode() + body)
    else:
        lines = [" ".join(f"{c:g}" for c in v) + (f" {f}" if with_flags else "") for v, f in zip(V, flags)]
        lines += [" ".join(map(str, [len(r), *r])) for r in rows]
        path.write_text(header + "\n".join(lines) + "\n")
    return path


def one_row(strips):
    """All strips in one list, -1 between them (igea.ply's layout)."""
    return [[i for s in strips for i in (*s, -1)][:-1]]


@pytest.mark.parametrize("binary", [False, True], ids=["ascii", "binary"])
def test_triangle_strips_are_read(binary, tmp_path):
    path = write_strips_ply(tmp_path / "strips.ply", GRID, one_row(STRIPS), binary)
    mesh = read_mesh(path)
    np.testing.assert_array_equal(mesh.vertices, GRID)  # every vertex, in file order
    np.testing.assert_array_equal(mesh.faces, strip_triangles(STRIPS))
    assert len(mesh.faces) == 16


@pytest.mark.parametrize("binary", [False, True], ids=["ascii", "binary"])
def test_distance_command_on_triangle_strips(binary, tmp_path, capsys):
    path = write_strips_ply(tmp_path / "igea-like.ply", GRID, one_row(STRIPS), binary)
    out = tmp_path / "d.npy"
    code, stdout, err = run(["distance", path, "-s", 0, "-o", out, "--refine", "0", "-q"], capsys)
    assert code == 0, err
    assert stdout == f"wrote {out}\n"
    d = np.load(out)
    np.testing.assert_allclose(d, hc.geodesic_distance(GRID, strip_triangles(STRIPS), [0], refine=0), rtol=1e-12)
    assert np.isinf(d[15]) and np.isfinite(d[:15]).all()  # the unused vertex is unreachable


@pytest.mark.parametrize("binary", [False, True], ids=["ascii", "binary"])
def test_strips_in_rows_of_different_lengths_and_zero_area_joins(binary, tmp_path):
    joined = [*STRIPS[0], 9, 5, *STRIPS[1]]  # no -1: repeated vertices join the strips (zero-area triangles)
    rows = [STRIPS[0], STRIPS[1][:6], STRIPS[1][4:], joined]
    mesh = read_mesh(write_strips_ply(tmp_path / "rows.ply", GRID, rows, binary))
    expected = strip_triangles([STRIPS[0], STRIPS[1][:6], STRIPS[1][4:], *STRIPS])  # the joins leave nothing
    np.testing.assert_array_equal(mesh.faces, expected)


@pytest.mark.parametrize("binary", [False, True], ids=["ascii", "binary"])
def test_strips_keep_the_meshlab_selection(binary, tmp_path, capsys):
    flags = np.zeros(len(GRID), int)
    flags[[4, 12]] = 0x20
    path = write_strips_ply(tmp_path / "selected.ply", GRID, one_row(STRIPS), binary, flags=flags)
    out = tmp_path / "d.npy"
    code, _, err = run(["distance", path, "-o", out, "--refine", "0"], capsys)
    assert code == 0, err
    assert "sources: 2 from the selection saved in selected.ply" in err
    np.testing.assert_allclose(np.load(out), hc.geodesic_distance(GRID, strip_triangles(STRIPS), [4, 12], refine=0),
                               rtol=1e-12)


@pytest.mark.parametrize("bad, message", [
    (99, "face 3 references vertex 99 but the mesh has 16 vertices (valid indices are 0..15)"),
    (-5, "face 3 references vertex -5 but the mesh has 16 vertices (valid indices are 0..15)"),
])
def test_strip_index_out_of_range_is_an_error_not_a_crash(bad, message, tmp_path, capsys):
    path = write_strips_ply(tmp_path / "bad.ply", GRID, [[0, 5, 1, 6, 2, bad]], binary=True)
    code, stdout, err = run(["distance", path, "-s", 0, "-o", tmp_path / "d.npy", "-q"], capsys)
    assert code == 1 and stdout == ""
    assert err == f"heatcore: error: {path}: {message}\n"


def _header(n_vertices, faces=None):
    text = f"ply\nformat ascii 1.0\nelement vertex {n_vertices}\nproperty float x\nproperty float y\nproperty float z\n"
    if faces is not None:
        text += f"element face {faces}\nproperty list uchar int vertex_indices\n"
    return text + "end_header\n"


BAD_FILES = {
    "empty.ply": (b"", "{p} is empty (0 bytes)"),
    "empty.obj": (b"", "{p} is empty (0 bytes)"),
    "empty.stl": (b"", "{p} is empty (0 bytes)"),
    "empty.off": (b"", "{p} is empty (0 bytes)"),
    "empty.vtk": (b"", "{p} is empty (0 bytes)"),
    "empty.msh": (b"", "{p} is empty (0 bytes)"),
    "novertex.ply": (_header(0, 0).encode(), "{p} holds no vertices (its PLY header declares element vertex 0)"),
    "noheader.ply": (b"ply\nformat ascii 1.0\nelement vertex 3\n", "cannot read {p}: the PLY header has no end_header line (a truncated file?)"),
    "text.ply": (b"solid cube\nfacet normal 0 0 1\n", "cannot read {p}: not a PLY file (it does not start with 'ply')"),
    "nostrips.ply": (b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                     b"property float z\nelement tristrips 1\nproperty list int int vertex_indices\nend_header\n"
                     b"0 0 0\n1 0 0\n0 1 0\n3 -1 -1 -1\n", "{p} holds no triangles (its triangle strips are empty)"),
    "shortstrips.ply": (b"ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\nend_header\n",
                        "{p} holds no vertices (its PLY header declares element vertex 0)"),
}


@pytest.mark.parametrize("name", sorted(BAD_FILES))
def test_unreadable_file_says_what_is_wrong(name, tmp_path, capsys):
    content, message = BAD_FILES[name]
    path = tmp_path / name
    path.write_bytes(content)
    code, stdout, err = run(["distance", path, "-s", 0, "-o", tmp_path / "d.npy", "-q"], capsys)
    assert code == 1 and stdout == ""
    assert err == f"heatcore: error: {message.format(p=path)}\n"


@pytest.mark.parametrize("binary", [False, True], ids=["ascii", "binary"])
def test_truncated_strips_file_says_so(binary, tmp_path, capsys):
    path = write_strips_ply(tmp_path / "cut.ply", GRID, one_row(STRIPS), binary)
    path.write_bytes(path.read_bytes()[:-8])
    code, stdout, err = run(["distance", path, "-s", 0, "-o", tmp_path / "d.npy", "-q"], capsys)
    assert code == 1 and stdout == ""
    why = ("the data ends inside tristrips 0 of the 1 its PLY header declares (a truncated file, or a header that "
           "overcounts)" if binary else "tristrips 0 (line 27) has 19 values, too few for its vertex_indices list of 21 items")
    assert err == f"heatcore: error: cannot read mesh file {path}: {why}\n"  # the reader's exception name before issue 38


def test_truncated_ply_names_the_problem_in_one_short_line(tmp_path, capsys):
    path = tmp_path / "truncated.ply"
    path.write_text(_header(3, 1) + "0 0 0\n1 0 0\n")  # one vertex and the face missing
    code, stdout, err = run(["distance", path, "-s", 0, "-o", tmp_path / "d.npy", "-q"], capsys)
    assert code == 1 and stdout == ""
    assert err == (f"heatcore: error: cannot read mesh file {path}: its PLY header declares 3 vertexes but the data "
                   "ends after 2 of them (a truncated file, or a header that overcounts)\n")  # was numpy's words


def test_reader_messages_are_capped(tmp_path, capsys):
    path = tmp_path / "huge.ply"  # meshio quotes the offending header line: 20,000 characters here
    path.write_text(_header(3, 1).replace("end_header", "element " + "v" * 20000 + " 1\nproperty float a\nend_header")
                    + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n1\n")
    code, stdout, err = run(["distance", path, "-s", 0, "-o", tmp_path / "d.npy", "-q"], capsys)
    assert code == 1 and stdout == ""
    assert err.startswith(f"heatcore: error: cannot read mesh file {path}: Expected `element vertex` or ")
    assert len(err.splitlines()) == 1 and len(err) == len(f"heatcore: error: cannot read mesh file {path}: ") + 301


@pytest.mark.parametrize("domain", ["auto", "triangle", "polygon", "tet", "points"])
def test_header_without_end_is_refused_for_every_domain(domain, tmp_path):
    """meshio and potpourri3d loop forever on such a header: a subprocess with a time limit checks it."""
    import subprocess
    import sys

    path = tmp_path / "cut.ply"
    path.write_text("ply\nformat ascii 1.0\nelement vertex 3\n")
    proc = subprocess.run([sys.executable, "-m", "heatcore", "distance", str(path), "--domain", domain, "-s", "0",
                           "-o", str(tmp_path / "d.npy"), "-q"], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 1 and proc.stdout == ""
    assert proc.stderr == f"heatcore: error: cannot read {path}: the PLY header has no end_header line (a truncated file?)\n"


def test_meshlab_ply_with_face_flags_is_read(tmp_path):
    """A PLY MeshLab saved with its selection has ``flags`` on the faces too; meshio 5.3 refused it as corrupt."""
    pymeshlab = pytest.importorskip("pymeshlab")
    V, F = hc.io.load_demo_mesh()
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(V, F.astype(np.int32)))
    ms.compute_selection_by_condition_per_vertex(condselect="vi == 7")
    path = tmp_path / "selected.ply"
    ms.save_current_mesh(str(path), save_vertex_flag=True, save_face_flag=True, binary=True)
    assert b"element face" in path.read_bytes()[:1000] and path.read_bytes()[:1000].count(b"property int flags") == 2
    mesh = hc.io.read_mesh(path)
    np.testing.assert_allclose(mesh.vertices, V)
    np.testing.assert_array_equal(np.sort(mesh.faces, axis=1), np.sort(F, axis=1))
    assert mesh.selected_vertices().tolist() == [7]


def test_ascii_ply_with_face_properties_is_read(tmp_path):
    path = tmp_path / "flags.ply"
    path.write_text("ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                    "element face 2\nproperty list uchar int vertex_indices\nproperty int flags\nend_header\n"
                    "0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2 0\n3 0 2 3 32\n")
    mesh = hc.io.read_mesh(path)
    assert mesh.faces.tolist() == [[0, 1, 2], [0, 2, 3]] and mesh.vertices.shape == (4, 3)
