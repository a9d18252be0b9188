"""Giving the C heap's free memory back to the operating system before a large factorization.

The C heap keeps much of what a mesh build frees (1M vertices: about 0.4 GB,
in chunks that a factor's large arrays cannot reuse); returning it before a
large factorization lowers the peak memory by that much. glibc's
``malloc_trim`` does it; it is looked up on the first call, not at import.

Examples
--------
>>> release_free_memory()  # a no-op where the C library has no malloc_trim
"""

import ctypes
import ctypes.util

from .libraries import once


@once
def _malloc_trim():
    """glibc's ``malloc_trim``, or None on other C libraries."""
    try:
        return ctypes.CDLL(ctypes.util.find_library("c")).malloc_trim
    except (AttributeError, OSError, TypeError):  # pragma: no cover - macOS, Windows, musl
        return None


def release_free_memory():
    """Give the heap memory that is free but still held back to the operating system.

    The C heap keeps much of what a mesh build frees (1M vertices: about 0.4 GB,
    in chunks that a factor's large arrays cannot reuse); returning it before
    a large factorization lowers the peak memory by that much. glibc only; a
    no-op elsewhere.

    Returns
    -------
    None

    Examples
    --------
    >>> release_free_memory() is None
    True
    """
    trim = _malloc_trim()
    if trim is not None:
        trim(0)
