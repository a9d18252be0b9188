"""What a running tool shows in Blender: the progress indicator, the header and the status bar.

One display for the tools that build a solver in the background while the UI
stays live (the *Geodesic Distance* operator's build; the geodesic probe's
display has the same calls: progress, text, ready, end): a modal timer that wakes the tool, the window manager's progress indicator,
the header of the area the tool was started from (what runs and how far it
is) and the status bar (the keys). Every call is guarded: an area, window or
workspace closed meanwhile is skipped.

Examples
--------
Outside Blender, with stand-ins for the context's window manager and area:

>>> from types import SimpleNamespace as NS
>>> shown = []
>>> wm = NS(event_timer_add=lambda step, window: NS(time_step=step), event_timer_remove=lambda timer: None,
...         progress_begin=lambda low, high: None, progress_update=lambda percent: shown.append(percent),
...         progress_end=lambda: shown.append("progress off"))
>>> area = NS(header_text_set=shown.append, tag_redraw=lambda: None)
>>> display = ProgressDisplay(NS(window_manager=wm, window=None, area=area), "Geodesic distance")
>>> display.progress(0.42, "factoring the heat matrix")
>>> display.end(); display.end()  # twice is harmless
>>> shown
[42, 'Geodesic distance: factoring the heat matrix (42%)', 'progress off', None]
"""

import time

#: Seconds between two looks at a background build (the modal timer) once it has run ``QUICK_SPAN``.
TIMER_STEP = 0.1
#: Seconds between two looks during the first ``QUICK_SPAN``: a small mesh's build is over in a few tenths of a
#: second, and a 0.1 s timer would add up to 0.1 s before its result is written.
QUICK_STEP = 0.02
#: Seconds of quick looks (:data:`QUICK_STEP`) before the timer slows to :data:`TIMER_STEP`.
QUICK_SPAN = 1.0
#: Seconds between two looks at a resting mouse (:meth:`ProgressDisplay.wake`).
WAKE_STEP = 0.04


def timer_step(elapsed):
    """Seconds between two looks at a build that has run ``elapsed`` seconds.

    Examples
    --------
    >>> timer_step(0.3), timer_step(2.0)
    (0.02, 0.1)
    """
    return QUICK_STEP if elapsed < QUICK_SPAN else TIMER_STEP


class ProgressDisplay:
    """The timer, progress indicator, header and status bar of one tool run; :meth:`end` takes them down.

    Parameters
    ----------
    context : bpy.types.Context
        Its window manager and window (timer, progress indicator), area
        (header) and workspace (status bar); a missing area or workspace is
        skipped.
    title : str
        What runs, shown before each stage in the header.
    keys : str, default "Esc: cancel"
        The status bar while the build runs.

    Attributes
    ----------
    timer : bpy.types.Timer or None
        The modal timer, None once the build is over (:meth:`ready`).
    ended : bool
        Whether :meth:`end` ran.
    """

    def __init__(self, context, title, keys="Esc: cancel"):
        self.wm, self.window = context.window_manager, context.window
        self.workspace, self.area = getattr(context, "workspace", None), getattr(context, "area", None)
        self.title, self.keys = title, keys
        self.started = time.monotonic()
        self.timer = self.wm.event_timer_add(timer_step(0.0), window=self.window)
        self.waking = None  # the timer of wake(), after the build
        self.wm.progress_begin(0, 100)
        self.ended = False

    @staticmethod
    def _try(call, *args):
        try:
            call(*args)
        except ReferenceError:  # the area, window or workspace was closed meanwhile
            pass

    def progress(self, fraction, message):
        """The build's stage ``message`` and its ``fraction`` (0..1) done: progress indicator and header."""
        self._pace()
        percent = int(100 * fraction)
        self._try(self.wm.progress_update, percent)
        self.text(f"{self.title}: {message} ({percent}%)", self.keys)

    def _pace(self):
        """Slow the timer to :data:`TIMER_STEP` once the build has run :data:`QUICK_SPAN`."""
        step = timer_step(time.monotonic() - self.started)
        if self.timer is not None and self.timer.time_step != step:
            self._try(self.wm.event_timer_remove, self.timer)
            self.timer = self.wm.event_timer_add(step, window=self.window)

    def text(self, header, status):
        """``header`` in the area's header, ``status`` in the status bar (None: Blender's own)."""
        if self.area is not None:
            self._try(self.area.header_text_set, header)
        if self.workspace is not None:
            self._try(self.workspace.status_text_set, status)

    def wake(self, on=True):
        """Keep a timer waking the tool while ``on`` (after the build: the probe's drag waits for the mouse to rest)."""
        if on and self.timer is None and not self.ended:
            self.waking = self.wm.event_timer_add(WAKE_STEP, window=self.window) if self.waking is None else self.waking
        elif not on and self.waking is not None:
            self._try(self.wm.event_timer_remove, self.waking)
            self.waking = None

    def ready(self):
        """The build is over: no more timer or progress indicator (the texts stay)."""
        if self.timer is not None:
            self._try(self.wm.event_timer_remove, self.timer)
            self._try(self.wm.progress_end)
            self.timer = None

    def end(self):
        """Take everything down and give the header and status bar back (idempotent)."""
        if self.ended:
            return
        self.ended = True
        self.ready()
        self.wake(False)
        self.text(None, None)
        if self.area is not None:
            self._try(self.area.tag_redraw)
