"""The path queries :class:`~heatcore.HeatSolver` offers: a mixin, so that ``heat.py`` stays the heat method.

Examples
--------
>>> import heatcore as hc
>>> issubclass(hc.HeatSolver, PathQueries)
True
"""


class PathQueries:
    """Geodesic paths on the solver's triangle mesh, from the solver's own distance queries.

    Examples
    --------
    >>> import heatcore as hc
    >>> solver = hc.HeatSolver(hc.TriangleMesh(*hc.io.load_demo_mesh()))
    >>> path = solver.geodesic_path(0, 1453)
    >>> path.points[0].tolist() == solver.domain.vertices[0].tolist()
    True
    >>> nearby = solver.geodesic_path(0, (100, [0.2, 0.3, 0.5]))  # a point inside face 100; the field of 0 is reused
    """

    def geodesic_path(self, source, target, *, both_ends=True):
        """The shortest path on the surface from ``source`` to ``target`` (triangle meshes).

        Parameters
        ----------
        source, target : int or (int, (3,) array_like)
            A vertex index, or a surface point ``(face, barycentric)``: a face
            index of the input mesh and three barycentric coordinates (>= 0,
            summing to 1).
        both_ends : bool, default True
            Also descend on the distance from ``target`` (a second query,
            kept for the next path) and keep the shorter result. False: one
            query per source, paths from it 5-10 times faster, and the
            largest excess over the exact length about 0.5% instead of 0.1%
            (docs/paths.md).

        Returns
        -------
        GeodesicPath
            ``points`` from ``source`` to ``target`` on the input faces,
            ``faces``/``edges``/``vertices`` crossed and ``length``. The same
            point twice gives a one-point path of length 0.

        Raises
        ------
        UnsupportedDomainError
            The solver's domain is not a :class:`~heatcore.TriangleMesh`.
        InvalidSourceError
            A bad index or coordinates, a vertex no face uses, or a target in
            another connected part than the source (the message names both).

        Notes
        -----
        The distance from ``source`` is one query of the solver's
        factorizations, kept for further targets from the same source. The
        path is a geodesic (straight across every edge, bending only at
        saddle or boundary vertices) in the homotopy class the heat distance
        points to: the shortest path except where two routes are within the
        heat distance's error of each other (docs/paths.md has the figures).
        """
        from .path import geodesic_path

        return geodesic_path(self, source, target, both_ends)
