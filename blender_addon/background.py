"""A solver build in a worker thread: progress, cancel between stages, one build at a time.

The operator's modal timer polls a :class:`BackgroundBuild` on the main
thread: :meth:`~BackgroundBuild.poll` gives the state and the latest stage
``(fraction, message)``, :meth:`~BackgroundBuild.cancel` asks the worker to
stop at its next stage (a stage itself runs to its end: the worker is then
left to finish it and its result is dropped), :meth:`~BackgroundBuild.result`
hands over what the worker made. No ``bpy`` here: the work passed in must not
touch Blender data (:func:`~.stages.build_solver` does not).

Only one build runs at a time, across all operators: :meth:`~BackgroundBuild.start`
raises :class:`Busy`, whose message says what runs, while another build's
thread is alive, including a cancelled one that is still finishing its stage.

Examples
--------
>>> import time
>>> def work(progress):
...     for i in range(3):
...         progress(i / 3, f"stage {i}")
...     progress(1.0, "done")
...     return 42
>>> build = BackgroundBuild(work, "example")
>>> build.start()
>>> build.wait(10)
True
>>> build.poll(), build.result(), [round(f, 2) for _, f, _ in build.updates]
('done', 42, [0.0, 0.33, 0.67, 1.0])
"""

import threading
import time

RUNNING, DONE, FAILED, CANCELLED = "running", "done", "failed", "cancelled"


class Cancelled(Exception):
    """Raised in the worker by the progress callback once the build was cancelled."""


class Busy(Exception):
    """Another build is running; the message says which, and how far it is."""


class BackgroundBuild:
    """``work(progress)`` run in a daemon thread, with its progress kept for the main thread.

    Parameters
    ----------
    work : callable
        ``work(progress) -> result``; calls ``progress(fraction, message)``
        at each stage (raising :class:`Cancelled` there once cancelled).
    label : str
        What is built, for messages ("the solver of 'Suzanne' (504,482 vertices)").

    Attributes
    ----------
    fraction, message
        The latest stage reported.
    updates : list of (seconds, fraction, message)
        Every stage reported, with the time since :meth:`start`.
    """

    _lock = threading.Lock()
    _active = None  # the build whose thread is alive (one at a time)

    def __init__(self, work, label):
        self.work = work
        self.label = label
        self.fraction, self.message = 0.0, "starting"
        self.updates = []
        self.started = None
        self._cancel = threading.Event()
        self._done = threading.Event()
        self._result = None
        self._error = None
        self._thread = None

    # ---- class-level state: one build at a time

    @classmethod
    def running(cls):
        """The build whose worker thread is still alive (cancelled or not), or None."""
        with cls._lock:
            active = cls._active
        return active if active is not None and not active._done.is_set() else None

    @classmethod
    def cancel_running(cls, wait=None):
        """Cancel the running build, if any; wait up to ``wait`` seconds for its thread to end."""
        active = cls.running()
        if active is not None:
            active.cancel()
            if wait:
                active.wait(wait)

    def busy_message(self):
        """Why another build cannot start while this one runs."""
        if self._cancel.is_set():
            return (f"the cancelled build of {self.label} is finishing its current stage ({self.message}); "
                    "try again in a moment")
        return (f"already building {self.label} ({self.message}, {100 * self.fraction:.0f}%): "
                "wait for it, or press Esc to cancel it")

    # ---- one build

    def start(self):
        """Start the worker thread.

        Raises
        ------
        Busy
            Another build's thread is alive.
        """
        cls = type(self)
        with cls._lock:
            active = cls._active
            if active is not None and not active._done.is_set():
                raise Busy(active.busy_message())
            cls._active = self
        self.started = time.perf_counter()
        self._thread = threading.Thread(target=self._run, name="heat-geodesics-build", daemon=True)
        self._thread.start()

    def _progress(self, fraction, message):
        if self._cancel.is_set():
            raise Cancelled(message)
        with self._lock:
            self.fraction, self.message = float(fraction), message
            self.updates.append((time.perf_counter() - self.started, self.fraction, message))

    def _run(self):
        try:
            result = self.work(self._progress)
            if not self._cancel.is_set():
                self._result = result
        except Cancelled:
            pass
        except BaseException as exc:  # noqa: BLE001 - handed to the main thread by result()
            self._error = exc
        finally:
            self._done.set()
            with self._lock:
                if type(self)._active is self:
                    type(self)._active = None

    def poll(self):
        """The state: ``"running"``, ``"done"``, ``"failed"`` or ``"cancelled"`` (as soon as asked)."""
        if self._cancel.is_set():
            return CANCELLED
        if not self._done.is_set():
            return RUNNING
        return FAILED if self._error is not None else DONE

    def progress(self):
        """The latest ``(fraction, message)``."""
        with self._lock:
            return self.fraction, self.message

    def cancel(self):
        """Ask the worker to stop at its next stage; :meth:`poll` says ``"cancelled"`` from now on."""
        self._cancel.set()

    def wait(self, timeout=None):
        """Wait for the worker thread to end; True when it has."""
        return self._done.wait(timeout)

    def result(self):
        """What ``work`` returned.

        Raises
        ------
        Cancelled
            The build was cancelled.
        RuntimeError
            The worker is still running.
        Exception
            What ``work`` raised.
        """
        state = self.poll()
        if state == CANCELLED:
            raise Cancelled(self.label)
        if state == RUNNING:
            raise RuntimeError(f"the build of {self.label} is still running")
        if self._error is not None:
            raise self._error
        return self._result
