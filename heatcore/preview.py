"""A coarse, fast preview of the distance on a large triangle mesh: what a drag shows until the mouse rests.

A query of a solver kept for a million vertices takes about half a second
(two triangular solves of that size); a drag moves the source every few
milliseconds. :class:`CoarsePreview` answers on a coarse copy of the mesh
instead: its vertices are clustered on a grid whose cells hold about
``n / vertices`` of them each (cells of one connected part only: separate
parts never merge), each cluster is one vertex at its members' mean, each
face joins the clusters of its corners (faces whose corners fall in fewer
than three clusters vanish), and a heat solver is built on that mesh
(``refine=0``). A query there costs a few milliseconds; each input vertex
reads its cluster's distance (a cluster whose faces all vanished, the nearest
cluster's). The answer is coarse (about one cell's size
off, a cluster's vertices share one value, and a fold thinner than a cell
may join its sides), which is why it is a preview: the exact field follows
when the mouse rests (Blender's probe, :mod:`blender_addon.probe`).

Examples
--------
>>> import numpy as np, heatcore as hc
>>> V, F = hc.io.load_demo_mesh()
>>> preview = CoarsePreview(hc.TriangleMesh(V, F, refine=0), vertices=500)
>>> d = preview.distance([0])
>>> preview.n_clusters < 700, bool(np.isfinite(d).all()), d.shape
(True, True, (2930,))
"""

import warnings

import numpy as np
from scipy.spatial import cKDTree

from .domains.parts import vertex_components
from .domains.polygon import polygon_arrays
from .domains.polygon_shape import area_vectors
from .domains.polygon_triangulate import covering_triangles
from .domains.sources import barycentric_array, index_list
from .domains.triangle import TriangleMesh
from .domains.validate import mesh_arrays, vertex_array
from .errors import HeatcoreWarning, UnsupportedDomainError
from .heat import HeatSolver

#: Clusters a preview aims at: a query on them takes about 15 ms (50k vertices, 2-core machine).
PREVIEW_VERTICES = 50_000


class CoarsePreview:
    """Approximate distances at every input vertex of a triangle mesh, from a coarse copy of it.

    Parameters
    ----------
    domain : TriangleMesh
        The mesh (its input vertices and kept faces; its refinement is not used).
    vertices : int, default PREVIEW_VERTICES
        About how many clusters (coarse vertices) to make.

    Attributes
    ----------
    solver : HeatSolver
        The coarse mesh's solver.
    n_clusters : int
    cluster : (n_input,) int array
        Each input vertex's cluster (-1 where no kept face uses it).
    triangles : (m, 3) int array
        The input's triangles (the domain's faces; :meth:`of_arrays`: its
        triangles, or those covering its polygons), which point sources name.

    Raises
    ------
    UnsupportedDomainError
        ``domain`` is not a :class:`~heatcore.TriangleMesh`.
    InvalidMeshError
        The coarse mesh has no area (a mesh too small or thin for ``vertices``).

    Examples
    --------
    >>> import heatcore as hc
    >>> V, F = hc.io.load_demo_mesh()
    >>> exact = hc.HeatSolver(hc.TriangleMesh(V, F, refine=0)).distance([0])
    >>> coarse = CoarsePreview(hc.TriangleMesh(V, F, refine=0), vertices=1000).distance([0])
    >>> bool(np.abs(coarse - exact).mean() < 0.03 * exact.max())
    True
    """

    def __init__(self, domain, vertices=PREVIEW_VERTICES):
        if not isinstance(domain, TriangleMesh):
            raise UnsupportedDomainError(f"a coarse preview is made of triangle meshes, not {type(domain).__name__}")
        compact = domain.vertex_map
        n = int(compact.max()) + 1
        X = np.zeros((n, 3))
        X[compact[compact >= 0]] = domain.vertices[compact >= 0]
        faces = compact[domain.faces[domain.face_map >= 0]]
        self._build(X, faces, None, compact, vertices)
        self.triangles = domain.faces

    @classmethod
    def of_arrays(cls, V, faces, vertices=PREVIEW_VERTICES, only_parts_of=None):
        """A preview straight from vertex and face arrays, with no domain built first.

        What a first click shows while the mesh's own solver builds (Blender's
        button, :mod:`blender_addon.preview`): the domain's build (intrinsic
        triangulation, checks, welding) is the part of the first answer it
        does not wait for. Faces are taken as given (no cleanup: a degenerate
        face vanishes in the clustering anyway).

        Parameters
        ----------
        V : (n, 3) array_like of float
        faces : (m, 3) array_like of int, or (offsets, indices)
            Triangles, or polygons as a tuple of two 1-D arrays as
            :class:`~heatcore.PolygonMesh` takes them, split into triangles
            that cover them (:func:`~heatcore.domains.polygon_triangulate.covering_triangles`:
            a polygon's fan where it covers it, else its triangulation). A
            point source's face is one of :attr:`triangles`.
        vertices : int, default PREVIEW_VERTICES
            About how many clusters to make.
        only_parts_of : array_like of int, optional
            Vertices: only the connected parts they are on are previewed
            (elsewhere ``inf``), as ``TriangleMesh(..., only_parts_of=)`` builds.

        Raises
        ------
        InvalidMeshError
            Bad arrays (:func:`~heatcore.domains.validate.mesh_arrays`), or no
            area left in the coarse mesh.

        Examples
        --------
        >>> import heatcore as hc
        >>> V, F = hc.io.load_demo_mesh()
        >>> preview = CoarsePreview.of_arrays(V, F, vertices=500, only_parts_of=[0])
        >>> bool(np.isfinite(preview.distance([0])).all())
        True
        """
        self = cls.__new__(cls)
        if isinstance(faces, tuple) and len(faces) == 2 and all(isinstance(a, np.ndarray) and a.ndim == 1 for a in faces):
            V = vertex_array(V)
            faces = covering_triangles(V, *polygon_arrays(faces, len(V)))
        V, F = mesh_arrays(V, faces)
        _, part = vertex_components(F, len(V))
        kept = F
        if only_parts_of is not None:
            sources = index_list(only_parts_of, len(V), "vertex")
            kept = F[np.isin(part[F[:, 0]], part[sources])]
        used = np.zeros(len(V), dtype=bool)
        used[kept.ravel()] = True
        compact = np.full(len(V), -1, dtype=np.int64)
        compact[used] = np.arange(np.count_nonzero(used))
        self._build(V[used], compact[kept], part[used], compact, vertices)
        self.triangles = F  # the input's triangles (or its polygons'): a point's face index is one of these
        return self

    def _build(self, X, faces, part, compact, vertices):
        """Cluster the compact mesh ``X``, ``faces`` (parts ``part``, or None to find them) and build the coarse solver;
        ``compact`` maps each input vertex to its row of ``X`` (-1: unused)."""
        self.n_input = compact.size
        cluster_of, C = _clusters(X, faces, vertices, part)
        coarse = cluster_of[faces]
        coarse = coarse[(coarse[:, 0] != coarse[:, 1]) & (coarse[:, 1] != coarse[:, 2]) & (coarse[:, 2] != coarse[:, 0])]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", HeatcoreWarning)  # duplicate faces of merged clusters: expected
            mesh = TriangleMesh(C, coarse, refine=0, weld=None)
        self.solver = HeatSolver(mesh, intent="interactive")
        self.n_clusters = len(C)
        cluster_of = _on_faces(cluster_of, C, mesh.vertex_map >= 0)
        self.cluster = np.where(compact >= 0, cluster_of[np.maximum(compact, 0)], -1)

    def distance(self, vertices=None, *, points=None):
        """Coarse distances at the input vertices from source vertices and points ``(faces, barycentric)``.

        A point counts as the corner of its face it is nearest to (largest
        barycentric coordinate). ``inf`` where unreachable.
        """
        sources = [np.zeros(0, dtype=np.int64)]
        if vertices is not None:
            sources.append(index_list(vertices, self.n_input, "vertex"))
        if points is not None:
            fi, bary = points
            fi = index_list(fi, len(self.triangles), "face")
            b = barycentric_array(bary, fi.size, 3)
            sources.append(self.triangles[fi, b.argmax(axis=1)])
        clusters = self.cluster[np.concatenate(sources)]
        d = self.solver.distance(np.unique(clusters[clusters >= 0]))
        return np.where(self.cluster >= 0, d[np.maximum(self.cluster, 0)], np.inf)


def _on_faces(cluster_of, C, used):
    """``cluster_of`` with each cluster that no coarse face kept (all its faces vanished) replaced by the nearest kept one."""
    if used.all():
        return cluster_of
    kept = np.flatnonzero(used)
    nearest = kept[cKDTree(C[kept]).query(C[~used])[1]]
    moved = np.arange(len(C))
    moved[~used] = nearest
    return moved[cluster_of]


def _clusters(X, faces, target, part=None):
    """Each vertex's cluster (grid cells of one part: ``part``, or the faces' connected parts) and the clusters' mean positions."""
    if part is None:
        _, part = vertex_components(faces, len(X))
    nx, ny, nz = area_vectors(X, faces)
    area = 0.5 * np.sqrt(nx**2 + ny**2 + nz**2).sum()
    cell = np.sqrt(area / max(int(target), 1)) or 1.0
    cells = np.floor((X - X.min(axis=0)) / cell).astype(np.int64)
    dims = cells.max(axis=0) + 1
    if float(part.max() + 1) * float(np.prod(dims, dtype=float)) < 2.0**62:  # one integer key per cell
        key = ((part * dims[0] + cells[:, 0]) * dims[1] + cells[:, 1]) * dims[2] + cells[:, 2]
        _, cluster_of = np.unique(key, return_inverse=True)
    else:
        _, cluster_of = np.unique(np.column_stack([part, cells]), axis=0, return_inverse=True)
    cluster_of = cluster_of.ravel()
    count = np.bincount(cluster_of)
    C = np.column_stack([np.bincount(cluster_of, weights=X[:, k]) / count for k in range(3)])
    return cluster_of, C
