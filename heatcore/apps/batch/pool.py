"""A local process pool in which a worker that dies fails only the task it held.

``concurrent.futures.ProcessPoolExecutor`` cannot tell which task a dead
worker held: one worker killed (the out-of-memory killer, SIGKILL, a crash in
native code) breaks the whole executor, and every future not finished, queued
ones too, fails with ``BrokenProcessPool`` (a batch of 20 meshes lost 19 that
way). Here each worker gets one task at a time over a pipe of its own, so the
parent always knows what a worker holds: when a worker's process ends without
answering, that task alone fails with :class:`WorkerDied` (saying how the
process ended), a fresh worker takes the dead one's place, and the queue goes
on. Workers still running are not disturbed.

:func:`imap_unordered` is the pool; :func:`heatcore.apps.batch.runners.run_pool`
runs a batch on it.

Examples
--------
>>> import os
>>> sorted((task, ok, value) for task, ok, value in imap_unordered(abs, [-1, 2, -3], 2))
[(-3, True, 3), (-1, True, 1), (2, True, 2)]
>>> [(task, ok, str(value)) for task, ok, value in imap_unordered(os._exit, [3], 1)]
[(3, False, 'worker process died (exited with status 3)')]
"""

import multiprocessing
import signal
import time
from multiprocessing.connection import wait

#: Seconds stopped workers get to exit after SIGTERM before they are killed.
STOP_GRACE = 1.0


def exit_reason(exitcode):
    """How a process ended, in words, from its ``exitcode`` (negative: the signal that killed it).

    Examples
    --------
    >>> exit_reason(-9)
    'killed by signal 9, SIGKILL: the out-of-memory killer sends it too'
    >>> exit_reason(-11), exit_reason(1)
    ('killed by signal 11, SIGSEGV', 'exited with status 1')
    """
    if exitcode is None:
        return "ended, its exit status unknown"
    if exitcode >= 0:
        return f"exited with status {exitcode}"
    number = -exitcode
    try:
        name = signal.Signals(number).name
    except ValueError:
        return f"killed by signal {number}"
    oom = ": the out-of-memory killer sends it too" if name == "SIGKILL" else ""
    return f"killed by signal {number}, {name}{oom}"


class WorkerDied(Exception):
    """The worker process that ran a task ended before it answered (killed, crashed, exited).

    Examples
    --------
    >>> err = WorkerDied(-9)
    >>> err.exitcode, str(err).split(":")[0]
    (-9, 'worker process died (killed by signal 9, SIGKILL')
    """

    def __init__(self, exitcode):
        self.exitcode = exitcode
        super().__init__(f"worker process died ({exit_reason(exitcode)})")


def _serve(conn, fn, initializer, initargs):
    """A worker's loop: run ``fn`` on each task received and send back ``(ok, value)``; ``None`` ends it."""
    if initializer is not None:
        initializer(*initargs)
    while True:
        try:
            task = conn.recv()
        except (EOFError, OSError):  # the parent closed its end
            return
        if task is None:
            return
        try:
            answer = (True, fn(task))
        except Exception as exc:  # noqa: BLE001 - the parent reports it for this task
            answer = (False, exc)
        try:
            conn.send(answer)  # pickled whole before anything is written
        except Exception as exc:  # noqa: BLE001 - a value or an error that does not pickle
            conn.send((False, RuntimeError(f"cannot send back {type(answer[1]).__name__}: {exc}")))


class _Worker:
    """One process and the parent's end of its pipe; ``task`` is what it computes (None: idle)."""

    def __init__(self, context, fn, initializer, initargs):
        self.conn, child = context.Pipe()
        self.process = context.Process(target=_serve, args=(child, fn, initializer, initargs),
                                       name="heatcore-batch-worker")
        self.process.start()
        child.close()
        self.task = None

    def answer(self):
        """``(ok, value)`` of the task it held; ``(False, WorkerDied)`` when its process ended without one."""
        try:
            if self.conn.poll():
                return self.conn.recv()
        except (EOFError, OSError):
            pass
        self.process.join(STOP_GRACE)  # it closed its pipe: it is exiting, or has
        self.conn.close()
        return False, WorkerDied(self.process.exitcode)


def stop_workers(processes, grace=STOP_GRACE):
    """End ``processes`` now: SIGTERM, then SIGKILL for those still running after ``grace`` seconds.

    Returns once every one has exited, so nothing of the pool writes afterwards.

    Examples
    --------
    >>> import time
    >>> p = multiprocessing.Process(target=time.sleep, args=(60,))
    >>> p.start()
    >>> stop_workers([p])
    >>> p.is_alive(), p.exitcode
    (False, -15)
    """
    for p in processes:
        if p.is_alive():
            p.terminate()
    deadline = time.monotonic() + grace
    for p in processes:
        p.join(max(deadline - time.monotonic(), 0.0))
        if p.is_alive():
            p.kill()
            p.join()


def imap_unordered(fn, tasks, workers, initializer=None, initargs=()):
    """Run ``fn(task)`` for every task on up to ``workers`` processes; yield ``(task, ok, value)`` as each ends.

    ``ok`` True: ``value`` is what ``fn`` returned. ``ok`` False: ``value`` is
    the exception ``fn`` raised, or :class:`WorkerDied` when the worker's
    process ended while it held the task (the task is not tried again; a new
    worker takes the dead one's place for the tasks still queued).

    Closing the generator early (``close()``, or an exception such as
    ``KeyboardInterrupt`` while it waits) stops every worker at once
    (:func:`stop_workers`); a complete run lets them exit on their own.

    Parameters
    ----------
    fn : callable
        Picklable (a module-level function) where processes are spawned.
    tasks : iterable
        Picklable tasks, sent in order.
    workers : int
        At most this many processes at once (no more than there are tasks).
    initializer : callable, optional
        Run with ``initargs`` once in each worker before its first task.

    Yields
    ------
    (task, ok, value)

    Examples
    --------
    >>> [ok for _, ok, _ in imap_unordered(int, ["1", "x"], 1)]
    [True, False]
    """
    queue = list(tasks)[::-1]  # popped from the end: tasks go out in their order
    context = multiprocessing.get_context()
    pool, complete = [], False
    try:
        while queue or any(w.task is not None for w in pool):
            for w in pool:
                if w.task is None and not w.process.is_alive():  # died idle (or after its answer)
                    w.conn.close()
            pool = [w for w in pool if w.task is not None or not w.conn.closed]
            while queue and len(pool) < workers:
                pool.append(_Worker(context, fn, initializer, initargs))
            for w in pool:
                if w.task is None and queue:
                    w.task = queue.pop()
                    try:
                        w.conn.send(w.task)
                    except (OSError, ValueError):  # it died before its task reached it: try another
                        queue.append(w.task)
                        w.task = None
                        w.process.join()
                        w.conn.close()
            busy = [w for w in pool if w.task is not None]
            if not busy:  # every worker died before its task reached it: start others
                continue
            ready = set(wait([w.conn for w in busy] + [w.process.sentinel for w in busy]))
            for w in busy:
                if w.conn in ready or w.process.sentinel in ready:
                    ok, value = w.answer()
                    task, w.task = w.task, None
                    yield task, ok, value
        complete = True
    finally:
        if complete:
            for w in pool:
                try:
                    w.conn.send(None)
                except (OSError, ValueError):
                    pass
            for w in pool:
                w.process.join()
                if not w.conn.closed:
                    w.conn.close()
        else:
            stop_workers([w.process for w in pool])
