"""Which shape is measured: the one on screen (world space, shape keys and modifiers) or the basis mesh.

``shape="EVALUATED"`` reads the vertex positions Blender displays: shape keys
mixed as shown and deform modifiers (Displace, Cast, Lattice, Armature,
Smooth, ...) applied. Modifiers that change the topology (Subdivision,
Mirror, Array, Boolean, ...) are switched off for the reading and named in a
warning: the distance is measured on the deformed cage of the mesh's own
vertices, which is where it is written. ``shape="BASIS"`` reads the mesh data
as stored. ``space="WORLD"`` applies the object's world matrix (scale,
rotation, parents), ``"LOCAL"`` measures in object coordinates.

:func:`evaluated_copy` is the other way to treat modifiers that change the
vertices: the whole evaluated mesh (every modifier applied) becomes a new
object, and the distance is measured and written there.

Examples
--------
>>> V, skipped = measured_positions(obj, "WORLD", "EVALUATED")   # doctest: +SKIP
"""

import bpy
import numpy as np
from scipy.spatial import cKDTree

from .adapters import AddonError, vertex_positions
from .cache import placed
from .material import is_isoline_modifier

SPACES = ("WORLD", "LOCAL")
SHAPES = ("EVALUATED", "BASIS")

#: Modifier types that move vertices and keep the mesh's vertices as they are (count and order).
DEFORM_MODIFIERS = frozenset({
    "ARMATURE", "CAST", "CORRECTIVE_SMOOTH", "CURVE", "DISPLACE", "HOOK", "LAPLACIANDEFORM",
    "LAPLACIANSMOOTH", "LATTICE", "MESH_CACHE", "MESH_DEFORM", "SHRINKWRAP", "SIMPLE_DEFORM", "SMOOTH",
    "SURFACE_DEFORM", "WARP", "WAVE",
})


def check_choice(name, value, choices):
    """``value`` if it is one of ``choices``; an :class:`AddonError` naming them otherwise."""
    if value not in choices:
        raise AddonError(f"{name} must be one of {', '.join(choices)}, got {value!r}")
    return value


def _evaluated_positions(obj, depsgraph):
    """Vertex positions of ``obj`` as ``depsgraph`` evaluates it, in object coordinates."""
    evaluated = obj.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    try:
        return vertex_positions(mesh)
    finally:
        evaluated.to_mesh_clear()


def _shown_as_stored(obj):
    """Whether ``obj`` is displayed as its mesh data: no shape keys, no modifier shown but the add-on's
    isoline modifier (it only sets a material), no parent deforming it.

    Then the displayed positions are read from the mesh without evaluating it
    (in Edit Mode that evaluation converts the whole edit mesh: 0.1 s at 500k
    vertices).
    """
    return (obj.data.shape_keys is None
            and not any(m.show_viewport and not is_isoline_modifier(m) for m in obj.modifiers)
            and (obj.parent is None or obj.parent_type not in ("ARMATURE", "LATTICE")))


def displayed_positions(obj):
    """The positions of ``obj``'s own vertices as displayed, and the topology-changing modifiers skipped.

    Returns
    -------
    V : (n, 3) float array
        One row per vertex of ``obj.data``, in object coordinates.
    skipped : list of str
        Names of the modifiers left out because they change the vertices
        (their switches are restored before this returns).
    """
    n = len(obj.data.vertices)
    if _shown_as_stored(obj):
        return vertex_positions(obj.data), []
    V = _evaluated_positions(obj, bpy.context.evaluated_depsgraph_get())
    if len(V) == n:
        return V, []
    # The add-on's isoline modifier only sets a material: it stays on and is never named.
    off = [m for m in obj.modifiers
           if m.show_viewport and m.type not in DEFORM_MODIFIERS and not is_isoline_modifier(m)]
    try:
        for m in off:
            m.show_viewport = False
        V = _evaluated_positions(obj, bpy.context.evaluated_depsgraph_get())
    finally:
        for m in off:
            m.show_viewport = True
        bpy.context.view_layer.update()
    if len(V) != n:
        raise AddonError(
            f"the modifiers of {obj.name!r} change its vertices even without "
            f"{', '.join(m.name for m in off) or 'any non-deforming modifier'}; use shape='BASIS'"
        )
    return V, [m.name for m in off]


def measured_positions(obj, space="WORLD", shape="EVALUATED"):
    """Vertex positions of ``obj``'s mesh where the distance is measured, and the modifiers skipped.

    The positions of :func:`object_positions` placed by :func:`measured_frame`.

    Parameters
    ----------
    obj : bpy.types.Object
        A mesh object (in Object Mode, or synced with ``update_from_editmode``).
    space : {"WORLD", "LOCAL"}
    shape : {"EVALUATED", "BASIS"}

    Returns
    -------
    V : (n, 3) float array
    skipped : list of str
        Topology-changing modifiers left out (``shape="EVALUATED"`` only).
    """
    frame = measured_frame(obj, space)
    V, skipped = object_positions(obj, shape)
    return placed(V, frame), skipped


def object_positions(obj, shape="EVALUATED"):
    """The vertex positions of ``shape`` in ``obj``'s own coordinates, and the modifiers skipped (see
    :func:`measured_positions`)."""
    if check_choice("shape", shape, SHAPES) == "EVALUATED":
        return displayed_positions(obj)
    return vertex_positions(obj.data), []


def measured_frame(obj, space="WORLD"):
    """The 4x4 matrix from ``obj``'s own coordinates to those of ``space``: its world matrix (float64), or None
    for ``"LOCAL"``. The cache keys the geometry by the object's coordinates and this frame
    (:func:`~.cache.geometry_key`), so that moving the object keeps its solver."""
    if check_choice("space", space, SPACES) == "WORLD":
        return np.array(obj.matrix_world, dtype=np.float64)
    return None


#: Custom property marking the objects :func:`evaluated_copy` made (value: the original's name).
COPY_MARKER = "heat_geodesic_copy_of"


def evaluated_copy(obj):
    """A new object holding ``obj``'s mesh as displayed, every modifier applied; reused on re-runs.

    The copy is named ``"<name> Geodesic"``, placed with ``obj``'s world
    matrix in ``obj``'s collections, and marked with :data:`COPY_MARKER`. A
    copy made earlier for the same object gets the new mesh (its old mesh is
    removed); ``obj`` itself is not modified.

    Returns
    -------
    bpy.types.Object

    Examples
    --------
    >>> copy = evaluated_copy(bpy.context.object)   # doctest: +SKIP
    >>> copy.name                                   # doctest: +SKIP
    'Suzanne Geodesic'
    """
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = bpy.data.meshes.new_from_object(evaluated)
    copy = next((o for o in bpy.data.objects if o.get(COPY_MARKER) == obj.name and o.type == "MESH"), None)
    if copy is None:
        mesh.name = f"{obj.name} Geodesic"
        copy = bpy.data.objects.new(mesh.name, mesh)
        copy[COPY_MARKER] = obj.name
        for collection in obj.users_collection or (bpy.context.scene.collection,):
            collection.objects.link(copy)
    else:
        old, copy.data = copy.data, mesh
        mesh.name = old.name
        if old.users == 0:
            bpy.data.meshes.remove(old)
    copy.matrix_world = obj.matrix_world
    return copy


def nearest_vertices(copy, positions):
    """Vertex of ``copy`` nearest to each of ``positions`` (object coordinates), as an int array.

    Maps source vertices of an object to the vertices of its
    :func:`evaluated_copy`: a vertex kept by the modifiers sits where it is
    displayed (Mirror, Array: the original side), a smoothed one (Subdivision)
    moves less than half an edge.

    Examples
    --------
    >>> nearest_vertices(copy, V[sources])   # doctest: +SKIP
    array([412])
    """
    co = np.empty(3 * len(copy.data.vertices), dtype=np.float32)
    copy.data.vertices.foreach_get("co", co)
    return cKDTree(co.reshape(-1, 3)).query(np.asarray(positions, dtype=np.float64).reshape(-1, 3))[1].astype(np.int64)
