"""Operator ``mesh.heat_geodesic_distance``: the button, and ``bpy.ops`` for scripts.

Runs :func:`compute_geodesic_distance` on the active object with progress
feedback, reports the result (or a clear error, leaving the mesh untouched)
and shows the color attribute in the viewport.
"""

import bpy

from ._heatcore import heatcore
from .adapters import AddonError
from .api import compute_geodesic_distance
from .properties import GeodesicOptions


def _status(context, text):
    workspace = getattr(context, "workspace", None)
    if workspace is not None:
        workspace.status_text_set(text)


def show_color_attribute(context):
    """Switch solid-shaded 3D views to attribute colors so the result is visible."""
    screen = getattr(context, "screen", None)
    for area in screen.areas if screen else ():
        if area.type == "VIEW_3D":
            shading = area.spaces.active.shading
            if shading.type == "SOLID":
                shading.color_type = "VERTEX"  # "Attribute" in the UI


class MESH_OT_heat_geodesic_distance(GeodesicOptions, bpy.types.Operator):
    """Geodesic distance from the selected vertices (heat method), stored as attributes and colors"""

    bl_idname = "mesh.heat_geodesic_distance"
    bl_label = "Geodesic Distance"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        if obj is None or obj.type != "MESH":
            cls.poll_message_set("The active object must be a mesh")
            return False
        if not obj.data.is_editmode and (obj.library or obj.data.library):
            cls.poll_message_set("Linked (library) meshes cannot be modified")
            return False
        return True

    def invoke(self, context, event):
        # From the UI, options not given explicitly come from the panel.
        settings = context.scene.heat_geodesic
        for name in GeodesicOptions.__annotations__:
            if not self.properties.is_property_set(name):
                setattr(self, name, getattr(settings, name))
        return self.execute(context)

    def execute(self, context):
        obj = context.active_object
        wm = context.window_manager
        wm.progress_begin(0, 100)

        def progress(fraction, message):
            wm.progress_update(int(100 * fraction))
            _status(context, f"Geodesic distance: {message}")

        try:
            result = compute_geodesic_distance(obj, progress=progress, **self.call_options())
        except (AddonError, heatcore.HeatcoreError) as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        finally:
            wm.progress_end()
            _status(context, None)

        stats = wm.heat_geodesic_stats
        stats.valid = True
        stats.object_name = result.object.name
        stats.vertices = result.n_vertices
        stats.sources = result.sources.size
        stats.max_distance = result.max_distance
        stats.seconds = result.seconds
        stats.solver_seconds = result.solver_seconds
        stats.cached = result.cached
        show_color_attribute(context)
        for note in result.warnings:
            self.report({"WARNING"}, note)
        how = "cached solver" if result.cached else f"solver built in {result.solver_seconds:.2f} s"
        where = f" (written to {result.object.name!r})" if result.object != obj else ""
        self.report(
            {"INFO"},
            f"Geodesic distance on {result.n_vertices:,} vertices{where} from {result.sources.size:,} sources: "
            f"max {result.max_distance:.4g}, {result.seconds:.2f} s ({how})",
        )
        return {"FINISHED"}
