"""Vectorized scans of text mesh files: lines, their tokens, and the numbers in them.

The checks of :mod:`heatcore.io.checks` compare what a text file holds with
what it declares (a PLY or OFF header's counts, an OBJ face's indices) before a
library reads it. They must cost little next to the read itself, so nothing
here loops over lines in Python: the bytes are viewed as a numpy array, lines
and tokens are found with comparisons and :func:`numpy.add.reduceat`, and
numbers are parsed by :func:`numpy.fromstring` in one call.

Examples
--------
>>> table = scan_lines(b"3 0 1 2\\n\\n  4 0 1 2 3\\n")
>>> table.tokens.tolist(), table.number.tolist()
([4, 5], [1, 3])
"""

import warnings
from typing import NamedTuple

import numpy as np

from ..errors import InvalidMeshError



def is_space(a):
    """Mask of the bytes of ``a`` (a uint8 array) that separate tokens: the space and control bytes.

    Examples
    --------
    >>> is_space(np.frombuffer(b"1 2\\t3\\r\\n", dtype=np.uint8)).tolist()
    [False, True, False, True, False, True, True]
    """
    return a <= 32  # one comparison: a table lookup is 10x slower on large files


def count_between(mask, bounds):
    """Number of true entries of ``mask`` in each ``[bounds[i], bounds[i + 1])``.

    Examples
    --------
    >>> count_between(np.array([1, 0, 1, 1, 0], bool), np.array([0, 2, 5])).tolist()
    [1, 2]
    """
    return np.diff(np.searchsorted(np.flatnonzero(mask), bounds))  # reduceat and cumsum of bools are slower


class Lines(NamedTuple):
    """The lines of a text, as offsets into it (see :func:`scan_lines`).

    Attributes
    ----------
    start : (k,) int64 array
        Offset of each line's first byte.
    end : (k,) int64 array
        Offset one past each line's last byte (its newline excluded).
    tokens : (k,) int64 array
        Number of whitespace-separated tokens on each line.
    number : (k,) int64 array
        Line numbers, counted from 1 (blank lines count too).

    Examples
    --------
    >>> scan_lines(b"a b\\nc\\n").end.tolist()
    [3, 5]
    """

    start: np.ndarray
    end: np.ndarray
    tokens: np.ndarray
    number: np.ndarray

    def take(self, which):
        """The lines selected by ``which`` (a mask or indices)."""
        return Lines(*(column[which] for column in self))


def scan_lines(data, keep_blank=False, first_line=1):
    """Lines of ``data`` and the number of tokens on each.

    Parameters
    ----------
    data : bytes
    keep_blank : bool, default False
        Keep lines without any token.
    first_line : int, default 1
        Number of the first line of ``data`` (in the file it comes from).

    Returns
    -------
    Lines

    Examples
    --------
    >>> scan_lines(b"x y z\\r\\n\\n1 2\\n", keep_blank=True).tokens.tolist()
    [3, 0, 2]
    """
    a = np.frombuffer(data, dtype=np.uint8)
    newlines = np.flatnonzero(a == 10)
    start = np.r_[0, newlines + 1]
    end = np.r_[newlines, a.size]
    number = np.arange(first_line, first_line + start.size)
    if start.size and start[-1] == a.size:  # the text ends with a newline
        start, end, number = start[:-1], end[:-1], number[:-1]
    if a.size == 0:
        return Lines(*(np.zeros(0, np.int64) for _ in range(4)))
    space = is_space(a)
    first = ~space
    first[1:] &= space[:-1]  # a token starts where a non-space byte follows a space
    tokens = count_between(first, np.r_[start, a.size])
    lines = Lines(start, end, tokens, number)
    return lines if keep_blank else lines.take(tokens > 0)


def numbers(data, expected, where):
    """Every token of ``data`` as a float, checked to be ``expected`` numbers.

    Parameters
    ----------
    data : bytes
        Whitespace-separated numbers.
    expected : int
        How many tokens ``data`` holds (from :func:`scan_lines`).
    where : str
        What ``data`` is, for the error message ("the face data of m.ply").

    Returns
    -------
    (expected,) float64 array

    Raises
    ------
    InvalidMeshError
        A token that is not a number.

    Examples
    --------
    >>> numbers(b"3 0 1 2.5\\n", 4, "faces").tolist()
    [3.0, 0.0, 1.0, 2.5]
    >>> numbers(b"3 0 x 2\\n", 4, "the faces of m.off")
    Traceback (most recent call last):
    ...
    heatcore.errors.InvalidMeshError: the faces of m.off hold a token that is not a number, or not 4 numbers
    """
    if expected == 0:
        return np.zeros(0)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # numpy 1 warns, then stops, at a token it cannot parse
            values = np.fromstring(data, dtype=np.float64, sep=" ")
    except ValueError:  # numpy 2 raises there instead
        values = None
    if values is None or values.size != expected:
        raise InvalidMeshError(f"{where} hold a token that is not a number, or not {expected} numbers")
    return values


def integral(values):
    """Mask of the finite whole numbers in ``values``.

    Examples
    --------
    >>> integral(np.array([1.0, 2.7, np.nan, -3.0])).tolist()
    [True, False, False, True]
    """
    with np.errstate(invalid="ignore"):
        return np.isfinite(values) & (values == np.floor(values))


def ranges(first, count):
    """Concatenated ``arange(first[i], first[i] + count[i])`` for every ``i``.

    Examples
    --------
    >>> ranges(np.array([0, 10, 20]), np.array([2, 0, 3])).tolist()
    [0, 1, 20, 21, 22]
    """
    first, count = np.asarray(first, dtype=np.int64), np.asarray(count, dtype=np.int64)
    keep = count > 0
    first, count = first[keep], count[keep]
    if first.size == 0:
        return np.zeros(0, dtype=np.int64)
    steps = np.ones(int(count.sum()), dtype=np.int64)
    steps[0] = first[0]
    steps[np.cumsum(count)[:-1]] = first[1:] - (first[:-1] + count[:-1] - 1)
    return np.cumsum(steps)
