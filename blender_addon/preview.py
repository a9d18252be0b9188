"""A first answer drawn at once while a small mesh's solver builds: the distance on the mesh unrefined.

heatcore refines every part of fewer than ``AUTO_REFINE_MIN_VERTICES``
(11,000) vertices (``refine="auto"``) before it solves on it: a click on a
162-vertex icosphere builds a solver of 40,962 vertices, 0.24 s of the
click's 0.27 s, and from the button the result appears one timer step after
that. So the button's click on such a mesh first solves on the mesh as it is
(``refine=0``: its own vertices, a few milliseconds) and draws that distance
with the probe's overlay (:mod:`.overlay`), while the refined solver builds
in the background. The overlay is drawn, never written: the result written
when the build ends is the refined one, the same as without a preview, in
the same one undo step; Esc, a failed build or a changed object take the
overlay down with nothing written, as before.

Examples
--------
>>> preview = Preview.show(obj, run) if wants_preview(run) else None  # doctest: +SKIP
>>> preview.remove()                                                  # doctest: +SKIP
"""

import dataclasses
import importlib
import warnings

import numpy as np

from ._heatcore import heatcore
from .overlay import Overlay, OverlayData, color_table, field_colors
from .probe_surface import DisplayedSurface
from .stages import build_solver

#: ``heatcore.domains.refine.AUTO_REFINE_MIN_VERTICES``: meshes under it are refined by default, and previewed.
AUTO_REFINE_MIN_VERTICES = importlib.import_module(heatcore.__name__ + ".domains.refine").AUTO_REFINE_MIN_VERTICES
#: What the header adds while a preview is shown.
PREVIEW_TITLE = " (preview on the unrefined mesh shown)"


def wants_preview(run):
    """Whether a button click's ``run`` (:class:`~.stages.PreparedRun`) shows a preview while its solver builds.

    It does where the solver is to be built on a refined mesh (refinement on,
    fewer than ``AUTO_REFINE_MIN_VERTICES`` vertices) from source vertices on
    the object itself: not for selected faces or edges, a new object or a
    point cloud.

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> run = NS(solver=None, new_object=False, points_only=False, kinds=None, sources=np.array([0]),
    ...          V=np.zeros((162, 3)), settings=NS(mesh=NS(refine="auto")))
    >>> wants_preview(run), wants_preview(NS(**{**vars(run), "settings": NS(mesh=NS(refine=0))}))
    (True, False)
    """
    return bool(run.solver is None and not run.new_object and not run.points_only and not run.kinds
                and run.sources.size and run.settings.mesh.refine != 0 and len(run.V) < AUTO_REFINE_MIN_VERTICES)


def preview_distance(run):
    """The distance from ``run``'s sources on its mesh unrefined (``refine=0``, ``accuracy="smooth"``), per vertex.

    Built as :func:`~.stages.build_solver` builds the run's own solver, on a
    copy of the run (the run is not changed); its warnings are left to that build.
    """
    settings = dataclasses.replace(run.settings, mesh=run.settings.mesh.replace(refine=0),
                                   solver=run.settings.solver.replace(accuracy="smooth"))
    coarse = dataclasses.replace(run, settings=settings, notes=[], solver=None)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        build_solver(coarse)
    return coarse.solver.distance(coarse.sources)


@dataclasses.dataclass
class Preview:
    """A preview on screen: its distance and the overlay drawing it.

    Attributes
    ----------
    distance : (n,) float array
        Per vertex of the mesh (``inf``: unreachable), unrefined.
    data : OverlayData
        What is drawn: the mesh as displayed, colored by ``distance``, and the sources.
    overlay : Overlay or None
        The draw handler; None once removed.
    """

    distance: np.ndarray
    data: OverlayData
    overlay: Overlay = None

    @classmethod
    def show(cls, obj, run):
        """Solve on the unrefined mesh (:func:`preview_distance`) and draw the distance over ``obj`` as displayed."""
        distance = preview_distance(run)
        surface = DisplayedSurface.of(obj, run)
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
