"""Writing results in Edit Mode: straight into the edit mesh's BMesh layers, without leaving Edit Mode.

In Edit Mode the mesh datablock's attribute arrays are empty, and whatever is
written there is overwritten from the edit mesh when Edit Mode ends. Leaving
Edit Mode to write and coming back costs Blender two conversions of the whole
mesh (0.38-0.5 s at 504k vertices, more than the distance query itself). The
edit mesh has no bulk writes from Python, but one loop over its vertices that
sets one layer value each is cheaper than those conversions (measured at 504k
vertices: 0.05 s for a float, 0.11 s for a color, 0.10 s for a vertex-group
weight). The layers themselves are made by ``Mesh.attributes`` (which adds
them to the edit mesh in Edit Mode) and vertex groups by
``Object.vertex_groups``, as in Object Mode; only the values go through here.

The edit mesh's vertices are iterated in their stored order, which is the
order of the mesh's vertices (and so of the distances) once synced by
``Object.update_from_editmode``.

Examples
--------
>>> write_vertex_floats(obj.data, "geodesic_distance", d)   # doctest: +SKIP
>>> finish(obj.data)                                          # doctest: +SKIP
"""

import bmesh
import numpy as np


def _vertices(mesh, count):
    """The edit mesh's vertex sequence, checked to hold ``count`` vertices (one value each)."""
    verts = bmesh.from_edit_mesh(mesh).verts
    if len(verts) != count:
        raise ValueError(f"{count} values for an edit mesh of {len(verts)} vertices")
    return verts


def write_vertex_floats(mesh, name, values):
    """Set the float point layer ``name`` (an existing attribute) of the edit mesh to ``values`` (n,)."""
    verts = _vertices(mesh, len(values))
    layer = verts.layers.float[name]
    for vert, value in zip(verts, np.asarray(values, dtype=np.float64).tolist()):
        vert[layer] = value


def write_vertex_colors(mesh, name, rgba):
    """Set the color point layer ``name`` (an existing FLOAT_COLOR attribute) to ``rgba`` (n, 4), linear."""
    verts = _vertices(mesh, len(rgba))
    layer = verts.layers.float_color[name]
    channels = [channel.tolist() for channel in np.asarray(rgba).T]  # 4 flat lists: 3x faster than rows of 4
    for vert, color in zip(verts, zip(*channels)):
        vert[layer] = color


def write_group_weights(mesh, group_index, weights):
    """Make every vertex a member of vertex group ``group_index`` with its weight in ``weights`` (n,), 0 included."""
    verts = _vertices(mesh, len(weights))
    layer = verts.layers.deform.verify()
    for vert, weight in zip(verts, np.asarray(weights, dtype=np.float64).tolist()):
        vert[layer][group_index] = weight


def finish(mesh):
    """Tell Blender the edit mesh's layers changed (redraw; no topology or normals to recompute)."""
    bmesh.update_edit_mesh(mesh, loop_triangles=False, destructive=False)
