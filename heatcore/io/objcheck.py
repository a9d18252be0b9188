"""Checking an OBJ file's face indices, and resolving its relative ones as the format defines.

An OBJ face names its vertices by 1-based position; a negative index counts
back from the last vertex read *so far* (``f -3 -2 -1`` is the triangle of the
three vertices just above it, wherever it stands in the file). The libraries
differ from the format there: trimesh resolves negative indices against the
end of the file (interleaved ``v v v f -3 -2 -1`` lines gave every face the
last three vertices), potpourri3d subtracts 1 from them; trimesh reads
``f 0 1 2`` as the face ``0 0 1`` and drops faces of fewer than 3 corners
silently. :func:`check_obj` finds every face's vertex indices with numpy
(:mod:`heatcore.io.textscan`; no loop over lines), raises on an index that
is 0, fractional, past the vertices of the file or before the first one, and
returns the text with relative indices made absolute, for the libraries to
read, where the file has any. :func:`scan_obj` also returns every face's
corners when some face has more than 3, for heatcore to triangulate
(:mod:`heatcore.io.faces`): the libraries' fans fold on concave polygons.

Examples
--------
>>> import tempfile, pathlib
>>> tmp = tempfile.TemporaryDirectory()
>>> path = pathlib.Path(tmp.name) / "rel.obj"
>>> _ = path.write_text("v 0 0 0\\nv 1 0 0\\nv 0 1 0\\nf -3 -2 -1\\nv 1 1 0\\nf -3 -1 -2\\n")
>>> print(check_obj(path).decode())
v 0 0 0
v 1 0 0
v 0 1 0
f 1 2 3
v 1 1 0
f 2 4 3
<BLANKLINE>
>>> tmp.cleanup()
"""

from pathlib import Path
from typing import NamedTuple

import numpy as np

from ..errors import InvalidMeshError
from .textscan import count_between, integral, is_space, numbers


class FileScan(NamedTuple):
    """What a scan of a mesh file learns besides its errors (:func:`scan_obj`, :func:`~heatcore.io.checks.scan_mesh_file`).

    Attributes
    ----------
    text : bytes or None
        The file's text with relative indices made absolute, None when it has none.
    polygons : tuple of int arrays or None
        ``(offsets, corners)``: every face's vertex indices (0-based, in the
        file's numbering, relative ones resolved) when some face has more
        than 3 corners; None when all are triangles (not parsed then).
    materials : bool
        The file has ``usemtl`` lines (OBJ).
    vertices : (n, 3) float array or None
        The file's vertices, where the scan read them (an OFF file with polygons).

    Examples
    --------
    >>> FileScan(None, None, False).polygons is None
    True
    """

    text: object
    polygons: object
    materials: bool
    vertices: object = None


def check_obj(path, noun="mesh file"):
    """Check the face indices of an OBJ file; its text with absolute indices where it has relative ones.

    Parameters
    ----------
    path : str or path-like
    noun : str, default "mesh file"
        What the file is, for the message.

    Returns
    -------
    bytes or None
        The file's text with every negative (relative) index replaced by
        the 1-based index it stands for (vertex, texture and normal indices
        alike), or None when the file has no negative index.

    Raises
    ------
    InvalidMeshError
        A face with fewer than 3 corners, or a vertex index that is not a
        whole number, is 0, is past the file's vertices, or counts back past
        the first vertex.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> tmp = tempfile.TemporaryDirectory()
    >>> path = pathlib.Path(tmp.name) / "zero.obj"
    >>> _ = path.write_text("v 0 0 0\\nv 1 0 0\\nv 0 1 0\\nf 0 1 2\\n")
    >>> check_obj(path)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    heatcore.errors.InvalidMeshError: cannot read mesh file ...zero.obj: line 4: a face references vertex 0, but OBJ indices start at 1 (-1 is the last vertex read)
    >>> tmp.cleanup()
    """
    return scan_obj(path, noun).text


def scan_obj(path, noun="mesh file", read=False):
    """Check an OBJ file as :func:`check_obj` does; also its polygons, where it has any.

    Parameters
    ----------
    path : str or path-like
    noun : str, default "mesh file"
        What the file is, for the message.
    read : bool, default False
        Also read the file where its vertex lines are plain (``v`` and at
        least 3 numbers, no line continued with ``\\``): the scan then
        returns the vertices and every face's corners, and no library needs
        to parse it (a 1M-vertex file: about 2 s, against 2-5 s through
        trimesh). The same arrays as trimesh's, which reads the others.

    Returns
    -------
    FileScan

    Raises
    ------
    InvalidMeshError
        As :func:`check_obj`.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> tmp = tempfile.TemporaryDirectory()
    >>> path = pathlib.Path(tmp.name) / "quad.obj"
    >>> _ = path.write_text("v 0 0 0\\nv 1 0 0\\nv 1 1 0\\nv 0 1 0\\nf 1 2 3 -1\\nf 1 2 3\\n")
    >>> offsets, corners = scan_obj(path).polygons
    >>> offsets.tolist(), corners.tolist()
    ([0, 4, 7], [0, 1, 2, 3, 0, 1, 2])
    >>> scan_obj(path, read=True).vertices.tolist()
    [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]]
    >>> tmp.cleanup()
    """
    path = Path(path)
    data = path.read_bytes()
    where = f"cannot read {noun} {path}"
    materials = b"usemtl" in data
    a = np.frombuffer(data, dtype=np.uint8)
    newline = np.flatnonzero(a == 10)
    starts, ends = np.r_[0, newline + 1], np.r_[newline, a.size]
    keyword = ends - starts >= 2  # a keyword and a space at least
    head = a[np.minimum(starts, a.size - 1)] if a.size else np.zeros(0, np.uint8)
    spaced = keyword & is_space(a[np.minimum(starts + 1, max(a.size - 1, 0))] if a.size else head)
    is_v = spaced & (head == ord("v"))
    is_f = spaced & (head == ord("f"))
    if not is_f.any():
        return FileScan(None, None, materials)
    lines = np.flatnonzero(is_f)
    before = np.cumsum(is_v)[lines]  # vertices read before each face line
    n_vertices = int(is_v.sum())
    text, corners, first = _keyword_lines(data, starts[lines], ends[lines])
    number = np.repeat(lines + 1, corners)
    few = corners < 3
    if few.any():
        i = int(np.flatnonzero(few)[0])
        raise InvalidMeshError(f"{where}: line {lines[i] + 1}: a face with {corners[i]} corner"
                               f"{'' if corners[i] == 1 else 's'} (a face needs at least 3)")
    t = np.frombuffer(text, dtype=np.uint8)
    odd = (t > 57) & (t != ord("f"))
    odd |= (t > 32) & (t < 47)
    if not read and not odd.any() and not (t[first] == ord("0")).any():  # digits, slashes, spaces: positive
        past = _leading_integers(t, first, len(str(n_vertices))) > n_vertices  # whole numbers; their range is left
        if past.any():
            k = int(np.flatnonzero(past)[0])
            index = _vertex_indices(t, first[k:k + 1], where)
            raise InvalidMeshError(f"{where}: line {number[k]}: a face references vertex {index[0]:.0f} but the "
                                   f"file has {n_vertices} vertices")
        if corners.max() == 3:  # triangles only: nothing more to parse
            return FileScan(None, None, materials)
    index = _vertex_indices(t, first, where)
    relative = np.repeat(before, corners)
    problems = [
        (~integral(index), lambda k: f"the face's vertex index {index[k]:g} is not a whole number"),
        (index == 0, lambda k: "a face references vertex 0, but OBJ indices start at 1 (-1 is the last vertex read)"),
        (index > n_vertices, lambda k: f"a face references vertex {index[k]:.0f} but the file has "
                                       f"{n_vertices} vertices"),
        (index + relative < 0, lambda k: f"a face references vertex {index[k]:.0f}, counting back from the "
                                         f"{relative[k]} vertices read so far: before the first one"),
    ]
    for bad, why in problems:
        if bad.any():
            k = int(np.flatnonzero(bad)[0])
            raise InvalidMeshError(f"{where}: line {number[k]}: {why(k)}")
    vertices = _plain_vertices(data, starts[is_v], ends[is_v]) if read else None
    polygons = None
    if corners.max() > 3 or vertices is not None:
        vertex = np.where(index < 0, relative + index, index - 1).astype(np.int64)
        polygons = (np.r_[0, np.cumsum(corners)].astype(np.int64), vertex)
    if vertices is not None:  # read: no library needs the text
        return FileScan(None, polygons, materials, vertices)
    if corners.max() == 3:
        polygons = None
    return FileScan(_absolute(data) if (index < 0).any() else None, polygons, materials)


def _plain_vertices(data, starts, ends):
    """The ``(n, 3)`` positions of the vertex lines ``data[starts[i]:ends[i]]`` (their first three numbers), or
    None where a line is not plain (fewer than 3 numbers, a token that is not one, a line continued with ``\\``)."""
    if b"\\" in data:
        return None
    text, tokens, _ = _keyword_lines(data, starts, ends)
    if tokens.size == 0 or tokens.min() < 3:
        return None if tokens.size else np.zeros((0, 3))
    if text.count(b"v") != tokens.size:  # a "v" inside a token ("1v"): not a number
        return None
    try:
        values = numbers(text.replace(b"v", b" "), int(tokens.sum()), "vertex lines")
    except InvalidMeshError:  # a token that is not a number: trimesh says what it makes of it
        return None
    first = np.r_[0, np.cumsum(tokens)[:-1]]
    return values[first[:, None] + np.arange(3)]


def _keyword_lines(data, starts, ends):
    """The text of the lines ``data[starts[i]:ends[i]]`` (face or vertex lines), each line's number of tokens
    after its keyword (a face's corners), and where each of those tokens starts in the text."""
    breaks = np.flatnonzero(starts[1:] != ends[:-1] + 1)  # runs of consecutive face lines: one slice each
    run_starts, run_ends = starts[np.r_[0, breaks + 1]], ends[np.r_[breaks, starts.size - 1]]
    text = b"\n".join([data[s:e] for s, e in zip(run_starts.tolist(), run_ends.tolist())])
    shift = run_starts - np.r_[0, np.cumsum(run_ends - run_starts + 1)[:-1]]
    offset = starts - np.repeat(shift, np.diff(np.r_[0, breaks + 1, starts.size]))  # each line's "f" in ``text``
    t = np.frombuffer(text, dtype=np.uint8)
    space = is_space(t)
    corner = ~space
    corner[1:] &= space[:-1]
    corner[offset] = False  # the "f"
    corners = count_between(corner, np.r_[offset, t.size])
    return text, corners, np.flatnonzero(corner)


def _leading_integers(t, first, digits):
    """The unsigned integers of digits that start at ``first`` in ``t``: exact for up to ``digits`` digits.

    Longer numbers come out as ``inf``: above any index with ``digits`` digits.
    """
    gap = is_space(t)
    gap |= t == ord("/")
    starts = ~gap
    starts[1:] &= gap[:-1]
    stops = ~gap
    stops[:-1] &= gap[1:]
    is_first = np.zeros(t.size, dtype=bool)
    is_first[first] = True
    length = (np.flatnonzero(stops) + 1 - np.flatnonzero(starts))[is_first[starts]]
    value = np.zeros(first.size)
    value[length > digits] = np.inf
    long = np.flatnonzero(length == digits)  # the only ones that may be past the last vertex: parse them
    parsed = np.zeros(long.size)
    for j in range(digits):
        parsed = parsed * 10 + (t[first[long] + j] - 48)
    value[long] = parsed
    return value


def _vertex_indices(t, first, where):
    """Each corner's vertex index (the number before its first ``/``)."""
    slash = t == ord("/")
    if slash[first].any():
        raise InvalidMeshError(f"{where}: a face corner without a vertex index")
    gap = is_space(t) | slash | (t == ord("f"))
    number = ~gap
    number[1:] &= gap[:-1]
    values = numbers(t.tobytes().replace(b"/", b" ").replace(b"f", b" "), int(number.sum()),
                     f"{where}: the face lines")
    corner = np.zeros(t.size, dtype=bool)
    corner[first] = True
    return values[corner[number]]


def _absolute(data):
    """``data`` with relative indices made absolute (a loop over lines: only files that have them pay it)."""
    out, seen = [], {b"v": 0, b"vt": 0, b"vn": 0}
    for raw in data.split(b"\n"):
        key = raw.split(None, 1)[0] if raw[:1] in (b"v", b"f") and raw.strip() else b""
        if key in seen:
            seen[key] += 1
        elif key == b"f" and b"-" in raw:
            corners = []
            for corner in raw.split()[1:]:
                parts = corner.split(b"/")
                for j, (part, kind) in enumerate(zip(parts, (b"v", b"vt", b"vn"))):
                    if part.startswith(b"-"):
                        parts[j] = b"%d" % (seen[kind] + int(part) + 1)
                corners.append(b"/".join(parts))
            raw = b"f " + b" ".join(corners) + (b"\r" if raw.endswith(b"\r") else b"")
        out.append(raw)
    return b"\n".join(out)
