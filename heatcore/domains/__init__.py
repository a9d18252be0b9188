"""Domains: what the heat method runs on. Each supplies its operators and its source pins.

A domain turns geometry (a triangle mesh, a polygon mesh, a tet mesh, a point
cloud) into an :class:`~heatcore.domains.operators.Operators` bundle and builds
:class:`~heatcore.domains.sources.SourcePins` for the sources a user names. Domains
never import the solver, the file readers or the factorization backends.

Examples
--------
>>> import numpy as np
>>> from heatcore.domains import TriangleMesh
>>> mesh = TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0)
>>> mesh.operators.laplacian.shape
(3, 3)
"""

from .operators import Operators
from .pointcloud import PointCloud
from .polygon import PolygonMesh
from .tet import TetMesh
from .triangle import TriangleMesh

__all__ = ["Operators", "PointCloud", "PolygonMesh", "TetMesh", "TriangleMesh"]
