"""Read a file as a heat-method domain: triangle, polygon or tetrahedral mesh, or point cloud.

Used by the command line (and by anything that takes "a mesh file" without knowing its kind).
With ``kind="auto"``: volume formats holding tetrahedra become a :class:`~heatcore.TetMesh`,
point lists (``.xyz``, and PLY/OBJ files without faces) a
:class:`~heatcore.domains.pointcloud.PointCloud`, everything else a :class:`~heatcore.TriangleMesh`
(polygons triangulated by :mod:`heatcore.io.faces`, inside each polygon). ``kind="polygon"`` keeps the polygons for a
:class:`~heatcore.PolygonMesh` (needs potpourri3d to read OBJ files with texture coordinates).

Examples
--------
>>> from heatcore.io import demo_mesh_path
>>> f = read_domain(demo_mesh_path())
>>> f.kind, f.surface.shape[1]
('triangle', 3)
"""

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import InvalidMeshError, NoFacesError
from ..options import OPTIONS, check
from ..settings import MeshSettings

#: How a file may be read (the ``domain`` option of :mod:`heatcore.options`).
DOMAIN_KINDS = OPTIONS["domain"].choices
VOLUME_SUFFIXES = {".msh", ".vtu", ".vtk", ".mesh", ".node", ".ele"}
POINT_SUFFIXES = {".xyz", ".pts", ".txt"}


@dataclass
class DomainFile:
    """What a file holds, ready to become a domain.

    Attributes
    ----------
    kind : {"triangle", "polygon", "tet", "points"}
    vertices : (n, 3) float array
    surface : (m, 3) int array or None
        Triangles to draw and to write in a PLY (polygons triangulated by
        :mod:`heatcore.io.faces`, boundary faces of a tet mesh once built,
        None for points).
    cells : object
        Triangles, ``(offsets, indices)`` polygons, ``(m, 4)`` tets, or
        normals (or None) for points.
    selection : (k,) int array
        Vertices selected in a MeshLab PLY (empty when none).

    Examples
    --------
    >>> import numpy as np
    >>> f = DomainFile("triangle", np.eye(3), np.array([[0, 1, 2]]), np.array([[0, 1, 2]]))
    >>> type(f.domain(refine=0)).__name__, f.selected_vertices().tolist()
    ('TriangleMesh', [])
    """

    kind: str
    vertices: np.ndarray
    surface: object
    cells: object
    selection: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))

    def selected_vertices(self):
        """Vertices selected in the file (MeshLab PLY flags)."""
        return self.selection

    def domain(self, settings=None, *, progress=None, only_parts_of=None, **options):
        """Build the domain, with the mesh options its user set.

        Parameters
        ----------
        settings : MeshSettings or Settings, optional
            The run's mesh options as a front end hands them over
            (:mod:`heatcore.settings`); ``settings.given`` names those its
            user set.
        progress : callable, optional
            A :mod:`heatcore.progress` callback; every kind of domain reports
            its build stages to it.
        only_parts_of : sequence of int, optional
            Input vertices (a one-off query's sources): a triangle or polygon
            mesh builds only the connected parts that hold them (see
            :class:`~heatcore.domains.TriangleMesh`); tet meshes and point
            clouds build every part.
        **options
            Mesh options (``robust``, ``refine``, ``weld``; see
            :mod:`heatcore.options`) set here, checked once
            (:meth:`~heatcore.settings.MeshSettings.of`); with ``settings``,
            they change it.

        Each option given must be one the kind of domain takes (its class's
        ``mesh_options``: the domain refuses another); those not given take
        the front end's defaults.

        Raises
        ------
        InvalidOptionError
            An option the kind of domain does not take (``refine`` for a tet
            mesh, ``weld`` for a polygon mesh, ...): it would otherwise be dropped.

        Examples
        --------
        >>> import numpy as np
        >>> from heatcore.settings import Settings
        >>> f = DomainFile("points", np.eye(3), None, None)
        >>> type(f.domain(refine=0)).__name__, type(f.domain(Settings.of("cli", refine=0))).__name__
        ('PointCloud', 'PointCloud')
        >>> f.domain(weld=0.5)
        Traceback (most recent call last):
        ...
        heatcore.errors.InvalidOptionError: a point cloud does not take the option weld (it takes refine)
        """
        settings = MeshSettings.of(settings, **options)
        cls = _domain_class(self.kind)
        if self.kind == "triangle":
            return cls(self.vertices, self.cells, settings, progress=progress, only_parts_of=only_parts_of)
        if self.kind == "polygon":
            return cls(self.vertices, self.cells, settings, progress=progress, only_parts_of=only_parts_of)
        mesh = cls(self.vertices, self.cells, settings, progress=progress)
        if self.kind == "tet":
            self.surface = mesh.boundary_faces
        return mesh


def _domain_class(kind):
    """The domain class that a file of ``kind`` becomes (imported on use: domains sit above io)."""
    if kind == "triangle":
        from ..domains.triangle import TriangleMesh

        return TriangleMesh
    if kind == "polygon":
        from ..domains.polygon import PolygonMesh

        return PolygonMesh
    if kind == "tet":
        from ..domains.tet import TetMesh

        return TetMesh
    from ..domains.pointcloud import PointCloud

    return PointCloud


def read_domain(path, kind="auto"):
    """Read ``path`` as a domain of the given kind (see the module docstring).

    Parameters
    ----------
    path : str or path-like
    kind : {"auto", "triangle", "polygon", "tet", "points"}

    Returns
    -------
    DomainFile

    Raises
    ------
    InvalidOptionError
        An unknown ``kind``.
    InvalidMeshError
        A missing, empty or unreadable file (:class:`~heatcore.errors.NoFacesError`
        for a surface file without faces, with a kind other than "auto" or "points").

    Examples
    --------
    >>> import tempfile, pathlib
    >>> tmp = tempfile.TemporaryDirectory()
    >>> path = pathlib.Path(tmp.name) / "three.xyz"
    >>> _ = path.write_text("0 0 0\\n1 0 0\\n0 1 0\\n")
    >>> f = read_domain(path)
    >>> f.kind, f.vertices.shape, f.surface
    ('points', (3, 3), None)
    >>> tmp.cleanup()
    """
    kind = check("domain", kind)
    from .files import check_input_file

    path = Path(path)
    check_input_file(path)
    suffix = path.suffix.lower()
    if suffix == ".ply":  # every reader below hangs on a PLY header without end_header
        from .ply import read_header

        read_header(path)
    if kind == "tet" or (kind == "auto" and suffix in VOLUME_SUFFIXES):
        from .tet import read_tet_mesh

        try:
            V, T = read_tet_mesh(path)
            return DomainFile("tet", V, None, T)
        except InvalidMeshError:
            if kind == "tet":
                raise
    if kind == "points" or (kind == "auto" and suffix in POINT_SUFFIXES):
        return _points(path)
    if kind == "polygon":
        from .faces import triangulate_faces
        from .polygon import read_polygon_mesh

        poly = read_polygon_mesh(path)
        surface = triangulate_faces(poly.vertices, poly.offsets, poly.indices, f"cannot read mesh file {path}")
        return DomainFile("polygon", poly.vertices, surface, poly.polygons)
    from .mesh import read_mesh

    try:
        mesh = read_mesh(path)
    except NoFacesError:
        from .pointcloud import POINT_CLOUD_SUFFIXES

        if kind == "auto" and suffix in POINT_CLOUD_SUFFIXES:  # a file of vertices only: a point cloud
            return _points(path)
        raise
    return DomainFile("triangle", mesh.vertices, mesh.faces, mesh.faces, mesh.selected_vertices())


def _points(path):
    from .pointcloud import read_point_cloud

    cloud = read_point_cloud(path)
    return DomainFile("points", cloud.points, None, cloud.normals)
