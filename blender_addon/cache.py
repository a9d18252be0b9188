"""Prefactored heat solvers kept across clicks, one per mesh.

Building a :class:`heatcore.HeatSolver` (intrinsic Delaunay triangulation,
two sparse factorizations) is the expensive part of a click; a query with
new sources is cheap. The cache keeps the last solver of each mesh and reuses
it while the geometry and the solver options are unchanged. The key is a hash
of the vertex positions and triangles themselves, so every geometry edit
(moving, adding or removing vertices, changing faces, undo) invalidates it,
whatever made the edit.

The cache is used from the main thread only: a solver built in a background
thread is stored when the main thread takes the result (``store``); a build
that is cancelled or fails stores nothing, and the mesh's stale solver was
dropped before it began (``discard``), so no half-built or stale solver stays.

Examples
--------
>>> cache = SolverCache()
>>> solver, hit = cache.get(mesh_id, V, F, {"m": 1.0}, build)   # doctest: +SKIP
>>> key = geometry_key(V, F, {"m": 1.0})                        # doctest: +SKIP
>>> cache.lookup(mesh_id, key) is solver                        # doctest: +SKIP
"""

import atexit
import hashlib
from collections import OrderedDict

import numpy as np


def geometry_key(V, F, options):
    """Hash of the geometry and the solver options: equal keys give equal solvers."""
    h = hashlib.blake2b(digest_size=16)
    for array in (V, F):
        a = np.ascontiguousarray(array)
        h.update(repr((a.dtype.str, a.shape)).encode())
        h.update(a.data)
    h.update(repr(sorted(options.items())).encode())
    return h.hexdigest()


class SolverCache:
    """Least-recently-used cache of heat solvers, at most one per mesh.

    Parameters
    ----------
    max_meshes : int
        Meshes whose solver is kept (each costs memory of the order of its
        sparse factorizations).
    """

    def __init__(self, max_meshes=4):
        self.max_meshes = max_meshes
        self._entries = OrderedDict()  # mesh id -> (key, solver)

    def lookup(self, mesh_id, key):
        """The solver cached for ``mesh_id`` under ``key`` (then the most recently used), or None."""
        entry = self._entries.get(mesh_id)
        if entry is None or entry[0] != key:
            return None
        self._entries.move_to_end(mesh_id)
        return entry[1]

    def store(self, mesh_id, key, solver):
        """Keep ``solver`` as the mesh's solver for ``key`` (replacing its previous one), dropping the oldest mesh's if full."""
        self._entries.pop(mesh_id, None)
        self._entries[mesh_id] = (key, solver)
        while len(self._entries) > self.max_meshes:
            self._entries.popitem(last=False)

    def discard(self, mesh_id):
        """Drop the mesh's solver (stale: free its memory before a new one is built)."""
        self._entries.pop(mesh_id, None)

    def get(self, mesh_id, V, F, options, build):
        """The solver for this geometry and options: cached, or made by ``build()`` and kept.

        Parameters
        ----------
        mesh_id : hashable
            Identity of the mesh datablock (its ``session_uid``).
        V, F : arrays
            The geometry the solver is built on.
        options : dict
            Every option that changes the solver.
        build : callable
            Makes the solver when the cache has none for this key. If it
            raises (a cancelled build, say), nothing is kept for the mesh.

        Returns
        -------
        (solver, cached)
            ``cached`` is True when the solver was reused.
        """
        key = geometry_key(V, F, options)
        solver = self.lookup(mesh_id, key)
        if solver is not None:
            return solver, True
        self.discard(mesh_id)  # free the stale solver before building
        solver = build()
        self.store(mesh_id, key, solver)
        return solver, False

    def __contains__(self, mesh_id):
        return mesh_id in self._entries

    def clear(self):
        """Drop every cached solver."""
        self._entries.clear()

    def __len__(self):
        return len(self._entries)


#: The add-on's cache, shared by the operator and the script API.
SOLVERS = SolverCache()
# Free the factorizations before interpreter teardown (native objects left to
# the final garbage collection make nanobind print leak warnings).
atexit.register(SOLVERS.clear)
