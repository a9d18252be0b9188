"""Input files that are not what their name says, and outputs that cannot be written (issue 38, inputs row).

Each case runs the real entry point (``heatcore.apps.cli.main``) and checks the whole error line:
the message is about the file the user named, in heatcore's words (never "No module named
'charset_normalizer'", "mesh file not found" for a file that exists, numpy's "cannot reshape", or
the name of a temporary file), with the documented exit status 1 (a file is wrong).
``charset_normalizer`` is hidden in every case: trimesh falls back on it for text that is not
UTF-8, and it is not a dependency of heatcore.
"""

import gzip
import os
import struct
import sys

import numpy as np
import pytest

import heatcore as hc
from heatcore.apps import cli

V = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
OBJ = "".join(f"v {x:g} {y:g} {z:g}\n" for x, y, z in V) + "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in F)


@pytest.fixture(autouse=True)
def no_charset_normalizer(monkeypatch):
    monkeypatch.setitem(sys.modules, "charset_normalizer", None)  # import charset_normalizer -> ImportError


def run(argv, capsys):
    code = cli.main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def refused(path, capsys, why, tmp_path, extra=()):
    code, out, err = run(["distance", path, "-s", 0, "-o", tmp_path / "d.npy", "-q", *extra], capsys)
    assert (code, out) == (1, "")
    assert err == f"heatcore: error: {why}\n"
    assert not (tmp_path / "d.npy").exists()


def binary_stl(count):
    triangles = b"".join(struct.pack("<12f", 0, 0, 0, *V[f].ravel()) + b"\0\0" for f in F)
    return bytes(80) + struct.pack("<I", count) + triangles


def test_a_latin1_byte_in_a_comment_is_read(tmp_path, capsys):
    path = tmp_path / "latin1.obj"
    path.write_bytes("# caf\xe9, \xa9 2024\n".encode("latin-1") + OBJ.encode())
    code, out, err = run(["distance", path, "-s", 0, "-o", tmp_path / "d.npy", "--refine", "0", "-q"], capsys)
    assert (code, out, err) == (0, f"wrote {tmp_path / 'd.npy'}\n", "")
    expected = hc.geodesic_distance(V, F, [0], refine=0)
    np.testing.assert_allclose(np.load(tmp_path / "d.npy"), expected, rtol=0, atol=1e-12)


def test_a_gzip_file_named_obj(tmp_path, capsys):
    path = tmp_path / "m.obj"
    path.write_bytes(gzip.compress(OBJ.encode()))
    refused(path, capsys, f"cannot read mesh file {path}: it is gzip-compressed (decompress it first: gunzip)",
            tmp_path)


@pytest.mark.parametrize("count", [1000, 10**9])
def test_a_binary_stl_with_a_wrong_triangle_count(count, tmp_path, capsys):
    path = tmp_path / "m.stl"
    path.write_bytes(binary_stl(count))
    why = (f"cannot read mesh file {path}: its binary STL header declares {count} triangles "
           f"(84 + 50 x {count} = {84 + 50 * count} bytes) but the file has 284 bytes (a truncated file, or a wrong count)")
    refused(path, capsys, why, tmp_path)
    refused(path, capsys, why, tmp_path, ["--domain", "polygon"])


def test_a_whole_binary_stl_and_an_ascii_one_with_a_latin1_name_are_read(tmp_path, capsys):
    facets = "".join(" facet normal 0 0 0\n  outer loop\n" + "".join(f"   vertex {x:g} {y:g} {z:g}\n" for x, y, z in V[f])
                     + "  endloop\n endfacet\n" for f in F)
    (tmp_path / "b.stl").write_bytes(binary_stl(4))
    (tmp_path / "a.stl").write_bytes(f"solid {'x' * 100} caf\xe9\n{facets}endsolid\n".encode("latin-1"))
    for name in ("b", "a"):  # the ASCII name is longer than a binary header: it must not be taken for one
        code, _, err = run(["distance", tmp_path / f"{name}.stl", "-s", 0, "-o", tmp_path / f"{name}.npy",
                            "--refine", "0", "-q"], capsys)
        assert (code, err) == (0, "")
    binary, ascii_ = np.load(tmp_path / "b.npy"), np.load(tmp_path / "a.npy")
    assert binary.shape == (12,)  # STL: three corners per triangle, unwelded by trimesh
    np.testing.assert_array_equal(ascii_, binary)


def test_a_folder_a_fifo_and_dev_null_are_not_mesh_files(tmp_path, capsys):
    folder = tmp_path / "meshes.obj"
    folder.mkdir()
    refused(folder, capsys, f"cannot read mesh file {folder}: it is a folder, not a regular file", tmp_path)
    if hasattr(os, "mkfifo"):  # POSIX: a FIFO would block a reader forever
        fifo = tmp_path / "pipe.obj"
        os.mkfifo(fifo)
        refused(fifo, capsys, f"cannot read mesh file {fifo}: it is a FIFO (named pipe), not a regular file", tmp_path)
    if os.path.exists("/dev/null"):
        refused("/dev/null", capsys, "cannot read mesh file /dev/null: it is a character device, not a regular file",
                tmp_path)


@pytest.mark.parametrize("domain", ["auto", "tet"])
def test_a_header_that_overcounts_is_said_in_our_words(domain, tmp_path, capsys):
    path = tmp_path / "m.off"  # the tet reader said "cannot reshape array of size 16 into shape (1000000000,3)"
    path.write_text("OFF\n1000000000 4 0\n" + "".join(f"{x:g} {y:g} {z:g}\n" for x, y, z in V) + "3 0 2 1\n")
    noun = "tet mesh file" if domain == "tet" else "mesh file"
    refused(path, capsys, f"cannot read {noun} {path}: its OFF header declares 1000000000 vertices but the data ends "
            "after 5 of them (a truncated file, or a header that overcounts)", tmp_path, ["--domain", domain])


def test_an_ascii_ply_header_that_overcounts(tmp_path, capsys):
    path = tmp_path / "m.ply"  # was numpy's "Some errors were detected ! Line #4 (got 4 columns instead of 3)"
    path.write_text("ply\nformat ascii 1.0\nelement vertex 1000000000\nproperty float x\nproperty float y\n"
                    "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                    + "".join(f"{x:g} {y:g} {z:g}\n" for x, y, z in V) + "3 0 1 2\n")
    refused(path, capsys, f"cannot read mesh file {path}: vertex 4 (line 14) has 4 values but its PLY header "
            "declares 3 properties for each vertex", tmp_path)


def test_an_output_that_cannot_be_written_is_named_not_its_temporary_file(tmp_path, capsys, monkeypatch):
    mesh = tmp_path / "m.obj"
    mesh.write_text(OBJ)
    blocker = tmp_path / "notes.txt"
    blocker.write_text("")
    code, out, err = run(["distance", mesh, "-s", 0, "-o", blocker / "d.npy", "-q"], capsys)
    why = f"cannot write {blocker / 'd.npy'}: {blocker} is a file, not a folder"
    assert (code, out, err) == (1, "", f"heatcore: error: {why}\n")

    def denied(src, dst):
        raise PermissionError(13, "Permission denied", str(src))

    monkeypatch.setattr(os, "replace", denied)  # a folder the user may not write to (root may write anywhere)
    code, out, err = run(["distance", mesh, "-s", 0, "-o", tmp_path / "d.npy", "-q"], capsys)
    assert (code, out, err) == (1, "", f"heatcore: error: cannot write {tmp_path / 'd.npy'}: Permission denied\n")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.obj", "notes.txt"]  # the temporary file removed


def test_a_missing_output_folder_is_created_by_every_command(tmp_path, capsys):
    mesh = tmp_path / "m.obj"
    mesh.write_text(OBJ)
    for argv, written in [(["distance", mesh, "-s", 0, "-o", tmp_path / "a" / "b" / "d.npy"], "a/b/d.npy"),
                          (["path", mesh, "--from", 0, "--to", 3, "-o", tmp_path / "c" / "p.obj"], "c/p.obj"),
                          (["demo", "-d", tmp_path / "e", "--refine", "0"], "e/demo.ply")]:
        code, _, err = run([*argv, "-q"], capsys)
        assert code == 0, err
        assert (tmp_path / written).is_file()
