"""Polylines as files: OBJ (``v`` + ``l``), legacy VTK (line cells) and PLY (vertex + edge).

No one format keeps the segments in every reader (measured with meshio 5.3
and trimesh 5.2; :data:`CURVE_READERS` says it once for the help texts):
OBJ's ``l`` elements are edges in MeshLab and Blender, but trimesh and
meshio load only the points; a legacy ``.vtk`` file of ``VTK_LINE`` cells
(:func:`write_vtk_curves`) is read by meshio (``line`` cells, the curve
of each as cell data ``curve``) and ParaView, while trimesh (through
meshio) keeps only the points; a PLY with an ``edge`` element
(:func:`write_ply_curves`) is a ``Path3D`` with its segments in trimesh,
while meshio refuses it. :func:`write_curves` picks the writer by suffix.

OBJ files: ``v`` lines for the points, an ``l`` line per segment.

MeshLab and PyMeshLab load the ``l`` elements as the edges of an edge mesh
(their reader takes one edge from an ``l`` line, so each segment has its own);
Blender's OBJ importer (``bpy.ops.wm.obj_import``) makes them the edges of a
mesh object, which Object > Convert > Curve turns into one spline per curve
(cyclic where the curve is closed). A closed curve's last segment comes back
to its first vertex. The vertices are written once each, curve after curve,
each curve after a comment line.

Examples
--------
>>> import io, numpy as np
>>> out = io.StringIO()
>>> square = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)
>>> write_obj_curves(out, [(square, True), (square[:2], False)], header="two curves")
>>> print(out.getvalue())
# two curves
# curve 0: 4 points, closed
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
l 1 2
l 2 3
l 3 4
l 4 1
# curve 1: 2 points, open
v 0 0 0
v 1 0 0
l 5 6
<BLANKLINE>
"""

from pathlib import Path

import numpy as np

#: The polyline formats and which readers keep the segments (the help texts of ``path``,
#: ``trace`` and ``--isolines-out`` quote it).
CURVE_READERS = {
    ".obj": "v and l elements: edges in MeshLab and Blender; trimesh and meshio load only the points",
    ".vtk": "legacy VTK line cells: segments in meshio (cell data 'curve') and ParaView; trimesh only the points",
    ".ply": "vertex and edge elements: a Path3D with its segments in trimesh; meshio refuses the edge element",
}


def curve_formats_help():
    """One sentence for ``--help``: each polyline suffix and which readers keep its segments.

    Examples
    --------
    >>> curve_formats_help().split("; ")[0]
    '.obj (v and l elements: edges in MeshLab and Blender'
    """
    return "; ".join(f"{suffix} ({what})" for suffix, what in CURVE_READERS.items())


def _curve_parts(curves):
    """Each curve's points ``(k, 3)`` and its segments as index pairs into the stacked points."""
    points, segments, owner, offset = [], [], [], 0
    for j, curve in enumerate(curves):
        pts, closed = (curve.points, curve.closed) if hasattr(curve, "points") else curve
        pts = np.asarray(pts, dtype=float).reshape(-1, 3)
        index = list(range(offset, offset + len(pts))) + ([offset] if closed and len(pts) > 2 else [])
        pairs = np.column_stack([index[:-1], index[1:]]).astype(np.int64).reshape(-1, 2)
        points.append(pts)
        segments.append(pairs)
        owner.append(np.full(len(pairs), j, dtype=np.int64))
        offset += len(pts)
    if not points:
        return np.zeros((0, 3)), np.zeros((0, 2), np.int64), np.zeros(0, np.int64)
    return np.concatenate(points), np.concatenate(segments), np.concatenate(owner)


def _write_text(target, lines):
    text = "\n".join(lines) + "\n"
    if hasattr(target, "write"):
        target.write(text)
    else:
        Path(target).write_text(text)


def write_vtk_curves(target, curves, header=None):
    """Write polylines as a legacy ASCII VTK file: one ``VTK_LINE`` cell per segment, cell data ``curve``.

    An ``UNSTRUCTURED_GRID`` (meshio reads no ``POLYDATA``); meshio returns
    the segments as ``line`` cells and each segment's curve index as
    ``cell_data["curve"]``.

    Parameters
    ----------
    target : path-like or text file object
    curves : iterable
        As :func:`write_obj_curves`.
    header : str, optional
        The file's title line (its first line, cut to 200 characters).

    Examples
    --------
    >>> import io, numpy as np
    >>> out = io.StringIO()
    >>> write_vtk_curves(out, [(np.eye(3), False)], header="a path")
    >>> print(out.getvalue().strip())  # doctest: +NORMALIZE_WHITESPACE
    # vtk DataFile Version 4.2
    a path
    ASCII
    DATASET UNSTRUCTURED_GRID
    POINTS 3 double
    1 0 0
    0 1 0
    0 0 1
    CELLS 2 6
    2 0 1
    2 1 2
    CELL_TYPES 2
    3
    3
    CELL_DATA 2
    SCALARS curve int 1
    LOOKUP_TABLE default
    0
    0
    """
    points, segments, owner = _curve_parts(curves)
    title = " ".join(str(header or "heatcore curves").split())[:200] or "heatcore curves"
    n = len(segments)
    lines = ["# vtk DataFile Version 4.2", title, "ASCII", "DATASET UNSTRUCTURED_GRID", f"POINTS {len(points)} double"]
    lines += [f"{x:.17g} {y:.17g} {z:.17g}" for x, y, z in points.tolist()]
    lines += [f"CELLS {n} {3 * n}"] + [f"2 {a} {b}" for a, b in segments.tolist()]
    lines += [f"CELL_TYPES {n}"] + ["3"] * n
    lines += [f"CELL_DATA {n}", "SCALARS curve int 1", "LOOKUP_TABLE default"] + [str(j) for j in owner.tolist()]
    _write_text(target, lines)


def write_ply_curves(target, curves, header=None):
    """Write polylines as an ASCII PLY of ``vertex`` and ``edge`` elements (trimesh: a ``Path3D``).

    Parameters
    ----------
    target : path-like or text file object
    curves : iterable
        As :func:`write_obj_curves`.
    header : str, optional
        A ``comment`` line per line.

    Examples
    --------
    >>> import io, numpy as np
    >>> out = io.StringIO()
    >>> write_ply_curves(out, [(np.eye(3), False)])
    >>> out.getvalue().splitlines()[-2:]
    ['0 1', '1 2']
    """
    points, segments, _ = _curve_parts(curves)
    comments = [f"comment {' '.join(line.split())}" for line in str(header).splitlines()] if header else []
    lines = ["ply", "format ascii 1.0", *comments, f"element vertex {len(points)}", "property double x",
             "property double y", "property double z", f"element edge {len(segments)}", "property int vertex1",
             "property int vertex2", "end_header"]
    lines += [f"{x:.17g} {y:.17g} {z:.17g}" for x, y, z in points.tolist()] + [f"{a} {b}" for a, b in segments.tolist()]
    _write_text(target, lines)


def write_curves(target, curves, header=None, labels=None):
    """Write polylines in the format of ``target``'s suffix: ``.obj``, ``.vtk`` or ``.ply`` (:data:`CURVE_READERS`).

    Parameters
    ----------
    target : path-like
    curves, header
        As :func:`write_obj_curves`.
    labels : sequence of str, optional
        Per-curve comments (OBJ only).

    Raises
    ------
    ValueError
        Another suffix.

    Examples
    --------
    >>> import tempfile, numpy as np
    >>> tmp = tempfile.TemporaryDirectory()
    >>> write_curves(Path(tmp.name) / "c.vtk", [(np.eye(3), True)])
    >>> (Path(tmp.name) / "c.vtk").read_text().count("\\n2 ")
    3
    >>> tmp.cleanup()
    """
    suffix = Path(target).suffix.lower()
    if suffix == ".obj":
        write_obj_curves(target, curves, header=header, labels=labels)
    elif suffix == ".vtk":
        write_vtk_curves(target, curves, header=header)
    elif suffix == ".ply":
        write_ply_curves(target, curves, header=header)
    else:
        raise ValueError(f"{target}: polylines are written as {', '.join(CURVE_READERS)}, not {suffix or 'no suffix'!r}")


def write_obj_curves(target, curves, header=None, labels=None):
    """Write polylines as an OBJ file of ``v`` and ``l`` elements (one ``l`` per segment).

    Parameters
    ----------
    target : path-like or text file object
    curves : iterable
        Each curve a ``(points, closed)`` pair, ``points`` ``(k, 3)``, or an
        object with ``.points`` and ``.closed`` (:class:`heatcore.Isoline`).
    header : str, optional
        A comment line (or lines) at the top.
    labels : sequence of str, optional
        A comment per curve (default: its point count and whether it is closed).

    Examples
    --------
    >>> import io, numpy as np, heatcore as hc
    >>> V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    >>> out = io.StringIO()
    >>> write_obj_curves(out, hc.isolines(V, [[0, 1, 2]], [0.0, 1.0, 1.0], [0.5]))
    >>> print(out.getvalue().strip())
    # curve 0: 2 points, open
    v 0 0.5 0
    v 0.5 0 0
    l 1 2
    """
    lines = [f"# {line}" for line in str(header).splitlines()] if header else []
    offset = 1
    for j, curve in enumerate(curves):
        points, closed = (curve.points, curve.closed) if hasattr(curve, "points") else curve
        points = np.asarray(points, dtype=float).reshape(-1, 3)
        label = labels[j] if labels is not None else f"curve {j}: {len(points)} points, {'closed' if closed else 'open'}"
        lines.append(f"# {label}")
        lines += [f"v {x:.17g} {y:.17g} {z:.17g}" for x, y, z in points.tolist()]
        index = list(range(offset, offset + len(points))) + ([offset] if closed and len(points) > 2 else [])
        lines += [f"l {a} {b}" for a, b in zip(index[:-1], index[1:])]
        offset += len(points)
    text = "\n".join(lines) + "\n"
    if hasattr(target, "write"):
        target.write(text)
    else:
        Path(target).write_text(text)
