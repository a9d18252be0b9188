"""Checking that a mesh file holds what it declares, before a library reads it.

Readers trust what a file says: a PLY or OFF header's counts, an OBJ face's
indices. A file that lies there was read as another mesh, with exit status 0
(faces past a header's count dropped, ``f 0 1 2`` read as ``0 0 1``, relative
OBJ indices resolved against the wrong vertices), or not at all (a binary PLY
header declaring ``10**9`` faces kept meshio walking for minutes).
:func:`check_mesh_file` runs the check for the file's format
(:mod:`heatcore.io.plycheck`, :mod:`heatcore.io.objcheck`, :func:`check_off`
here), each a numpy scan of the file, and every reader of :mod:`heatcore.io`
calls it: a file that lies is an :class:`~heatcore.errors.InvalidMeshError`.

Examples
--------
>>> from heatcore.io import demo_mesh_path
>>> check_mesh_file(demo_mesh_path()) is None  # spot.obj: no relative index to resolve
True
"""

import re
from pathlib import Path

import numpy as np

from ..domains.validate import one_based_hint
from ..errors import InvalidMeshError
from .objcheck import FileScan, scan_obj
from .plycheck import check_ply_body
from .textscan import integral, numbers, ranges, scan_lines


def check_mesh_file(path, noun="mesh file"):
    """Check a PLY, OFF or OBJ file against what it declares (other formats pass as they are).

    Parameters
    ----------
    path : str or path-like
    noun : str, default "mesh file"
        What the file is, for the message.

    Returns
    -------
    bytes or None
        For an OBJ file with relative (negative) indices, its text with them
        made absolute (see :func:`~heatcore.io.objcheck.check_obj`): what the
        libraries must read instead of the file. None otherwise.

    Raises
    ------
    InvalidMeshError
        The file does not hold what it declares.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> tmp = tempfile.TemporaryDirectory()
    >>> path = pathlib.Path(tmp.name) / "frac.obj"
    >>> _ = path.write_text("v 0 0 0\\nv 1 0 0\\nv 0 1 0\\nf 1 2 2.7\\n")
    >>> check_mesh_file(path)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    heatcore.errors.InvalidMeshError: cannot read mesh file ...frac.obj: line 4: the face's vertex index 2.7 is not a whole number
    >>> tmp.cleanup()
    """
    return scan_mesh_file(path, noun).text


def scan_mesh_file(path, noun="mesh file", read=False):
    """Check a mesh file as :func:`check_mesh_file` does; also an OBJ or OFF file's polygons.

    Parameters
    ----------
    path : str or path-like
    noun : str, default "mesh file"
        What the file is, for the message.
    read : bool, default False
        Also read a plain OBJ file's vertices and faces (:func:`~heatcore.io.objcheck.scan_obj`).

    Returns
    -------
    heatcore.io.objcheck.FileScan
        ``text`` as :func:`check_mesh_file` returns it; ``polygons``, the
        ``(offsets, corners)`` of every face of an OBJ or OFF file that has a
        face of more than 3 corners (None otherwise); ``materials``, whether
        an OBJ file has ``usemtl`` lines; ``vertices``, an OFF file's
        vertices where it has polygons (trimesh fails on an OFF file of
        triangles and larger polygons mixed), and a plain OBJ file's with
        ``read`` (``polygons`` then lists every face).

    Raises
    ------
    InvalidMeshError
        The file does not hold what it declares.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> tmp = tempfile.TemporaryDirectory()
    >>> path = pathlib.Path(tmp.name) / "quad.off"
    >>> _ = path.write_text("OFF\\n4 1 0\\n0 0 0\\n1 0 0\\n1 1 0\\n0 1 0\\n4 0 1 2 3\\n")
    >>> [a.tolist() for a in scan_mesh_file(path).polygons]
    [[0, 4], [0, 1, 2, 3]]
    >>> tmp.cleanup()
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix == ".obj":
        return scan_obj(path, noun, read=read)
    if suffix == ".ply":
        check_ply_body(path, noun=noun)
    elif suffix == ".off":
        polygons = check_off(path, noun)
        if polygons is not None:
            return FileScan(None, polygons[:2], False, polygons[2])
    return FileScan(None, None, False)


def check_off(path, noun="mesh file"):
    """Check an OFF file's vertex and face lines against the counts it declares.

    As trimesh and potpourri3d read it: ``#`` comments, the ``OFF`` keyword
    (``COFF``, ``NOFF``, ...), the counts ``nv nf [ne]`` (on that line or
    the next), then ``nv`` vertex lines of at least 3 numbers and ``nf`` face
    lines ``k i_1 ... i_k`` (colour values may follow).

    Parameters
    ----------
    path : str or path-like
    noun : str, default "mesh file"
        What the file is, for the message.

    Returns
    -------
    tuple or None
        ``(offsets, corners, vertices)``: every face's corners and the
        ``(n, 3)`` vertices when some face has more than 3 corners; None when
        all are triangles (the vertices are not parsed then).

    Raises
    ------
    InvalidMeshError
        Fewer or more lines than declared, a face with fewer indices than its
        count, a fractional count or index, or an index out of range.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> tmp = tempfile.TemporaryDirectory()
    >>> path = pathlib.Path(tmp.name) / "more.off"
    >>> _ = path.write_text("OFF\\n3 2 0\\n0 0 0\\n1 0 0\\n0 1 0\\n3 0 1 2\\n")
    >>> check_off(path)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    heatcore.errors.InvalidMeshError: cannot read mesh file ...more.off: its OFF header declares 2 faces but the data ends after 1 of them (a truncated file, or a header that overcounts)
    >>> tmp.cleanup()
    """
    path = Path(path)
    where = f"cannot read {noun} {path}"
    data = path.read_bytes()
    if b"#" in data:  # blank comments out, keeping every byte (and line number) in place
        data = re.sub(rb"#[^\n]*", lambda m: b" " * len(m.group()), data)
    lines = scan_lines(data)
    if lines.start.size == 0:
        return None
    head = data[lines.start[0]:lines.end[0]].split()
    if not head[0].endswith(b"OFF") or b"BINARY" in head[1:]:
        return None  # not an OFF text file: left to the readers to refuse
    counts, rest = (head[1:], 1) if len(head) > 1 else (data[lines.start[1]:lines.end[1]].split() if lines.start.size > 1 else [], 2)
    try:
        n_vertices, n_faces = int(counts[0]), int(counts[1])
    except (IndexError, ValueError):
        raise InvalidMeshError(f"{where}: the OFF counts line {b' '.join(counts).decode(errors='replace')!r} "
                               "does not give the numbers of vertices and faces") from None
    vertices = lines.take(slice(rest, rest + n_vertices))
    faces = lines.take(slice(rest + n_vertices, rest + n_vertices + n_faces))
    few = vertices.tokens < 3
    if few.any():
        i = int(np.flatnonzero(few)[0])
        raise InvalidMeshError(f"{where}: line {vertices.number[i]}: vertex {i} has {vertices.tokens[i]} "
                               "coordinates, not 3")
    for got, declared, name in ((vertices.start.size, n_vertices, "vertices"), (faces.start.size, n_faces, "faces")):
        if got < declared:
            _check_off_faces(data, faces, n_vertices, where)
            raise InvalidMeshError(f"{where}: its OFF header declares {declared} {name} but the data ends after "
                                   f"{got} of them (a truncated file, or a header that overcounts)")
    polygons = _check_off_faces(data, faces, n_vertices, where)
    extra = lines.start.size - (rest + n_vertices + n_faces)
    if extra > 0:
        raise InvalidMeshError(f"{where}: {extra} more line{'s' if extra > 1 else ''} of data follow"
                               f"{'s' if extra == 1 else ''} the {n_faces} faces its OFF header declares "
                               f"(line {lines.number[rest + n_vertices + n_faces]}: a header that undercounts, "
                               "or trailing data)")
    if polygons is None:
        return None
    values = numbers(data[vertices.start[0]:vertices.end[-1]], int(vertices.tokens.sum()), f"{where}: the vertex lines")
    first = np.r_[0, np.cumsum(vertices.tokens)[:-1]]
    return (*polygons, values[first[:, None] + np.arange(3)])


def _check_off_faces(data, faces, n_vertices, where):
    """The faces' ``(offsets, corners)`` when some face has more than 3 corners, else None."""
    if faces.start.size == 0:
        return None
    values = numbers(data[faces.start[0]:faces.end[-1]], int(faces.tokens.sum()), f"{where}: the face lines")
    first = np.r_[0, np.cumsum(faces.tokens)[:-1]]
    count = values[first]
    problems = [
        (~integral(count) | (count < 3), lambda i: f"face {i} has {count[i]:g} corners (a whole number >= 3)"),
        (faces.tokens < 1 + np.where(integral(count), count, 0),
         lambda i: f"face {i} has {faces.tokens[i] - 1} indices, fewer than its count {count[i]:g}"),
    ]
    for bad, why in problems:
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            raise InvalidMeshError(f"{where}: line {faces.number[i]}: {why(i)}")
    count = count.astype(np.int64)
    index = values[ranges(first + 1, count)]
    face = np.repeat(np.arange(count.size), count)
    for bad, why in ((~integral(index), "is not a whole number"),
                     ((index < 0) | (index >= n_vertices), f"is out of range (the file has {n_vertices} vertices)")):
        if bad.any():
            k = int(np.flatnonzero(bad)[0])
            hint = one_based_hint(index, n_vertices) if why.startswith("is out") else ""
            raise InvalidMeshError(f"{where}: line {faces.number[face[k]]}: face {face[k]} references vertex "
                                   f"{index[k]:g}, which {why}{hint}")
    return (np.r_[0, np.cumsum(count)], index.astype(np.int64)) if count.max() > 3 else None
