"""Mesh files that lie give a typed error or the right mesh, never another mesh or a hang (issue 32).

Before: OBJ relative indices interleaved with vertex lines were resolved
against the end of the file (trimesh) or off by one (potpourri3d); a PLY or
OFF header's counts were trusted (faces past the count dropped, faces missing
ignored); ``3 0 1 2.7`` became the face ``0 1 2`` and ``f 0 1 2`` the face
``0 0 1``; a binary PLY header declaring 10**9 faces kept meshio walking for
minutes. Every reading path is tried: triangle meshes, polygon meshes, point
clouds, :func:`read_domain`, and the ``distance`` command.
"""

import struct
import time

import numpy as np
import pytest
from test_cli import run

import heatcore as hc
from heatcore.errors import InvalidMeshError
from heatcore.io import read_domain, read_mesh, read_point_cloud, read_polygon_mesh

#: A 5 x 5 grid, slightly bent, and its 32 triangles.
_X, _Y = np.meshgrid(np.arange(5.0), np.arange(5.0))
V = np.column_stack([_X.ravel(), _Y.ravel(), 0.1 * np.sin(_X.ravel() + _Y.ravel())])
F = np.array([f for a in (y * 5 + x for y in range(4) for x in range(4)) for f in ([a, a + 1, a + 6], [a, a + 6, a + 5])])

SURFACE_READERS = {
    "mesh": read_mesh,
    "polygon": read_polygon_mesh,
    "domain": read_domain,
    "domain-polygon": lambda p: read_domain(p, "polygon"),
}
ALL_READERS = {**SURFACE_READERS, "cloud": read_point_cloud}


def ply(V, F, binary=False, n_vertices=None, n_faces=None, index_type="int", count_type="uchar", rows=None):
    """A PLY file's bytes; ``rows`` (text or bytes) replaces the face rows."""
    header = (f"ply\nformat {'binary_little_endian' if binary else 'ascii'} 1.0\n"
              f"element vertex {len(V) if n_vertices is None else n_vertices}\n"
              "property float x\nproperty float y\nproperty float z\n"
              f"element face {len(F) if n_faces is None else n_faces}\n"
              f"property list {count_type} {index_type} vertex_indices\nend_header\n").encode()
    if binary:
        code = {"uchar": "B", "char": "b"}[count_type] + ("3i" if index_type == "int" else "3f")
        faces = b"".join(struct.pack("<" + code, 3, *f) for f in F) if rows is None else rows
        return header + V.astype("<f4").tobytes() + faces
    faces = "".join(f"3 {a} {b} {c}\n" for a, b, c in F) if rows is None else rows
    return header + ("".join(f"{x:g} {y:g} {z:g}\n" for x, y, z in V) + faces).encode()


def off(V, F, n_faces=None, rows=None):
    faces = "".join(f"3 {a} {b} {c}\n" for a, b, c in F) if rows is None else rows
    return (f"OFF\n{len(V)} {len(F) if n_faces is None else n_faces} 0\n"
            + "".join(f"{x:g} {y:g} {z:g}\n" for x, y, z in V) + faces).encode()


def obj(V, F):
    return ("".join(f"v {x:g} {y:g} {z:g}\n" for x, y, z in V) + "".join(f"f {a} {b} {c}\n" for a, b, c in F)).encode()


def refused(path, capsys, message, readers=ALL_READERS, domain=None):
    """Every reader and the distance command refuse ``path`` with ``message`` (a part of it)."""
    for name, reader in readers.items():
        with pytest.raises(InvalidMeshError) as info:
            reader(path)
        assert message in str(info.value), name
    out = path.parent / "d.npy"
    for extra in ([], ["--domain", "polygon"]) if domain is None else (domain,):
        code, stdout, err = run(["distance", path, "-s", 0, "-o", out, "-q", *extra], capsys)
        assert code == 1 and stdout == "" and not out.exists()
        assert err.startswith("heatcore: error: ") and message in err and len(err.splitlines()) == 1


# relative OBJ indices -------------------------------------------------------------------------------------------

def interleaved_obj():
    """Each triangle written after its own three vertices, with relative indices (the second one turned)."""
    lines, V2, F2 = [], [], []
    for k, f in enumerate(F):
        for i in f:
            lines.append("v {!r} {!r} {!r}".format(*map(float, V[i])))
            V2.append(V[i])
        n = len(V2)
        lines.append("f -3 -2 -1" if k % 2 == 0 else "f -3 -1 -2")
        F2.append([n - 3, n - 2, n - 1] if k % 2 == 0 else [n - 3, n - 1, n - 2])
    return ("\n".join(lines) + "\n").encode(), np.array(V2), np.array(F2)


def test_relative_obj_indices_count_back_from_the_vertices_read_so_far(tmp_path, capsys):
    text, V2, F2 = interleaved_obj()
    path = tmp_path / "relative.obj"
    path.write_bytes(text)
    mesh = read_mesh(path)
    np.testing.assert_array_equal(mesh.vertices, V2)
    np.testing.assert_array_equal(mesh.faces, F2)
    for polygons in (read_polygon_mesh(path), read_domain(path, "polygon")):
        offsets, indices = polygons.polygons if hasattr(polygons, "polygons") else polygons.cells
        np.testing.assert_array_equal(np.asarray(indices).reshape(-1, 3), F2)
    out = tmp_path / "d.npy"
    code, _, err = run(["distance", path, "-s", 0, "-o", out, "--refine", "0", "-q"], capsys)
    assert code == 0, err
    np.testing.assert_allclose(np.load(out), hc.geodesic_distance(V2, F2, [0], refine=0), rtol=1e-12)


def test_relative_texture_indices_are_resolved_too(tmp_path):
    path = tmp_path / "uv.obj"
    path.write_text("v 0 0 0\nvt 0 0\nv 1 0 0\nvt 1 0\nv 0 1 0\nvt 0 1\nf -3/-3 -2/-2 -1/-1\n"
                    "v 1 1 0\nvt 1 1\nf -3/-3 -1/-1 -2/-2\n")
    assert read_mesh(path).faces.tolist() == [[0, 1, 2], [1, 3, 2]]
    assert read_polygon_mesh(path).indices.tolist() == [1 - 1, 2 - 1, 3 - 1, 2 - 1, 4 - 1, 3 - 1]


@pytest.mark.parametrize("face, message", [
    ("f 0 1 2", "line 26: a face references vertex 0, but OBJ indices start at 1 (-1 is the last vertex read)"),
    ("f 1 2 2.7", "line 26: the face's vertex index 2.7 is not a whole number"),
    ("f 1 2 99", "line 26: a face references vertex 99 but the file has 25 vertices"),
    ("f 1 2 -26", "line 26: a face references vertex -26, counting back from the 25 vertices read so far: "
                  "before the first one"),
    ("f 1 2", "line 26: a face with 2 corners (a face needs at least 3)"),
], ids=["zero", "fractional", "past-the-end", "before-the-first", "two-corners"])
def test_bad_obj_indices_are_errors(face, message, tmp_path, capsys):
    path = tmp_path / "bad.obj"
    path.write_bytes(obj(V, F + 1).replace(b"f 1 2 7\n", face.encode() + b"\n"))
    refused(path, capsys, f"cannot read mesh file {path}: {message}", readers=SURFACE_READERS)
    with pytest.raises(InvalidMeshError, match="line 26"):
        read_point_cloud(path)


# PLY counts, lists and sizes ------------------------------------------------------------------------------------

@pytest.mark.parametrize("binary", [False, True], ids=["ascii", "binary"])
def test_ply_header_with_fewer_faces_than_the_file_holds(binary, tmp_path, capsys):
    path = tmp_path / "half.ply"
    path.write_bytes(ply(V, F, binary, n_faces=16))
    if binary:
        message = "208 bytes of data follow the 16 faces its PLY header declares (a header that undercounts, or trailing data)"
    else:
        message = "16 more lines of data follow the 16 faces its PLY header declares (line 51: a header that undercounts, or trailing data)"
    refused(path, capsys, message)


@pytest.mark.parametrize("binary", [False, True], ids=["ascii", "binary"])
def test_ply_trailing_garbage(binary, tmp_path, capsys):
    path = tmp_path / "trailing.ply"
    path.write_bytes(ply(V, F, binary) + (b"\x00garbage" if binary else b"garbage 1 2\n"))
    refused(path, capsys, "follow" + ("s" if not binary else "") + " the 32 faces its PLY header declares")


def test_ply_header_with_more_vertices_than_present(tmp_path, capsys):
    path = tmp_path / "morev.ply"
    path.write_bytes(ply(V, F, binary=True, n_vertices=30))  # the point cloud got 5 points made of face bytes
    refused(path, capsys, "the data ends inside face 28 of the 32 its PLY header declares",
            readers={k: ALL_READERS[k] for k in ("polygon", "domain-polygon", "cloud")}, domain=["--domain", "polygon"])
    with pytest.raises(InvalidMeshError, match="the data ends inside face 28 of the 32 its PLY header declares"):
        read_mesh(path)  # meshio's numpy words before issue 38; the header check's words now
    path.write_bytes(ply(V, F, binary=False, n_vertices=30))  # --domain polygon hung
    refused(path, capsys, "vertex 25 (line 35) has 4 values but its PLY header declares 3 properties for each vertex",
            readers={k: ALL_READERS[k] for k in ("polygon", "domain-polygon", "cloud")}, domain=["--domain", "polygon"])


@pytest.mark.parametrize("binary", [False, True], ids=["ascii", "binary"])
def test_fractional_ply_face_indices(binary, tmp_path, capsys):
    if binary:  # float indices: meshio gave float cells, cast to int
        rows = b"".join(struct.pack("<B3f", 3, *f) for f in F[:-1]) + struct.pack("<B3f", 3, 0, 1, 2.7)
        path = tmp_path / "frac.ply"
        path.write_bytes(ply(V, F, binary, index_type="float", rows=rows))
        refused(path, capsys, "face 31 holds the vertex_indices [0.0, 1.0, 2.700000047683716]: "
                              "vertex indices must be integers")
        return
    path = tmp_path / "frac.ply"
    path.write_bytes(ply(V, F, rows="".join(f"3 {a} {b} {c}\n" for a, b, c in F[:-1]) + "3 0 1 2.7\n"))
    message = "face 31 (line 66) holds the vertex_indices value 2.7: vertex indices must be integers"
    refused(path, capsys, message, readers={k: ALL_READERS[k] for k in ("polygon", "domain-polygon", "cloud")},
            domain=["--domain", "polygon"])
    path.write_bytes(ply(V, F, index_type="float", rows="".join(f"3 {a} {b} {c}\n" for a, b, c in F[:-1]) + "3 0 1 2.7\n"))
    refused(path, capsys, message)


@pytest.mark.parametrize("binary", [False, True], ids=["ascii", "binary"])
def test_negative_ply_list_count(binary, tmp_path, capsys):
    if binary:
        rows = struct.pack("<b3i", -3, *F[0]) + b"".join(struct.pack("<b3i", 3, *f) for f in F[1:])
        path = tmp_path / "negative.ply"
        path.write_bytes(ply(V, F, binary, count_type="char", rows=rows))
        readers = {k: ALL_READERS[k] for k in ("polygon", "domain-polygon", "cloud")}  # meshio refuses char counts
        refused(path, capsys, "face 0 has a vertex_indices list of -3 items", readers, domain=["--domain", "polygon"])
        return
    path = tmp_path / "negative.ply"
    path.write_bytes(ply(V, F, rows="".join(f"{-3 if k == 0 else 3} {a} {b} {c}\n" for k, (a, b, c) in enumerate(F))))
    refused(path, capsys, "face 0 (line 35) has a vertex_indices list of -3 items (a list count is a whole number >= 0)")


@pytest.mark.parametrize("binary", [False, True], ids=["ascii", "binary"])
def test_ply_header_claiming_a_billion_faces_fails_at_once(binary, tmp_path, capsys):
    path = tmp_path / "billion.ply"
    path.write_bytes(ply(V, F, binary, n_faces=10**9))
    assert path.stat().st_size < 16_000
    for name, reader in ALL_READERS.items():
        start = time.perf_counter()
        with pytest.raises(InvalidMeshError):  # the triangle readers keep meshio's words on an ASCII file
            reader(path)
        assert time.perf_counter() - start < 0.5, name
    if binary:
        message = ("its PLY header declares 1000000000 faces, at least 1,000,000,300 bytes, but 716 bytes of data "
                   "follow the header (a truncated file, or a header that overcounts)")
    else:
        message = ("its PLY header declares 1000000000 faces but the data ends after 32 of them "
                   "(a truncated file, or a header that overcounts)")
    refused(path, capsys, message, readers={k: ALL_READERS[k] for k in ("polygon", "domain-polygon", "cloud")},
            domain=["--domain", "polygon"])
    if binary:
        refused(path, capsys, message, readers={"mesh": read_mesh}, domain=[])


# OFF counts -----------------------------------------------------------------------------------------------------

@pytest.mark.parametrize("n_faces, message", [
    (64, "its OFF header declares 64 faces but the data ends after 32 of them (a truncated file, or a header that "
         "overcounts)"),
    (16, "16 more lines of data follow the 16 faces its OFF header declares (line 44: a header that undercounts, "
         "or trailing data)"),
], ids=["more-declared", "fewer-declared"])
def test_off_header_counts_must_match_the_faces(n_faces, message, tmp_path, capsys):
    path = tmp_path / "counts.off"
    path.write_bytes(off(V, F, n_faces=n_faces))
    refused(path, capsys, f"cannot read mesh file {path}: {message}", readers=SURFACE_READERS)


def test_fractional_off_face_index(tmp_path, capsys):
    path = tmp_path / "frac.off"
    path.write_bytes(off(V, F, rows="".join(f"3 {a} {b} {c}\n" for a, b, c in F[:-1]) + "3 0 1 2.7\n"))
    refused(path, capsys, "line 59: face 31 references vertex 2.7, which is not a whole number",
            readers={k: SURFACE_READERS[k] for k in ("polygon", "domain-polygon")}, domain=["--domain", "polygon"])
