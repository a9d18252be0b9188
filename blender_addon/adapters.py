"""Blender mesh data <-> numpy arrays: reading geometry and sources, writing results.

Everything here moves data; there is no geometry processing. Reads use
``foreach_get`` (no Python loops over vertices, except for vertex-group
membership, which Blender exposes only per vertex). Writes go to the mesh
datablock in Object Mode (see :func:`object_mode`).

Examples
--------
>>> V, F = mesh_arrays(obj.data)                       # doctest: +SKIP
>>> selected = selected_vertices(obj.data)             # doctest: +SKIP
>>> write_float_attribute(obj.data, "geodesic_distance", d)  # doctest: +SKIP
"""

from contextlib import contextmanager

import bpy
import numpy as np

#: Value written to the distance attribute at vertices no source reaches
#: (another connected piece of the mesh, or a loose vertex).
UNREACHABLE_VALUE = -1.0


class AddonError(Exception):
    """A problem the user can fix (no selection, name clash, ...); its message is reported as is."""


def mesh_arrays(mesh):
    """Vertex positions and triangles of a mesh (n-gons split by Blender's loop triangles).

    Parameters
    ----------
    mesh : bpy.types.Mesh
        In Object Mode, or synced with ``Object.update_from_editmode()``.

    Returns
    -------
    V : (n, 3) float64 array
        Vertex positions in object (local) coordinates.
    F : (m, 3) int64 array
        Triangles; every face with more than three corners becomes
        ``corners - 2`` triangles.
    """
    n = len(mesh.vertices)
    V = np.empty(3 * n, dtype=np.float32)
    mesh.vertices.foreach_get("co", V)
    mesh.calc_loop_triangles()
    F = np.empty(3 * len(mesh.loop_triangles), dtype=np.int32)
    mesh.loop_triangles.foreach_get("vertices", F)
    return V.reshape(-1, 3).astype(np.float64), F.reshape(-1, 3).astype(np.int64)


def selected_vertices(mesh):
    """Indices of the selected vertices (the mesh must be synced with Edit Mode first)."""
    sel = np.zeros(len(mesh.vertices), dtype=bool)
    mesh.vertices.foreach_get("select", sel)
    return np.flatnonzero(sel)


def vertex_group_members(obj, name):
    """Indices of the vertices in the vertex group ``name`` with a weight above 0.

    Raises
    ------
    AddonError
        The object has no vertex group of that name.
    """
    group = obj.vertex_groups.get(name)
    if group is None:
        names = ", ".join(repr(g.name) for g in obj.vertex_groups) or "none"
        raise AddonError(f"object {obj.name!r} has no vertex group {name!r} (its groups: {names})")
    index = group.index
    return np.array(
        [v.index for v in obj.data.vertices if any(g.group == index and g.weight > 0.0 for g in v.groups)],
        dtype=np.int64,
    )


def check_attribute_free(mesh, name, domain, data_type):
    """Make sure ``name`` is free or already holds an attribute this add-on can overwrite.

    Raises
    ------
    AddonError
        The name is taken by an attribute of another type or domain (the
        user's data: it is never replaced), or is a reserved name.
    """
    if not name:
        raise AddonError("attribute names must not be empty")
    existing = mesh.attributes.get(name)
    if existing is not None and (existing.domain != domain or existing.data_type != data_type):
        raise AddonError(
            f"mesh {mesh.name!r} already has an attribute {name!r} of type {existing.data_type} on the "
            f"{existing.domain} domain; choose another name for the {data_type} output"
        )
    if existing is None and (name.startswith(".") or name in ("position", "id", "material_index")):
        raise AddonError(f"{name!r} is a name Blender reserves; choose another attribute name")


def _attribute(mesh, name, domain, data_type):
    check_attribute_free(mesh, name, domain, data_type)
    attr = mesh.attributes.get(name)
    if attr is None:
        attr = mesh.attributes.new(name=name, type=data_type, domain=domain)
    return attr


def write_float_attribute(mesh, name, values):
    """Write one float per vertex into the POINT attribute ``name`` (created if needed)."""
    attr = _attribute(mesh, name, "POINT", "FLOAT")
    attr.data.foreach_set("value", np.ascontiguousarray(values, dtype=np.float32))
    return attr


def srgb_to_linear(rgb):
    """sRGB-encoded colors in [0, 1] to linear values (color attributes store linear color)."""
    rgb = np.asarray(rgb, dtype=np.float64)
    return np.where(rgb <= 0.04045, rgb / 12.92, ((rgb + 0.055) / 1.055) ** 2.4)


def write_color_attribute(mesh, name, rgb):
    """Write per-vertex colors into the FLOAT_COLOR POINT attribute ``name`` and make it active.

    Parameters
    ----------
    rgb : (n, 3) array
        sRGB display colors in [0, 1] (as colormaps are defined); stored
        linear with alpha 1 so the viewport shows the colormap's colors.
    """
    attr = _attribute(mesh, name, "POINT", "FLOAT_COLOR")
    rgba = np.ones((len(rgb), 4), dtype=np.float32)
    rgba[:, :3] = srgb_to_linear(rgb)
    attr.data.foreach_set("color", rgba.ravel())
    colors = mesh.color_attributes
    colors.active_color = colors[name]
    colors.render_color_index = colors.active_color_index
    return attr


def write_vertex_group(obj, name, weights):
    """Set the weights of vertex group ``name`` (created if needed); ``NaN`` weights leave a vertex out.

    The group is emptied first, so a re-run replaces earlier weights.
    """
    group = obj.vertex_groups.get(name) or obj.vertex_groups.new(name=name)
    n = len(obj.data.vertices)
    group.remove(list(range(n)))
    weights = np.asarray(weights, dtype=np.float64)
    keep = np.flatnonzero(np.isfinite(weights))
    # One call per distinct weight: Blender takes index lists with a single weight.
    values, inverse = np.unique(weights[keep].astype(np.float32), return_inverse=True)
    order = np.argsort(inverse, kind="stable")
    bounds = np.searchsorted(inverse[order], np.arange(values.size + 1))
    for k, w in enumerate(values):
        group.add(keep[order[bounds[k] : bounds[k + 1]]].tolist(), float(w), "REPLACE")
    return group


def read_float_attribute(mesh, name):
    """Values of a float POINT attribute as a float64 array (for tests and scripts)."""
    attr = mesh.attributes[name]
    out = np.empty(len(attr.data), dtype=np.float32)
    attr.data.foreach_get("value", out)
    return out.astype(np.float64)


@contextmanager
def object_mode(obj):
    """Run a block with ``obj`` in Object Mode, then return it to the mode it was in.

    Mesh attribute data is empty in Edit Mode and edits made to it there are
    overwritten when Edit Mode ends, so results are written in Object Mode.
    """
    mode = obj.mode
    if mode == "OBJECT":
        yield
        return
    with bpy.context.temp_override(active_object=obj, object=obj):
        bpy.ops.object.mode_set(mode="OBJECT")
    try:
        yield
    finally:
        with bpy.context.temp_override(active_object=obj, object=obj):
            bpy.ops.object.mode_set(mode=mode)
