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

Moving the object is no edit. In World space the arrays are the object's
own coordinates and the key also holds the world matrix (the *frame*), of
which only its metric counts (``A^T A``, ``A`` its 3x3 part, up to a
factor: :func:`similar_frames`): a translation, a rotation or a mirror
(of the object or of a parent) keeps the key, and so does a uniform scale,
which scales every length the solver gives (:class:`Placement`: the
solver's coordinates mapped to the run's, its distances scaled); a
non-uniform scale or a shear changes the geodesics and the key.

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
import dataclasses
from collections import OrderedDict, namedtuple

import numpy as np

#: Frames whose metrics (normalized by their mean) differ by at most this are similar: world matrices are
#: float32, which holds a rotation's ``A^T A = I`` to about 1e-7 (parents' products included).
FRAME_TOLERANCE = 1e-6


def geometry_key(V, F, options, copy=True, frame=None, rescale=True):
    """What a solver is built from: the options (as text), the arrays and their frame; equal keys
    (:func:`same_key`) give equal solvers, up to where the frame puts them.

    ``F`` is an array or a tuple of arrays (the triangles, or what fixes
    them). ``copy=False`` keeps the arrays themselves: a key to look up with,
    or to keep when nothing will modify them. ``frame``: the 4x4 matrix that
    places ``V`` where it is measured (World space: the object's world
    matrix), kept as a copy; None: ``V`` is measured as it is. ``rescale``:
    a uniform scale of the frame keeps the key (False where an option is a
    length, such as a weld tolerance: then only rigid motions keep it).

    Examples
    --------
    >>> key = geometry_key(np.zeros((3, 3)), (np.arange(3),), {"m": 1.0})
    >>> same_key(key, geometry_key(np.zeros((3, 3)), (np.arange(3),), {"m": 1.0}, copy=False))
    True
    >>> same_key(key, geometry_key(np.zeros((3, 3)), (np.arange(3),), {"m": 2.0}))
    False
    >>> turned = geometry_key([1.0], [0], {}, frame=[[0, -2, 0, 5], [2, 0, 0, 0], [0, 0, 2, 0], [0, 0, 0, 1]])
    >>> same_key(geometry_key([1.0], [0], {}, frame=np.eye(4)), turned)   # turned by 90 degrees, moved, scaled 2x
    True
    """
    arrays = (V, *F) if isinstance(F, tuple) else (V, F)
    frame = None if frame is None else np.array(frame, dtype=np.float64)
    return (repr(sorted(options.items())), tuple(np.array(a) if copy else np.asarray(a) for a in arrays),
            frame, bool(rescale))


def same_key(key, other, exact=False):
    """Whether two keys of :func:`geometry_key` are equal: same options, arrays equal in dtype, shape and
    values, and similar frames (:func:`similar_frames`; ``exact``: equal frames).

    Examples
    --------
    >>> same_key(geometry_key([1.0], [0], {}), geometry_key([1.0, 2.0], [0], {}))
    False
    >>> same_key(geometry_key([1.0], [0], {}, frame=np.eye(4)), geometry_key([1.0], [0], {}, frame=2 * np.eye(4)))
    True
    """
    return key[0] == other[0] and len(key[1]) == len(other[1]) and all(
        a.dtype == b.dtype and a.shape == b.shape and np.array_equal(a, b) for a, b in zip(key[1], other[1])
    ) and (_equal_frames(key[2], other[2]) if exact else similar_frames(key[2], other[2], key[3] and other[3]))


def _equal_frames(a, b):
    return (a is None) == (b is None) and (a is None or np.array_equal(a, b))


def metric(frame):
    """The metric of a frame's 3x3 part ``A``, ``A^T A``, and its mean scale squared (a third of its trace).

    Examples
    --------
    >>> G, s2 = metric(np.diag([2.0, 2.0, 2.0, 1.0]))
    >>> G.diagonal().tolist(), float(s2)
    ([4.0, 4.0, 4.0], 4.0)
    """
    A = np.asarray(frame, dtype=np.float64)[:3, :3]
    G = A.T @ A
    return G, np.trace(G) / 3.0


def similar_frames(a, b, rescale=True):
    """Whether frames ``a`` and ``b`` (4x4 or None) measure the same object coordinates alike: the same
    metric (to :data:`FRAME_TOLERANCE`) up to a factor (``rescale``) or exactly.

    Translations, rotations and mirrors are similar; so is a uniform scale where ``rescale``; a non-uniform
    scale or a shear is not. None (no frame) is similar to None only.

    Examples
    --------
    >>> turn = np.array([[0.6, -0.8, 0, 3], [0.8, 0.6, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])
    >>> similar_frames(np.eye(4), turn), similar_frames(np.eye(4), np.diag([1, 1, 2, 1]))
    (True, False)
    >>> similar_frames(np.eye(4), 3 * turn), similar_frames(np.eye(4), 3 * turn, rescale=False)
    (True, False)
    """
    if a is None or b is None:
        return a is None and b is None
    if np.array_equal(a[:3, :3], b[:3, :3]):
        return True
    (Ga, sa), (Gb, sb) = metric(a), metric(b)
    if not (sa > 0 and sb > 0) or (not rescale and not abs(sb / sa - 1.0) <= FRAME_TOLERANCE):
        return False
    return bool(np.abs(Ga / sa - Gb / sb).max() <= FRAME_TOLERANCE)


def placed(points, frame):
    """``points`` (``(k, 3)``) placed by a 4x4 matrix, ``points @ A.T + t``; as they are for None.

    Examples
    --------
    >>> placed(np.array([[1.0, 0.0, 0.0]]), np.diag([2.0, 2.0, 2.0, 1.0])).tolist()
    [[2.0, 0.0, 0.0]]
    """
    if frame is None:
        return points
    return points @ frame[:3, :3].T + frame[:3, 3]


class Placement(namedtuple("Placement", "matrix scale")):
    """Where a cached solver's coordinates are in a run: the 4x4 ``matrix`` from the coordinates it was built
    in (its key's frame) to the run's measured ones (None: the same), and ``scale``, the factor of every length
    (1.0 for a rigid motion, whose factor is 1 to :data:`FRAME_TOLERANCE`).

    Examples
    --------
    >>> moved = Placement.between(np.eye(4), np.diag([2.0, 2.0, 2.0, 1.0]))
    >>> moved.scale, moved.distance(np.array([1.5])).tolist(), moved.points(np.ones((1, 3))).tolist()
    (2.0, [3.0], [[2.0, 2.0, 2.0]])
    >>> Placement.between(None, None) is IDENTITY
    True
    """

    @classmethod
    def between(cls, built, now):
        """The placement of a solver built in frame ``built`` in a run measured in frame ``now`` (similar frames)."""
        if built is None or now is None or np.array_equal(built, now):
            return IDENTITY
        if np.array_equal(built[:3, :3], now[:3, :3]):  # moved only: exactly a translation
            matrix = np.eye(4)
            matrix[:3, 3] = now[:3, 3] - built[:3, 3]
            return cls(matrix, 1.0)
        scale = float(np.sqrt(metric(now)[1] / metric(built)[1]))
        return cls(now @ np.linalg.inv(built), 1.0 if abs(scale - 1.0) <= FRAME_TOLERANCE else scale)

    def distance(self, d):
        """Distances (an array or a float) from the solver, in the run's units."""
        return d if self.scale == 1.0 else d * self.scale

    def points(self, points):
        """Points in the solver's coordinates, in the run's measured coordinates."""
        return placed(np.asarray(points, dtype=np.float64), self.matrix)

    def path(self, path):
        """A ``heatcore.GeodesicPath`` (or ``TracedPath``) of the solver, its points and lengths in the run's
        coordinates and units."""
        if self.matrix is None:
            return path
        legs = {"leg_lengths": self.distance(np.asarray(path.leg_lengths))} if hasattr(path, "leg_lengths") else {}
        return dataclasses.replace(path, points=self.points(path.points), length=self.distance(path.length), **legs)


#: The placement of a solver in the run it was built for.
IDENTITY = Placement(None, 1.0)


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

    def entry(self, mesh_id, key, exact=False):
        """``(key, solver)`` cached for ``mesh_id`` under a key equal to ``key`` (:func:`same_key`; then the
        most recently used), or None. The key returned is the solver's own: its frame is the one it was built in."""
        entry = self._entries.get(mesh_id)
        if entry is None or not same_key(entry[0], key, exact):
            return None
        self._entries.move_to_end(mesh_id)
        return entry

    def lookup(self, mesh_id, key, exact=False):
        """The solver cached for ``mesh_id`` under ``key`` (:meth:`entry`), or None."""
        entry = self.entry(mesh_id, key, exact)
        return None if entry is None else entry[1]

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
