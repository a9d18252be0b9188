"""Prefactored heat solvers kept across clicks, one per mesh.

Building a :class:`heatcore.HeatSolver` (intrinsic Delaunay triangulation,
two sparse factorizations) is the expensive part of a click; a query with
new sources is cheap. The cache keeps the last solver of each mesh and reuses
it while the geometry and the solver options are unchanged. The geometry
itself is the key (:func:`geometry_key`): the arrays a solver was built from
are kept beside it and compared, value for value, with the next click's (a
few milliseconds at 500k vertices, where hashing them took tens), so every
geometry edit (moving, adding or removing vertices, changing faces, undo)
invalidates it, whatever made the edit.

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
>>> same_key(key, geometry_key(V, F, {"m": 1.0}, copy=False))   # doctest: +SKIP
True
"""

import atexit
from collections import OrderedDict

import numpy as np


def geometry_key(V, F, options, copy=True):
    """What a solver is built from: the options (as text) and the arrays; equal keys (:func:`same_key`) give equal solvers.

    ``F`` is an array or a tuple of arrays (the triangles, or what fixes
    them). ``copy=False`` keeps the arrays themselves: a key to look up with,
    or to keep when nothing will modify them.

    Examples
    --------
    >>> key = geometry_key(np.zeros((3, 3)), (np.arange(3),), {"m": 1.0})
    >>> same_key(key, geometry_key(np.zeros((3, 3)), (np.arange(3),), {"m": 1.0}, copy=False))
    True
    >>> same_key(key, geometry_key(np.zeros((3, 3)), (np.arange(3),), {"m": 2.0}))
    False
    """
    arrays = (V, *F) if isinstance(F, tuple) else (V, F)
    return repr(sorted(options.items())), tuple(np.array(a) if copy else np.asarray(a) for a in arrays)


def same_key(key, other):
    """Whether two keys of :func:`geometry_key` are equal: same options, arrays equal in dtype, shape and values.

    Examples
    --------
    >>> same_key(geometry_key([1.0], [0], {}), geometry_key([1.0, 2.0], [0], {}))
    False
    """
    return key[0] == other[0] and len(key[1]) == len(other[1]) and all(
        a.dtype == b.dtype and a.shape == b.shape and np.array_equal(a, b) for a, b in zip(key[1], other[1])
    )


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
        if entry is None or not same_key(entry[0], key):
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
            The geometry the solver is built on: positions, and the
            triangles or a tuple of arrays that fixes them.
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
        solver = self.lookup(mesh_id, geometry_key(V, F, options, copy=False))
        if solver is not None:
            return solver, True
        self.discard(mesh_id)  # free the stale solver before building
        key = geometry_key(V, F, options)  # copied before build() so that nothing can change it
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
