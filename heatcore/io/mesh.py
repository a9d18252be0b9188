"""Mesh file reading and writing through library readers (meshio, trimesh).

meshio reads and writes PLY (keeping extra vertex properties such as
MeshLab's selection flags and quality) and volume formats; trimesh reads OBJ
(meshio's OBJ reader rejects files with texture coordinates), OFF, STL and
glTF without reordering vertices. PLY files of triangle strips
(``element tristrips``, strips separated by ``-1``, as in the Stanford
scans), which meshio rejects, are read by :mod:`heatcore.io.ply`.

A file that cannot be read gives one :class:`~heatcore.errors.InvalidMeshError`
saying why (an empty file, a PLY without vertices, the reader's own words cut
to :data:`~heatcore.errors.MAX_DETAIL` characters), never the reader's printout.
Nor does a file that lies (:mod:`heatcore.io.checks`): a PLY or OFF file whose
data does not match its header's counts, an OBJ face index that is 0,
fractional or out of range. OBJ relative indices are resolved against the
vertices read so far, as the format defines (trimesh counts from the end).

Examples
--------
>>> V, F = load_demo_mesh()
>>> V.shape[1], F.shape[1]
(3, 3)
"""

from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path

import numpy as np

from ..errors import MAX_DETAIL, InvalidMeshError, NoFacesError, short  # noqa: F401 (short, MAX_DETAIL: kept importable here)
from .files import check_input_file, is_text_mesh, utf8_text

#: MeshLab (VCG) stores the selection in bit 5 of the per-vertex ``flags`` PLY property.
MESHLAB_SELECTED_FLAG = 0x20

TRIMESH_SUFFIXES = {".obj", ".off", ".stl", ".glb", ".gltf"}


@dataclass
class SurfaceMesh:
    """A surface mesh read from a file.

    Attributes
    ----------
    vertices : (n, 3) float array
    faces : (m, 3) int array, triangles (polygons triangulated by :mod:`heatcore.io.faces`)
    vertex_data : dict of (n,) arrays, extra per-vertex properties (PLY)

    Examples
    --------
    >>> mesh = SurfaceMesh(np.eye(3), np.array([[0, 1, 2]]), {"flags": np.array([0, 0x20, 0])})
    >>> mesh.selected_vertices().tolist()
    [1]
    """

    vertices: np.ndarray
    faces: np.ndarray
    vertex_data: dict = field(default_factory=dict)

    def selected_vertices(self):
        """Vertices marked selected in a MeshLab PLY (``flags`` property), possibly empty."""
        flags = self.vertex_data.get("flags")
        if flags is None:
            return np.zeros(0, dtype=np.int64)
        return np.flatnonzero(np.asarray(flags).astype(np.int64) & MESHLAB_SELECTED_FLAG)


def demo_mesh_path():
    """Path of the bundled demo mesh (spot, Keenan Crane, public domain).

    Returns
    -------
    pathlib.Path

    Examples
    --------
    >>> demo_mesh_path().name
    'spot.obj'
    """
    return Path(str(resources.files("heatcore") / "data" / "spot.obj"))


def load_demo_mesh():
    """Vertices and faces of the bundled demo mesh.

    Returns
    -------
    V : (n, 3) float array
    F : (m, 3) int array

    Examples
    --------
    >>> V, F = load_demo_mesh()
    >>> V.shape, F.shape
    ((2930, 3), (5856, 3))
    """
    mesh = read_mesh(demo_mesh_path())
    return mesh.vertices, mesh.faces


def read_mesh(path):
    """Read a surface mesh file.

    Parameters
    ----------
    path : str or path-like
        Any format trimesh (OBJ, OFF, STL, glTF) or meshio (PLY, VTK, ...) reads.

    Returns
    -------
    SurfaceMesh

    Raises
    ------
    InvalidMeshError
        A missing, empty or unreadable file; :class:`~heatcore.errors.NoFacesError`
        when it holds vertices but no faces.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> tmp = tempfile.TemporaryDirectory()
    >>> path = pathlib.Path(tmp.name) / "tri.obj"
    >>> _ = path.write_text("v 0 0 0\\nv 1 0 0\\nv 0 1 0\\nf 1 2 3\\n")
    >>> mesh = read_mesh(path)
    >>> mesh.vertices.shape, mesh.faces.tolist()
    ((3, 3), [[0, 1, 2]])
    >>> tmp.cleanup()
    """
    from .checks import scan_mesh_file

    path = Path(path)
    check_input_file(path)
    suffix = path.suffix.lower()
    try:
        if suffix in TRIMESH_SUFFIXES:
            return _read_trimesh(path, scan_mesh_file(path, read=True))
        if suffix == ".ply":
            return _read_ply(path)
        return _read_meshio(path)
    except InvalidMeshError:
        raise
    except (Exception, SystemExit) as exc:  # readers raise many types; meshio may even exit
        raise InvalidMeshError(f"cannot read mesh file {path}: {short(exc) or type(exc).__name__}") from exc


def _read_trimesh(path, scan):
    """``scan``: :func:`~heatcore.io.checks.scan_mesh_file`'s answer (the text to read, the polygons)."""
    import io

    import trimesh

    from .faces import triangulate_faces

    if scan.vertices is not None:  # read by the scan (an OFF file with polygons)
        return SurfaceMesh(scan.vertices, triangulate_faces(scan.vertices, *scan.polygons,
                                                            f"cannot read mesh file {path}"))
    text = scan.text
    if is_text_mesh(path):  # a Latin-1 byte must not stop trimesh (it would ask charset_normalizer)
        text = utf8_text(text if text is not None else path.read_bytes())
    if scan.materials:  # trimesh splits an OBJ at each usemtl, each part with its own copy of the vertices
        text = (text if text is not None else path.read_bytes()).replace(b"usemtl", b"usemt_")
    source = {"file_obj": str(path)} if text is None else {
        "file_obj": io.BytesIO(text), "file_type": path.suffix.lower()[1:],
        "resolver": trimesh.resolvers.FilePathResolver(str(path))}
    mesh = trimesh.load(**source, process=False, maintain_order=True, force="mesh")
    if len(mesh.faces) == 0:
        raise NoFacesError(f"{path} holds no faces")
    V = np.asarray(mesh.vertices, dtype=float)
    if scan.polygons is None:
        return SurfaceMesh(V, np.asarray(mesh.faces, dtype=np.int64))
    return SurfaceMesh(V, triangulate_faces(V, *scan.polygons, f"cannot read mesh file {path}"))


def _read_ply(path):
    from .plycheck import check_ply_body, check_ply_size

    header = _read_ply_header(path)
    check_ply_size(path, header)  # before the readers: meshio would walk a 10**9-face header for minutes
    try:
        mesh = _read_ply_data(path, header)
    except NoFacesError:
        raise
    except InvalidMeshError:  # a reader's parse error: a header that lies is said in our words first
        check_ply_body(path, header)
        raise
    check_ply_body(path, header)
    return mesh


def _read_ply_header(path):
    from .ply import read_header

    header = read_header(path)
    counts = header.counts()
    if not counts.get("vertex"):
        declared = "no vertex element" if "vertex" not in counts else "element vertex 0"
        raise InvalidMeshError(f"{path} holds no vertices (its PLY header declares {declared})")
    return header


def _read_ply_data(path, header):
    from .ply import read_tristrips

    counts = header.counts()
    if counts.get("tristrips"):
        return SurfaceMesh(*read_tristrips(path, header))
    if not counts.get("face"):
        raise NoFacesError(f"{path} holds no faces")
    face = next(e for e in header.elements if e.name == "face")
    if len(face.properties) > 1:  # MeshLab's face flags beside the corners: meshio misreads such faces
        return _ply_with_face_properties(path, header)
    import meshio
    import meshio.ply

    try:
        return _surface(meshio.ply.read(str(path)), path)
    except (NoFacesError, meshio.ReadError):
        raise
    except Exception as exc:  # numpy's complaint while parsing: the body does not match the header
        raise InvalidMeshError(f"cannot read mesh file {path}: {short(exc, 160) or type(exc).__name__} "
                               "(the data does not match the header: a truncated or corrupt file?)") from None


def _ply_with_face_properties(path, header):
    """A PLY whose faces hold more than their corners (MeshLab saves ``flags``), read by :mod:`heatcore.io.ply`.

    meshio 5.3 reads the corner lists of such a file wrongly (a file MeshLab saved with its selection flags
    was refused as corrupt).
    """
    from .faces import triangulate_faces
    from .ply import read_elements

    elements = read_elements(path, header)
    vertex, face = elements["vertex"], elements["face"]
    if not all(c in vertex for c in "xyz"):
        raise InvalidMeshError(f"cannot read mesh file {path}: its vertices have no x, y, z")
    rows = face.get("vertex_indices", face.get("vertex_index"))
    if rows is None:
        raise NoFacesError(f"{path}: its faces have no vertex_indices list")
    V = np.column_stack([np.asarray(vertex[c], dtype=float) for c in "xyz"])
    sizes = np.array([len(r) for r in rows], dtype=np.int64)
    corners = np.concatenate(rows).astype(np.int64) if len(rows) else np.zeros(0, dtype=np.int64)
    faces = triangulate_faces(V, np.r_[0, np.cumsum(sizes)], corners, f"cannot read mesh file {path}")
    data = {k: np.asarray(v) for k, v in vertex.items() if k not in "xyz" and np.ndim(v) == 1}
    return SurfaceMesh(V, faces, data)


def meshio_read(path, what="mesh file", reader=None, **kwargs):
    """``meshio.read`` (or ``reader``) that never ends the process: its printout and exits become one error.

    meshio prints why it cannot read a file and then calls ``sys.exit(1)``
    (a PLY with an ``edge`` element, a VTK ``POLYDATA`` file); every heatcore
    reader goes through here, so that a library never exits the process.

    Parameters
    ----------
    path : path-like
    what : str, default "mesh file"
        What the file is, for the message.
    reader : callable, optional
        A meshio reader (``meshio.ply.read``); default ``meshio.read``.
    **kwargs
        Passed to the reader (``file_format=``).

    Raises
    ------
    InvalidMeshError
        meshio exited, or raised (its message, cut short).

    Examples
    --------
    >>> import tempfile
    >>> tmp = tempfile.TemporaryDirectory()
    >>> path = Path(tmp.name) / "edges.ply"
    >>> _ = path.write_text("ply\\nformat ascii 1.0\\nelement vertex 1\\nproperty float x\\nproperty float y\\n"
    ...                     "property float z\\nelement edge 0\\nproperty int vertex1\\nproperty int vertex2\\n"
    ...                     "end_header\\n0 0 0\\n")
    >>> meshio_read(path)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    heatcore.errors.InvalidMeshError: cannot read mesh file .../edges.ply: Expected `element vertex` or ...
    >>> tmp.cleanup()
    """
    import contextlib
    import io

    import meshio

    chatter = io.StringIO()
    try:
        with contextlib.redirect_stdout(chatter), contextlib.redirect_stderr(chatter):
            return (reader or meshio.read)(str(path), **kwargs)
    except SystemExit:
        detail = short(" ".join(chatter.getvalue().split())) or "no reader accepts it"
    except InvalidMeshError:
        raise
    except Exception as exc:  # readers raise many types
        detail = short(exc) or type(exc).__name__
    raise InvalidMeshError(f"cannot read {what} {path}: {detail}")


def _read_meshio(path):
    return _surface(meshio_read(path), path)


def _surface(mesh, path):
    """meshio's triangle and polygon blocks as triangles (:mod:`heatcore.io.faces`), in block order."""
    from .faces import triangulate_faces

    blocks = [np.asarray(b.data, dtype=np.int64) for b in mesh.cells
              if b.type in ("triangle", "quad") or b.type.startswith("polygon")]
    if not blocks:
        raise NoFacesError(f"{path} holds no triangles or polygons")
    V = np.asarray(mesh.points, dtype=float)[:, :3]
    sizes = np.concatenate([np.full(len(b), b.shape[1]) for b in blocks])
    faces = triangulate_faces(V, np.r_[0, np.cumsum(sizes)], np.concatenate([b.ravel() for b in blocks]),
                              f"cannot read mesh file {path}")
    data = {k: np.asarray(v) for k, v in mesh.point_data.items() if np.ndim(v) == 1}
    return SurfaceMesh(V, faces, data)


def write_ply(path, V, F, quality, colors, selection=None, texcoords=None):
    """Write a binary PLY with per-vertex quality, colors and (optionally) MeshLab selection flags and UVs.

    Parameters
    ----------
    path : str or path-like
    V : (n, 3) float array
    F : (m, 3) int array (``m`` may be 0: a point cloud)
    quality : (n,) float array, written as ``property double quality``
    colors : (n, 3) uint8 array
    selection : (k,) int array, optional
        Vertices to flag as selected (MeshLab's ``flags`` bit).
    texcoords : (n, 2) float array, optional
        Per-vertex texture coordinates, written twice: as ``s``, ``t`` (what
        Blender's PLY importer reads into a UV map) and as ``texture_u``,
        ``texture_v`` (what MeshLab reads).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> tmp = tempfile.TemporaryDirectory()
    >>> path = pathlib.Path(tmp.name) / "d.ply"
    >>> V, F = np.eye(3), np.array([[0, 1, 2]])
    >>> write_ply(path, V, F, [0.0, 1.0, 1.0], np.zeros((3, 3)), selection=[0])
    >>> mesh = read_mesh(path)
    >>> mesh.vertex_data["quality"].tolist(), mesh.selected_vertices().tolist()
    ([0.0, 1.0, 1.0], [0])
    >>> write_ply(path, V, F, [0.0, 1.0, 1.0], np.zeros((3, 3)), texcoords=[[0, 0], [1, 0], [0, 1]])
    >>> read_mesh(path).vertex_data["texture_v"].tolist()
    [0.0, 0.0, 1.0]
    >>> tmp.cleanup()
    """
    import meshio

    data = {"quality": np.asarray(quality, dtype=np.float64)}
    for name, channel in zip(("red", "green", "blue"), np.asarray(colors, dtype=np.uint8).T):
        data[name] = channel
    if selection is not None:
        flags = np.zeros(len(V), dtype=np.int32)
        flags[np.asarray(selection, dtype=np.int64)] = MESHLAB_SELECTED_FLAG
        data["flags"] = flags
    if texcoords is not None:
        uv = np.asarray(texcoords, dtype=np.float64)
        data["s"], data["t"], data["texture_u"], data["texture_v"] = uv[:, 0], uv[:, 1], uv[:, 0], uv[:, 1]
    F = np.asarray(F, dtype=np.int32).reshape(-1, 3)
    cells = [("triangle", F)] if len(F) else []  # a point cloud has no faces
    mesh = meshio.Mesh(np.asarray(V, dtype=float), cells, point_data=data)
    meshio.write(str(path), mesh, file_format="ply", binary=True)
