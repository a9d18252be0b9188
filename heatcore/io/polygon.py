"""Reading polygon meshes (OBJ, PLY, OFF) with their polygons kept whole.

:func:`heatcore.io.read_mesh` triangulates polygons (:mod:`heatcore.io.faces`;
the libraries fan them on load). For :class:`~heatcore.domains.polygon.PolygonMesh` the polygons must survive
reading, and the libraries differ there (measured on the shared test meshes):

* potpourri3d's ``read_polygon_mesh`` (geometry-central's readers) keeps
  every polygon, in file order, for OBJ (texture coordinates and normals
  included), PLY and OFF: used first when installed;
* meshio keeps polygon cells of PLY files (grouped by size) but rejects OBJ
  files with texture coordinates and reads only triangles from OFF: the
  fallback;
* pymeshlab's ``polygonal_face_list()`` rebuilds polygons from faux edges and
  merges some neighbours (beast.obj: 32,362 polygons instead of 32,364), and
  trimesh triangulates: neither is used.

Every file is checked first (:func:`heatcore.io.checks.check_mesh_file`): the
readers trust a PLY or OFF header's counts and cast fractional indices, and
potpourri3d misreads relative OBJ indices, which are made absolute for it.

Examples
--------
>>> import tempfile, pathlib, meshio, numpy as np
>>> V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0.5, 0]], float)
>>> tmp = tempfile.TemporaryDirectory()
>>> path = pathlib.Path(tmp.name) / "two.ply"
>>> meshio.write(str(path), meshio.Mesh(V, [("quad", [[0, 1, 2, 3]]), ("triangle", [[1, 4, 2]])]))
>>> mesh = read_polygon_mesh(path)
>>> mesh.vertices.shape, mesh.polygon_sizes.tolist()
((5, 3), [4, 3])
>>> tmp.cleanup()
"""

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InvalidMeshError, short
from .files import check_input_file
from .mesh import meshio_read


@dataclass
class PolygonSurface:
    """A polygon mesh read from a file.

    Attributes
    ----------
    vertices : (n, 3) float array
    offsets : (m + 1,) int array
        Polygon ``p`` is ``indices[offsets[p]:offsets[p + 1]]``.
    indices : (offsets[-1],) int array

    Examples
    --------
    >>> mesh = PolygonSurface(np.zeros((5, 3)), np.array([0, 4, 7]), np.array([0, 1, 2, 3, 1, 4, 2]))
    >>> mesh.polygon_sizes.tolist(), [p.tolist() for p in mesh.polygon_list()]
    ([4, 3], [[0, 1, 2, 3], [1, 4, 2]])
    """

    vertices: np.ndarray
    offsets: np.ndarray
    indices: np.ndarray

    @property
    def polygons(self):
        """``(offsets, indices)``, as :class:`~heatcore.domains.polygon.PolygonMesh` accepts them."""
        return self.offsets, self.indices

    @property
    def polygon_sizes(self):
        """Number of corners of each polygon."""
        return np.diff(self.offsets)

    def polygon_list(self):
        """The polygons as a list of index arrays."""
        return np.split(self.indices, self.offsets[1:-1])


def read_polygon_mesh(path):
    """Read a polygon mesh file, keeping its polygons (see the module docstring for the readers).

    Parameters
    ----------
    path : str or path-like
        OBJ, PLY or OFF (potpourri3d), or any surface format meshio reads.

    Returns
    -------
    PolygonSurface

    Raises
    ------
    InvalidMeshError
        Missing file, a file no reader accepts, or a file without polygons.

    Examples
    --------
    >>> import pytest, tempfile, pathlib
    >>> _ = pytest.importorskip("potpourri3d")  # the polygon extra
    >>> tmp = tempfile.TemporaryDirectory()
    >>> path = pathlib.Path(tmp.name) / "quad.off"
    >>> _ = path.write_text("OFF\\n4 1 0\\n0 0 0\\n1 0 0\\n1 1 0\\n0 1 0\\n4 0 1 2 3\\n")
    >>> read_polygon_mesh(path).polygon_sizes.tolist()
    [4]
    >>> tmp.cleanup()
    """
    from .checks import check_mesh_file

    path = Path(path)
    check_input_file(path)
    text = check_mesh_file(path)  # before the readers: both hang on a PLY header without end_header
    if text is not None:  # an OBJ with relative indices: the readers get them made absolute
        import tempfile

        with tempfile.TemporaryDirectory() as folder:
            (Path(folder) / path.name).write_bytes(text)
            return _read_polygons(Path(folder) / path.name, path)
    return _read_polygons(path, path)


def _read_polygons(source, path):
    """The first reader's polygons of ``source``; errors name ``path``."""
    errors = []
    for reader in (_read_potpourri3d, _read_meshio):
        try:
            V, offsets, indices = reader(source)
        except ImportError as exc:
            errors.append(f"{reader.__name__[6:]} not installed ({exc})")
            continue
        except (Exception, SystemExit) as exc:  # readers raise many types; meshio may even exit
            errors.append(f"{reader.__name__[6:]}: {short(exc, 150) or type(exc).__name__}")
            continue
        if offsets.size < 2:
            errors.append(f"{reader.__name__[6:]}: no polygons")
            continue
        return PolygonSurface(V, offsets, indices)
    raise InvalidMeshError(f"cannot read polygon mesh file {path}: " + "; ".join(errors))


def _read_potpourri3d(path):
    import potpourri3d

    V, polygons = potpourri3d.read_polygon_mesh(str(path))
    sizes = np.fromiter((len(p) for p in polygons), dtype=np.int64, count=len(polygons))
    indices = np.fromiter((i for p in polygons for i in p), dtype=np.int64, count=int(sizes.sum()))
    return np.asarray(V, dtype=float), np.r_[0, np.cumsum(sizes)].astype(np.int64), indices


def _read_meshio(path):

    mesh = meshio_read(path)  # meshio's exits become InvalidMeshError
    blocks = []
    for block in mesh.cells:
        if block.type in ("triangle", "quad") or block.type.startswith("polygon"):
            blocks.extend(np.asarray(c, dtype=np.int64).reshape(-1) for c in block.data)
    sizes = np.fromiter((b.size for b in blocks), dtype=np.int64, count=len(blocks))
    indices = np.concatenate(blocks) if blocks else np.zeros(0, dtype=np.int64)
    return np.asarray(mesh.points, dtype=float)[:, :3], np.r_[0, np.cumsum(sizes)].astype(np.int64), indices
