"""Runners of a batch: a local process pool or a Dask cluster; workers that die with their parent.

:func:`run_pool` and :func:`run_dask` are generators of ``(task, summary_row)``
in completion order. Closing one (``generator.close()``, or an exception such
as ``KeyboardInterrupt`` raised while it waits) stops the work: queued tasks
are cancelled and, on the local pool, the running worker processes are
terminated at once (their files are written atomically, so a killed task
leaves at most a temporary file, see :func:`heatcore.apps.batch.storage.clean_temporaries`).

A worker process that dies (killed by the out-of-memory killer, SIGKILL, a
crash) fails the mesh it was computing and no other: the local pool
(:mod:`heatcore.apps.batch.pool`) knows which task each worker holds and
replaces the dead one; on Dask a mesh whose workers died is tried again alone
before it is reported (:func:`run_dask`).

Pool workers ignore SIGINT (the parent decides what Ctrl-C does) and exit
when their parent process is gone, also when it was killed with SIGKILL: a
watchdog thread in each worker polls the parent every
:data:`WATCHDOG_INTERVAL` seconds (every OS, :func:`watch_parent`). There is
no ``prctl(PR_SET_PDEATHSIG)`` on Linux: it needs ``ctypes``, which the
package imports only in :mod:`heatcore.linalg`.

Examples
--------
>>> rows = list(run_pool([1, 2, 3], 2, abs))
>>> sorted(row for _, row in rows)
[1, 2, 3]
"""

import os
import signal
import threading
import time
import traceback
import uuid
from pathlib import Path

from ...errors import HeatcoreError, InvalidOptionError
from .pool import WorkerDied, imap_unordered
from .processes import pid_alive

#: Seconds between two checks of the parent process in a pool worker.
WATCHDOG_INTERVAL = 0.2
#: Exit status of a worker whose parent is gone.
ORPHAN_EXIT_STATUS = 70


def error_message(exc):
    """One line for a failed task: the message of a heatcore error, else type, message and place.

    Examples
    --------
    >>> error_message(HeatcoreError("mesh.obj is empty (0 bytes)"))
    'mesh.obj is empty (0 bytes)'
    >>> try:
    ...     int("x")
    ... except ValueError as exc:
    ...     error_message(exc)  # doctest: +ELLIPSIS
    "ValueError: invalid literal for int() with base 10: 'x' (at ...)"
    """
    if isinstance(exc, HeatcoreError):
        return str(exc)
    frame = traceback.extract_tb(exc.__traceback__)[-1] if exc.__traceback__ else None
    where = f" (at {Path(frame.filename).name}:{frame.lineno})" if frame else ""
    return f"{type(exc).__name__}: {exc}{where}"


def crash_row(task, exc):
    """The summary row of a task whose worker failed (its process died, or the task raised there).

    Examples
    --------
    >>> crash_row("meshes/a.obj", OSError("disk gone"))["error"]
    'worker failed: OSError: disk gone'
    >>> crash_row("meshes/a.obj", WorkerDied(-9))["error"]  # doctest: +ELLIPSIS
    'worker process died (killed by signal 9, SIGKILL: ...) while computing meshes/a.obj'
    """
    path = str(getattr(task, "path", task))
    error = f"{exc} while computing {path}" if isinstance(exc, WorkerDied) else f"worker failed: {error_message(exc)}"
    return {"file": path, "vertices": "", "sources": "", "seconds": "", "status": "error", "error": error}


# --------------------------------------------------------------------------- workers die with their parent


def _parent_gone(parent_pid, direct):
    if direct:  # our parent itself (fork, spawn): re-parented to init or a subreaper once it died
        return os.getppid() != parent_pid
    return not pid_alive(parent_pid)  # started by a fork server, or on Windows


def watch_parent(parent_pid, interval=WATCHDOG_INTERVAL):
    """Start a daemon thread that ends this process (``os._exit``) once ``parent_pid`` is gone.

    ``parent_pid`` is the process that owns the work: our parent process, or
    (started by a fork server) the process that asked for us. Our own parent
    is watched through ``os.getppid()`` (it changes once the parent died);
    another process, and any on Windows, through
    :func:`heatcore.apps.batch.processes.pid_alive`. This thread is the only
    way a pool worker follows its parent (no ``prctl(PR_SET_PDEATHSIG)``: that
    needs ``ctypes``, which only :mod:`heatcore.linalg` imports).

    Returns
    -------
    threading.Thread

    Examples
    --------
    >>> import subprocess, sys
    >>> code = ("import os, time; from heatcore.apps.batch.runners import watch_parent; "
    ...         "watch_parent(os.getppid()); time.sleep(0.3); print('parent alive: still running')")
    >>> subprocess.run([sys.executable, "-c", code], capture_output=True, text=True).stdout.strip()
    'parent alive: still running'
    """
    direct = os.name != "nt" and os.getppid() == parent_pid

    def watch():
        while not _parent_gone(parent_pid, direct):
            time.sleep(interval)
        os._exit(ORPHAN_EXIT_STATUS)

    thread = threading.Thread(target=watch, name="heatcore-parent-watchdog", daemon=True)
    thread.start()
    return thread


def worker_init(parent_pid):
    """Initializer of a pool worker: ignore SIGINT, die with the parent ``parent_pid``.

    Dying with the parent is the watchdog thread's job alone
    (:func:`watch_parent`, on every OS): the worker exits at most about
    :data:`WATCHDOG_INTERVAL` seconds after the parent is gone, as soon as the
    thread gets the interpreter (numpy and the factorizations release it while
    they compute). Linux's ``prctl(PR_SET_PDEATHSIG)`` is not used: it needs
    ``ctypes``, which the package imports only in :mod:`heatcore.linalg`.

    Parameters
    ----------
    parent_pid : int
        The process that owns the work (see :func:`watch_parent`).

    Examples
    --------
    Run in a child process (it changes the SIGINT handler of the process that calls it):

    >>> import subprocess, sys
    >>> code = ("import os, signal; from heatcore.apps.batch.runners import worker_init; "
    ...         "worker_init(os.getppid()); print(signal.getsignal(signal.SIGINT) is signal.SIG_IGN)")
    >>> subprocess.run([sys.executable, "-c", code], capture_output=True, text=True).stdout.strip()
    'True'
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    watch_parent(parent_pid)  # also exits at once if the parent died before we got here


# --------------------------------------------------------------------------- local pool


def run_pool(tasks, workers, fn):
    """Run ``fn(task)`` on a pool of ``workers`` processes; yield ``(task, row)`` as they finish.

    A task whose worker process dies gets an error row saying how the process
    ended (:func:`crash_row`); the other tasks go on, on a fresh worker for the
    queued ones (:func:`heatcore.apps.batch.pool.imap_unordered`). Closing the
    generator early, or an exception while it waits, stops the workers at once.

    Parameters
    ----------
    tasks : iterable
        Picklable tasks (:class:`~heatcore.apps.batch.spec.MeshTask` in a batch).
    workers : int
        At most this many processes (no more than there are tasks).
    fn : callable
        A picklable function, ``fn(task) -> row`` (a dict in a batch).

    Yields
    ------
    (task, row)
        In completion order.

    Examples
    --------
    >>> sorted(row for _, row in run_pool([-1, 2, -3], 2, abs))
    [1, 2, 3]

    A worker that dies (here ``os._exit(3)`` ends it at once) fails its task
    only; a new worker would take the tasks queued behind it:

    >>> [(task, row["error"]) for task, row in run_pool([3], 1, os._exit)]
    [(3, 'worker process died (exited with status 3) while computing 3')]
    """
    rows = imap_unordered(fn, tasks, workers, initializer=worker_init, initargs=(os.getpid(),))
    try:
        for task, ok, value in rows:
            yield task, (value if ok else crash_row(task, value))
    finally:
        rows.close()  # early: stops the workers now


# --------------------------------------------------------------------------- Dask


def run_dask(tasks, scheduler, fn):
    """Run ``fn(task)`` on a ``dask.distributed`` scheduler (address or Client); yield ``(task, row)``.

    One Dask task per mesh. A task lost with its worker is rerun by the
    scheduler on another worker (each task gives one row). The scheduler gives
    up on a task once ``distributed.scheduler.allowed-failures`` + 1 workers
    (4 by default) died while holding it, and it counts every task a dying
    worker held, also those queued behind the one that killed it. So a task
    given up that way is tried once more with no other mesh of this batch on
    the cluster, after the others: a mesh that was only beside the culprit
    then succeeds, and the culprit fails alone, after at most twice the
    allowed tries, its row saying so. Closing the generator early cancels the
    tasks not finished; a task already running on a worker cannot be
    interrupted and still writes its result (atomically).

    Parameters
    ----------
    tasks : list of MeshTask
        Their ``path`` names the Dask tasks.
    scheduler : str or distributed.Client
        A scheduler's address (a client is made and closed here) or a client
        (left open).
    fn : callable
        ``fn(task) -> row``, run on the workers.

    Yields
    ------
    (task, row)
        In completion order.

    Raises
    ------
    InvalidOptionError
        ``dask.distributed`` is not installed.
    BatchError
        The scheduler cannot be reached (within 30 s).

    Examples
    --------
    With a running cluster (``dask scheduler``, ``dask worker ...``), not run here::

        rows = dict(run_dask(tasks, "tcp://10.0.0.5:8786", process_mesh))

    Nothing happens before the first row is asked for (no import of Dask, no
    connection), and a generator closed before that leaves nothing behind:

    >>> rows = run_dask([], "tcp://10.0.0.5:8786", abs)
    >>> rows.close()
    >>> list(rows)
    []
    """
    from .spec import BatchError

    try:
        from distributed import Client, KilledWorker
        from distributed import as_completed as dask_completed
    except ImportError:
        raise InvalidOptionError(
            "--scheduler needs dask.distributed: pip install 'heatcore[batch]' (or 'dask[distributed]')"
        ) from None
    own = not isinstance(scheduler, Client)
    try:
        client = Client(scheduler, timeout="30s") if own else scheduler
    except (OSError, TimeoutError) as exc:
        raise BatchError(f"cannot connect to the Dask scheduler at {scheduler}: {exc}") from exc
    futures = []
    try:
        # One task per mesh: its factorization is built and used on the worker that runs it.
        keys = [f"heatcore-batch-{Path(t.path).name}-{uuid.uuid4().hex[:8]}" for t in tasks]
        futures = client.map(fn, tasks, pure=False, key=keys)
        by_key = {f.key: t for f, t in zip(futures, tasks)}
        suspects = []  # (task, allowed failures): the scheduler gave up on them, maybe for a neighbour's crash
        for fut in dask_completed(futures):
            task, row = by_key[fut.key], None
            try:
                row = fut.result()
            except KilledWorker as exc:
                suspects.append((task, exc.allowed_failures))
            except Exception as exc:  # noqa: BLE001 - a task that failed on every worker fails its mesh only
                row = crash_row(task, exc)
            fut.release()
            if row is not None:
                yield task, row
        for task, allowed in suspects:  # alone now: only its own crash can kill its worker
            fut = client.submit(fn, task, pure=False, key=f"heatcore-batch-alone-{Path(task.path).name}-"
                                                            f"{uuid.uuid4().hex[:8]}")
            futures.append(fut)
            try:
                row = fut.result()
            except KilledWorker:
                row = crash_row(task, RuntimeError())
                row["error"] = (f"worker process died while computing {task.path}: {2 * (allowed + 1)} Dask workers "
                                f"died running it, the last {allowed + 1} with no other mesh of this batch beside "
                                f"it (the scheduler's allowed-failures is {allowed}; out of memory? see the workers' "
                                f"logs)")
            except Exception as exc:  # noqa: BLE001 - it failed otherwise this time: its mesh only
                row = crash_row(task, exc)
            fut.release()
            yield task, row
    finally:
        pending = [f for f in futures if not f.done()]
        if pending:
            try:
                client.cancel(pending)
            except Exception:  # noqa: BLE001 - the scheduler may be gone already
                pass
        if own:
            client.close()
