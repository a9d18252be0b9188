"""Processes on this machine: whether one still runs, on POSIX and on Windows, without ``ctypes``.

A batch asks this of the writer of a temporary file
(:func:`heatcore.apps.batch.storage.clean_temporaries`: a dead writer's
partial file is removed) and of a pool worker's parent
(:func:`heatcore.apps.batch.runners.watch_parent`). ``ctypes`` is imported
only in :mod:`heatcore.linalg` (docs/design.md), so Windows is asked through
the standard library's ``_winapi`` instead of ``kernel32`` by hand.

Examples
--------
>>> import subprocess, sys
>>> child = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True)
>>> pid_alive(os.getpid()), pid_alive(int(child.stdout))
(True, False)
"""

import os


def _pid_alive_windows(pid):
    """Windows: ask the kernel through the standard library's ``_winapi``, else psutil, else say yes.

    ``_winapi`` (the module behind :mod:`subprocess` and :mod:`multiprocessing`
    on Windows) opens the process for a limited query: access denied means it
    exists, no such process means it is gone, and a process that opened is
    alive while its exit code is ``STILL_ACTIVE``. No ``ctypes`` (the house
    rule: ctypes lives only in :mod:`heatcore.linalg`). Without ``_winapi``
    (another Python) ``psutil`` answers when importable; without either, the
    answer is the conservative "alive": a lock or temporary file is never
    taken from a live writer (at worst a dead one's waits for
    :data:`STALE_TEMPORARY_SECONDS`).
    """
    try:
        import _winapi
    except ImportError:
        _winapi = None
    if _winapi is not None and hasattr(_winapi, "OpenProcess"):
        try:
            handle = _winapi.OpenProcess(0x1000, False, pid)  # PROCESS_QUERY_LIMITED_INFORMATION
        except PermissionError:  # access denied: it exists
            return True
        except OSError:  # ERROR_INVALID_PARAMETER: no such process
            return False
        try:
            return _winapi.GetExitCodeProcess(handle) == getattr(_winapi, "STILL_ACTIVE", 259)
        except OSError:
            return False
        finally:
            _winapi.CloseHandle(handle)
    try:
        import psutil
    except ImportError:
        return True
    try:
        return psutil.Process(pid).is_running()
    except psutil.NoSuchProcess:
        return False
    except psutil.Error:  # access denied and the like: it exists
        return True


def pid_alive(pid):
    """Whether a process with this id runs on this machine (POSIX and Windows).

    POSIX: ``os.kill(pid, 0)``, and on Linux a zombie (exited, not yet reaped)
    counts as gone. Windows (where ``os.kill(pid, 0)`` would terminate the
    process): the standard library's ``_winapi`` queries the process, else
    ``psutil``, else the pid is taken as alive (conservative: nothing of a
    live writer is ever removed). No ``ctypes`` here: it lives only in
    :mod:`heatcore.linalg`.

    Parameters
    ----------
    pid : int
        A process id; ``0`` and negative ids are never alive.

    Returns
    -------
    bool

    Examples
    --------
    >>> pid_alive(os.getpid()), pid_alive(0)
    (True, False)
    """
    if pid <= 0:
        return False
    if os.name == "nt":
        return _pid_alive_windows(pid)
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # EPERM: someone else's process
        return True
    try:  # Linux: an exited process not yet reaped (a zombie) no longer runs
        with open(f"/proc/{pid}/stat", "rb") as fh:
            return fh.read().rsplit(b")", 1)[1].split()[0] != b"Z"
    except (OSError, IndexError):
        return True
