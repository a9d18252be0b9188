"""What the geodesic probe draws over the 3D View while it runs: the field, the sources, the path.

The distance button's preview (:mod:`.preview`) draws its field and sources with the same overlay.

Nothing is written to the mesh while the probe runs: the colors of the
field (heatcore's colormap with its isoline stripes, the colors the probe
writes when confirmed), the source points, the target and the geodesic path
are drawn by a ``gpu`` draw handler (``SpaceView3D.draw_handler_add``,
``POST_VIEW``). :class:`OverlayData` holds the arrays drawn, made by the
probe on each update (no ``gpu`` needed: tests read them); :class:`Overlay`
owns the draw handler and turns the data into ``gpu`` batches when Blender
draws (a headless ``bpy`` has no GPU: there the callback never runs).

The field's colors come from a table of :data:`COLOR_STEPS` colors of
:func:`heatcore.viz.colormap.colorize` (linear, as the color attribute stores
them): one gather per update, 15 ms at 1M vertices where ``colorize`` and the
sRGB conversion take 125 ms. The surface is drawn with a depth offset
(:func:`offset_projection`, Blender's own polygon offset) so that it covers
the mesh it lies on without z-fighting.

Examples
--------
>>> table = color_table("viridis", isolines=10)               # doctest: +SKIP
>>> colors = field_colors(distance, table)                    # doctest: +SKIP
>>> overlay = Overlay()                                       # doctest: +SKIP
>>> overlay.update(OverlayData(positions, triangles, colors)) # doctest: +SKIP
>>> overlay.remove()                                          # doctest: +SKIP
"""

import dataclasses
import typing

import bpy
import numpy as np

from ._heatcore import colormap as colormaps
from ._heatcore import heatcore
from .adapters import srgb_to_linear

#: Colors in the field's table (the last row, one more, is the unreachable grey).
COLOR_STEPS = 4096
#: RGBA (linear) of the sources, the target and the path; line width in pixels.
SOURCE_COLOR = (1.0, 0.2, 0.02, 1.0)
TARGET_COLOR = (0.02, 0.6, 1.0, 1.0)
PATH_COLOR = (1.0, 1.0, 1.0, 1.0)
ISOLINE_COLOR = (0.0, 0.0, 0.0, 1.0)
LINE_WIDTH = 2.5
POINT_SIZE = 10.0


def color_table(colormap, isolines):
    """The colors of ``colorize`` at ``COLOR_STEPS`` even steps of distance / maximum, linear RGBA float32.

    Row ``COLOR_STEPS`` is the color of unreachable vertices.

    Examples
    --------
    >>> color_table("viridis", 0).shape                        # doctest: +SKIP
    (4097, 4)
    """
    steps = np.r_[np.linspace(0.0, 1.0, COLOR_STEPS), np.inf]
    rgba = np.ones((COLOR_STEPS + 1, 4), dtype=np.float32)
    rgba[:, :3] = srgb_to_linear(colormaps.colorize(steps, colormap=colormap, isolines=int(isolines), vmax=1.0))
    return rgba


def field_colors(distance, table):
    """Per-vertex linear RGBA of ``distance`` (``inf``: unreachable) from a :func:`color_table`.

    The nearest of the table's steps (``floor(d / max * (COLOR_STEPS - 1) + 0.5)``):
    ``colorize`` within 1/8190 of the maximum (its isoline stripes included).

    Examples
    --------
    >>> field_colors(np.array([0.0, 2.0, np.inf]), color_table("viridis", 0))[:, 0]  # doctest: +SKIP
    array([0.05832..., 0.98225..., 0.21404...], dtype=float32)
    """
    d = np.asarray(distance, dtype=np.float64)
    dmax = float(np.max(d, where=np.isfinite(d), initial=0.0))
    scale = (COLOR_STEPS - 1) / dmax if dmax > 0 else 0.0
    # Nearest step (halves up); inf (unreachable) -> the last row.
    index = np.minimum(d * scale + 0.5, COLOR_STEPS).astype(np.intp)
    rows = np.ascontiguousarray(table, dtype=np.float32).view(np.complex128).ravel()  # one 16-byte item a row
    return np.take(rows, index).view(np.float32).reshape(-1, 4)  # 7x faster than table[index]


@dataclasses.dataclass
class OverlayData:
    """The arrays the overlay draws, in world coordinates (float32).

    Attributes
    ----------
    positions : (n, 3) float32
        The vertices as displayed.
    triangles : (m, 3) uint32
        The mesh's loop triangles.
    colors : (n, 4) float32 or None
        Linear RGBA of the field (None before the first source).
    sources : (k, 3) float32
        The source points.
    target : (3,) float32 or None
    path : (p, 3) float32 or None
        The geodesic path's points, source to target.
    isolines : list of (q, 3) float32
        Isoline polylines (from ``heatcore.isolines`` where this heatcore has it).
    """

    positions: np.ndarray
    triangles: np.ndarray
    colors: np.ndarray = None
    sources: np.ndarray = dataclasses.field(default_factory=lambda: np.zeros((0, 3), dtype=np.float32))
    target: np.ndarray = None
    path: np.ndarray = None
    isolines: list = dataclasses.field(default_factory=list)

    @classmethod
    def of(cls, probe):
        """What a :class:`~.probe.GeodesicProbe` shows now: its field, sources, target and path, in world
        coordinates (the path, measured in Local space, moved by the object's matrix), and, when no drag is
        under way, the field's isoline curves (``heatcore.isolines``: 35 ms at 100k vertices, too slow for
        every mouse move; the colors' stripes show the isolines while dragging)."""
        surface = probe.surface
        data = cls(positions=surface.positions32, triangles=surface.triangles32)
        if probe.distance is not None:
            data.colors = field_colors(probe.distance, probe.color_table)
        data.sources = np.array([surface.point(*s) for s in probe.sources], dtype=np.float32).reshape(-1, 3)
        if probe.target is not None:
            data.target = surface.point(*probe.target).astype(np.float32)
        shown = probe.trace if getattr(probe, "trace", None) is not None else probe.path  # a trace, else the path
        if shown is not None:
            M = probe.matrix
            data.path = np.asarray(shown.points if M is None else shown.points @ M[:3, :3].T + M[:3, 3],
                                   dtype=np.float32)
        isolines, count = getattr(heatcore, "isolines", None), int(probe.run.outputs["isolines"])
        if isolines is not None and probe.distance is not None and count and not probe.dragging:
            curves = isolines(surface.positions, surface.triangles, probe.distance, count)
            data.isolines = [np.asarray(c.points, dtype=np.float32) for c in curves]
        return data


def offset_projection(projection, view_distance, offset=1.0):
    """``projection`` with the depth pulled towards the viewer, as Blender's ``GPU_polygon_offset``.

    Perspective: the depth term scaled by ``1 + 0.00125 * offset``;
    orthographic: moved by ``0.000005 * offset * view_distance``.

    Examples
    --------
    >>> from mathutils import Matrix
    >>> offset_projection(Matrix.Identity(4), 10.0)[2][3]        # doctest: +SKIP
    -5e-05
    """
    result = projection.copy()
    half = 0.5 * offset
    if projection[3][3] > 0.5:  # orthographic
        result[2][3] -= 0.00001 * half * view_distance
    else:
        result[2][3] -= projection[2][3] * -0.0025 * half
    return result


class Overlay:
    """A ``POST_VIEW`` draw handler in every 3D View drawing an :class:`OverlayData`.

    ``Overlay.live`` holds the overlays whose handler is installed (a leak
    shows there). The callback only draws: batches are made from the data
    the first time it is drawn after :meth:`update`.
    """

    live: typing.ClassVar[set] = set()

    def __init__(self):
        self.data = None
        self._batches = None
        self.handle = bpy.types.SpaceView3D.draw_handler_add(self.draw, (), "WINDOW", "POST_VIEW")
        Overlay.live.add(self)

    def update(self, data):
        """Draw ``data`` from the next redraw on."""
        self.data = data
        self._batches = None
        redraw_3d_views()

    def remove(self):
        """Remove the draw handler (idempotent) and redraw the 3D Views."""
        if self.handle is not None:
            bpy.types.SpaceView3D.draw_handler_remove(self.handle, "WINDOW")
            self.handle = None
        Overlay.live.discard(self)
        self.data = self._batches = None
        redraw_3d_views()

    def draw(self):  # pragma: no cover - Blender calls it while drawing a 3D View (never headless)
        """The draw callback: the field's surface, the isolines, the path, the points."""
        import gpu

        if self.data is None:
            return
        if self._batches is None:
            self._batches = make_batches(self.data)
        region = bpy.context.region
        rv3d = bpy.context.region_data
        gpu.state.depth_test_set("LESS_EQUAL")
        gpu.state.depth_mask_set(False)
        surface, lines, points = self._batches
        if surface is not None:
            with gpu.matrix.push_pop_projection():
                gpu.matrix.load_projection_matrix(offset_projection(gpu.matrix.get_projection_matrix(), rv3d.view_distance))
                surface[1].bind()
                surface[0].draw(surface[1])
        gpu.state.blend_set("ALPHA")
        for batch, shader, color in lines:
            shader.bind()
            shader.uniform_float("viewportSize", (region.width, region.height))
            shader.uniform_float("lineWidth", LINE_WIDTH)
            shader.uniform_float("color", color)
            batch.draw(shader)
        gpu.state.depth_test_set("NONE")
        for batch, shader, color in points:
            shader.bind()
            shader.uniform_float("color", color)
            try:
                shader.uniform_float("size", POINT_SIZE)  # POINT_UNIFORM_COLOR's size (Blender 4.1 and later)
            except ValueError:
                gpu.state.point_size_set(POINT_SIZE)
            batch.draw(shader)
        gpu.state.point_size_set(1.0)
        gpu.state.blend_set("NONE")
        gpu.state.depth_mask_set(True)


def line_segments(polylines):
    """Polylines as one ``LINES`` array: each point but the last joined to the next.

    Examples
    --------
    >>> line_segments([np.zeros((3, 3))]).shape                   # doctest: +SKIP
    (4, 3)
    """
    pieces = [np.repeat(np.asarray(p, dtype=np.float32), 2, axis=0)[1:-1] for p in polylines if len(p) > 1]
    return np.concatenate(pieces) if pieces else np.zeros((0, 3), dtype=np.float32)


def make_batches(data):  # pragma: no cover - needs a GPU
    """The ``gpu`` batches of ``data``: (surface or None, [(lines, shader, color)], [(points, shader, color)])."""
    import gpu
    from gpu_extras.batch import batch_for_shader

    surface = None
    if data.colors is not None:
        shader = gpu.shader.from_builtin("SMOOTH_COLOR")
        batch = batch_for_shader(shader, "TRIS", {"pos": data.positions, "color": data.colors}, indices=data.triangles)
        surface = (batch, shader)
    line = gpu.shader.from_builtin("POLYLINE_UNIFORM_COLOR")
    lines = []
    for polylines, color in ((data.isolines, ISOLINE_COLOR), ([] if data.path is None else [data.path], PATH_COLOR)):
        segments = line_segments(polylines)
        if len(segments):
            lines.append((batch_for_shader(line, "LINES", {"pos": segments}), line, color))
    point = gpu.shader.from_builtin("POINT_UNIFORM_COLOR")
    points = []
    for where, color in ((data.sources, SOURCE_COLOR), (data.target, TARGET_COLOR)):
        if where is not None and len(where):
            points.append((batch_for_shader(point, "POINTS", {"pos": np.reshape(where, (-1, 3))}), point, color))
    return surface, lines, points


def redraw_3d_views():
    """Tag every 3D View of every window for redraw (none in a headless ``bpy``)."""
    wm = bpy.context.window_manager
    for window in wm.windows if wm is not None else ():
        for area in window.screen.areas:
            if area.type == "VIEW_3D":
                area.tag_redraw()
