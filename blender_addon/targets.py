"""Which objects a click measures: every selected mesh object, each on its own, and why others are left out.

In Object Mode the targets are the active object and the other selected
objects; in Edit Mode the objects in Edit Mode (multi-object editing). Each
is measured alone, from its own sources. An object that cannot be measured
(not a mesh, hidden, linked from a library, sharing its mesh with an object
measured already) is left out, and :func:`skipped_message` names it with the
reason, as does an object whose run failed (no sources selected).

Examples
--------
>>> targets, skipped = target_objects(bpy.context)      # doctest: +SKIP
>>> skipped_message([("Camera", "not a mesh")])
"Skipped 'Camera' (not a mesh)"
"""


def refusal(obj):
    """Why ``obj`` cannot be measured and written to, or None.

    Examples
    --------
    >>> refusal(bpy.data.objects["Camera"])  # doctest: +SKIP
    'not a mesh'
    """
    if obj.type != "MESH":
        return "not a mesh"
    if not obj.visible_get():
        return "hidden"
    if not obj.data.is_editmode and (obj.library or obj.data.library):
        return "linked from a library: it cannot be modified"
    return None


def target_objects(context):
    """The objects to measure, the active one first, and ``(name, reason)`` of those left out.

    Parameters
    ----------
    context : bpy.types.Context

    Returns
    -------
    targets : list of bpy.types.Object
    skipped : list of (str, str)
    """
    active = context.active_object
    if active is not None and active.mode == "EDIT":
        others = getattr(context, "objects_in_mode", None) or ()
    else:
        others = getattr(context, "selected_objects", None) or ()
    targets, skipped, meshes = [], [], {}
    for obj in [active, *(o for o in others if o != active)]:
        if obj is None:
            continue
        why = refusal(obj)
        if why is None and obj.data in meshes:
            why = f"shares its mesh with {meshes[obj.data]!r}, measured already"
        if why is None:
            meshes[obj.data] = obj.name
            targets.append(obj)
        else:
            skipped.append((obj.name, why))
    return targets, skipped


def skipped_message(skipped):
    """One line naming the objects left out and why (empty when none)."""
    if not skipped:
        return ""
    return "Skipped " + "; ".join(f"{name!r} ({why})" for name, why in skipped)
