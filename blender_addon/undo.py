"""Keep the active color attribute valid across undo and redo.

Edit Mode undo restores the mesh's layers but not which color attribute is
active: undoing a run made in Edit Mode removes the distance colors and leaves
the mesh's active (and render) color naming a layer that no longer exists.
Each run remembers the color attribute that was active before it; after an
undo or redo, a mesh whose active color names a missing layer gets back the
run's colors if they exist, else the one active before the run.

Examples
--------
>>> remember_active_color(obj.data, "geodesic_distance_color")   # doctest: +SKIP
>>> bpy.ops.ed.undo()                                           # doctest: +SKIP
>>> obj.data.color_attributes.active_color_name                 # doctest: +SKIP
'Col'
"""

import bpy
from bpy.app.handlers import persistent

#: Mesh name -> (color attribute active before the run, the run's color attribute).
_BEFORE_RUN = {}


def remember_active_color(mesh, ours):
    """Note the color attribute active on ``mesh`` before a run writes ``ours`` and activates it.

    Examples
    --------
    >>> remember_active_color(obj.data, "geodesic_distance_color")   # doctest: +SKIP
    """
    previous = mesh.color_attributes.active_color_name
    if previous != ours:
        _BEFORE_RUN[mesh.name_full] = (previous, ours)


@persistent
def restore_active_color(*_):
    """Handler of ``undo_post`` and ``redo_post``: repoint active colors that name a missing layer.

    Examples
    --------
    >>> bpy.app.handlers.undo_post.append(restore_active_color)   # doctest: +SKIP
    """
    for name, (previous, ours) in _BEFORE_RUN.items():
        mesh = bpy.data.meshes.get(name)
        if mesh is None:
            continue
        colors = mesh.color_attributes
        if colors.get(colors.active_color_name or "") is not None:
            continue
        target = next((c for c in (ours, previous) if c and colors.get(c) is not None), None)
        if target is not None:
            colors.active_color_name = target
            colors.render_color_index = colors.active_color_index


def register():
    """Install the undo and redo handlers (once)."""
    for handlers in (bpy.app.handlers.undo_post, bpy.app.handlers.redo_post):
        if restore_active_color not in handlers:
            handlers.append(restore_active_color)


def unregister():
    """Remove the handlers and forget the runs."""
    for handlers in (bpy.app.handlers.undo_post, bpy.app.handlers.redo_post):
        while restore_active_color in handlers:
            handlers.remove(restore_active_color)
    _BEFORE_RUN.clear()
