"""Point clouds: heat-method operators from local tangent-plane Delaunay triangles.

A point cloud has no connectivity, so the operators are built on a triangle
set that the points propose themselves, following the point-cloud Laplacian
of Sharp and Crane ("A Laplacian for Nonmanifold Triangle Meshes", SGP 2020,
section 5), one module per step:

1. :mod:`~heatcore.domains.pointcloud.neighborhoods`: duplicates merged; the
   ``k`` nearest neighbors of each point (a KD-tree), without neighbors much
   farther than the local spacing (so that separate clusters and stray points
   stay separate); tangent planes by PCA of each neighborhood, unless normals
   are given;
2. :mod:`~heatcore.domains.pointcloud.local_delaunay`: neighbors far off the
   tangent plane (slope above ``MAX_SLOPE``: the other side of a thin part)
   are left out, the others are projected onto the tangent plane and the
   point's 1-ring in the planar Delaunay triangulation of its neighborhood is
   kept (computed for all points at once: a neighbor ``q`` of the point ``p``
   at the origin is a Delaunay neighbor exactly when its inversion
   ``q / |q|^2`` is a vertex of the convex hull of the inverted neighbors and
   the origin);
3. :mod:`~heatcore.domains.pointcloud.tufted`: the union of all proposed
   triangles (each kept once, edge lengths = 3D distances), midpoint-subdivided
   on coarse clouds like a triangle mesh, is doubled into its tufted cover
   (each triangle as two sheets, glued around every edge in angular order, so
   that non-manifold and inconsistently oriented triangles form one manifold);
4. :mod:`~heatcore.domains.pointcloud.cloud`: :class:`PointCloud` ties the
   steps together; the cover is mollified and flipped to intrinsic Delaunay,
   and the cotan Laplacian, lumped mass, per-triangle gradients and divergence
   all come from the same intrinsic triangles, by the same build as a triangle
   mesh's (:func:`heatcore.domains.cotan.intrinsic_operators`).

Gradient and divergence are therefore consistent with the Laplacian
(``L = G^T diag(A) G``). This differs from the construction the reference
report describes (a Voronoi-area mass with a separate point-cloud Laplacian,
and weighted-least-squares gradients on moving-least-squares tangent planes),
where the three operators are built independently.

Examples
--------
>>> import numpy as np
>>> import heatcore as hc
>>> rng = np.random.default_rng(0)
>>> P = np.column_stack([rng.random((400, 2)), np.zeros(400)])
>>> cloud = PointCloud(P, k=16)
>>> d = hc.HeatSolver(cloud).distance([0])
>>> bool(np.all(np.isfinite(d)))
True
"""

from .cloud import DEFAULT_K, MAX_K, MIN_K, PointCloud
from .local_delaunay import MAX_SLOPE, MIN_SINE, local_delaunay_triangles
from .neighborhoods import (
    DUPLICATE_TOLERANCE,
    MAX_NEIGHBOR_RATIO,
    SPACING_RANK,
    merge_duplicates,
    nearest_neighbors,
    pca_normals,
)
from .tufted import tufted_cover

__all__ = [
    "DEFAULT_K",
    "DUPLICATE_TOLERANCE",
    "MAX_K",
    "MAX_NEIGHBOR_RATIO",
    "MAX_SLOPE",
    "MIN_K",
    "MIN_SINE",
    "SPACING_RANK",
    "PointCloud",
    "local_delaunay_triangles",
    "merge_duplicates",
    "nearest_neighbors",
    "pca_normals",
    "tufted_cover",
]
