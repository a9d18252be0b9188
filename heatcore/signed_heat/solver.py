"""``SignedHeatSolver``: signed distance to curves on a surface, by the signed heat method (Feng and Crane 2024).

The method ("A Heat Method for Generalized Signed Distance", ACM TOG 2024):

0. on a refined mesh, move the refined vertices onto curved triangles
   (:mod:`heatcore.signed_heat.surface`): the operators below live there;
1. start the vector heat flow with the curves' normals, pointing to their left
   (:mod:`heatcore.signed_heat.curves`), and diffuse for the heat method's
   time ``t = m h^2``, ``t/2`` where a signed curve is open:
   ``(M + t L∇) Y = Y0`` (the vector heat method's factor);
2. read ``Y`` on each triangle and scale it to length 1
   (:mod:`heatcore.signed_heat.face_field`);
3. integrate: ``L phi = G^T (volumes * X)``, with the curves as level sets
   (:mod:`heatcore.signed_heat.level_sets`), and shift the curves to 0.

Where the curves bound a region the result is the signed distance, positive
on their left; broken, open or crossing curves give a smooth generalization
(the field is what their normals, diffused, agree on). Every operator is the
surface's: the vector heat factor and the heat method's grounded Poisson factor.

Examples
--------
>>> import numpy as np, heatcore as hc
>>> V, F = hc.io.load_demo_mesh()
>>> solver = hc.SignedHeatSolver(hc.TriangleMesh(V, F))
>>> loop = [int(v) for v in hc.region_boundary_curves(F, range(200))[0]]
>>> phi = solver.distance([loop])
>>> phi.shape, bool(np.isfinite(phi).all())
((2930,), True)
"""

import warnings

import numpy as np

from ..domains.pointcloud import PointCloud
from ..domains.polygon import PolygonMesh
from ..domains.polygon_triangulate import triangulate_polygons
from ..domains.triangle import TriangleMesh
from ..errors import (
    HeatcoreWarning,
    InvalidOptionError,
    InvalidSourceError,
    UnsupportedDomainError,
)
from ..settings import SolverSettings
from .curves import away_source, parse_curve, signed_source
from .fields import OPEN_CURVE_TIME, CloudField, MeshField
from .level_sets import LEVEL_SETS, constrained_poisson, constraint_rows
from .normals import flow_keeping_normals

#: Whose defaults fill the options not given, and which it offers (``heatcore.settings``: no ``accuracy``).
FRONT_END = "signed heat"


class SignedHeatSolver:
    """Prefactored signed heat method on a triangle or polygon mesh.

    Parameters
    ----------
    domain : TriangleMesh, PolygonMesh or PointCloud
        A polygon mesh is measured on heatcore's triangulation of its
        polygons (``triangulate_polygons``), refined as the domain was asked
        to be; curves on it, and on a point cloud, are given by vertex (point)
        indices. A point cloud's normals are oriented first
        (:meth:`~heatcore.PointCloud.oriented_normals`): given normals keep
        their signs, and the left of a curve is seen along them.
    settings : SolverSettings or Settings, optional
        As for :class:`~heatcore.HeatSolver`.
    m : float, default 1.0
        Time factor, ``t = m h^2`` for the vector and the scalar flows
        (the vector flow runs for ``t/2`` in a query with an open signed
        curve: ``heatcore.signed_heat.fields.OPEN_CURVE_TIME``).
    accuracy : {"smooth"}
        "high" is refused: the eikonal pass's distance to a curve's points
        was 23-144 times further from the analytic distance than the signed
        heat method's own (a circle on a disc, the equator of two spheres;
        docs/signed.md), so it would not sharpen anything.
    boundary, backend
        As in :class:`~heatcore.HeatSolver`.

    Attributes
    ----------
    field : MeshField or CloudField
        Where the vectors live (:mod:`heatcore.signed_heat.fields`): on a
        mesh, the vector heat method's frames and factor on its ``surface``
        (the domain itself where it is flat or not refined, when they are
        shared with any :class:`~heatcore.VectorHeatSolver` of the domain),
        and the Poisson factor that integrates the field (``poisson_solver``).
    distance_solver : HeatSolver
        The heat method on the domain as given: it measures unsigned
        sources (built at first use where it is not the field's).
    timings : dict

    Raises
    ------
    UnsupportedDomainError
        Point clouds and tet meshes.

    Examples
    --------
    >>> import numpy as np, heatcore as hc
    >>> V = np.array([[x, y, 0.0] for y in range(5) for x in range(5)])
    >>> F = np.array([[i, i + 1, i + 6] for i in range(20) if i % 5 < 4] + [[i, i + 6, i + 5] for i in range(20) if i % 5 < 4])
    >>> solver = SignedHeatSolver(hc.TriangleMesh(V, F, refine=0))
    >>> phi = solver.distance([[10, 11, 12, 13, 14]])   # along the row y = 2, eastwards: north is on the left
    >>> phi.reshape(5, 5)[:, 2].round(3).tolist()
    [-2.0, -1.0, 0.0, 1.0, 2.0]
    """

    def __init__(self, domain, settings=None, **options):
        settings = SolverSettings(FRONT_END, **options) if settings is None else SolverSettings.of(settings, **options)
        if settings.accuracy == "high":
            raise InvalidOptionError(
                'the signed heat method has no accuracy="high": its own distance is already 23-144 times closer to '
                "exact than the eikonal pass from the curve's points (docs/signed.md); use the default"
            )
        if settings.accuracy == "auto":  # the Python API's default, from its settings: never the march here
            settings = settings.replace(accuracy="smooth")
        self._vertices_only = isinstance(domain, (PolygonMesh, PointCloud))
        if isinstance(domain, PolygonMesh):
            domain = _triangulated(domain)
        if isinstance(domain, TriangleMesh):
            self.field = MeshField(domain, settings)
        elif isinstance(domain, PointCloud):
            self.field = CloudField(domain, settings)
        else:
            raise UnsupportedDomainError(
                f"the signed heat method runs on triangle and polygon meshes and point clouds, not on a "
                f"{domain.domain_name}"
            )
        self.domain = domain
        self.settings = settings
        self.timings = dict(self.field.timings)

    @property
    def distance_solver(self):
        """The heat method on the domain as given: it measures unsigned sources."""
        return self.field.distance_solver

    def distance(self, curves, signed=True, *, points=None, level_set="zero", keep_normals=False):
        """Signed distance from the curves (and unsigned distance from ``points``) at every input vertex.

        Parameters
        ----------
        curves : sequence of curves
            Each an ordered sequence of surface points: vertex indices, or
            ``(face, (b0, b1, b2))`` points on input faces; a closed curve
            repeats its first point at the end.
        signed : bool or sequence of bool, default True
            Per curve (or for all): oriented (positive on its left, looking
            along the surface normal) or not (a distance positive on both sides).
        points : sequence of surface points, optional
            Isolated points: unsigned distance from them too.
        level_set : {"zero", "multiple", "none"}, default "zero"
            How the curves fix the result's constant: all on the zero set,
            each on a level set of its own, or not at all (then shifted so that
            their mean is 0); see :mod:`heatcore.signed_heat.level_sets`.
        keep_normals : bool, default False
            Keep the flow at the curves normal to them (the paper's "preserve
            source normals": a constrained flow, one solve per curve point more).

        Returns
        -------
        (n,) float array
            At each input vertex; ``inf`` in connected parts no curve reaches
            and at vertices no face uses.

        Raises
        ------
        InvalidSourceError
            No curve and no point, a curve of fewer than two points, a bad index or coordinates.
        InvalidOptionError
            An unknown ``level_set``, a ``signed`` list of the wrong length.
        """
        parsed, is_signed = self._parse(curves, signed, points)
        if level_set not in LEVEL_SETS:
            raise InvalidOptionError(f"level_set must be one of {', '.join(LEVEL_SETS)}, got {level_set!r}")
        if not any(is_signed):
            return self._unsigned(parsed)
        field, ops, hs = self.field, self.field.surface.operators, self.field.poisson_solver
        nodes = field.nodes(parsed)
        n = ops.n_vertices
        rhs = np.zeros(n, dtype=complex)
        h = float(np.mean(ops.mean_edge_length))
        check_segments(nodes, is_signed, h * 2 ** getattr(self.domain, "levels", 0))
        for c, s in enumerate(is_signed):
            if s:
                signed_source(nodes, rhs, c, field.operator_basis)
            else:
                away_source(nodes, rhs, c, field.operator_basis, field.positions, ops.laplacian, h)
        time_scale = OPEN_CURVE_TIME if any(s and not c.closed for c, s in zip(parsed, is_signed)) else 1.0
        if keep_normals:
            Y = flow_keeping_normals(field, rhs, nodes, is_signed, time_scale)
        else:
            Y = field.diffuse(rhs, time_scale)
        b = field.divergence(Y)
        C = constraint_rows(nodes.carriers, n)
        groups = np.zeros(nodes.curve.size, dtype=np.int64) if level_set != "multiple" else nodes.curve
        phi = hs.poisson.solve_grounded(b.copy()) if level_set == "none" else constrained_poisson(hs.poisson, b, C, groups)
        return self._on_input(np.ldexp(self._shifted(phi, C, nodes), ops.unit_exponent))

    def _parse(self, curves, signed, points):
        try:
            curve_list = list(curves) if curves is not None else []
        except TypeError:
            raise InvalidSourceError("curves must be a list of curves (each a sequence of surface points)") from None
        parsed = [parse_curve(c, f"curve {i}") for i, c in enumerate(curve_list)]
        if self._vertices_only and not all(c.kinds.all() for c in parsed):
            raise InvalidSourceError("on a polygon mesh or a point cloud, a curve is a sequence of vertex indices")
        flags = [bool(signed)] * len(parsed) if np.ndim(signed) == 0 else [bool(s) for s in signed]
        if len(flags) != len(parsed):
            raise InvalidOptionError(f"signed: {len(flags)} flags for {len(parsed)} curves")
        for i, p in enumerate(list(points) if points is not None else []):
            single = parse_curve([p, p], f"point {i}")
            parsed.append(single._replace(**{k: getattr(single, k)[:1] for k in single._fields}))
            flags.append(False)
        if not parsed:
            raise InvalidSourceError("no source given: pass at least one curve or one point")
        return parsed, flags

    def _shifted(self, phi, C, nodes):
        """``phi`` minus the mean of its values at the curve points of each part; ``inf`` in parts with none."""
        hs = self.field.poisson_solver
        at_points = C @ phi
        weight = _node_weights(nodes)
        part_of_point = hs.component[np.array([v[np.argmax(w)] for v, w in nodes.carriers])]
        total = np.bincount(part_of_point, weights=weight, minlength=hs.n_components)
        mean = np.bincount(part_of_point, weights=weight * at_points, minlength=hs.n_components)
        reached = total > 0
        shift = np.where(reached, mean / np.where(reached, total, 1.0), 0.0)
        out = phi - shift[hs.component]
        out[~reached[hs.component]] = np.inf
        return out

    def _unsigned(self, parsed):
        """The heat method's distance to unsigned curves and points only: their vertices, edges and face points.

        Measured on spot (two vertices; a loop of edges around 200 faces): 0.85% and 1.9% from exact, where the
        signed heat method's vectors pointing away from them gave 8.2% and 8.3% (potpourri3d's: 5.4% and 25.6%).
        """
        vertices = np.concatenate([c.vertices[c.kinds] for c in parsed])
        faces = np.concatenate([c.faces[~c.kinds] for c in parsed])
        bary = np.concatenate([c.barycentric[~c.kinds] for c in parsed])
        edges = np.concatenate([np.column_stack([c.vertices[:-1], c.vertices[1:]])[c.kinds[:-1] & c.kinds[1:]]
                                for c in parsed])
        kinds = {"points": (faces, bary)} if faces.size else {}
        if "edges" in self.domain.source_kinds and (edges[:, 0] != edges[:, 1]).any():
            kinds["edges"] = edges[edges[:, 0] != edges[:, 1]]
        return self.distance_solver.distance(vertices if vertices.size else None, **kinds)

    def _on_input(self, values):
        index = self.domain.output_vertices
        out = np.full(index.size, np.inf)
        out[index >= 0] = values[index[index >= 0]]
        return out


#: A segment longer than this many mean edge lengths (of the mesh as given) is a chord through space, not a
#: curve on the surface: warned about.
LONG_SEGMENT_EDGES = 4.0


def check_segments(nodes, is_signed, edge_length):
    """Refuse a signed curve of no length; warn about segments much longer than the mesh's edges.

    Examples
    --------
    >>> from heatcore.signed_heat.curves import CurveNodes
    >>> one = (np.array([0]), np.ones(1))
    >>> nodes = CurveNodes([one, one], np.zeros((2, 3)), np.zeros((2, 3)), np.zeros(2, int))
    >>> check_segments(nodes, [True], 1.0)
    Traceback (most recent call last):
    ...
    heatcore.errors.InvalidSourceError: curve 0 has no length (its points are all at one place): it has no sides
    """
    same = nodes.curve[1:] == nodes.curve[:-1]
    length = np.linalg.norm(np.diff(nodes.positions, axis=0), axis=1) * same
    total = np.bincount(nodes.curve[1:], weights=length, minlength=len(is_signed))
    for c, signed in enumerate(is_signed):
        if signed and not total[c] > 0:
            raise InvalidSourceError(f"curve {c} has no length (its points are all at one place): it has no sides")
    long = np.flatnonzero(length > LONG_SEGMENT_EDGES * edge_length)
    if long.size:
        warnings.warn(f"{long.size} curve segment(s) span more than {LONG_SEGMENT_EDGES:g} edge lengths (the longest "
                      f"{length.max() / edge_length:.0f}): a segment is the straight chord between its points, so "
                      "give points along the surface, one per edge or face crossed (a geodesic path between them, "
                      "say)", HeatcoreWarning, stacklevel=3)


def _node_weights(nodes):
    """Each curve point's share of its curve's length (half of each segment at each end); 1 for a lone point."""
    weight = np.zeros(nodes.curve.size)
    same = nodes.curve[1:] == nodes.curve[:-1]
    length = np.linalg.norm(np.diff(nodes.positions, axis=0), axis=1) * same
    weight[1:] += 0.5 * length
    weight[:-1] += 0.5 * length
    lone = weight == 0
    weight[lone] = 1.0
    return weight


def _triangulated(domain):
    """The :class:`TriangleMesh` of heatcore's triangulation of a polygon mesh's polygons, refined alike."""
    faces, _ = triangulate_polygons(domain.vertices, domain.offsets, domain.indices)
    return TriangleMesh(domain.vertices, faces, domain.mesh_settings)
