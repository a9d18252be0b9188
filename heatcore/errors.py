"""Exception and warning types raised by heatcore, and the helper that keeps their messages short.

Every error carries a message that says what is wrong and where, so that a
user can act on it (for example ``face 12 references vertex 900 but the mesh
has 800 vertices``). Every layer may raise these; this module imports nothing
from heatcore.

Examples
--------
>>> from heatcore.errors import HeatcoreError, InvalidMeshError
>>> try:
...     raise InvalidMeshError("face 12 references vertex 900 but the mesh has 800 vertices")
... except HeatcoreError as error:
...     print(error)
face 12 references vertex 900 but the mesh has 800 vertices
"""

#: Longest reader message kept in an error (some readers quote whole files).
MAX_DETAIL = 300


def short(text, limit=MAX_DETAIL):
    """``text`` on one line, at most ``limit`` characters (a reader's message inside one of ours).

    Parameters
    ----------
    text : object
        The message (anything ``str`` accepts, an exception for example).
    limit : int, default :data:`MAX_DETAIL`
        Longest result, in characters; a longer text is cut and ends with ``...``.

    Returns
    -------
    str

    Examples
    --------
    >>> short("line one\\n   line two")
    'line one line two'
    >>> len(short("x" * 5000))
    300
    """
    text = " ".join(str(text).split())
    return text if len(text) <= limit else text[: limit - 3] + "..."


class HeatcoreError(Exception):
    """Base class of all heatcore errors.

    Catch it to handle any error heatcore raises on purpose.

    Examples
    --------
    >>> issubclass(InvalidMeshError, HeatcoreError), issubclass(SolverError, HeatcoreError)
    (True, True)
    """


class InvalidMeshError(HeatcoreError, ValueError):
    """The mesh arrays are malformed: wrong shapes, bad indices, NaN/inf coordinates.

    Also raised by the file readers for a file that cannot be read.

    Examples
    --------
    >>> import numpy as np
    >>> from heatcore import TriangleMesh
    >>> try:
    ...     TriangleMesh(np.zeros((3, 3)), [[0, 1, 5]])
    ... except InvalidMeshError:
    ...     print("rejected")
    rejected
    """


class NoFacesError(InvalidMeshError):
    """A surface mesh file holds vertices but no faces (it may be read as a point cloud).

    Examples
    --------
    >>> issubclass(NoFacesError, InvalidMeshError)
    True
    """


class InvalidSourceError(HeatcoreError, ValueError):
    """The source specification is empty, out of range or refers to unused geometry.

    Examples
    --------
    >>> issubclass(InvalidSourceError, ValueError)
    True
    """


class InvalidOptionError(HeatcoreError, ValueError):
    """A solver option has a value outside its allowed set or range.

    Examples
    --------
    >>> issubclass(InvalidOptionError, ValueError)
    True
    """


class SolverError(HeatcoreError, RuntimeError):
    """A linear solve failed (for example a factorization that is not positive definite).

    Examples
    --------
    >>> issubclass(SolverError, RuntimeError)
    True
    """


class UnsupportedDomainError(InvalidOptionError, TypeError):
    """The domain cannot do what was asked of it: the one error for that, wherever it is asked.

    ``accuracy="high"`` on a domain without triangles to sweep, a geodesic
    path or the vector heat method off a triangle mesh. It is an
    :class:`InvalidOptionError` (what was asked does not fit the domain:
    ``except InvalidOptionError``, which ``accuracy="high"`` on another
    domain raised before, still catches it) and a ``TypeError`` (the kind of
    domain is wrong: what it was before). The vector heat method raised
    :class:`InvalidMeshError` for other domains before; it raises this now.

    Examples
    --------
    >>> issubclass(UnsupportedDomainError, InvalidOptionError), issubclass(UnsupportedDomainError, TypeError)
    (True, True)
    >>> import numpy as np, heatcore as hc
    >>> try:
    ...     hc.HeatSolver(hc.PointCloud(np.eye(3)), accuracy="high")
    ... except hc.InvalidOptionError as error:  # what it raised before
    ...     print(type(error).__name__)
    UnsupportedDomainError
    """


class HeatcoreWarning(UserWarning):
    """Input was repaired (duplicate or degenerate faces dropped) or a result is degraded.

    Examples
    --------
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     warnings.warn("2 duplicate faces dropped", HeatcoreWarning)
    >>> caught[0].category.__name__
    'HeatcoreWarning'
    """
