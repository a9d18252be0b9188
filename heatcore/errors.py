"""Exception and warning types raised by heatcore.

Every error carries a message that says what is wrong and where, so that a
user can act on it (for example ``face 12 references vertex 900 but the mesh
has 800 vertices``).
"""


class HeatcoreError(Exception):
    """Base class of all heatcore errors."""


class InvalidMeshError(HeatcoreError, ValueError):
    """The mesh arrays are malformed: wrong shapes, bad indices, NaN/inf coordinates."""


class NoFacesError(InvalidMeshError):
    """A surface mesh file holds vertices but no faces (it may be read as a point cloud)."""


class InvalidSourceError(HeatcoreError, ValueError):
    """The source specification is empty, out of range or refers to unused geometry."""


class InvalidOptionError(HeatcoreError, ValueError):
    """A solver option has a value outside its allowed set or range."""


class SolverError(HeatcoreError, RuntimeError):
    """A linear solve failed (for example a factorization that is not positive definite)."""


class HeatcoreWarning(UserWarning):
    """Input was repaired (duplicate or degenerate faces dropped) or a result is degraded."""
