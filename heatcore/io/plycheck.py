"""Checking a PLY file's data against its header, so that a file that lies is an error.

The libraries that read PLY trust the header's counts: meshio and
potpourri3d read the rows a header declares and ignore the rest (a header
declaring 400 of 800 faces gave a mesh with half its faces), cast fractional
indices to integers, and walk a binary list element of ``10**9`` declared
faces far past the end of a 15 kB file (meshio spins there, growing by
25 MB/s). :func:`check_ply_body` compares the data with the header first:

* binary: the bytes the header declares at the least (each list empty) must
  be there (:func:`check_ply_size`, instant); then the rows are walked,
  numpy reading runs of rows of one layout at once, and must end exactly
  where the file does (trailing whitespace aside);
* ASCII (one row per line, as every writer and reader does): each element's
  rows must have the values their properties and list counts call for,
  list counts and integer properties must be whole numbers (``3 0 1 2.7`` is
  an error, not the face ``0 1 2``), and no line of data may follow the last
  element. Lines and tokens are found with numpy (:mod:`heatcore.io.textscan`),
  and only elements with lists are parsed.

Examples
--------
>>> import tempfile, pathlib
>>> tmp = tempfile.TemporaryDirectory()
>>> path = pathlib.Path(tmp.name) / "m.ply"
>>> _ = path.write_text("ply\\nformat ascii 1.0\\nelement vertex 3\\nproperty float x\\nproperty float y\\n"
...                     "property float z\\nelement face 1\\nproperty list uchar int vertex_indices\\nend_header\\n"
...                     "0 0 0\\n1 0 0\\n0 1 0\\n3 0 1 2\\n3 0 2 1\\n")
>>> check_ply_body(path)
Traceback (most recent call last):
...
heatcore.errors.InvalidMeshError: cannot read mesh file ...m.ply: 1 more line of data follows the 1 face its PLY header declares (line 14: a header that undercounts, or trailing data)
>>> tmp.cleanup()
"""

import sys
from pathlib import Path

import numpy as np

from ..errors import InvalidMeshError
from .ply import read_header
from .textscan import integral, numbers, ranges, scan_lines

#: Rows walked one by one (in Python) after a short run of one layout, before numpy tries again.
SLOW_ROWS = 256
#: numpy's byte order codes as :meth:`int.from_bytes` names them.
BYTE_ORDER = {"<": "little", ">": "big", "|": "little", "=": sys.byteorder}
#: List properties that hold vertex indices (their items must be whole numbers).
INDEX_LISTS = {"vertex_indices", "vertex_index"}


def _plural(count, name):
    return f"{count} {name}" + ("" if count == 1 else ("es" if name.endswith(("x", "s")) else "s"))


def check_ply_size(path, header=None, noun="mesh file"):
    """Raise when a binary PLY file is too small for the rows its header declares.

    Every row takes at least its scalars and its lists' counts; this costs
    nothing and stops readers that would walk a ``10**9``-face header.

    Parameters
    ----------
    path : str or path-like
    header : Header, optional
        Already parsed (:func:`heatcore.io.ply.read_header`).
    noun : str, default "mesh file"
        What the file is, for the message.

    Raises
    ------
    InvalidMeshError

    Examples
    --------
    >>> import tempfile, pathlib
    >>> tmp = tempfile.TemporaryDirectory()
    >>> path = pathlib.Path(tmp.name) / "big.ply"
    >>> _ = path.write_bytes(b"ply\\nformat binary_little_endian 1.0\\nelement face 1000000000\\n"
    ...                      b"property list uchar int vertex_indices\\nend_header\\n" + bytes(20))
    >>> check_ply_size(path)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    heatcore.errors.InvalidMeshError: cannot read mesh file ...big.ply: its PLY header declares 1000000000 faces, at least 1,000,000,000 bytes, but 20 bytes of data follow the header (a truncated file, or a header that overcounts)
    >>> tmp.cleanup()
    """
    path = Path(path)
    header = header or read_header(path)
    if header.format == "ascii":
        return
    size = path.stat().st_size - header.size
    need = 0
    for e in header.elements:
        row = sum(np.dtype(p[1]).itemsize for p in e.properties)  # a list's count type, or a scalar's type
        need += e.count * row
        if need > size:
            raise InvalidMeshError(
                f"cannot read {noun} {path}: its PLY header declares {_plural(e.count, e.name)}, at least "
                f"{need:,} bytes, but {size:,} bytes of data follow the header (a truncated file, or a header "
                "that overcounts)")


def check_ply_body(path, header=None, noun="mesh file"):
    """Raise when a PLY file's data does not match its header (see the module docstring).

    Parameters
    ----------
    path : str or path-like
    header : Header, optional
        Already parsed (:func:`heatcore.io.ply.read_header`).
    noun : str, default "mesh file"
        What the file is, for the message.

    Raises
    ------
    InvalidMeshError
        Fewer or more rows than declared, a row with the wrong number of
        values, a negative or fractional list count, a fractional index, or
        trailing data.

    Examples
    --------
    >>> from heatcore.io import write_ply
    >>> import tempfile, pathlib
    >>> tmp = tempfile.TemporaryDirectory()
    >>> path = pathlib.Path(tmp.name) / "ok.ply"
    >>> write_ply(path, np.eye(3), [[0, 1, 2]], [0, 1, 1], np.zeros((3, 3)))
    >>> check_ply_body(path)
    >>> tmp.cleanup()
    """
    path = Path(path)
    header = header or read_header(path)
    check_ply_size(path, header, noun)
    data = path.read_bytes()
    body = data[header.size:]
    where = f"cannot read {noun} {path}"
    if header.format == "ascii":
        _check_ascii(body, header.elements, where, data.count(b"\n", 0, header.size) + 1)
    else:
        _check_binary(body, header.elements, "<" if header.format.endswith("little_endian") else ">", where)


def _check_ascii(body, elements, where, first_line):
    lines = scan_lines(body, first_line=first_line)
    row0 = 0
    for e in elements:
        rows = lines.take(slice(row0, row0 + e.count))
        _check_ascii_rows(body, e, rows, where)
        if rows.start.size < e.count:
            raise InvalidMeshError(f"{where}: its PLY header declares {_plural(e.count, e.name)} but the data ends "
                                   f"after {rows.start.size} of them (a truncated file, or a header that overcounts)")
        row0 += e.count
    extra = lines.start.size - row0
    if extra > 0:
        last = elements[-1] if elements else None
        after = f"the {_plural(last.count, last.name)} its PLY header declares" if last else "its PLY header"
        raise InvalidMeshError(f"{where}: {extra} more line{'s' if extra > 1 else ''} of data follow"
                               f"{'s' if extra == 1 else ''} {after} (line {lines.number[row0]}: a header "
                               "that undercounts, or trailing data)")


def _check_ascii_rows(body, e, rows, where):
    """The values on each of ``rows`` (lines of one element) against its properties."""
    if rows.start.size == 0:
        return

    def fail(bad, why):
        i = int(np.flatnonzero(bad)[0])
        raise InvalidMeshError(f"{where}: {e.name} {i} (line {rows.number[i]}) {why(i)}")

    if all(len(p) == 2 for p in e.properties):  # scalars only: count the values, parse nothing
        bad = rows.tokens != len(e.properties)
        if bad.any():
            fail(bad, lambda i: f"has {rows.tokens[i]} values but its PLY header declares "
                                f"{len(e.properties)} properties for each {e.name}")
        return
    values = numbers(body[rows.start[0]:rows.end[-1]], int(rows.tokens.sum()), f"{where}: the {e.name} rows")
    first = np.r_[0, np.cumsum(rows.tokens)[:-1]]
    at = np.zeros(rows.start.size, dtype=np.int64)  # each row's next value
    for p in e.properties:
        short = at >= rows.tokens
        if short.any():
            fail(short, lambda i: f"has {rows.tokens[i]} values, too few for the properties its PLY header declares")
        head = values[first + at]
        if len(p) == 2:
            if p[1][0] in "iu" and not integral(head).all():
                fail(~integral(head), lambda i: f"has {p[0]} = {head[i]:g}, but the PLY header declares it an integer")
            at += 1
            continue
        bad = ~integral(head) | (head < 0)
        if bad.any():
            fail(bad, lambda i: f"has a {p[0]} list of {head[i]:g} items (a list count is a whole number >= 0)")
        count = head.astype(np.int64)
        over = at + 1 + count > rows.tokens
        if over.any():
            fail(over, lambda i: f"has {rows.tokens[i]} values, too few for its {p[0]} list of {count[i]} items")
        if p[2][0] in "iu" or p[0] in INDEX_LISTS:
            items = values[ranges(first + at + 1, count)]
            bad = ~integral(items)
            if bad.any():
                k = int(np.flatnonzero(bad)[0])
                row = np.repeat(np.arange(count.size), count)[k]
                raise InvalidMeshError(f"{where}: {e.name} {row} (line {rows.number[row]}) holds the {p[0]} "
                                       f"value {items[k]:g}: vertex indices must be integers")
        at += 1 + count
    bad = at != rows.tokens
    if bad.any():
        fail(bad, lambda i: f"has {rows.tokens[i]} values but its properties and list counts call for {at[i]}")


def _check_binary(body, elements, order, where):
    offset = 0
    for e in elements:
        if all(len(p) == 2 for p in e.properties):
            offset += e.count * sum(np.dtype(p[1]).itemsize for p in e.properties)
        else:
            offset = _walk_lists(body, offset, e, order, where)
    if offset > len(body):
        raise InvalidMeshError(f"{where}: the data ends inside the {elements[-1].name} rows its PLY header declares "
                               "(a truncated file, or a header that overcounts)")
    if body[offset:].strip():
        last = elements[-1]
        raise InvalidMeshError(f"{where}: {len(body) - offset:,} bytes of data follow the {_plural(last.count, last.name)} "
                               "its PLY header declares (a header that undercounts, or trailing data)")


def _walk_lists(body, offset, e, order, where):
    """Offset past element ``e``'s rows, which hold lists: runs of one layout read by numpy at once."""
    props = [(p[0], np.dtype(order + p[1])) + ((np.dtype(order + p[2]),) if len(p) == 3 else ()) for p in e.properties]
    dtypes, row, slow = {}, 0, 0
    while row < e.count:
        counts = _row_counts(body, offset, props, e, row, where)
        if counts not in dtypes:
            fields = []
            for j, p in enumerate(props):
                fields.append((f"f{j}", p[1]))
                if len(p) == 3:
                    fields.append((f"l{j}", p[2], (counts[j],)))
            dtypes[counts] = np.dtype(fields)
        dtype = dtypes[counts]
        if slow:  # a short run of this layout just ended: step row by row for a while
            offset, row, slow = offset + dtype.itemsize, row + 1, slow - 1
            continue
        n = min(e.count - row, (len(body) - offset) // dtype.itemsize)
        if n == 0:
            raise InvalidMeshError(f"{where}: the data ends inside {e.name} {row} of the "
                                   f"{e.count} its PLY header declares (a truncated file, or a header that overcounts)")
        view = np.frombuffer(body, dtype, n, offset)
        same = np.ones(n, dtype=bool)
        for j, p in enumerate(props):
            if len(p) == 3:
                same &= view[f"f{j}"] == counts[j]
        k = n if same.all() else int(np.argmin(same))
        for j, p in enumerate(props):
            if len(p) == 3 and p[0] in INDEX_LISTS and p[2].kind == "f" and counts[j]:
                bad = ~integral(view[f"l{j}"][:k].astype(np.float64)).all(axis=1)
                if bad.any():
                    i = int(np.flatnonzero(bad)[0])
                    raise InvalidMeshError(f"{where}: {e.name} {row + i} holds the {p[0]} "
                                           f"{view[f'l{j}'][i].tolist()}: vertex indices must be integers")
        row, offset = row + k, offset + k * dtype.itemsize
        slow = SLOW_ROWS if k < 8 and row < e.count else 0
    return offset


def _row_counts(body, offset, props, e, row, where):
    """The list counts of the row at ``offset``, read one property at a time."""
    counts = []
    for p in props:
        if offset + p[1].itemsize > len(body):
            raise InvalidMeshError(f"{where}: the data ends inside {e.name} {row} of the {e.count} its PLY header "
                                   "declares (a truncated file, or a header that overcounts)")
        if len(p) == 3:
            size = p[1].itemsize
            count = int.from_bytes(body[offset:offset + size], BYTE_ORDER[p[1].byteorder],
                                   signed=p[1].kind == "i")
            if count < 0:
                raise InvalidMeshError(f"{where}: {e.name} {row} has a {p[0]} list of {count} items "
                                       "(a list count is a whole number >= 0)")
            counts.append(int(count))
            offset += p[1].itemsize + count * p[2].itemsize
        else:
            counts.append(0)
            offset += p[1].itemsize
    return tuple(counts)
