"""Tetrahedral mesh files through meshio: read tets, write distances as point data.

Reads Gmsh ``.msh``, VTK ``.vtk``/``.vtu``, Medit ``.mesh``/``.meshb``, TetGen
``.node``/``.ele`` and the other volume formats meshio knows. Writes the
distance as the point-data field ``distance`` in ``.vtu``, ``.vtk`` or
``.msh`` (for ParaView and Gmsh). meshio is imported lazily, inside the
functions (see the design notes on import order with ``bpy``).

Examples
--------
>>> import numpy as np, tempfile, os
>>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
>>> tmp = tempfile.TemporaryDirectory()
>>> path = os.path.join(tmp.name, "tet.vtu")
>>> write_tet_distance(path, V, [[0, 1, 2, 3]], [0.0, 1.0, 1.0, 1.0])
>>> V2, T2 = read_tet_mesh(path)
>>> V2.shape, T2.tolist()
((4, 3), [[0, 1, 2, 3]])
>>> tmp.cleanup()
"""

import warnings
from pathlib import Path

import numpy as np

from ..errors import HeatcoreWarning, InvalidMeshError, InvalidOptionError
from .checks import check_mesh_file
from .files import check_input_file
from .mesh import meshio_read

#: Suffixes whose meshio writer keeps point data, and the meshio format used.
DISTANCE_FORMATS = {".vtu": "vtu", ".vtk": "vtk", ".msh": "gmsh"}

#: meshio cell types holding tets; higher-order tets keep their 4 corners.
TET_CELL_TYPES = ("tetra", "tetra10")


def read_tet_mesh(path):
    """Read the tetrahedra of a volume mesh file.

    Parameters
    ----------
    path : str or path-like
        A file meshio reads: Gmsh ``.msh``, ``.vtu``/``.vtk``, Medit
        ``.mesh``, TetGen ``.node`` or ``.ele`` (the other of the pair must
        sit beside it), and more.

    Returns
    -------
    V : (n, 3) float array
        All points of the file (those used by no tet get ``inf`` distance).
    T : (m, 4) int array
        Every tet of every cell block, in file order. Quadratic tets
        (``tetra10``) keep their 4 corners, with a warning.

    Raises
    ------
    InvalidMeshError
        Missing or unreadable file, or a file without tetrahedra.

    Examples
    --------
    >>> import os, tempfile, numpy as np, scipy.spatial
    >>> P = np.random.default_rng(0).random((30, 3))
    >>> tmp = tempfile.TemporaryDirectory()
    >>> path = os.path.join(tmp.name, "part.vtu")
    >>> write_tet_distance(path, P, scipy.spatial.Delaunay(P).simplices, np.zeros(30))
    >>> V, T = read_tet_mesh(path)
    >>> V.shape, T.shape[1]
    ((30, 3), 4)
    >>> tmp.cleanup()
    """

    path = Path(path)
    check_input_file(path, "tet mesh file")
    suffix = path.suffix.lower()
    if suffix in (".ply", ".off", ".obj"):  # a header that lies, in our words before meshio's numpy errors
        check_mesh_file(path, "tet mesh file")
    fmt = "gmsh" if suffix == ".msh" else None  # meshio would try ANSYS first
    mesh = meshio_read(path, "tet mesh file", file_format=fmt)  # meshio's exits become InvalidMeshError
    blocks = [b for b in mesh.cells if b.type in TET_CELL_TYPES]
    if not blocks:
        kinds = sorted({b.type for b in mesh.cells}) or ["none"]
        raise InvalidMeshError(
            f"{path} holds no tetrahedra (cell types: {', '.join(kinds)}); "
            "for a surface mesh use heatcore.io.read_mesh and TriangleMesh"
        )
    if any(b.type == "tetra10" for b in blocks):
        warnings.warn(
            f"{path}: quadratic tets (tetra10) are used as linear tets (their 4 corners); "
            "mid-edge nodes get distance inf",
            HeatcoreWarning,
            stacklevel=2,
        )
    T = np.concatenate([np.asarray(b.data, dtype=np.int64)[:, :4] for b in blocks])
    V = np.asarray(mesh.points, dtype=float)
    if V.ndim != 2 or V.shape[1] != 3:
        raise InvalidMeshError(f"{path}: tet mesh points must be 3D, got shape {V.shape}")
    return V, T


def write_tet_distance(path, V, T, distance, *, unreachable=np.nan):
    """Write a tet mesh with the point-data field ``distance``.

    Parameters
    ----------
    path : str or path-like
        ``.vtu`` or ``.vtk`` (ParaView) or ``.msh`` (Gmsh, format 2.2 binary via meshio).
    V : (n, 3) array_like of float
    T : (m, 4) array_like of int
    distance : (n,) array_like of float
        Distance per vertex, as :meth:`HeatSolver.distance` returns it.
    unreachable : float, default nan
        Written in place of ``inf`` (vertices no source reaches): ParaView
        shows NaN in its "NaN colour" and leaves the colour range alone.
        Pass ``np.inf`` to keep infinities.

    Raises
    ------
    InvalidOptionError
        A file suffix whose format cannot store point data.
    InvalidMeshError
        ``distance`` does not have one value per vertex.

    Examples
    --------
    >>> import os, tempfile, numpy as np, scipy.spatial, heatcore as hc
    >>> V = np.random.default_rng(0).random((40, 3))
    >>> T = scipy.spatial.Delaunay(V).simplices
    >>> d = hc.HeatSolver(hc.TetMesh(V, T)).distance([0])
    >>> tmp = tempfile.TemporaryDirectory()
    >>> write_tet_distance(os.path.join(tmp.name, "out.vtu"), V, T, d)
    >>> tmp.cleanup()
    """
    import meshio

    path = Path(path)
    fmt = DISTANCE_FORMATS.get(path.suffix.lower())
    if fmt is None:
        raise InvalidOptionError(
            f"cannot store a distance field in {path.suffix or 'a file without suffix'}: "
            f"use one of {', '.join(DISTANCE_FORMATS)}"
        )
    V = np.asarray(V, dtype=float)
    T = np.asarray(T, dtype=np.int64)
    d = np.asarray(distance, dtype=float).ravel()
    if d.shape[0] != V.shape[0]:
        raise InvalidMeshError(f"distance has {d.shape[0]} values but the mesh has {V.shape[0]} vertices")
    d = np.where(np.isinf(d), unreachable, d)
    mesh = meshio.Mesh(V, [("tetra", T)], point_data={"distance": d})
    kwargs = {}
    if fmt == "gmsh":
        kwargs["file_format"] = "gmsh22"
        mesh.cell_data = {"gmsh:physical": [np.ones(len(T), dtype=np.int32)],
                          "gmsh:geometrical": [np.ones(len(T), dtype=np.int32)]}
    else:
        kwargs["file_format"] = fmt
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # meshio's notes on missing gmsh tags and the like
        meshio.write(str(path), mesh, **kwargs)
