"""heatcore: geodesic distance on meshes by heat flow (Crane, Weischedel, Wardetzky 2013).

Examples
--------
>>> import heatcore as hc
>>> V, F = hc.io.load_demo_mesh()
>>> d = hc.geodesic_distance(V, F, [0])
>>> solver = hc.HeatSolver(hc.TriangleMesh(V, F))   # precompute once
>>> d1, d2 = solver.distance([0]), solver.distance([5, 9])
"""

from . import io, linalg
from .domains.operators import Operators
from .domains.pointcloud import PointCloud
from .domains.polygon import PolygonMesh
from .domains.tet import TetMesh
from .domains.triangle import TriangleMesh
from .errors import (
    HeatcoreError,
    HeatcoreWarning,
    InvalidMeshError,
    InvalidOptionError,
    InvalidSourceError,
    SolverError,
)
from .heat import HeatSolver

__version__ = "0.1.0"

__all__ = [
    "HeatSolver",
    "HeatcoreError",
    "HeatcoreWarning",
    "InvalidMeshError",
    "InvalidOptionError",
    "InvalidSourceError",
    "Operators",
    "PointCloud",
    "PolygonMesh",
    "SolverError",
    "TetMesh",
    "TriangleMesh",
    "geodesic_distance",
    "io",
    "linalg",
]


def geodesic_distance(
    V,
    F,
    sources=None,
    *,
    face_points=None,
    edges=None,
    faces=None,
    m=1.0,
    boundary="robin",
    robust=True,
    refine="auto",
    accuracy="smooth",
    weld=0.0,
):
    """Geodesic distance from sources on a triangle mesh, in one call.

    Parameters
    ----------
    V : (n, 3) array_like of float
    F : (m, 3) array_like of int
    sources : int or sequence of int, optional
        Source vertices.
    face_points : (face_indices, barycentric) pair, optional
        Source points on faces.
    edges : (k, 2) array_like of int, optional
        Source edges (distance to their union).
    faces : sequence of int, optional
        Source faces (distance to their union).
    m : float, default 1.0
        Time factor, ``t = m h^2``; larger is smoother.
    boundary : {"robin", "neumann", "dirichlet"}
    robust : bool, default True
        Intrinsic Delaunay operators (see :class:`TriangleMesh`).
    refine : "auto" or int
        Midpoint subdivision levels (see :class:`TriangleMesh`).
    accuracy : {"smooth", "high"}
        "high" adds an ordered eikonal pass (see :class:`HeatSolver`).
    weld : float or None, default 0.0
        Merge vertices closer than this (0: at exactly the same position;
        None: never), see :class:`TriangleMesh`.

    Returns
    -------
    (n,) float array; ``inf`` where unreachable.

    Examples
    --------
    >>> import numpy as np
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    >>> d = geodesic_distance(V, [[0, 1, 2]], [0])
    >>> bool(abs(d[1] - 1.0) < 0.02)
    True
    """
    mesh = TriangleMesh(V, F, robust=robust, refine=refine, weld=weld)
    solver = HeatSolver(mesh, m=m, boundary=boundary, accuracy=accuracy)
    return solver.distance(sources, face_points=face_points, edges=edges, faces=faces)
