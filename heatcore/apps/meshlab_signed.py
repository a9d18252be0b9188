"""The MeshLab-style signed filter: signed distance to the boundary of a :class:`pymeshlab.MeshSet`'s selected faces.

:func:`signed_distance_from_selection` takes the selected faces of the current
mesh as a region; its border (the sides it shares with faces outside it: not
the mesh's own boundary) makes the curves of the signed heat method
(:class:`heatcore.SignedHeatSolver`), oriented with the region on their left,
so the field is positive inside the selection and negative outside. It is
written as vertex quality and as a custom vertex scalar attribute, and the
vertices get blue-to-red colors (:func:`heatcore.viz.colormap.colorize_signed`).
No numerics live here.

pymeshlab is imported by the caller only (``bpy`` must be imported before
pymeshlab in a process).

Examples
--------
>>> DEFAULT_SIGNED_ATTRIBUTE
'heat_signed_distance'
"""

import time

import numpy as np

from ..domains.edge_curves import region_boundary_curves
from ..domains.triangle import TriangleMesh
from ..errors import InvalidOptionError, InvalidSourceError
from ..settings import Settings
from ..signed_heat import SignedHeatSolver
from ..viz import colormap as _colormap
from .meshlab_filter import current_mesh, write_vertex_attribute

#: Name of the custom per-vertex scalar attribute that receives the signed distance.
DEFAULT_SIGNED_ATTRIBUTE = "heat_signed_distance"

_COLOR_ATTRIBUTES = ("heatcore_signed_red", "heatcore_signed_green", "heatcore_signed_blue")


def signed_from_arguments(ms, args):
    """``heatcore meshlab --signed``: the face selection (the file's, or ``--select-faces``) and the run's options.

    Raises
    ------
    InvalidOptionError
        ``--accuracy high`` (the signed method's own distance is the sharper one), or vertex sources given.
    InvalidSourceError
        ``--select-faces`` selects no face, or nothing is selected.

    Examples
    --------
    >>> import argparse
    >>> args = argparse.Namespace(sources=[0], select=None, accuracy="smooth")
    >>> signed_from_arguments(None, args)
    Traceback (most recent call last):
    ...
    heatcore.errors.InvalidOptionError: --signed measures to the border of selected faces: give --select-faces or save a face selection, not vertex sources (--sources, --select)
    """
    if args.sources is not None or args.select is not None:
        raise InvalidOptionError("--signed measures to the border of selected faces: give --select-faces or save a "
                                 "face selection, not vertex sources (--sources, --select)")
    if args.accuracy == "high":
        raise InvalidOptionError("--signed has no --accuracy high: the signed heat method's own distance is the "
                                 "sharper one (docs/signed.md)")
    if args.select_faces is not None:
        ms.compute_selection_by_condition_per_face(condselect=args.select_faces)
        if not ms.current_mesh().face_selection_array().any():
            raise InvalidSourceError(f"--select-faces {args.select_faces!r} selects no face")
    return signed_distance_from_selection(ms, m=args.m, boundary=args.boundary, backend=args.backend,
                                          robust=args.robust, refine=args.refine, weld=args.weld,
                                          isolines=args.isolines)


def signed_summary(stats):
    """The printed report of a signed run.

    Examples
    --------
    >>> print(signed_summary({"curves": 1, "faces_selected": 4, "vertices": 9, "faces": 8, "min": -0.5, "max": 0.25,
    ...                       "unreachable": 0, "seconds": {"setup": 0.1, "distance": 0.01, "write": 0.02},
    ...                       "output": "m_distance.ply"}))
    1 curve(s) bordering 4 selected faces, 9 vertices, 8 faces
    signed distance: min -0.5, max 0.25 (inside positive)
    time: setup 0.100 s, distance 0.010 s, write 0.020 s
    wrote m_distance.ply (quality = signed distance, colours: blue outside, red inside, selection kept)
    """
    s = stats["seconds"]
    return "\n".join([
        f"{stats['curves']} curve(s) bordering {stats['faces_selected']} selected faces, {stats['vertices']} vertices, "
        f"{stats['faces']} faces",
        f"signed distance: min {stats['min']:.6g}, max {stats['max']:.6g} (inside positive)"
        + (f"; {stats['unreachable']} vertices in parts no border reaches" if stats["unreachable"] else ""),
        f"time: setup {s['setup']:.3f} s, distance {s['distance']:.3f} s, write {s['write']:.3f} s",
        f"wrote {stats['output']} (quality = signed distance, colours: blue outside, red inside, selection kept)",
    ])


def signed_distance_from_selection(ms, *, m=1.0, boundary="robin", backend="auto", robust=True, refine="auto",
                                   weld=0.0, isolines=0, attribute=DEFAULT_SIGNED_ATTRIBUTE, unreachable=0.0,
                                   colors=True):
    """Signed distance to the boundary of the selected faces of a MeshSet's current mesh (inside positive).

    Parameters
    ----------
    ms : pymeshlab.MeshSet
        Its current mesh is the input (polygons as pymeshlab triangulates them).
    m, boundary, backend, robust, refine, weld
        As for :func:`~heatcore.apps.meshlab_filter.geodesic_distance_from_selection`.
    isolines : int, default 0
        Dark stripes at 0 and at this many levels on each side, in the colors.
    attribute : str, default "heat_signed_distance"
        The custom vertex scalar attribute that receives the field.
    unreachable : float, default 0.0
        Quality and attribute value of the vertices of parts that hold no
        selected face's boundary (MeshLab's tools do not handle ``inf``);
        they are colored gray and counted in the statistics.
    colors : bool, default True
        Color the vertices (False: colors untouched).

    Returns
    -------
    dict
        ``curves`` (boundary loops), ``faces_selected``, ``vertices``,
        ``faces``, ``reached``, ``unreachable``, ``min``, ``max``,
        ``attribute``, ``seconds`` (``setup``, ``distance``, ``write``,
        ``total``), ``distance`` ((n,) array, ``inf`` where unreached) and
        ``solver``.

    Raises
    ------
    InvalidSourceError
        No face is selected, or the selection has no boundary (it covers whole closed parts).
    InvalidOptionError
        A bad attribute name or unreachable value.

    Examples
    --------
    >>> import pytest
    >>> pymeshlab = pytest.importorskip("pymeshlab")  # the test extra
    >>> import heatcore as hc
    >>> V, F = hc.io.load_demo_mesh()
    >>> ms = pymeshlab.MeshSet()
    >>> ms.add_mesh(pymeshlab.Mesh(V, F.astype(np.int32)))
    >>> ms.compute_selection_by_condition_per_face(condselect="(x0 > 0.2) && (x1 > 0.2) && (x2 > 0.2)")
    >>> stats = signed_distance_from_selection(ms, refine=0)
    >>> stats["curves"] >= 1, stats["min"] < 0 < stats["max"]
    (True, True)
    """
    start = time.perf_counter()
    if not isinstance(attribute, str) or not attribute.isidentifier():
        raise InvalidOptionError(f"attribute must be a name (letters, digits, _), got {attribute!r}")
    if not np.isfinite(unreachable):
        raise InvalidOptionError(f"unreachable must be a finite number (MeshLab cannot hold inf), got {unreachable!r}")
    settings = Settings.of("signed heat", intent="one query", m=m, boundary=boundary, backend=backend, robust=robust,
                           refine=refine, weld=weld)
    mesh = current_mesh(ms)
    V = np.asarray(mesh.vertex_matrix(), dtype=np.float64)
    F = np.asarray(mesh.face_matrix(), dtype=np.int64)
    region = np.flatnonzero(mesh.face_selection_array())
    if region.size == 0:
        raise InvalidSourceError("no face is selected: the signed distance is to the boundary of the selected faces")
    loops = region_boundary_curves(F, region, mesh_boundary=False)
    if not loops:
        raise InvalidSourceError("the selected faces have no boundary (they cover whole closed parts): nothing to "
                                 "measure a signed distance to")
    solver = SignedHeatSolver(TriangleMesh(V, F, settings.mesh), settings.solver)
    setup = time.perf_counter()
    d = solver.distance([[int(v) for v in loop] for loop in loops])
    query = time.perf_counter()
    finite = np.isfinite(d)
    write_vertex_attribute(ms, mesh, attribute, np.where(finite, d, float(unreachable)))
    ms.compute_scalar_by_function_per_vertex(q=attribute)
    if colors:
        rgb = _colormap.to_uint8(_colormap.colorize_signed(d, isolines=isolines))
        for name, channel in zip(_COLOR_ATTRIBUTES, rgb.T):
            write_vertex_attribute(ms, mesh, name, channel.astype(np.float64))
        ms.compute_color_by_function_per_vertex(x=_COLOR_ATTRIBUTES[0], y=_COLOR_ATTRIBUTES[1],
                                                z=_COLOR_ATTRIBUTES[2], a="255")
    done = time.perf_counter()
    return {
        "curves": len(loops),
        "faces_selected": int(region.size),
        "vertices": int(V.shape[0]),
        "faces": int(F.shape[0]),
        "reached": int(finite.sum()),
        "unreachable": int((~finite).sum()),
        "min": float(d[finite].min()) if finite.any() else float("nan"),
        "max": float(d[finite].max()) if finite.any() else float("nan"),
        "attribute": attribute,
        "seconds": {"setup": setup - start, "distance": query - setup, "write": done - query, "total": done - start},
        "distance": d,
        "solver": solver,
    }
