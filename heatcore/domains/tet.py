"""Tetrahedral meshes: cotan Laplacian from dihedral angles, lumped mass, per-tet gradient.

The heat method runs unchanged inside a volume: :class:`TetMesh` hands
:class:`~heatcore.HeatSolver` the same operator bundle as a triangle mesh,
with 3-component gradients per tet, tet volumes as element measures and the
vertices of the boundary surface as the Dirichlet set (so the default Robin
boundary condition works as on surfaces with boundary).

Input repair, chosen so that the result stays well defined:

* tets with negative orientation are reoriented (two vertices swapped). The
  operators depend only on the metric (edge lengths, volumes), which is the
  same for both orientations, so this changes nothing but signs; the count is
  kept in ``TetMesh.n_reoriented``. Mixed orientations are common (SciPy's
  Delaunay simplices, for one, have no consistent orientation).
* tets with repeated vertices, duplicate tets and tets of (numerically) zero
  volume are dropped with a :class:`~heatcore.HeatcoreWarning`. A flat tet
  covers no volume, so the domain is unchanged; its cotan weights would be
  infinite. The boundary surface is computed before dropping flat tets, so
  an interior flat tet does not open a spurious boundary.
* vertices used by no (kept) tet, and pieces of the mesh that no source
  reaches, get ``inf``.

Examples
--------
>>> import numpy as np, heatcore as hc
>>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 1]], float)
>>> mesh = TetMesh(V, [[0, 1, 2, 3], [1, 2, 3, 4]])
>>> mesh.operators.dim, mesh.operators.volumes.round(3).tolist()
(3, [0.167, 0.333])
>>> d = hc.HeatSolver(mesh).distance([0])
>>> float(d[0]), bool(np.isfinite(d).all())
(0.0, True)
"""

import logging
import warnings

import numpy as np
import scipy.sparse as sp

from ..errors import HeatcoreWarning, InvalidMeshError, InvalidSourceError
from ..progress import Progress
from ..settings import MeshSettings
from .base import MeshDomain
from .sources import barycentric_array, index_list
from .tet_geometry import (
    FLAT_TET_TOLERANCE,
    TET_EDGES,
    boundary_faces,
    signed_volumes,
    tet_faces,
    tet_operators,
)
from .validate import clean_elements, index_array, vertex_array

log = logging.getLogger("heatcore")


class TetMesh(MeshDomain):
    """A tetrahedral mesh as a heat-method domain (distance inside a volume).

    Parameters
    ----------
    V : (n, 3) array_like of float
        Vertex positions.
    T : (m, 4) array_like of int
        Tets (vertex indices), either orientation. See the module docstring
        for what is repaired: reoriented tets, dropped flat, duplicate and
        repeated-vertex tets; unreferenced vertices get ``inf``.
    settings : MeshSettings or Settings, optional
        The mesh options, checked (:mod:`heatcore.settings`), as front ends
        hand them over; the keyword options below (checked here) change them.
        An option this domain does not take (:attr:`mesh_options`), given
        explicitly, is an :class:`~heatcore.InvalidOptionError`.
    pin_neighbors : bool, default True
        For a source vertex, also pin the vertices of its tets to their edge
        length from it, which is their exact distance (the edge lies in the
        mesh). This removes most of the underestimate that the Poisson step
        makes at the cone tip of a point source in 3D (measured on a cube:
        1.4% -> 1.0% mean relative error, see docs/tet.md) at the cost of one
        extra triangular solve per pinned vertex and query. ``False`` pins the
        source vertex alone (cheapest queries).
    progress : callable, optional
        ``progress(fraction, message)`` at the start of each stage (tets,
        boundary surface, operators), as :class:`~heatcore.TriangleMesh`
        reports (:mod:`heatcore.progress`).

    Attributes
    ----------
    vertices : (n, 3) float array
        The input vertices.
    tets : (m, 4) int array
        The input tets as given (validated, not reoriented).
    operators : Operators
        Operators on the referenced vertices (``vertex_map`` order).
    vertex_map : (n,) int array
        Operator vertex of each input vertex, ``-1`` where unreferenced.
    tet_map : (m,) int array
        Operator element of each input tet, ``-1`` where dropped.
    boundary_faces : (k, 3) int array
        The boundary surface (input vertex indices), wound outward.
    n_reoriented : int
        Tets that had negative orientation.
    n_flat : int
        Tets dropped for zero volume.
    pin_neighbors : bool
        See the parameter.

    Raises
    ------
    InvalidMeshError
        Wrong shapes, non-finite coordinates, out-of-range indices, or no tet
        with a volume.

    Examples
    --------
    >>> import numpy as np, heatcore as hc
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    >>> mesh = TetMesh(V, [[0, 2, 1, 3]])   # negative orientation: reoriented
    >>> mesh.n_reoriented, len(mesh.boundary_faces)
    (1, 4)
    >>> d = hc.HeatSolver(mesh).distance(points=([0], [[0.25, 0.25, 0.25, 0.25]]))
    >>> bool(np.allclose(d, np.linalg.norm(V - 0.25, axis=1)))
    True
    """

    element_name = "tet"
    domain_name = "tet mesh"
    source_kinds = ("vertices", "points", "region")

    #: The options of :class:`~heatcore.settings.MeshSettings` this domain takes: none.
    mesh_options = ()

    def __init__(self, V, T, settings=None, *, pin_neighbors=True, progress=None, **options):
        MeshSettings.of(settings, **options).refuse_untaken(self.mesh_options, self.domain_name)
        progress = Progress(progress)
        progress(0.0, "reading the tets")
        self.pin_neighbors = bool(pin_neighbors)
        self.vertices = vertex_array(V)
        if np.asarray(V).shape[1] != 3:
            raise InvalidMeshError(f"a tet mesh needs 3D vertices: V must have shape (n, 3), got {np.shape(V)}")
        T_arr = np.asarray(T) if not isinstance(T, np.ndarray) else T
        if getattr(T_arr, "ndim", 0) == 2 and T_arr.shape[1] == 3:
            raise InvalidMeshError(
                f"T must have shape (m, 4), got {T_arr.shape}: rows of 3 vertices are triangles "
                "(use TriangleMesh for a surface mesh)"
            )
        self.tets = index_array(T, self.vertices.shape[0], 4, element="tet", name="T")
        n = self.vertices.shape[0]

        kept = clean_elements(self.tets, element="tet")
        oriented = self.tets.copy()
        vol = signed_volumes(self.vertices, oriented)
        negative = vol < 0
        oriented[negative] = oriented[negative][:, [0, 1, 3, 2]]
        self.n_reoriented = int((negative & kept).sum())
        if self.n_reoriented:
            log.info("reoriented %d of %d tets with negative orientation", self.n_reoriented, kept.sum())

        # The boundary surface of the mesh as given (flat tets included).
        progress(0.2, "finding the boundary surface")
        self.boundary_faces, overshared = boundary_faces(oriented[kept])
        if overshared:
            warnings.warn(
                f"{overshared} faces are shared by more than two tets: the tets overlap there, "
                "and distances near them are unreliable",
                HeatcoreWarning,
                stacklevel=2,
            )

        P = self.vertices[oriented]
        lmax = np.linalg.norm(P[:, TET_EDGES[:, 0]] - P[:, TET_EDGES[:, 1]], axis=2).max(axis=1)
        flat = kept & (6.0 * np.abs(vol) <= FLAT_TET_TOLERANCE * lmax**3)
        self.n_flat = int(flat.sum())
        kept &= ~flat
        if not kept.any():
            raise InvalidMeshError(
                f"none of the {self.tets.shape[0]} tets has a volume (all are flat or repeat a vertex): "
                "are the vertices coplanar?"
            )
        used = np.unique(oriented[kept])
        if self.n_flat:
            lost = np.setdiff1d(np.unique(oriented[flat]), used).size
            warnings.warn(
                f"ignored {self.n_flat} tets of zero volume (flat)"
                + (f"; {lost} vertices used only by them get distance inf" if lost else ""),
                HeatcoreWarning,
                stacklevel=2,
            )
        self.vertex_map = np.full(n, -1, dtype=np.int64)
        self.vertex_map[used] = np.arange(used.size)
        self.tet_map = np.full(self.tets.shape[0], -1, dtype=np.int64)
        self.tet_map[kept] = np.arange(int(kept.sum()))
        boundary = np.zeros(used.size, dtype=bool)
        on_surface = self.vertex_map[self.boundary_faces.ravel()]
        boundary[on_surface[on_surface >= 0]] = True
        self._positions = self.vertices[used]
        self._incidence = None
        faces = self.vertex_map[self.boundary_faces]
        faces = faces[(faces >= 0).all(axis=1)]  # faces of flat tets' own vertices are no surface
        progress(0.4, "cotan Laplacian and gradients of the tets")
        self.operators = tet_operators(self._positions, self.vertex_map[oriented[kept]], boundary, faces)
        progress(1.0, "tet mesh ready")

    def _element_corners(self):
        kept = np.flatnonzero(self.tet_map >= 0)
        return np.repeat(kept, 4), self.tets[kept].ravel()

    def _element_sides(self, mark, elements=None):
        if elements is None:
            elements = mark[self.tets].any(axis=1) & (self.tet_map >= 0)
        tets = self.tets[elements]
        a, b = np.triu_indices(4, 1)
        return tets[:, a].ravel(), tets[:, b].ravel()

    def _point_elements(self):
        return self.tets

    def _pin_vertices(self, vertices, pins):
        """Source vertices, interior or on the boundary (distance 0); with ``pin_neighbors``, their tets' vertices too."""
        v = self._referenced(index_list(vertices, self.n_input_vertices, "vertex"))
        pins.add(v)
        if self.pin_neighbors:
            nv, nd = self._neighbor_pins(v)
            pins.add(nv, nd, (), ())

    def _pin_points(self, points, pins):
        """Points inside tets ``(tet_indices, barycentric (k, 4))``: the tet's vertices at their straight-line distance.

        The heat impulse is the barycentric weights.
        """
        try:
            ti, bary = points
        except (TypeError, ValueError) as exc:
            raise InvalidSourceError("points must be a pair (tet_indices, barycentric)") from exc
        ti = index_list(ti, self.tets.shape[0], "tet")
        b = barycentric_array(bary, ti.size, 4)
        corners = self.vertices[self.tets[ti]]  # (k, 4, 3)
        inside = np.einsum("kc,kcd->kd", b, corners)
        v = self._referenced(self.tets[ti].ravel())
        pins.add(v, np.linalg.norm(corners - inside[:, None, :], axis=2).ravel(), v, b.ravel())

    def _pin_region(self, triangles, pins):
        """Faces of the boundary surface, ``(k, 3)`` vertex triples (any order): distance 0 on their union."""
        f = np.asarray(triangles)
        if f.size and (f.ndim != 2 or f.shape[1] != 3):
            raise InvalidSourceError(f"region must have shape (k, 3) (boundary vertex triples), got {f.shape}")
        f = index_list(f.reshape(-1), self.n_input_vertices, "vertex").reshape(-1, 3)
        self._check_boundary_faces(f)
        pins.add(self._referenced(np.unique(f)))

    def _neighbor_pins(self, sources):
        """Vertices of the tets around operator vertices ``sources`` and their edge length from them."""
        ops = self.operators
        if self._incidence is None:
            T = ops.elements
            m = T.shape[0]
            self._incidence = sp.csr_matrix(
                (np.ones(T.size), (T.ravel(), np.repeat(np.arange(m), 4))), shape=(ops.n_vertices, m)
            )
        star = self._incidence[np.unique(sources)].tocoo()
        src = np.unique(sources)[star.row]
        around = ops.elements[star.col]  # (pairs, 4)
        dist = np.linalg.norm(self._positions[around] - self._positions[src][:, None, :], axis=2)
        return around.ravel(), dist.ravel()

    def _check_boundary_faces(self, f):
        missing = ~_rows_in(np.sort(f, axis=1), np.sort(self.boundary_faces, axis=1))
        if missing.any():
            bad = f[np.flatnonzero(missing)[0]]
            inside = _rows_in(np.sort(bad)[None, :], np.sort(tet_faces(self.tets), axis=1))[0]
            why = "an interior face (shared by two tets)" if inside else "not a face of any tet"
            raise InvalidSourceError(
                f"vertex triple {bad.tolist()} is not a boundary face of the tet mesh: it is {why}"
            )


def _rows_in(query, table):
    """Whether each row of ``query`` is a row of ``table`` (integer arrays of equal width)."""
    if table.shape[0] == 0:
        return np.zeros(query.shape[0], dtype=bool)
    _, inverse = np.unique(np.vstack([table, query]), axis=0, return_inverse=True)
    inverse = inverse.ravel()
    return np.isin(inverse[table.shape[0] :], inverse[: table.shape[0]])
