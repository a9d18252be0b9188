"""What an input path holds, before a reader opens it: a regular, non-empty, uncompressed file.

A reader handed a folder, a FIFO or ``/dev/null`` either blocks, reads nothing
or says "not found"; handed a gzip stream named ``.obj``, or a binary STL whose
triangle count does not match its size, trimesh tried to decode it as text and
failed on a missing optional package (``charset_normalizer``). Every reader of
:mod:`heatcore.io` calls :func:`check_input_file` first, so that each of these
is one :class:`~heatcore.errors.InvalidMeshError` about the file.
:func:`utf8_text` gives the text readers UTF-8 (the files :func:`is_text_mesh`
names): a byte that is not UTF-8 (a Latin-1 ``é`` in a comment) is read as Latin-1.

Examples
--------
>>> check_input_file("/dev/null")
Traceback (most recent call last):
...
heatcore.errors.InvalidMeshError: cannot read mesh file /dev/null: it is a character device, not a regular file
>>> utf8_text(b"# caf\\xe9\\nv 0 0 0\\n")
b'# caf\\xc3\\xa9\\nv 0 0 0\\n'
"""

import stat
import struct
from pathlib import Path

from ..errors import InvalidMeshError

#: The first bytes of compressed archives, and what to do about them.
COMPRESSED = {b"\x1f\x8b": "gzip-compressed (decompress it first: gunzip)",
              b"PK\x03\x04": "a zip archive (extract the mesh file first)",
              b"BZh": "bzip2-compressed (decompress it first: bunzip2)",
              b"\xfd7zXZ\x00": "xz-compressed (decompress it first: unxz)"}

#: Suffixes whose files are read as text (or, for STL, as text or binary): a compressed one cannot be read.
TEXT_SUFFIXES = {".obj", ".off", ".ply", ".stl", ".txt", ".xyz", ".pts", ".csv", ".vtk", ".msh"}

_NOT_REGULAR = ((stat.S_ISDIR, "a folder"), (stat.S_ISFIFO, "a FIFO (named pipe)"),
                (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
                (stat.S_ISSOCK, "a socket"))


def check_input_file(path, noun="mesh file"):
    """Raise unless ``path`` is a regular, non-empty file that is not compressed, and a whole binary STL.

    Parameters
    ----------
    path : str or path-like
    noun : str, default "mesh file"
        What the file is, for the message.

    Raises
    ------
    InvalidMeshError
        No such file; a folder, FIFO, device or socket; an empty file; a
        compressed file with a mesh suffix; a binary STL whose size does not
        match its triangle count.

    Examples
    --------
    >>> check_input_file("no/such/file.obj")
    Traceback (most recent call last):
    ...
    heatcore.errors.InvalidMeshError: mesh file not found: no/such/file.obj
    """
    path = Path(path)
    try:
        info = path.stat()
    except OSError:
        raise InvalidMeshError(f"{noun} not found: {path}") from None
    for test, what in _NOT_REGULAR:
        if test(info.st_mode):
            raise InvalidMeshError(f"cannot read {noun} {path}: it is {what}, not a regular file")
    size = info.st_size
    if size == 0:
        raise InvalidMeshError(f"{path} is empty (0 bytes)")
    with open(path, "rb") as f:
        head = f.read(84)
    if path.suffix.lower() in TEXT_SUFFIXES:
        for magic, what in COMPRESSED.items():
            if head.startswith(magic):
                raise InvalidMeshError(f"cannot read {noun} {path}: it is {what}")
    if path.suffix.lower() == ".stl":
        check_stl_size(path, head, size, noun)


def check_stl_size(path, head, size, noun="mesh file"):
    """Raise when a binary STL's size is not 84 bytes plus 50 per triangle its header counts.

    A file that begins with ``solid`` is taken as text (ASCII STL) and not
    checked here, unless its size is a binary STL's (some binary headers begin
    with ``solid`` too).

    Parameters
    ----------
    path : path-like
    head : bytes
        The file's first 84 bytes (or all of it, when shorter).
    size : int
        The file's size in bytes.
    noun : str, default "mesh file"

    Examples
    --------
    >>> check_stl_size("t.stl", bytes(80) + (3).to_bytes(4, "little"), 134)
    Traceback (most recent call last):
    ...
    heatcore.errors.InvalidMeshError: cannot read mesh file t.stl: its binary STL header declares 3 triangles (84 + 50 x 3 = 234 bytes) but the file has 134 bytes (a truncated file, or a wrong count)
    """
    if not _binary_stl(head, size):
        return  # ASCII STL
    if len(head) < 84:
        raise InvalidMeshError(f"cannot read {noun} {path}: {size} bytes, too short for a binary STL "
                               "(84-byte header) and not an ASCII STL")
    (count,) = struct.unpack("<I", head[80:84])
    if size != 84 + 50 * count:
        raise InvalidMeshError(f"cannot read {noun} {path}: its binary STL header declares {count} triangles "
                               f"(84 + 50 x {count} = {84 + 50 * count} bytes) but the file has {size} bytes "
                               "(a truncated file, or a wrong count)")


def _binary_stl(head, size):
    """Whether an STL file of ``size`` bytes starting with ``head`` is binary (as trimesh decides)."""
    if not head.lstrip().startswith(b"solid"):
        return True
    return len(head) >= 84 and size == 84 + 50 * struct.unpack("<I", head[80:84])[0]


def is_text_mesh(path):
    """Whether trimesh reads ``path`` as text: an OBJ, an OFF or an ASCII STL file.

    Examples
    --------
    >>> from heatcore.io import demo_mesh_path
    >>> is_text_mesh(demo_mesh_path()), is_text_mesh("scene.glb")
    (True, False)
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix != ".stl":
        return suffix in (".obj", ".off")
    with open(path, "rb") as f:
        return not _binary_stl(f.read(84), path.stat().st_size)


def utf8_text(data):
    """``data`` (bytes) as UTF-8 bytes: itself when it is ASCII or UTF-8, else decoded as Latin-1.

    Text mesh formats are ASCII but for comments and names; a byte that is not
    UTF-8 there (an editor's Latin-1 ``é``) must not stop the read.

    Parameters
    ----------
    data : bytes

    Returns
    -------
    bytes

    Examples
    --------
    >>> utf8_text(b"v 0 0 0\\n") == b"v 0 0 0\\n", utf8_text("é".encode()) == "é".encode()
    (True, True)
    """
    if data.isascii():
        return data
    try:
        data.decode("utf-8")
    except UnicodeDecodeError:
        return data.decode("latin-1").encode("utf-8")
    return data
