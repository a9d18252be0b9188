"""The geodesic probe: sources placed at surface points, the distance field follows, written on confirm.

:class:`GeodesicProbe` is the interactive tool's logic without a window (the
modal operator of :mod:`.probe_tool` is a thin shell over it; scripts and
tests drive it). A source is a surface point ``(face, barycentric)``, ``face``
a loop triangle of the mesh (the solver's triangle), or a vertex. Each update
queries the solver and redraws the overlay (:mod:`.overlay`); nothing is
written to the mesh before :meth:`~GeodesicProbe.confirm` (the outputs of
:func:`~.api.compute_geodesic_distance`, one undo step), so
:meth:`~GeodesicProbe.cancel` leaves the mesh as it was. The solver comes
from the add-on's cache or is built (now, or in the background); any change
in the scene flags running probes, which then re-read the geometry and refuse
to go on with a stale solver (:meth:`~GeodesicProbe.check`).

Examples
--------
>>> probe = GeodesicProbe(bpy.context.object, isolines=10)     # doctest: +SKIP
>>> d = probe.move_to(120, (0.2, 0.3, 0.5))                    # doctest: +SKIP
>>> probe.distance_at(4000, (1.0, 0.0, 0.0))                   # doctest: +SKIP
1.734...
>>> result = probe.confirm()                                   # doctest: +SKIP
"""

import time
import weakref

import bpy
import numpy as np

from ._heatcore import heatcore
from .adapters import AddonError
from .background import DONE, FAILED, RUNNING, BackgroundBuild
from .cache import SOLVERS, same_key
from .outputs import check_outputs, write_outputs
from .overlay import Overlay, OverlayData, color_table
from .curves import path_available, write_probe_curves
from .probe_surface import DisplayedSurface, displayed_positions
from .stages import (
    GeodesicResult,
    build_solver,
    current_key,
    find_object,
    prepare_run,
)

#: Probes running now: the depsgraph handler flags them when anything changes.
_ACTIVE = weakref.WeakSet()

#: From this many solver vertices a drag shows the coarse preview (``heatcore.CoarsePreview``: about 40 ms
#: at 1M vertices, where a query takes 0.5 s) until the mouse rests (:meth:`GeodesicProbe.settle`). A mesh of
#: this many vertices built in the background gets its preview first, from its arrays: sources can be placed
#: and dragged on it while the solver builds (:attr:`GeodesicProbe.preview_ready`).
PREVIEW_FROM = 200_000


class GeodesicProbe:
    """Interactive geodesic distance on one mesh object: sources at surface points, written on confirm.

    Parameters
    ----------
    obj : bpy.types.Object
        A mesh object with faces (Object or Edit Mode).
    background : bool
        Build a missing solver in a worker thread (:meth:`poll` says when it
        is ready; on a large mesh sources can be placed on its coarse preview
        before, :attr:`preview_ready`); default: build it now.
    overlay : bool
        Draw the field over the 3D Views (:class:`~.overlay.Overlay`).
    path_curve, isoline_curves : bool
        :meth:`confirm` also writes the geodesic path to the target, or the
        isolines, as curve objects ``"<name> Geodesic Path"``, ``"... Isolines"``.
    **options
        The keywords of :func:`~.api.compute_geodesic_distance` but the
        sources (``space``, ``shape``, outputs, solver options).

    Raises
    ------
    AddonError
        Not a mesh with faces, ``new_object``, or an output option
        :func:`~.api.compute_geodesic_distance` refuses.
    """

    def __init__(self, obj, *, background=False, overlay=True, path_curve=False, isoline_curves=False, **options):
        if obj is None or getattr(obj, "type", None) != "MESH":
            raise AddonError(f"the geodesic probe needs a mesh object; {getattr(obj, 'name', obj)!r} is not one")
        if options.pop("new_object", False):
            raise AddonError("the geodesic probe measures the object itself: new_object is not available")
        self.run = prepare_run(obj, sources_later=True, **options)  # Edit Mode synced
        if not len(obj.data.polygons):
            raise AddonError(f"the geodesic probe places sources on faces: mesh {obj.data.name!r} has none")
        self.notes = self.run.notes
        self.path_curve, self.isoline_curves = path_curve, isoline_curves
        self.sources = []  # (face, barycentric) or (vertex, None)
        self.active = None  # index of the dragged source
        self.target = self.path = self.distance = None
        #: A traced geodesic (the tool's Alt+drag, :mod:`.probe_trace`): its start and heatcore's ``TracedPath``.
        self.trace_start = self.trace = None
        self.changed = False
        self.ended = False
        #: Whether the field shown is the solver's (False: the coarse preview of a drag, until :meth:`settle`).
        self.exact = True
        #: A drag under way (set by the tool between press and release): the overlay skips the isoline curves.
        self.dragging = False
        self._adopted = False
        self.timings = {}
        self.color_table = color_table(self.run.outputs["colormap"], self.run.outputs["isolines"])
        #: The mesh as displayed (world): ray casting, the overlay, the loop triangles.
        self.surface = DisplayedSurface.of(obj, self.run)
        self.triangles = self.surface.triangles
        #: Measured to world coordinates (Space Local), for the path; None in World space.
        self.matrix = None if self.run.space == "WORLD" else np.array(obj.matrix_world, dtype=np.float64)
        self.build = None
        #: The coarse preview made from the mesh's arrays before its solver (a large mesh built in the background).
        self.early_preview = None
        _settle(obj)
        _ACTIVE.add(self)  # flagged by any change from now on (during a background build too)
        try:
            if self.run.solver is not None and self.surface.tree is not None:
                self._adopt()
            elif background:
                label = f"the heat solver of {obj.name!r} ({len(self.run.V):,} vertices)"
                self.build = BackgroundBuild(self._build, label)
                self.build.start()  # raises Busy while another build runs
            else:
                self._build(None)
                self._adopt()
        except BaseException:
            _ACTIVE.discard(self)
            raise
        self._overlay = Overlay() if overlay else None

    # ---- building

    @property
    def ready(self):
        """Whether the solver and the ray-casting tree are there, checked and kept (queries can run)."""
        return self._adopted

    @property
    def preview_ready(self):
        """Whether sources can be placed and dragged before :attr:`ready`: a large mesh's coarse preview and the
        ray-casting tree are there while its solver builds (the field then stays the preview: :meth:`settle`
        waits for the solver, :meth:`confirm` refuses)."""
        return self.early_preview is not None and not self.ended

    def _build(self, progress):
        """Worker: the solver (if not cached) and the ray-casting tree; no Blender data read. A large mesh
        (``PREVIEW_FROM``) gets the tree and its coarse preview first (:attr:`preview_ready`)."""
        if progress is not None and self.run.solver is None and len(self.run.V) >= PREVIEW_FROM:
            self._build_early_preview(progress)
        if self.run.solver is None:
            if self.run.F is None:
                self.run.F = self.triangles
            build_solver(self.run, progress)
        if progress is not None and self.surface.tree is None:
            progress(0.8, "preparing the ray casting")
        self.surface.build_tree()
        if self._previews():
            if progress is not None and self.early_preview is None:
                progress(0.9, "a coarse copy of the mesh, for fast drags")
            self._preview()  # kept in the domain's cache (the early one, where there is one)
        return self.run.solver

    def _build_early_preview(self, progress):
        """Worker: the ray-casting tree, then the coarse preview from the mesh's arrays (:attr:`preview_ready`); a
        mesh the preview refuses gets none (its solver's build goes on and says why, if it fails too)."""
        progress(0.0, "preparing the ray casting")
        self.surface.build_tree()
        progress(0.05, "a coarse copy of the mesh, to place sources on while the solver builds")
        try:
            self.early_preview = heatcore.CoarsePreview.of_arrays(self.run.V, self.triangles)
        except heatcore.HeatcoreError:
            self.early_preview = None

    def _previews(self):
        """Whether drags show the coarse preview: a large mesh (``PREVIEW_FROM``) measured as triangles."""
        if self.early_preview is not None:
            return True
        domain = self.run.solver.domain
        return isinstance(domain, heatcore.TriangleMesh) and domain.operators.n_vertices >= PREVIEW_FROM

    def _preview(self):
        """The coarse preview of the solver's mesh, kept in the domain's cache (made once per solver: the one made
        from the arrays before the solver where there is one); while the solver builds, that one."""
        if self.run.solver is None:
            return self.early_preview
        domain = self.run.solver.domain
        return domain.derived.get_or_build(("coarse preview", None),
                                           lambda: self.early_preview or heatcore.CoarsePreview(domain))

    def _adopt(self):
        """Keep what was built: the solver in the add-on's cache, the tree beside it."""
        if not self.run.cached:
            SOLVERS.store(self.run.cache_id, self.run.key, self.run.solver)
        self.surface.keep(self.run.solver)
        self._adopted = True

    def poll(self):
        """State of the background build: ``"running"``, ``"done"`` (ready to use) or ``"cancelled"``.

        Once the build is done the object is checked (:meth:`check`) and
        the solver kept in the cache.

        Raises
        ------
        AddonError
            The object was deleted or changed during the build (nothing kept).
        Exception
            What the build raised.
        """
        if self.ready:
            return DONE
        state = self.build.poll()
        if state == RUNNING:
            return RUNNING
        if state == FAILED:
            self.build.result()  # raises the worker's error
        if state != DONE:
            return state
        self.check(built=True)
        self._adopt()
        return DONE

    def progress(self):
        """The build's latest ``(fraction, message)`` (``(1.0, "ready")`` when nothing is built)."""
        return self.build.progress() if self.build is not None and not self.ready else (1.0, "ready")

    # ---- the object and its geometry

    def object(self):
        """The probed object (found again by ``session_uid``).

        Raises
        ------
        AddonError
            It was deleted, or its mesh replaced.
        """
        obj = find_object(self.run)
        if obj is None:
            raise AddonError(f"{self.run.object_name!r} was deleted while the geodesic probe ran; nothing was written")
        return obj

    def check(self, built=False):
        """Make sure the object still exists and has the geometry the solver and the overlay were made for.

        Raises
        ------
        AddonError
            Deleted, or its measured or displayed shape changed (an edit, a
            shape key, a modifier, a move in World space, undo).
        """
        obj = self.object()
        run = self.run
        key, _ = current_key(obj, run)  # the placement is checked with the displayed positions
        if not same_key(run.key, key) or not np.array_equal(displayed_positions(obj, run), self.surface.positions):
            when = "while its solver was being built" if built else "while the geodesic probe ran"
            raise AddonError(f"{obj.name!r} changed {when} (its shape or its vertices); nothing was written: "
                             "start the probe again")
        _settle(obj)
        self.changed = False
        return obj

    def _require(self, preview=False):
        """Refuse an ended probe, or one whose solver is still being built (with ``preview``: unless its coarse
        preview is ready, :attr:`preview_ready`)."""
        if self.ended:
            raise AddonError("this geodesic probe has ended (confirmed or cancelled)")
        if not self.ready and not (preview and self.preview_ready):
            raise AddonError(f"the heat solver of {self.run.object_name!r} is still being built")
        if self.changed:
            self.check()

    # ---- sources, queries

    def _point(self, face, barycentric):
        """A source or target as ``(face, barycentric)`` or ``(vertex, None)``, checked."""
        if barycentric is None:
            vertex = int(face)
            if not 0 <= vertex < len(self.run.V):
                raise AddonError(f"vertex {vertex} is not a vertex of {self.run.object_name!r}")
            return vertex, None
        face = int(face)
        if not 0 <= face < len(self.triangles):
            raise AddonError(f"face {face} is not a triangle of {self.run.object_name!r} "
                             f"(it has {len(self.triangles):,} loop triangles)")
        b = np.asarray(barycentric, dtype=np.float64).reshape(3)
        return face, b

    def move_to(self, face, barycentric=None, preview=False):
        """Move the dragged source (the last placed; the first one if none) to a surface point.

        Parameters
        ----------
        face : int
            A loop triangle of the mesh, or a vertex index when ``barycentric`` is None.
        barycentric : (3,) array_like, optional
            Coordinates in the triangle's corners (>= 0, summing to 1).
        preview : bool
            On a large mesh (``PREVIEW_FROM``), show the coarse preview
            (``heatcore.CoarsePreview``) instead of the solver's field: a drag's move.
            :meth:`settle` (the mouse at rest) shows the solver's. While the solver
            builds (:attr:`preview_ready`) every move shows the preview.

        Returns
        -------
        (n,) float array
            The distance at every vertex (``inf`` where unreachable).
        """
        self._require(preview=True)
        point = self._point(face, barycentric)
        if self.active is None:
            return self.add(face, barycentric)
        previous = self.sources[self.active]
        self.sources[self.active] = point
        return self._update(undo=lambda: self.sources.__setitem__(self.active, previous),
                            preview=preview and self._previews())

    def settle(self):
        """Replace a drag's coarse preview by the solver's field (the mouse at rest, or the solver just built);
        the distance. While the solver builds the preview stays."""
        if not self.exact and self.sources and self.ready:
            self._update(undo=lambda: None)
        return self.distance

    def add(self, face, barycentric=None):
        """Add a source at a surface point (or a vertex); it becomes the dragged one. Returns the distance."""
        self._require(preview=True)
        self.sources.append(self._point(face, barycentric))
        previous, self.active = self.active, len(self.sources) - 1

        def undo():
            self.sources.pop()
            self.active = previous

        return self._update(undo=undo)

    def place(self, sources):
        """Start again from ``sources`` (as :attr:`sources` holds them: ``(face, barycentric)`` or ``(vertex, None)``).

        The last becomes the dragged one. Returns the distance (None for no sources).
        """
        self._require(preview=True)
        previous = self.sources, self.active
        self.sources = [self._point(s, b) for s, b in sources]
        self.active = len(self.sources) - 1 if self.sources else None

        def undo():
            self.sources, self.active = previous

        if not self.sources:
            self.distance = None
            self.show()
            return None
        return self._update(undo=undo)

    def _update(self, undo, preview=False):
        start = time.perf_counter()
        vertices = [s for s, b in self.sources if b is None]
        points = [(s, b) for s, b in self.sources if b is not None]
        preview = preview or not self.ready  # the solver still builds: the preview (preview_ready)
        solver = self._preview() if preview else self.run.solver
        try:
            self.distance = self.run.placement.distance(solver.distance(
                vertices or None,
                points=(np.array([f for f, _ in points]), np.array([b for _, b in points])) if points else None,
            ))
        except heatcore.HeatcoreError:
            undo()  # the field stays that of the sources before
            raise
        self.exact = not preview
        queried = time.perf_counter()
        if self.target is not None:
            self.path = None  # from the old sources: recomputed by update_path()
        self.show()
        self.timings = {"query": queried - start, "display": time.perf_counter() - queried,
                        "update": time.perf_counter() - start}
        return self.distance

    def distance_at(self, face, barycentric=None):
        """The distance at a surface point (linear in its triangle), or None before the first source."""
        if self.distance is None:
            return None
        face, b = self._point(face, barycentric)
        if b is None:
            return float(self.distance[face])
        values = self.distance[self.triangles[face]]
        return float(b @ values) if np.isfinite(values).all() else float("inf")

    def path_to(self, face, barycentric=None):
        """heatcore's ``GeodesicPath`` (``points`` in measured space, ``length``) to a target point from the
        nearest source (the shortest of their paths).

        Raises
        ------
        AddonError
            No source yet, or this heatcore has no geodesic paths
            (``HeatSolver.geodesic_path``).
        """
        self._require()
        if not path_available(self.run.solver):
            raise AddonError("drawing a path needs heatcore's geodesic paths (HeatSolver.geodesic_path), which "
                             "this copy of heatcore does not have")
        if not self.sources:
            raise AddonError("place a source first: the path runs from the nearest source to the target")
        self.target = self._point(face, barycentric)
        return self.update_path()

    def end_drag(self):
        """The button is up: the path follows the moved source, the overlay gets its isoline curves again."""
        self.dragging = False
        self.settle()
        if self.target is not None and self.path is None and self.sources:
            self.update_path()
        else:
            self.show()

    def update_path(self):
        """Recompute the path to the target from the current sources (after a move); None without a target."""
        if self.target is None or not self.sources:
            return None
        target = self.target[0] if self.target[1] is None else self.target
        paths = [self.run.placement.path(self.run.solver.geodesic_path(s if b is None else (s, b), target))
                 for s, b in self.sources]
        self.path = min(paths, key=lambda p: p.length)
        self.show()
        return self.path

    # ---- where the cursor is

    def ray_cast(self, origin, direction):
        """The first :data:`~.probe_surface.Hit` (face, barycentric, location, depth) of a world-space ray on the
        mesh as displayed, or None."""
        return self.surface.ray_cast(origin, direction) if self.ready or self.preview_ready else None

    def world_point(self, face, barycentric=None):
        """The world position of a surface point (or vertex) as displayed."""
        return self.surface.point(*self._point(face, barycentric))

    # ---- display

    def overlay_data(self):
        """What the overlay draws now (:class:`~.overlay.OverlayData`)."""
        return OverlayData.of(self)

    def show(self):
        """Redraw the overlay with what the probe holds now."""
        if self._overlay is not None:
            self._overlay.update(self.overlay_data())

    # ---- the end

    def confirm(self, push_undo=True):
        """Write the outputs for the current sources (and the path curve if asked), as one undo step.

        ``push_undo=False`` when an operator returns ``FINISHED`` (Blender
        pushes its undo step then). The probe ends.

        Returns
        -------
        GeodesicResult

        Raises
        ------
        AddonError
            No source placed, the object deleted or changed, or an output
            name taken meanwhile: nothing is written (the probe goes on).
        """
        self._require()
        if self.distance is None:
            raise AddonError("no source placed: click on the mesh first; nothing was written")
        obj = self.check()
        run = self.run
        check_outputs(obj, **run.outputs)
        self.settle()  # never a drag's coarse preview written
        dmax = write_outputs(obj, self.distance, run.space, **run.outputs)
        write_probe_curves(self, obj)
        if push_undo and bpy.ops.ed.undo_push.poll():
            bpy.ops.ed.undo_push(message="Geodesic Probe")
        self.end()
        vertices = np.array(sorted(s for s, b in self.sources if b is None), dtype=np.int64)
        return GeodesicResult(self.distance, vertices, dmax, len(run.V), self.timings.get("update", 0.0),
                              run.solver_seconds, run.cached, run.skipped_modifiers, run.notes, obj)

    def cancel(self):
        """End without writing anything: the overlay goes, a running build is cancelled; the mesh is as it was."""
        self.end()

    def __del__(self):  # a script that drops a probe without cancel() leaves no overlay behind
        try:
            self.end()
        except Exception:  # noqa: BLE001, S110 - interpreter teardown
            pass

    def end(self):
        """Take the overlay down and stop listening for changes (idempotent)."""
        if getattr(self, "build", None) is not None and not self.ready:
            self.build.cancel()
        if getattr(self, "_overlay", None) is not None:
            self._overlay.remove()
            self._overlay = None
        _ACTIVE.discard(self)
        self.ended = True


def _settle(obj):
    """In Edit Mode, evaluate now the updates that reading the mesh tagged (``update_from_editmode``, the
    temporary copies of :func:`~.adapters.stored`), so that the change handler sees them before the probe is
    marked unchanged (else each check would flag the next)."""
    if obj.mode == "EDIT":
        bpy.context.view_layer.update()


def running():
    """The probes running now (not ended).

    Examples
    --------
    >>> [p.run.object_name for p in running()]   # doctest: +SKIP
    ['Suzanne']
    """
    return list(_ACTIVE)
