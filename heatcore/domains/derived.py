"""The one cache of what is derived from a domain, kept on the domain and dropped with it.

Everything computed from a domain alone (or from the domain and a value
named in its key), that later work on the same domain can reuse, lives in
``domain.derived``, a :class:`DerivedCache` that :class:`~heatcore.domains.base.Domain`
creates on first use. There is no module-level table keyed by domain
anywhere in heatcore: when the domain goes, everything derived from it goes
with it, and two domains never share an entry.

Keys are pairs ``(kind, variant)``: ``kind`` one of :data:`KINDS`, ``variant``
what else the value depends on (the resolved backend name of a
factorization, ``None`` where nothing). The cache holds values; it does not
know how to make them: each user passes a ``build`` function to
:meth:`DerivedCache.get_or_build`.

Examples
--------
>>> import numpy as np
>>> from heatcore.domains import TriangleMesh
>>> mesh = TriangleMesh(np.eye(3), [[0, 1, 2]], refine=0)
>>> mesh.derived.get_or_build(("path mesh", None), lambda: "built once")
'built once'
>>> mesh.derived.get_or_build(("path mesh", None), lambda: "not called")
'built once'
"""

from collections.abc import MutableMapping

#: The kinds of entry heatcore keeps, with who keeps them and what ``variant`` is.
KINDS = {
    "ordering": "linalg fill-reducing ordering of the Laplacian's pattern (steps/factors.py): a StartedOrdering "
                "while it may run, then an Ordering or None; variant: backend",
    "nested": "METIS nested dissection: a Future while it runs, then an Ordering or None; variant: backend",
    "poisson": "factor of the grounded Laplacian, shared by the domain's solvers; variant: backend",
    "vector frames": "vertex frames, connection Laplacian, translation matrix, tangent basis (vector_heat); None",
    "vector heat": "factor of the vector heat matrix M + t L_conn (vector_heat); variant: (m, backend)",
    "vector scalar heat": "factor of the scalar heat matrix M + t L of the vector heat method's flows; variant: (m, backend)",
    "eikonal corners": "CornerTable of the vectorized accuracy='high' pass (eikonal.py); None",
    "fast marching": "fast_marching.Readers of the compiled accuracy='high' pass (high_accuracy.py); None",
    "path mesh": "PathMesh, the input faces as geodesic paths see them (paths/surface.py); None",
    "vertex elements": "every input vertex's elements (Domain.index_straight_neighbours); None",
    "welded twins": "whether two input vertices share an operator vertex (steps/source_bounds.py); None",
    "displayed surface": "Blender: the probe's DisplayedSurface with its ray-casting tree; None",
    "probe sources": "Blender: the sources of the probe tool's last click on this mesh; None",
    "coarse preview": "CoarsePreview, the fast coarse answer of a drag on a large mesh (preview.py); None",
    "oriented normals": "a point cloud's normals with consistent signs (pointcloud/orientation.py); None",
    "cloud connection": "a point cloud's tangent frames and connection Laplacian (signed_heat/cloud.py); None",
    "signed vector heat": "factor of M + t L_conn of a point cloud (signed_heat/cloud.py); variant: (m, backend)",
}


class DerivedCache(MutableMapping):
    """A dict of what is derived from one domain, keyed by ``(kind, variant)`` (see :data:`KINDS`).

    It is a mutable mapping (``in``, ``[]``, ``get``, iteration over keys,
    ``len``) with :meth:`get_or_build` to fill it and :meth:`clear` to drop
    everything (the domain rebuilds what it needs on next use). It is not
    locked: two threads asking for a missing entry at once may both build it,
    and the later one is kept.

    Examples
    --------
    >>> cache = DerivedCache()
    >>> cache["poisson", "qdldl"] = "a factor"
    >>> ("poisson", "qdldl") in cache, len(cache), sorted(kind for kind, _ in cache)
    (True, 1, ['poisson'])
    >>> cache.get_or_build(("ordering", "supernodal"), lambda: "an ordering")
    'an ordering'
    >>> cache.clear()
    >>> len(cache)
    0
    >>> cache["colour", None] = 1  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    KeyError: "a derived-data key is a pair (kind, variant) with kind one of [...], not ('colour', None)"
    """

    def __init__(self):
        self._entries = {}

    def get_or_build(self, key, build):
        """The entry ``key``; where there is none, ``build()``'s value, kept under ``key``.

        Parameters
        ----------
        key : (str, object) pair
            ``(kind, variant)``, ``kind`` one of :data:`KINDS`.
        build : callable
            Called with no argument, only when ``key`` is missing.

        Returns
        -------
        object

        Examples
        --------
        >>> cache = DerivedCache()
        >>> calls = []
        >>> [cache.get_or_build(("path mesh", None), lambda: calls.append(1) or len(calls)) for _ in range(2)]
        [1, 1]
        """
        try:
            return self._entries[key]
        except KeyError:
            value = build()
            self[key] = value
            return value

    def clear(self):
        """Drop every entry (faster than the mapping's one-by-one ``clear``)."""
        self._entries.clear()

    def __getitem__(self, key):
        return self._entries[key]

    def __setitem__(self, key, value):
        if not (isinstance(key, tuple) and len(key) == 2 and key[0] in KINDS):
            raise KeyError(f"a derived-data key is a pair (kind, variant) with kind one of {sorted(KINDS)}, not {key!r}")
        self._entries[key] = value

    def __delitem__(self, key):
        del self._entries[key]

    def __iter__(self):
        return iter(self._entries)

    def __len__(self):
        return len(self._entries)

    def __repr__(self):
        return f"DerivedCache({sorted(map(repr, self._entries))})"
