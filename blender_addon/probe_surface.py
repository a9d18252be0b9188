"""The surface the probe's cursor moves on: the mesh as displayed, in world coordinates.

A ray from the 3D View hits the loop triangles of the mesh with the shape
the user sees (shape keys and deform modifiers applied, the object's world
matrix applied), through a ``mathutils`` BVH tree of those triangles; the
hit is a loop triangle (the heat solver's triangle, the same index in every
shape of the mesh) and barycentric coordinates in its corners
(``mathutils.interpolate.poly_3d_calc``). So a point found on the displayed
shape is the same surface point of the measured shape, whatever ``space``
and ``shape`` measure.

Building the tree takes 0.3 s at 65k vertices and 3.4 s at 1M; it is kept
in the cache of the solver's domain (under :data:`SURFACE_KEY`, dropped
with the solver and its domain) and reused while the displayed positions are
the same.

Examples
--------
>>> surface = DisplayedSurface.of(obj, run)                  # doctest: +SKIP
>>> surface.build_tree()                                     # doctest: +SKIP
>>> hit = surface.ray_cast((0, 0, 5), (0, 0, -1))            # doctest: +SKIP
>>> surface.point(hit.face, hit.barycentric)                 # doctest: +SKIP
array([0.01, 0.02, 0.99])
"""

from collections import namedtuple

import numpy as np
from mathutils import Vector, interpolate
from mathutils.bvhtree import BVHTree

from . import adapters
from .shape import measured_positions

#: Where a cached solver keeps its displayed surface: its domain's cache (``heatcore.domains.derived``).
SURFACE_KEY = ("displayed surface", None)

#: A ray's hit: the loop triangle, barycentric coordinates, world location and distance along the ray.
Hit = namedtuple("Hit", "face barycentric location depth")


def displayed_positions(obj, run):
    """The vertices of ``obj`` as displayed, in world coordinates (``run.V`` itself when it measures them)."""
    if (run.space, run.shape) == ("WORLD", "EVALUATED"):
        return run.V
    return measured_positions(obj, "WORLD", "EVALUATED")[0]


class DisplayedSurface:
    """The loop triangles of a mesh at its displayed world positions, with a ray-casting tree.

    Parameters
    ----------
    positions : (n, 3) float array
        World positions as displayed.
    triangles : (m, 3) int array
        The loop triangles (the solver's triangles).
    tree : mathutils.bvhtree.BVHTree, optional
        Made by :meth:`build_tree` when not given.
    """

    def __init__(self, positions, triangles, tree=None):
        self.positions = positions
        self.triangles = triangles
        self.tree = tree
        self.positions32 = positions.astype(np.float32)
        self.triangles32 = triangles.astype(np.uint32)

    @classmethod
    def of(cls, obj, run):
        """The displayed surface of ``obj`` for a :class:`~.stages.PreparedRun`: the one kept with its cached
        solver when the displayed positions are unchanged, else a new one (without a tree yet)."""
        positions = displayed_positions(obj, run)
        kept = run.solver.domain.derived.get(SURFACE_KEY) if run.solver is not None else None
        if kept is not None and np.array_equal(kept.positions, positions):
            return kept
        return cls(positions, adapters.mesh_arrays(obj.data)[1])

    def build_tree(self):
        """Make the ray-casting tree (any thread: no Blender data is read)."""
        if self.tree is None:
            self.tree = BVHTree.FromPolygons(self.positions.tolist(), self.triangles.tolist(), all_triangles=True)
        return self.tree

    def keep(self, solver):
        """Keep this surface beside ``solver`` (in its domain's cache) for the next probe on the same mesh."""
        solver.domain.derived[SURFACE_KEY] = self

    def ray_cast(self, origin, direction):
        """The first hit of a world-space ray, or None (also before the tree is built)."""
        if self.tree is None:
            return None
        location, _, face, depth = self.tree.ray_cast(Vector(origin), Vector(direction).normalized())
        if face is None:
            return None
        return Hit(face, self.barycentric(face, location), np.array(location), depth)

    def barycentric(self, face, location):
        """Barycentric coordinates of a world location in loop triangle ``face`` (clipped into it)."""
        corners = [Vector(p) for p in self.positions[self.triangles[face]]]
        w = np.clip(np.array(interpolate.poly_3d_calc(corners, Vector(location))), 0.0, None)
        return w / w.sum() if w.sum() > 0 else np.full(3, 1 / 3)

    def point(self, face, barycentric=None):
        """World position of a surface point ``(face, barycentric)``, or of vertex ``face`` (``barycentric`` None)."""
        if barycentric is None:
            return self.positions[face]
        return np.asarray(barycentric) @ self.positions[self.triangles[face]]
