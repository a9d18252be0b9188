"""PLY headers, and PLY files of triangle strips (which meshio rejects).

The Stanford scans (igea.ply and others) store their surface as
``element tristrips`` with one ``property list int int vertex_indices``:
strips separated by ``-1``. meshio refuses the element, trimesh parses it
only when every row has the same length (binary), and pymeshlab reads it
but crashes the process on a strip index out of range; so the few lines of
PLY parsing it takes live here: the header, then each element in order
(scalar-only elements as one numpy read, list elements row by row).

Examples
--------
>>> import tempfile, pathlib
>>> tmp = tempfile.TemporaryDirectory()
>>> path = pathlib.Path(tmp.name) / "strip.ply"
>>> _ = path.write_text(
...     "ply\\nformat ascii 1.0\\nelement vertex 4\\nproperty float x\\nproperty float y\\n"
...     "property float z\\nelement tristrips 1\\nproperty list int int vertex_indices\\nend_header\\n"
...     "0 0 0\\n1 0 0\\n0 1 0\\n1 1 0\\n4 0 1 2 3\\n")
>>> V, F, data = read_tristrips(path)
>>> V.shape, F.tolist()
((4, 3), [[0, 1, 2], [2, 1, 3]])
>>> tmp.cleanup()
"""

from pathlib import Path
from typing import NamedTuple

import numpy as np

from ..errors import InvalidMeshError, short

#: A PLY header longer than this is not a header.
MAX_HEADER_BYTES = 1 << 20
#: PLY scalar types and their numpy codes (without byte order).
PLY_TYPES = {
    "char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2", "int16": "i2",
    "ushort": "u2", "uint16": "u2", "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
    "float": "f4", "float32": "f4", "double": "f8", "float64": "f8",
}


class Element(NamedTuple):
    """One ``element`` of a PLY header.

    Attributes
    ----------
    name : str
    count : int
        Number of rows.
    properties : list
        ``(name, code)`` for scalars, ``(name, count code, item code)`` for
        lists (numpy type codes without byte order).

    Examples
    --------
    >>> Element("vertex", 3, [("x", "f4"), ("y", "f4"), ("z", "f4")]).count
    3
    """

    name: str
    count: int
    properties: list  # (name, code) for scalars, (name, count code, item code) for lists


class Header(NamedTuple):
    """A parsed PLY header (see :func:`read_header`).

    Attributes
    ----------
    format : str
        "ascii", "binary_little_endian" or "binary_big_endian".
    elements : list of Element
        In file order.
    size : int
        Bytes up to and including the ``end_header`` line.

    Examples
    --------
    >>> Header("ascii", [Element("vertex", 3, []), Element("face", 1, [])], 80).counts()
    {'vertex': 3, 'face': 1}
    """

    format: str  # "ascii", "binary_little_endian" or "binary_big_endian"
    elements: list
    size: int  # bytes up to and including the end_header line

    def counts(self):
        """``{element name: count}``."""
        return {e.name: e.count for e in self.elements}


def read_header(path):
    """Parse the header of a PLY file.

    Parameters
    ----------
    path : str or path-like

    Returns
    -------
    Header

    Raises
    ------
    InvalidMeshError
        Not a PLY file, an unknown format or type, or no ``end_header`` line.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> tmp = tempfile.TemporaryDirectory()
    >>> path = pathlib.Path(tmp.name) / "h.ply"
    >>> _ = path.write_text("ply\\nformat ascii 1.0\\nelement vertex 0\\nproperty float x\\nend_header\\n")
    >>> read_header(path).counts()
    {'vertex': 0}
    >>> tmp.cleanup()
    """
    path = Path(path)
    with open(path, "rb") as f:
        head = f.read(MAX_HEADER_BYTES)
    if head.split(b"\n", 1)[0].strip() != b"ply":
        raise InvalidMeshError(f"cannot read {path}: not a PLY file (it does not start with 'ply')")
    end = head.find(b"end_header")
    if end < 0:
        raise InvalidMeshError(f"cannot read {path}: the PLY header has no end_header line (a truncated file?)")
    size = head.find(b"\n", end) + 1 or len(head)
    fmt, elements = None, []
    for raw in head[:end].split(b"\n")[1:]:
        words = raw.decode("ascii", "replace").split()

        def bad(why):
            return InvalidMeshError(f"{path}: {why} in the PLY header line {short(' '.join(words), 80)!r}")

        if not words or words[0] in ("comment", "obj_info"):
            continue
        if words[0] == "format":
            if len(words) < 2 or words[1] not in ("ascii", "binary_little_endian", "binary_big_endian"):
                raise bad("unknown format")
            fmt = words[1]
        elif words[0] == "element":
            if len(words) != 3 or not words[2].isdigit():
                raise bad("a malformed element")
            elements.append(Element(words[1], int(words[2]), []))
        elif words[0] == "property":
            if not elements:
                raise bad("a property before any element")
            if words[1:2] == ["list"] and len(words) == 5 and words[2] in PLY_TYPES and words[3] in PLY_TYPES:
                elements[-1].properties.append((words[4], PLY_TYPES[words[2]], PLY_TYPES[words[3]]))
            elif len(words) == 3 and words[1] in PLY_TYPES:
                elements[-1].properties.append((words[2], PLY_TYPES[words[1]]))
            else:
                raise bad("an unknown property type")
    if fmt is None:
        raise InvalidMeshError(f"{path}: the PLY header has no format line")
    return Header(fmt, elements, size)


def read_elements(path, header=None):
    """Every element of a PLY file: ``{name: {property: values}}``.

    Scalar properties are ``(count,)`` arrays; list properties are lists of
    arrays (one per row).

    Parameters
    ----------
    path : str or path-like
    header : Header, optional
        Already parsed (:func:`read_header`).

    Returns
    -------
    dict of {str: dict of {str: array or list of arrays}}

    Raises
    ------
    InvalidMeshError
        The data ends before the header's elements do.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> tmp = tempfile.TemporaryDirectory()
    >>> path = pathlib.Path(tmp.name) / "e.ply"
    >>> _ = path.write_text("ply\\nformat ascii 1.0\\nelement vertex 2\\nproperty float x\\n"
    ...                     "element face 1\\nproperty list uchar int vertex_indices\\nend_header\\n"
    ...                     "0.5\\n2\\n3 0 1 1\\n")
    >>> elements = read_elements(path)
    >>> elements["vertex"]["x"].tolist(), [row.tolist() for row in elements["face"]["vertex_indices"]]
    ([0.5, 2.0], [[0, 1, 1]])
    >>> tmp.cleanup()
    """
    path = Path(path)
    header = header or read_header(path)
    with open(path, "rb") as f:
        body = f.read()[header.size:]
    try:
        if header.format == "ascii":
            return _ascii(body.split(), header.elements)
        return _binary(body, header.elements, "<" if header.format.endswith("little_endian") else ">")
    except (IndexError, ValueError) as exc:
        raise InvalidMeshError(
            f"{path}: the data ends before the elements its header declares, or does not match them "
            f"(a truncated or corrupt file?): {type(exc).__name__}"
        ) from None


def _ascii(tokens, elements):
    out, pos = {}, 0
    for e in elements:
        if all(len(p) == 2 for p in e.properties):
            n = e.count * len(e.properties)
            if pos + n > len(tokens):
                raise IndexError("end of data")
            table = np.array(tokens[pos:pos + n]).reshape(e.count, len(e.properties))
            out[e.name] = {p[0]: table[:, j].astype(p[1]) for j, p in enumerate(e.properties)}
            pos += n
            continue
        columns = {p[0]: [] for p in e.properties}
        for _ in range(e.count):
            for p in e.properties:
                if len(p) == 2:
                    columns[p[0]].append(float(tokens[pos]))
                    pos += 1
                else:
                    k = int(tokens[pos])
                    if k < 0 or pos + 1 + k > len(tokens):
                        raise IndexError("end of data")
                    columns[p[0]].append(np.array(tokens[pos + 1:pos + 1 + k]).astype(p[2]))
                    pos += 1 + k
        out[e.name] = columns
    return out


def _binary(body, elements, order):
    out, offset = {}, 0
    for e in elements:
        if all(len(p) == 2 for p in e.properties):
            dtype = np.dtype([(p[0], order + p[1]) for p in e.properties])
            table = np.frombuffer(body, dtype, e.count, offset)
            out[e.name] = {name: table[name] for name in dtype.names}
            offset += e.count * dtype.itemsize
            continue
        columns = {p[0]: [] for p in e.properties}
        for _ in range(e.count):
            for p in e.properties:
                dtype = np.dtype(order + p[1])
                value = np.frombuffer(body, dtype, 1, offset)[0]
                offset += dtype.itemsize
                if len(p) == 2:
                    columns[p[0]].append(value)
                    continue
                item = np.dtype(order + p[2])
                k = int(value)
                if k < 0:
                    raise ValueError("negative list length")
                columns[p[0]].append(np.frombuffer(body, item, k, offset))
                offset += k * item.itemsize
        out[e.name] = columns
    return out


def strip_triangles(stream):
    """Triangles of triangle strips, ``-1`` between strips (the PLY ``tristrips`` convention).

    Every other triangle of a strip is flipped so that all keep the first
    one's orientation; triangles with a repeated vertex (the zero-area joins
    some files use instead of ``-1``) are left out.

    Parameters
    ----------
    stream : (k,) array_like of int

    Returns
    -------
    (m, 3) int64 array

    Examples
    --------
    >>> strip_triangles([0, 1, 2, 3, -1, 4, 5, 6]).tolist()
    [[0, 1, 2], [2, 1, 3], [4, 5, 6]]
    """
    s = np.asarray(stream, dtype=np.int64).ravel()
    if s.size < 3:
        return np.zeros((0, 3), dtype=np.int64)
    sep = s == -1
    pos = np.arange(s.size)
    k = pos - np.maximum.accumulate(np.where(sep, pos, -1)) - 1  # place within its strip
    i = pos[:-2][~(sep[:-2] | sep[1:-1] | sep[2:])]
    a, b, c = s[i], s[i + 1], s[i + 2]
    odd = k[i] % 2 == 1
    F = np.column_stack([np.where(odd, b, a), np.where(odd, a, b), c])
    return F[(F[:, 0] != F[:, 1]) & (F[:, 1] != F[:, 2]) & (F[:, 0] != F[:, 2])]


def read_tristrips(path, header=None):
    """Vertices, triangles and other vertex properties of a PLY file of triangle strips.

    Parameters
    ----------
    path : str or path-like
    header : Header, optional
        Already parsed.

    Returns
    -------
    V : (n, 3) float array
        Every vertex, in file order.
    F : (m, 3) int64 array
        The strips' triangles (indices not checked here: the mesh does that).
    vertex_data : dict of (n,) arrays
        The other scalar vertex properties (``flags``, ``confidence``, ...).

    Raises
    ------
    InvalidMeshError
        No ``x y z`` vertex properties, no ``vertex_indices`` list, no triangle,
        or data that does not match the header.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> tmp = tempfile.TemporaryDirectory()
    >>> path = pathlib.Path(tmp.name) / "strip.ply"
    >>> _ = path.write_text(
    ...     "ply\\nformat ascii 1.0\\nelement vertex 4\\nproperty float x\\nproperty float y\\n"
    ...     "property float z\\nelement tristrips 1\\nproperty list int int vertex_indices\\nend_header\\n"
    ...     "0 0 0\\n1 0 0\\n0 1 0\\n1 1 0\\n4 0 1 2 3\\n")
    >>> V, F, data = read_tristrips(path)
    >>> V.shape, F.tolist(), data
    ((4, 3), [[0, 1, 2], [2, 1, 3]], {})
    >>> tmp.cleanup()
    """
    path = Path(path)
    elements = read_elements(path, header)
    vertex = elements.get("vertex", {})
    if not all(c in vertex for c in "xyz"):
        raise InvalidMeshError(f"{path}: its vertices have no x, y and z properties")
    V = np.column_stack([np.asarray(vertex[c], dtype=float) for c in "xyz"])
    rows = elements.get("tristrips", {}).get("vertex_indices")
    if rows is None:
        raise InvalidMeshError(f"{path}: its tristrips element has no vertex_indices list")
    stream = np.concatenate([np.r_[np.asarray(r, dtype=np.int64), -1] for r in rows] or [np.zeros(0, np.int64)])
    F = strip_triangles(stream)
    if len(F) == 0:
        raise InvalidMeshError(f"{path} holds no triangles (its triangle strips are empty)")
    data = {k: np.asarray(v) for k, v in vertex.items() if k not in ("x", "y", "z") and isinstance(v, np.ndarray)}
    return V, F, data
