"""A first answer drawn while the button's solver builds: the distance on a cheaper mesh, never written.

A button click whose solver is not cached waits for its build: 0.24 s of a
162-vertex icosphere's 0.27 s (heatcore refines every part of fewer than
``AUTO_REFINE_MIN_VERTICES`` vertices, to 40,962 here), about 0.3 s at 50k
vertices, seconds at 500k. So the click first answers on a cheaper mesh
(:class:`PreviewWork`) and draws that distance with the probe's overlay
(:mod:`.overlay`):

- ``"unrefined"``: a mesh the build refines is solved on as it is
  (``refine=0``: its own vertices, a few milliseconds), drawn at once,
  before the build starts;
- ``"coarse"``: a mesh of ``COARSE_PREVIEW_FROM`` vertices or more is
  clustered to about ``COARSE_PREVIEW_CLUSTERS`` vertices straight from its
  faces (``heatcore.CoarsePreview.of_arrays``: no domain built
  first; 0.06-0.1 s at 51k, 0.4-0.7 s at 504k), each vertex showing its
  cluster's distance, computed by the build's worker thread before the
  solver (beside it, it slowed the build by more than its own time: 0.8 s
  at 504k) and drawn at the next timer event.

The overlay is drawn, never written: the result written when the build ends
is the mesh's own, the same as without a preview, in the same one undo step;
Esc, a failed build or a changed object take the overlay down with nothing
written, as before.

Examples
--------
>>> work = PreviewWork(run) if wants_preview(run) else None  # doctest: +SKIP
>>> work.compute()                                          # doctest: +SKIP
>>> preview = Preview.show(obj, run, work.distance, work.triangles)  # doctest: +SKIP
>>> preview.remove()                                                            # doctest: +SKIP
"""

import dataclasses
import importlib
import logging
import threading
import warnings

import numpy as np

from ._heatcore import heatcore
from .overlay import Overlay, OverlayData, color_table, field_colors
from .probe_surface import DisplayedSurface, displayed_positions
from .stages import build_solver

#: ``heatcore.domains.refine.AUTO_REFINE_MIN_VERTICES``: meshes under it are refined by default, and previewed.
AUTO_REFINE_MIN_VERTICES = importlib.import_module(heatcore.__name__ + ".domains.refine").AUTO_REFINE_MIN_VERTICES
#: From this many vertices a click's preview is a coarse one (a solver build there takes 0.3 s and more).
COARSE_PREVIEW_FROM = 20_000
#: About how many vertices a coarse preview clusters a mesh to (at most a tenth of the mesh's): 0.06-0.1 s at 51k
#: vertices (6,382 clusters), 0.4-0.7 s at 504k; off by 0.6-2.1% of the largest distance on average, 3-8% at worst,
#: against the polygon solver's result (docs/blender-benchmarks.md).
COARSE_PREVIEW_CLUSTERS = 10_000
#: What the header adds while each kind of preview is (about to be) shown.
PREVIEW_TITLES = {"unrefined": " (preview on the unrefined mesh shown)", "coarse": " (coarse preview shown)"}

log = logging.getLogger(__name__)


def preview_kind(run):
    """The preview a button click's ``run`` (:class:`~.stages.PreparedRun`) shows while its solver builds, or None.

    ``"coarse"`` from ``COARSE_PREVIEW_FROM`` vertices, ``"unrefined"`` below
    where the solver is to be built on a refined mesh (``refine="auto"`` under
    ``AUTO_REFINE_MIN_VERTICES`` vertices, or refinement levels asked for);
    only from source vertices on the object itself: not for selected faces or
    edges, a new object or a point cloud.

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> run = NS(solver=None, new_object=False, points_only=False, kinds=None, sources=np.array([0]),
    ...          V=np.zeros((162, 3)), settings=NS(mesh=NS(refine="auto")))
    >>> preview_kind(run), preview_kind(NS(**{**vars(run), "settings": NS(mesh=NS(refine=0))}))
    ('unrefined', None)
    >>> preview_kind(NS(**{**vars(run), "V": np.zeros((15_000, 3))})), preview_kind(NS(**{**vars(run), "V": np.zeros((50_000, 3))}))
    (None, 'coarse')
    """
    if run.solver is not None or run.new_object or run.points_only or run.kinds or not run.sources.size:
        return None
    n, refine = len(run.V), run.settings.mesh.refine
    if n >= COARSE_PREVIEW_FROM:
        return "coarse"
    return "unrefined" if refine != 0 and (refine != "auto" or n < AUTO_REFINE_MIN_VERTICES) else None


def wants_preview(run):
    """Whether a button click's ``run`` shows a preview while its solver builds (:func:`preview_kind`)."""
    return preview_kind(run) is not None


def preview_title(run):
    """What the header adds for ``run``'s preview ("" without one)."""
    return PREVIEW_TITLES.get(preview_kind(run), "")


def preview_distance(run):
    """The distance from ``run``'s sources, per vertex, for its :func:`preview_kind`, and the triangles to draw it on.

    ``"unrefined"``: built as :func:`~.stages.build_solver` builds the run's
    own solver, on a copy of the run (``refine=0``, ``accuracy="smooth"``; the
    run is not changed), its warnings left to that build; drawn on the mesh's
    loop triangles (triangles None: read from Blender when drawn).
    ``"coarse"``: ``heatcore.CoarsePreview.of_arrays`` of the run's triangles
    or polygons (fans where they cover their polygons, else triangulated), drawn on
    the triangles it used (reading Blender's loop triangles would hold it
    0.13 s at 504k vertices); the parts of its sources only.

    Returns
    -------
    distance : (n,) float array
    triangles : (m, 3) int array or None
    """
    if preview_kind(run) == "coarse":
        faces = run.F if run.F is not None else run.polygons
        clusters = min(COARSE_PREVIEW_CLUSTERS, len(run.V) // 10)
        preview = heatcore.CoarsePreview.of_arrays(run.V, faces, vertices=clusters, only_parts_of=run.sources)
        return preview.distance(run.sources), preview.triangles
    settings = dataclasses.replace(run.settings, mesh=run.settings.mesh.replace(refine=0),
                                   solver=run.settings.solver.replace(accuracy="smooth"))
    coarse = dataclasses.replace(run, settings=settings, notes=[], solver=None)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        build_solver(coarse)
    return coarse.solver.distance(coarse.sources), None


class PreviewWork:
    """:func:`preview_distance` of a run, computed by :meth:`compute` in any thread (no ``bpy``), for the main thread.

    ``distance`` (and ``triangles``) are None until it is done, and ``distance``
    stays None where the mesh or sources are refused (``heatcore.HeatcoreError``:
    the build reports what is wrong) or the preview failed otherwise (a bug:
    its traceback is logged; the click goes on without a preview).
    """

    def __init__(self, run):
        self.run = run
        self.distance = self.triangles = None
        self._done = threading.Event()

    def compute(self):
        """Compute the preview (once; later calls return at once)."""
        if self._done.is_set():
            return
        try:
            self.distance, self.triangles = preview_distance(self.run)
        except heatcore.HeatcoreError:
            pass
        except Exception:  # a preview must not cost the click its answer: the traceback is logged
            log.exception("the geodesic distance preview failed")
        finally:
            self._done.set()

    def done(self):
        """Whether :meth:`compute` has ended."""
        return self._done.is_set()

    def wait(self, timeout=None):
        """Wait for :meth:`compute` to end (at most ``timeout`` seconds); whether it has."""
        return self._done.wait(timeout)


@dataclasses.dataclass
class Preview:
    """A preview on screen: its distance and the overlay drawing it.

    Attributes
    ----------
    distance : (n,) float array
        Per vertex of the mesh (``inf``: unreachable), on the unrefined or the coarse mesh.
    data : OverlayData
        What is drawn: the mesh as displayed, colored by ``distance``, and the sources.
    overlay : Overlay or None
        The draw handler; None once removed.
    """

    distance: np.ndarray
    data: OverlayData
    overlay: Overlay = None

    @classmethod
    def show(cls, obj, run, distance, triangles=None):
        """Draw ``distance`` over ``obj`` as displayed, on ``triangles`` (default: its loop triangles); None where its
        vertices are not the distance's any more (the object was edited meanwhile: the build's end says so)."""
        surface = DisplayedSurface.of(obj, run) if triangles is None else DisplayedSurface(
            displayed_positions(obj, run), triangles)
        if len(surface.positions) != len(distance):
            return None
        colors = field_colors(distance, color_table(run.outputs["colormap"], run.outputs["isolines"]))
        data = OverlayData(surface.positions32, surface.triangles32, colors, surface.positions32[run.sources])
        overlay = Overlay()
        overlay.update(data)
        return cls(distance, data, overlay)

    def remove(self):
        """Take the overlay down (idempotent)."""
        if self.overlay is not None:
            self.overlay.remove()
            self.overlay = None
