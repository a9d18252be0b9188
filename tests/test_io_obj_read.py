"""A plain OBJ file is read by heatcore's own scan (no library parses it), into trimesh's arrays.

``read_mesh`` used to check an OBJ file with numpy, then hand it to trimesh,
whose parse of a 1M-vertex file took 2-5 s in Python loops. Where every
vertex line is plain, the scan's numbers are the mesh now; here both readers
are put side by side on the files users bring (groups, objects, texture and
normal indices, unused vertices, colors, relative indices, polygons), and
the files that are not plain still go to trimesh.
"""

import numpy as np
import pytest
import trimesh
from conftest import shared_mesh_path

import heatcore as hc
from heatcore.io import objcheck

PLAIN = {
    "uv and normal indices": "o A\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvt 1 1\nvn 0 0 1\n"
                             "f 1/1/1 2/2/1 3/3/1\nf 2/4/1 4/4/1 3/3/1\n",
    "two objects, faces after both": "o A\nv 0 0 0\nv 1 0 0\nv 0 1 0\no B\nv 5 0 0\nv 6 0 0\nv 5 1 0\nf 4 5 6\n"
                                     "o C\nf 1 2 3\n",
    "unused vertices": "v 0 0 0\nv 9 9 9\nv 1 0 0\nv 0 1 0\nf 1 3 4\nv 7 7 7\n",
    "vertex colors": "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nf 1 2 3\n",
    "groups and materials": "mtllib m.mtl\ng x\nusemtl m\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\ng y\n"
                            "usemtl n\nf 2 4 3\n",
    "repeated corner, exponents, CRLF": "v 0 0 0\r\nv 1e0 0 0\r\nv 0 1.0E+0 -0\r\n# a comment\r\nf 1 2 2\r\nf 1 2 3\r\n",
    "relative indices": "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 1 1 0\nf -3 -1 -2\n",
}


def library_read(path, monkeypatch):
    """``read_mesh`` as before: the scan does not read the file, trimesh does (with heatcore's checks around it)."""
    with monkeypatch.context() as patch:
        patch.setattr(objcheck, "_plain_vertices", lambda *args: None)
        return hc.io.read_mesh(path)


@pytest.mark.parametrize("case", sorted(PLAIN))
def test_plain_files_are_read_by_the_scan_as_the_library_read_them(tmp_path, case, monkeypatch):
    path = tmp_path / "m.obj"
    path.write_text(PLAIN[case])
    assert objcheck.scan_obj(path, read=True).vertices is not None  # the scan reads it
    mesh, before = hc.io.read_mesh(path), library_read(path, monkeypatch)
    np.testing.assert_array_equal(mesh.vertices, before.vertices)
    np.testing.assert_array_equal(mesh.faces, before.faces)
    if case == "groups and materials":  # trimesh alone splits the vertices at each material: heatcore hides them
        assert len(trimesh.load(file_obj=str(path), process=False, maintain_order=True, force="mesh").vertices) == 8
        assert len(mesh.vertices) == 4


@pytest.mark.parametrize("name", ["spot", "suzanne", "nefertiti", "beast"])
def test_shared_meshes_read_as_before(name, monkeypatch):
    """The scan's arrays, and those of the library path it replaces (quads triangulated by heatcore on both)."""
    path = shared_mesh_path(name)
    fast, slow = hc.io.read_mesh(path), library_read(path, monkeypatch)
    np.testing.assert_array_equal(fast.vertices, slow.vertices)
    np.testing.assert_array_equal(fast.faces, slow.faces)


@pytest.mark.parametrize("text", [
    "v 0 0 0 # a comment on a vertex line\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    "v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    "v 0 0 \\\n0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    "v 0 0 0v\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
])
def test_other_files_go_to_trimesh(tmp_path, text):
    """A comment, a vertex of two numbers, a continued line, a letter in a number: trimesh reads them, as before."""
    path = tmp_path / "odd.obj"
    path.write_text(text)
    assert objcheck.scan_obj(path, read=True).vertices is None


def test_bad_indices_are_still_reported(tmp_path):
    path = tmp_path / "bad.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n")
    with pytest.raises(hc.InvalidMeshError, match="line 4: a face references vertex 4 but the file has 3 vertices"):
        hc.io.read_mesh(path)


def test_tab_separated_lines_are_read(tmp_path):
    """Tabs separate tokens as spaces do (trimesh found no faces in this file: ``NoFacesError`` before)."""
    path = tmp_path / "tabs.obj"
    path.write_text("v\t0\t0\t0\nv\t1 0  0\nv 0 1 0   \nf\t1\t2\t3\n")
    mesh = hc.io.read_mesh(path)
    assert mesh.vertices.tolist() == [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
    assert mesh.faces.tolist() == [[0, 1, 2]]
