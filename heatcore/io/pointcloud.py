"""Reading point clouds (PLY, XYZ, OBJ) through library readers.

PLY goes through meshio, OBJ through trimesh, and XYZ text (``x y z`` or
``x y z nx ny nz`` per line, spaces or commas) through :func:`numpy.loadtxt`.
Faces in the file, if any, are ignored: only the vertices are read.

Examples
--------
>>> import tempfile, pathlib, numpy as np
>>> tmp = tempfile.TemporaryDirectory()
>>> path = pathlib.Path(tmp.name) / "cloud.xyz"
>>> _ = path.write_text("0 0 0\\n1 0 0\\n0 1 0\\n")
>>> read_point_cloud(path).points.shape
(3, 3)
>>> tmp.cleanup()
"""

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InvalidMeshError, short
from .files import check_input_file
from .mesh import meshio_read

#: Suffixes read as XYZ text.
XYZ_SUFFIXES = {".xyz", ".txt", ".pts", ".csv"}
POINT_CLOUD_SUFFIXES = {".ply", ".obj"} | XYZ_SUFFIXES


@dataclass
class PointCloudFile:
    """Points (and normals, where the file has them) read from a file.

    Attributes
    ----------
    points : (n, 3) float array
    normals : (n, 3) float array or None

    Examples
    --------
    >>> cloud = PointCloudFile(np.zeros((4, 3)))
    >>> cloud.points.shape, cloud.normals is None
    ((4, 3), True)
    """

    points: np.ndarray
    normals: np.ndarray | None = None


def read_point_cloud(path):
    """Read the vertices of a point-cloud file.

    Parameters
    ----------
    path : str or path-like
        ``.ply`` (meshio; ``nx ny nz`` vertex properties become normals),
        ``.obj`` (trimesh; ``v`` lines, ``vn`` normals when there is one per
        vertex) or ``.xyz``/``.txt``/``.pts``/``.csv`` (3 or 6 numeric columns).

    Returns
    -------
    PointCloudFile

    Raises
    ------
    InvalidMeshError
        Missing or unreadable file, unknown suffix, no points, or a wrong
        number of columns. Coordinates are not checked here: NaN points are
        reported by :class:`~heatcore.domains.pointcloud.PointCloud`.

    Examples
    --------
    >>> from heatcore.io import demo_mesh_path
    >>> read_point_cloud(demo_mesh_path()).points.shape
    (2930, 3)
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in POINT_CLOUD_SUFFIXES:
        raise InvalidMeshError(
            f"cannot read {path}: point clouds are read from {', '.join(sorted(POINT_CLOUD_SUFFIXES))} files"
        )
    check_input_file(path, "point cloud file")
    try:
        if suffix in (".ply", ".obj"):  # a file whose data does not match its header or faces is an error
            from .checks import check_mesh_file

            check_mesh_file(path, "point cloud file")
        if suffix == ".ply":
            cloud = _read_ply(path)
        elif suffix == ".obj":
            cloud = _read_obj(path)
        else:
            cloud = _read_xyz(path)
    except InvalidMeshError:
        raise
    except (Exception, SystemExit) as exc:  # readers raise many types; meshio may even exit
        raise InvalidMeshError(f"cannot read point cloud file {path}: {short(exc) or type(exc).__name__}") from exc
    if cloud.points.shape[0] == 0:
        raise InvalidMeshError(f"{path} holds no points")
    return cloud


def _read_ply(path):

    import meshio.ply

    from .ply import read_header

    read_header(path)  # meshio hangs on a header without end_header
    mesh = meshio_read(path, "point cloud file", reader=meshio.ply.read)  # meshio's exits: InvalidMeshError
    points = np.asarray(mesh.points, dtype=float)
    data = mesh.point_data
    normals = None
    if all(k in data for k in ("nx", "ny", "nz")):
        normals = np.column_stack([np.asarray(data[k], dtype=float) for k in ("nx", "ny", "nz")])
    return PointCloudFile(_three_columns(points, path), normals)


def _read_obj(path):
    import trimesh

    geom = trimesh.load(str(path), process=False, maintain_order=True)
    if isinstance(geom, trimesh.Scene):
        geom = trimesh.util.concatenate(list(geom.geometry.values())) if geom.geometry else None
    if geom is None or not hasattr(geom, "vertices"):
        raise InvalidMeshError(f"{path} holds no vertices")
    points = np.asarray(geom.vertices, dtype=float)
    normals = None
    raw = getattr(geom, "vertex_normals", None) if isinstance(geom, trimesh.PointCloud) else None
    if raw is not None and np.shape(raw) == points.shape:
        normals = np.asarray(raw, dtype=float)
    return PointCloudFile(_three_columns(points, path), normals)


#: What a text point cloud holds, said when one cannot be read.
XYZ_FORMAT = (f"{'/'.join(sorted(XYZ_SUFFIXES))} point clouds hold 3 (x y z) or 6 (x y z nx ny nz) numbers per line, "
              "separated by spaces or commas, with '#' or '//' comments and no header line; point clouds are also "
              "read from .ply and .obj files")


def _read_xyz(path):
    text = path.read_bytes().decode("latin-1")
    delimiter = "," if "," in text.split("\n", 1)[0] else None
    try:
        table = np.loadtxt(path, delimiter=delimiter, ndmin=2, comments=("#", "//"), encoding="latin-1")
    except ValueError:
        why = _first_bad_line(text, delimiter)
        raise InvalidMeshError(f"cannot read point cloud file {path}: {why}; {XYZ_FORMAT}") from None
    if table.size == 0:
        return PointCloudFile(np.zeros((0, 3)))
    if table.shape[1] not in (3, 6):
        raise InvalidMeshError(
            f"{path} has {table.shape[1]} columns per line: {XYZ_FORMAT}"
        )
    normals = table[:, 3:6] if table.shape[1] == 6 else None
    return PointCloudFile(table[:, :3].astype(float), normals)


def _first_bad_line(text, delimiter):
    """Where and why ``text`` is not a table of numbers: ``"line 3 ('x y z') is not numbers"``."""
    width = None
    for number, line in enumerate(text.splitlines(), 1):
        tokens = [t for t in line.split("#")[0].split("//")[0].split(delimiter) if t.strip()]
        try:
            [float(t) for t in tokens]
        except ValueError:
            return f"line {number} ({short(line, 60)!r}) is not numbers"
        if tokens and width is not None and len(tokens) != width:
            return f"line {number} has {len(tokens)} numbers, the lines before it {width}"
        width = width or len(tokens) or None
    return "its lines are not a table of numbers"


def _three_columns(points, path):
    if points.ndim != 2 or points.shape[1] not in (2, 3):
        raise InvalidMeshError(f"{path}: points must have 3 coordinates, got shape {points.shape}")
    if points.shape[1] == 2:
        points = np.column_stack([points, np.zeros(points.shape[0])])
    return points
