"""Blender mesh data <-> numpy arrays: reading geometry and sources, writing results.

Everything here moves data; there is no geometry processing. Reads and
writes use ``foreach_get``/``foreach_set`` on contiguous arrays, through the
mesh's attributes where Blender stores the data as one (positions, face
corners, the selection: a plain copy, where ``mesh.vertices`` goes element by
element); there is no Python loop over vertices, except for reading
vertex-group membership, which Blender exposes only per vertex, and for
writes in Edit Mode (:mod:`edit_layers`). Vertex-group
weights are written through a temporary attribute that Blender's own
*Convert Attribute* turns into the group (:func:`write_vertex_group`).
Writes go to the mesh datablock in Object Mode, and in Edit Mode to the
edit mesh's layers (:mod:`edit_layers`: one loop over its vertices, cheaper
than leaving Edit Mode and coming back); :func:`writing` frames a batch of them.

Examples
--------
>>> V, F = mesh_arrays(obj.data)                       # doctest: +SKIP
>>> selected = selected_vertices(obj.data)             # doctest: +SKIP
>>> write_float_attribute(obj.data, "geodesic_distance", d)  # doctest: +SKIP
"""

from contextlib import contextmanager

import bpy
import numpy as np

from . import edit_layers

#: Value written to the distance attribute at vertices no source reaches
#: (another connected piece of the mesh, or a loose vertex).
UNREACHABLE_VALUE = -1.0


class AddonError(Exception):
    """A problem the user can fix (no selection, name clash, ...); its message is reported as is."""


@contextmanager
def stored(mesh):
    """``mesh``, or in Edit Mode a temporary copy of it whose attributes hold the stored arrays.

    In Edit Mode ``mesh.attributes`` lists the edit mesh's layers, without
    data, so reads would go element by element (0.1 s per array at 500k
    vertices). A copy of the mesh (synced by ``update_from_editmode``) shares
    its arrays (Blender copies them only on write): reading it costs what it
    does in Object Mode. The copy is removed on exit.
    """
    if not mesh.is_editmode:
        yield mesh
        return
    copy = mesh.copy()
    try:
        yield copy
    finally:
        bpy.data.meshes.remove(copy)


def vertex_positions(mesh):
    """Vertex positions of ``mesh`` in its own coordinates, as an (n, 3) float64 array."""
    co = np.empty(3 * len(mesh.vertices), dtype=np.float32)
    with stored(mesh) as data:
        position = data.attributes.get("position")
        if position is not None and position.data_type == "FLOAT_VECTOR" and len(position.data) == len(data.vertices):
            position.data.foreach_get("vector", co)  # a plain copy
        else:
            data.vertices.foreach_get("co", co)
    return co.reshape(-1, 3).astype(np.float64)


def _int_attribute(mesh, name, size):
    attr = mesh.attributes.get(name)
    if attr is None or attr.data_type != "INT" or len(attr.data) != size:
        return None
    out = np.empty(size, dtype=np.int32)
    attr.data.foreach_get("value", out)
    return out


def topology(mesh):
    """What fixes the triangles of :func:`mesh_arrays` besides the positions, read cheaply (no triangulation copied).

    Returns
    -------
    corner_verts : (corners,) int32 array
        The vertex of each face corner, face after face: every vertex a face
        uses appears here (loose vertices do not).
    triangle_faces : (m,) int32 array
        The face of each loop triangle: a face of ``k`` corners has ``k - 2``,
        so this fixes how the corners split into faces.
    """
    with stored(mesh) as data:
        corner_verts = _int_attribute(data, ".corner_vert", len(data.loops))
        if corner_verts is None:
            corner_verts = np.empty(len(data.loops), dtype=np.int32)
            data.loops.foreach_get("vertex_index", corner_verts)
        data.calc_loop_triangles()
        triangle_faces = np.empty(len(data.loop_triangles), dtype=np.int32)
        data.loop_triangle_polygons.foreach_get("value", triangle_faces)
    return corner_verts, triangle_faces


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
    mesh.calc_loop_triangles()
    F = np.empty(3 * len(mesh.loop_triangles), dtype=np.int32)
    mesh.loop_triangles.foreach_get("vertices", F)
    return vertex_positions(mesh), F.reshape(-1, 3).astype(np.int64)


def selected_vertices(mesh):
    """Indices of the selected vertices (the mesh must be synced with Edit Mode first)."""
    sel = np.zeros(len(mesh.vertices), dtype=bool)
    with stored(mesh) as data:
        layer = data.attributes.get(".select_vert")  # Blender drops it when nothing is selected
        if layer is not None and layer.data_type == "BOOLEAN" and layer.domain == "POINT":
            layer.data.foreach_get("value", sel)  # a plain copy
        else:  # element by element: nothing selected, or a layer stored another way
            data.vertices.foreach_get("select", sel)
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


#: Longest vertex-group name Blender keeps, in bytes (``MAX_VGROUP_NAME`` less the terminating zero).
MAX_GROUP_NAME = 63


def check_output_names(obj, attribute, color_attribute, weight_group, source_group=None):
    """Refuse output names that collide, before anything is written.

    Blender looks attributes and vertex groups up by the same names (Geometry
    Nodes' *Named Attribute* reads either, and Blender flags a name held by
    both), so the weight group must not be named like any attribute of the
    mesh (UV maps included) or like the distance or color output, and the
    distance and color attributes must not be named like a vertex group.
    The weight group must not be the source group either (the run would
    overwrite its own sources). None skips an output.

    Raises
    ------
    AddonError
        A collision, an empty name, or an attribute name taken by another
        type (:func:`check_attribute_free`).

    Examples
    --------
    >>> check_output_names(obj, "geodesic_distance", "geodesic_distance_color", "geodesic_weight")  # doctest: +SKIP
    """
    mesh = obj.data
    if attribute is not None and attribute == color_attribute:
        raise AddonError(f"the distance and color attributes are both named {attribute!r}; give them two names")
    for name, data_type, what in ((attribute, "FLOAT", "distance"), (color_attribute, "FLOAT_COLOR", "color")):
        if name is None:
            continue
        check_attribute_free(mesh, name, "POINT", data_type)
        if obj.vertex_groups.get(name) is not None:
            raise AddonError(f"{obj.name!r} has a vertex group {name!r}: choose another name for the {what} "
                             "attribute (attributes and vertex groups share one set of names)")
    if weight_group is None:
        return
    if not weight_group:
        raise AddonError("the weight group name must not be empty")
    if len(weight_group.encode()) > MAX_GROUP_NAME:
        raise AddonError(f"vertex group names are at most {MAX_GROUP_NAME} bytes; {weight_group!r} is longer")
    if weight_group in (attribute, color_attribute):
        what = "distance" if weight_group == attribute else "color"
        raise AddonError(f"the weight group and the {what} attribute are both named {weight_group!r}; give the "
                         "weight group another name (attributes and vertex groups share one set of names)")
    if mesh.attributes.get(weight_group) is not None:
        raise AddonError(f"mesh {mesh.name!r} has an attribute {weight_group!r}: choose another name for the weight "
                         "group (attributes and vertex groups share one set of names)")
    if weight_group == source_group:
        raise AddonError(f"the weight group {weight_group!r} is the source group; writing weights would replace "
                         "the sources: choose another name")


def _attribute(mesh, name, domain, data_type):
    check_attribute_free(mesh, name, domain, data_type)
    attr = mesh.attributes.get(name)
    if attr is None:
        attr = mesh.attributes.new(name=name, type=data_type, domain=domain)
    return attr


def write_float_attribute(mesh, name, values):
    """Write one float per vertex into the POINT attribute ``name`` (created if needed)."""
    attr = _attribute(mesh, name, "POINT", "FLOAT")
    if mesh.is_editmode:
        edit_layers.write_vertex_floats(mesh, name, values)
    else:
        attr.data.foreach_set("value", np.ascontiguousarray(values, dtype=np.float32))
    return attr


def srgb_to_linear(rgb):
    """sRGB-encoded colors in [0, 1] to linear values (color attributes store linear color), as float32."""
    rgb = np.asarray(rgb, dtype=np.float32)
    out = np.power((rgb + np.float32(0.055)) / np.float32(1.055), np.float32(2.4))
    low = rgb <= 0.04045
    out[low] = rgb[low] / np.float32(12.92)
    return out


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
    if mesh.is_editmode:
        edit_layers.write_vertex_colors(mesh, name, rgba)
    else:
        attr.data.foreach_set("color", rgba.ravel())
    colors = mesh.color_attributes
    colors.active_color = colors[name]
    colors.render_color_index = colors.active_color_index
    return attr


def write_vertex_group(obj, name, weights):
    """Give every vertex its weight in vertex group ``name``, make it the active group, and return it.

    Every vertex becomes a member, with its weight (0 included). A group of
    that name made earlier is replaced: it moves to the end of the list
    (modifiers find it by name) and keeps its lock. The name must not be an
    attribute's (see :func:`check_output_names`).

    Blender sets group weights one value at a time (``VertexGroup.add`` takes
    one weight for a list of vertices: one call per vertex for continuous
    weights). Here the weights go into a FLOAT point attribute of that name,
    which Blender's *Convert Attribute* operator (``geometry.attribute_convert``,
    mode ``VERTEX_GROUP``) turns into the group in one pass; it leaves out
    vertices of weight 0, which one more ``add`` call puts in. The mesh's active
    attribute is restored. Where that operator cannot run, each distinct
    weight gets one ``add`` call (correct, slow). In Edit Mode the weights go
    into the edit mesh's deform layer (:func:`edit_layers.write_group_weights`).

    Parameters
    ----------
    weights : (n,) array of float in [0, 1]

    Examples
    --------
    >>> group = write_vertex_group(obj, "geodesic_weight", 1 - d / d.max())  # doctest: +SKIP
    """
    w = np.ascontiguousarray(weights, dtype=np.float32)
    old = obj.vertex_groups.get(name)
    locked = old is not None and old.lock_weight
    if old is not None:
        obj.vertex_groups.remove(old)
    if obj.data.is_editmode:
        group = obj.vertex_groups.new(name=name)
        edit_layers.write_group_weights(obj.data, group.index, w)
    else:
        group = _converted_group(obj, name, w)
    group.lock_weight = locked
    obj.vertex_groups.active_index = group.index
    return group


def _converted_group(obj, name, w):
    """A new vertex group ``name`` holding every vertex with its weight ``w`` (Object Mode; see :func:`write_vertex_group`)."""
    mesh = obj.data
    active = mesh.attributes.active.name if mesh.attributes.active is not None else None
    attr = mesh.attributes.new(name=name, type="FLOAT", domain="POINT")
    converted = False
    if attr is not None:
        attr.data.foreach_set("value", w)
        mesh.attributes.active = attr
        with bpy.context.temp_override(object=obj, active_object=obj):
            converted = bpy.ops.geometry.attribute_convert.poll() and _convert_to_vertex_group()
        if not converted and mesh.attributes.get(name) is not None:
            mesh.attributes.remove(mesh.attributes[name])
    group = obj.vertex_groups.get(name) if converted else None
    if group is None:
        group = _write_group_by_value(obj, name, w)
    zero = np.flatnonzero(w == 0)
    if zero.size:
        group.add(zero.tolist(), 0.0, "REPLACE")
    if active is not None and mesh.attributes.get(active) is not None:
        mesh.attributes.active = mesh.attributes[active]
    else:
        mesh.attributes.active_index = -1
    return group


def _convert_to_vertex_group():
    """Run *Convert Attribute* (mode ``VERTEX_GROUP``) on the context's active attribute, with no undo step.

    Returns whether it finished. (Through ``bpy.ops``, which updates the view
    layer around the call: about 30 ms at 500k vertices. Blender's private
    operator entry point would skip that; it is not used.)
    """
    return "FINISHED" in bpy.ops.geometry.attribute_convert("EXEC_DEFAULT", False, mode="VERTEX_GROUP")


def _write_group_by_value(obj, name, w):
    """A new vertex group with weights ``w`` (> 0), one ``add`` call per distinct weight."""
    group = obj.vertex_groups.new(name=name)
    keep = np.flatnonzero(w > 0)
    values, inverse = np.unique(w[keep], return_inverse=True)
    order = np.argsort(inverse, kind="stable")
    bounds = np.searchsorted(inverse[order], np.arange(values.size + 1))
    for k, value in enumerate(values):
        group.add(keep[order[bounds[k] : bounds[k + 1]]].tolist(), float(value), "REPLACE")
    return group


def read_float_attribute(mesh, name):
    """Values of a float POINT attribute as a float64 array (for tests and scripts)."""
    attr = mesh.attributes[name]
    out = np.empty(len(attr.data), dtype=np.float32)
    attr.data.foreach_get("value", out)
    return out.astype(np.float64)


@contextmanager
def writing(obj):
    """Run a block of writes to ``obj``'s mesh, then tell Blender its data changed.

    In Edit Mode the writers go to the edit mesh (:mod:`edit_layers`), which
    stays as it is; in any other mode the block runs in Object Mode
    (:func:`object_mode`).

    Examples
    --------
    >>> with writing(obj):                                         # doctest: +SKIP
    ...     write_float_attribute(obj.data, "geodesic_distance", d)
    """
    if obj.data.is_editmode:
        yield
        edit_layers.finish(obj.data)
        return
    with object_mode(obj):
        yield
        obj.data.update()


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
