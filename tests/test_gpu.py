"""The gpu backend (cuDSS through nvmath-python): a clear error where it cannot run, CPU answers where it can.

CI has no GPU: there the first test runs and the others are skipped. On a machine with a CUDA GPU
and the gpu extra, the others run (and every test parametrized by ``available_backends()`` runs
the gpu backend too).
"""

import numpy as np
import pytest
import scipy.sparse as sp
from shapes import grid

import heatcore as hc
from heatcore import linalg
from heatcore.errors import SolverError
from heatcore.linalg.gpu import gpu_count

HAS_GPU = "gpu" in linalg.available_backends()
needs_gpu = pytest.mark.skipif(not HAS_GPU, reason="needs a CUDA GPU and the gpu extra (nvmath-python)")


@pytest.mark.skipif(HAS_GPU, reason="the gpu backend can run here")
def test_without_a_gpu_asking_for_it_says_what_is_missing():
    assert gpu_count() == 0 or linalg.libraries.optional("nvmath") is None
    with pytest.raises(SolverError, match=r"heatcore\[gpu\]|CUDA GPU"):
        linalg.factor(sp.identity(4, format="csr"), "gpu")
    V, F = grid(5, 5)
    with pytest.raises(SolverError, match=r"heatcore\[gpu\]|CUDA GPU"):
        hc.HeatSolver(hc.TriangleMesh(V, F, refine=0), backend="gpu")
    assert linalg.choose_backend(10**7) != "gpu"


@needs_gpu
def test_gpu_distances_are_the_cpu_distances():
    V, F = grid(60, 50, jitter=0.2)
    mesh = hc.TriangleMesh(V, F)  # a boundary: Neumann and Dirichlet heat factors, and the Poisson one
    cpu = hc.HeatSolver(mesh, backend="superlu")
    gpu = hc.HeatSolver(mesh, backend="gpu")
    sources = [[0], [1234], [5, 900, 2999]]
    for s in sources:
        d_cpu, d_gpu = cpu.distance(s), gpu.distance(s)
        assert np.abs(d_gpu - d_cpu).max() < 1e-9 * d_cpu.max()
    both = gpu.distances([s[0] for s in sources])  # several right-hand sides in one call
    assert np.abs(both - cpu.distances([s[0] for s in sources])).max() < 1e-9 * both.max()


@needs_gpu
def test_gpu_factor_refuses_a_matrix_that_is_not_positive_definite():
    A = sp.diags([1.0, -2.0, 3.0]).tocsr()
    with pytest.raises(SolverError, match="not positive definite|could not factor"):
        linalg.factor(A, "gpu").solve(np.ones(3))
