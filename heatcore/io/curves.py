"""Polylines as OBJ files: ``v`` lines for the points, an ``l`` line per segment.

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
