"""Reading and writing files: surfaces, tet meshes, polygon meshes, point clouds.

Every reader raises the core errors (:class:`~heatcore.InvalidMeshError`, ...),
never a front end's. :func:`read_domain` reads any file as the right domain.

Examples
--------
>>> import heatcore as hc
>>> V, F = hc.io.load_demo_mesh()
>>> V.shape[1], F.shape[1]
(3, 3)
"""

from .domain import DomainFile, read_domain
from .mesh import (
    MESHLAB_SELECTED_FLAG,
    SurfaceMesh,
    demo_mesh_path,
    load_demo_mesh,
    read_mesh,
    write_ply,
)
from .pointcloud import PointCloudFile, read_point_cloud
from .polygon import PolygonSurface, read_polygon_mesh
from .tet import read_tet_mesh, write_tet_distance

__all__ = [
    "MESHLAB_SELECTED_FLAG",
    "DomainFile",
    "PointCloudFile",
    "PolygonSurface",
    "SurfaceMesh",
    "demo_mesh_path",
    "load_demo_mesh",
    "read_domain",
    "read_mesh",
    "read_point_cloud",
    "read_polygon_mesh",
    "read_tet_mesh",
    "write_ply",
    "write_tet_distance",
]
