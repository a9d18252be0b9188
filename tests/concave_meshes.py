"""Polygon meshes with concave n-gons, made by Blender itself (bmesh operators), and their measurements.

Used by tests/test_polygon_concave.py and tests/test_blender_concave.py (issue 32). Each builder
is deterministic (seeded) and returns ``(V, P)``: an ``(n, 3)`` float array and a list of polygons
(lists of vertex indices), the mesh as Blender holds it after the operator:

- :func:`dissolved_grid`: Dissolve Edges (``use_verts=False``) on random interior edges of a grid:
  concave n-gons and 180-degree corners;
- :func:`dissolved_uv_sphere`: Limited Dissolve of a UV sphere (non-planar concave n-gons);
- :func:`bumpy_cube`: a subdivided cube with some faces extruded, then Limited Dissolve: each flat
  side merges into concave n-gons around the bumps;
- :func:`holed_plate`: a grid with holes cut out, and the band of faces around each hole dissolved
  (Dissolve Faces) in two halves: U-shaped polygons around the holes;
- :func:`text_mesh`: a text object evaluated to a mesh (Blender fills letters with triangles),
  then Limited Dissolve: one deeply concave n-gon per letter, letters with holes ('e', 'a')
  split by the edges that Limited Dissolve keeps (BMesh faces have no holes).

:func:`measure` gives the errors of ``PolygonMesh`` and of ``TriangleMesh`` on heatcore's own
triangulation of the same polygons (``triangulate_polygons``), at one ``refine``.

Needs ``bpy`` (import it before pymeshlab: tests/conftest.py does).
"""

import math
import random
import subprocess
import sys
import tempfile
from pathlib import Path

import blender_required  # noqa: F401 (first: without bpy, the module is skipped)
import bmesh
import bpy
import numpy as np

import heatcore as hc
from heatcore.domains.polygon import polygon_arrays
from heatcore.domains.polygon_triangulate import concave_polygons, triangulate_polygons
from heatcore.reference import mean_relative_error


def arrays(bm):
    """The vertices and faces of a BMesh, as arrays (the BMesh is freed)."""
    bm.verts.index_update()
    V = np.array([v.co[:] for v in bm.verts], dtype=float)
    P = [[v.index for v in f.verts] for f in bm.faces]
    bm.free()
    return V, P


def _drop_loose(bm):
    loose = [v for v in bm.verts if not v.link_faces]
    if loose:
        bmesh.ops.delete(bm, geom=loose, context="VERTS")


def dissolved_grid(n=24, count=150, seed=0):
    """An ``n`` x ``n`` grid (side 2, centred) with ``count`` random interior edges dissolved (Dissolve Edges)."""
    bm = bmesh.new()
    bmesh.ops.create_grid(bm, x_segments=n, y_segments=n, size=1.0)
    rng = random.Random(seed)
    bm.edges.ensure_lookup_table()
    interior = [e for e in bm.edges if not e.is_boundary]
    rng.shuffle(interior)
    done = 0
    for edge in interior:
        if done >= count:
            break
        if not edge.is_valid or edge.is_boundary or len(edge.link_faces) != 2:
            continue
        bmesh.ops.dissolve_edges(bm, edges=[edge], use_verts=False, use_face_split=False)
        done += 1
    _drop_loose(bm)
    return arrays(bm)


def dissolved_uv_sphere(angle=10.0, segments=32, rings=16, jitter=0.01, seed=0):
    """A unit UV sphere, its vertices moved by up to ``jitter`` (seeded) and put back on it, after Limited Dissolve.

    The jitter breaks ties: on the perfect sphere every edge has the same angle, and which of them
    Limited Dissolve takes first differs from one process to the next (measured: 158 or 160
    vertices at 20 degrees).
    """
    bm = bmesh.new()
    bmesh.ops.create_uvsphere(bm, u_segments=segments, v_segments=rings, radius=1.0)
    rng = np.random.default_rng(seed)
    for v in bm.verts:
        p = np.array(v.co[:]) + rng.uniform(-jitter, jitter, 3)
        v.co = p / np.linalg.norm(p)
    bmesh.ops.dissolve_limit(bm, angle_limit=math.radians(angle), verts=bm.verts[:], edges=bm.edges[:])
    return arrays(bm)


def bumpy_cube(cuts=5, bumps=8, seed=0, angle=5.0):
    """A cube (side 2) subdivided with ``cuts`` cuts, ``bumps`` random faces extruded by 0.3, then Limited Dissolve."""
    bm = bmesh.new()
    bmesh.ops.create_cube(bm, size=2.0)
    bmesh.ops.subdivide_edges(bm, edges=bm.edges[:], cuts=cuts, use_grid_fill=True)
    faces = list(bm.faces)
    random.Random(seed).shuffle(faces)
    for face in faces[:bumps]:
        top = bmesh.ops.extrude_discrete_faces(bm, faces=[face])["faces"][0]
        bmesh.ops.translate(bm, vec=top.normal * 0.3, verts=top.verts[:])
    bmesh.ops.dissolve_limit(bm, angle_limit=math.radians(angle), verts=bm.verts[:], edges=bm.edges[:])
    return arrays(bm)


def holed_plate(n=20, holes=((4, 4, 3, 3), (12, 6, 2, 4), (6, 13, 4, 2)), band=2):
    """An ``n`` x ``n`` grid (side 2) with rectangular holes ``(i, j, width, height)`` in cells cut out.

    The faces within ``band`` cells of each hole are dissolved (Dissolve Faces, ``use_verts=False``)
    in two halves, left and right of the hole's middle (a face with a hole does not exist in BMesh):
    two U-shaped concave n-gons around each hole, quads elsewhere.
    """
    bm = bmesh.new()
    bmesh.ops.create_grid(bm, x_segments=n, y_segments=n, size=1.0)
    step = 2.0 / n
    cut, halves = [], {}
    for face in bm.faces:
        c = face.calc_center_median()
        i, j = int((c.x + 1.0) / step), int((c.y + 1.0) / step)
        for h, (a, b, w, t) in enumerate(holes):
            if a <= i < a + w and b <= j < b + t:
                cut.append(face)
            elif a - band <= i < a + w + band and b - band <= j < b + t + band:
                halves.setdefault((h, 2 * i < 2 * a + w), []).append(face)
    bmesh.ops.delete(bm, geom=cut, context="FACES")
    for faces in halves.values():
        bmesh.ops.dissolve_faces(bm, faces=[f for f in faces if f.is_valid], use_verts=False)
    _drop_loose(bm)
    return arrays(bm)


def text_mesh(body="heat GS", angle=5.0):
    """A text object's mesh (its letters filled, as Blender evaluates it), after Limited Dissolve.

    The font curve and its object are made through ``bpy.data`` and removed again (no operator, no
    context needed).
    """
    curve = bpy.data.curves.new("ConcaveText", type="FONT")
    curve.body = body
    obj = bpy.data.objects.new("ConcaveText", curve)
    bpy.context.scene.collection.objects.link(obj)
    try:
        depsgraph = bpy.context.evaluated_depsgraph_get()
        evaluated = obj.evaluated_get(depsgraph)
        mesh = evaluated.to_mesh()
        bm = bmesh.new()
        bm.from_mesh(mesh)
        evaluated.to_mesh_clear()
    finally:
        bpy.data.objects.remove(obj)
        bpy.data.curves.remove(curve)
    bmesh.ops.remove_doubles(bm, verts=bm.verts[:], dist=1e-7)
    bmesh.ops.dissolve_limit(bm, angle_limit=math.radians(angle), verts=bm.verts[:], edges=bm.edges[:])
    _drop_loose(bm)
    return arrays(bm)


def heatcore_triangles(V, P):
    """heatcore's own triangulation of the polygons (``triangulate_polygons``)."""
    return triangulate_polygons(V, *polygon_arrays(P, len(V)))[0]


def n_concave(V, P):
    """How many polygons have a reflex corner in their plane."""
    return int(concave_polygons(V, *polygon_arrays(P, len(V))).sum())


def reflex_corner(V, P, near=(0.0, 0.0, 0.0)):
    """A vertex at a reflex corner of a concave polygon, the nearest to ``near``."""
    offsets, corners = polygon_arrays(P, len(V))
    best, best_gap = None, np.inf
    for p in np.flatnonzero(concave_polygons(V, offsets, corners)):
        ring = corners[offsets[p]:offsets[p + 1]]
        X = V[ring]
        normal = np.cross(X - X.mean(axis=0), np.roll(X, -1, axis=0) - X.mean(axis=0)).sum(axis=0)
        turn = np.cross(X - np.roll(X, 1, axis=0), np.roll(X, -1, axis=0) - X) @ normal
        for v in ring[turn < -1e-12 * (normal @ normal)]:
            gap = np.linalg.norm(V[v] - np.asarray(near))
            if gap < best_gap:
                best, best_gap = int(v), gap
    assert best is not None, "no reflex corner"
    return best


def nearest_vertex(V, point):
    return int(np.argmin(np.linalg.norm(V - np.asarray(point, dtype=float), axis=1)))


_EXACT = (
    "import sys, numpy as np; from heatcore.reference import exact_distance; d = np.load(sys.argv[1]); "
    "np.save(sys.argv[2], np.array([exact_distance(d['V'], d['T'], [int(s)]) for s in d['s']]))"
)


def exact_geodesics(V, T, sources):
    """Exact (MMP, gdist) distances on the triangles ``T``, one row per source; ``inf`` across parts.

    gdist runs in a child process: it segfaults on non-manifold input.
    """
    with tempfile.TemporaryDirectory() as tmp:
        inp, out = Path(tmp) / "in.npz", Path(tmp) / "out.npy"
        np.savez(inp, V=V, T=np.asarray(T, dtype=np.int64), s=np.asarray(sources, dtype=np.int64))
        run = subprocess.run([sys.executable, "-c", _EXACT, str(inp), str(out)], capture_output=True, timeout=300)
        assert run.returncode == 0, run.stderr.decode()[-500:]
        return np.load(out)


def measure(V, P, T, sources, exact, refine):
    """Mean relative errors ``(polygon, triangles, n_triangulated)`` per source, at one ``refine``.

    ``exact[i]`` is the reference for ``sources[i]``; ``T`` is :func:`heatcore_triangles`. The twin is
    built unwelded (``weld=None``), as :class:`~heatcore.PolygonMesh` builds its triangles: welded, suzanne's
    eyes were pinned to its head at two coincident vertices, a surface neither the polygons nor the exact
    geodesics have.
    """
    polygon_mesh = hc.PolygonMesh(V, P, refine=refine)
    polygons = hc.HeatSolver(polygon_mesh)
    triangles = hc.HeatSolver(hc.TriangleMesh(V, T, refine=refine, weld=None))
    e_poly = [mean_relative_error(polygons.distance([s]), e) for s, e in zip(sources, exact)]
    e_tri = [mean_relative_error(triangles.distance([s]), e) for s, e in zip(sources, exact)]
    return np.array(e_poly), np.array(e_tri), polygon_mesh.n_triangulated
