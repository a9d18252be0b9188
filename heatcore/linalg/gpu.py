"""cuDSS's sparse Cholesky on an NVIDIA GPU, through nvmath-python: for meshes of millions of vertices.

The ``gpu`` backend is chosen by name only (``backend="gpu"``; "auto" never
picks it): it needs the ``gpu`` extra (nvmath-python with its CUDA 13 wheels,
cuDSS among them) and a CUDA GPU. Where either is missing, asking for it
raises a :class:`~heatcore.errors.SolverError` that says which, and
:func:`~heatcore.linalg.available_backends` leaves it out.

cuDSS plans (orders and analyses) and factors the matrix on the GPU, where it
stays for the factor's life; a solve copies the right-hand side there and the
solution back (one column at a time: cuDSS solves the width it was planned
for). The measured speed against the CPU backends is in ``docs/scale.md``.

Examples
--------
The GPU where there is one, else the CPU's best:

>>> import scipy.sparse as sp
>>> from heatcore.linalg import available_backends, factor
>>> backend = "gpu" if "gpu" in available_backends() else "auto"
>>> factor(sp.diags([2.0, 4.0]).tocsr(), backend).solve([2.0, 4.0]).round(12).tolist()
[1.0, 1.0]
"""

import glob
import os
import sys
import weakref

import numpy as np

from ..errors import SolverError
from .interface import Factor, canonical_csr
from .libraries import optional


def gpu_count():
    """The number of CUDA GPUs that nvmath-python can use here (0 without it, or without a driver).

    Examples
    --------
    >>> isinstance(gpu_count(), int)
    True
    """
    if optional("nvmath") is None:
        return 0
    try:
        from cuda.bindings import runtime  # installed with nvmath-python

        error, count = runtime.cudaGetDeviceCount()
    except Exception:  # noqa: BLE001 - no driver, or a broken CUDA install: no GPU to use
        return 0
    return int(count) if error == runtime.cudaError_t.cudaSuccess else 0


def threading_layer():
    """cuDSS's OpenMP threading layer, installed with its wheel, or None where it is not found.

    With it cuDSS orders the matrix on every CPU core (the 1M-vertex cube
    sphere's heat matrix: 2.1 s against 7.2 s on one core, 16 cores, H200).
    ``CUDSS_THREADING_LIB`` names another.

    Examples
    --------
    >>> threading_layer() is None or "mtlayer" in threading_layer()
    True
    """
    if os.environ.get("CUDSS_THREADING_LIB"):
        return os.environ["CUDSS_THREADING_LIB"]
    pattern = ("nvidia", "cu*", "bin" if os.name == "nt" else "lib", "*cudss_mtlayer*")
    found = sorted(p for entry in sys.path for p in glob.glob(os.path.join(entry, *pattern)))
    return found[0] if found else None


class GPUFactor(Factor):
    """A Cholesky factor held by cuDSS on the GPU.

    Parameters
    ----------
    A : (n, n) sparse symmetric positive definite matrix
    ordering : ignored
        cuDSS orders the matrix itself (nested dissection).

    Raises
    ------
    SolverError
        nvmath-python is not installed, no CUDA GPU is found, or ``A`` is not
        positive definite.

    Examples
    --------
    >>> import scipy.sparse as sp
    >>> from heatcore.linalg import factor
    >>> A = sp.csr_matrix([[4.0, 1.0], [1.0, 3.0]])
    >>> if gpu_count():
    ...     x = GPUFactor(A).solve([5.0, 4.0])
    ... else:
    ...     x = factor(A, "superlu").solve([5.0, 4.0])  # the same answer on the CPU
    >>> [round(float(v), 12) for v in x]
    [1.0, 1.0]
    """

    backend = "gpu"

    def __init__(self, A, ordering=None):
        nvmath = optional("nvmath")
        if nvmath is None:
            raise SolverError("backend 'gpu' needs nvmath-python with cuDSS: pip install 'heatcore[gpu]'")
        if gpu_count() == 0:
            raise SolverError("backend 'gpu' needs a CUDA GPU, and none was found")
        advanced = nvmath.sparse.advanced
        A = canonical_csr(A).astype(np.float64)
        A.indptr, A.indices = A.indptr.astype(np.int32), A.indices.astype(np.int32)  # what cuDSS reads
        self.n = A.shape[0]
        options = advanced.DirectSolverOptions(sparse_system_type=advanced.DirectSolverMatrixType.SPD,
                                               multithreading_lib=threading_layer())
        self._solver = advanced.DirectSolver(A, np.zeros(self.n), options=options)
        self._free = weakref.finalize(self, self._solver.free)  # the GPU memory goes with the factor
        try:
            self._solver.plan()
            info = self._solver.factorize().info
        except Exception as exc:  # noqa: BLE001 - cuDSS's errors (out of GPU memory, ...) have no common type
            self._free()
            raise SolverError(f"cuDSS could not factor the {self.n} x {self.n} matrix on the GPU: {exc}") from exc
        if info != 0:
            self._free()
            raise SolverError(f"sparse Cholesky factorization failed: the matrix is not positive definite "
                              f"(cuDSS stopped at pivot {info})")

    def _solve(self, b):
        return self._solve_columns(b, self._solve_one)

    def _solve_one(self, b):
        self._solver.reset_operands(b=np.ascontiguousarray(b))
        return np.array(self._solver.solve(), dtype=np.float64)
