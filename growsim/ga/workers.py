"""Worker processes that end with their run.

Every local process pool growsim starts (``--workers N`` of run and sweep, the GA's
``executor=N``, fit-image's runs side by side) is a :class:`WorkerPool`: a
``concurrent.futures.ProcessPoolExecutor`` whose workers are bound to the process that
started them (:func:`bind_to_parent`). When that process dies, however it dies (SIGKILL,
the OOM killer, a closed terminal, a batch system's time limit), its workers die with it
instead of sleeping forever on a queue nobody feeds:

- on Linux the kernel sends each worker SIGKILL when its parent dies
  (``prctl(PR_SET_PDEATHSIG)``, set as the worker starts);
- on every platform a watchdog thread in each worker checks its parent every
  :data:`WATCH_SECONDS` and ends the worker once the parent is gone.

Linux sends the signal when the *thread* that started the worker ends: a pool is started
by the thread that first submits to it (the GA's and the fit's own thread), which holds it
until the pool is shut down.

:meth:`WorkerPool.terminate` ends a pool at once (its workers killed, what they were
evaluating dropped): what a run stopped by Ctrl-C or SIGTERM does, rather than wait for
its workers' current tasks.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import os
import signal
import sys
import threading
from concurrent.futures import ProcessPoolExecutor

__all__ = ["WATCH_SECONDS", "WorkerPool", "bind_to_parent"]

#: how often a worker's watchdog checks that its parent is alive (seconds)
WATCH_SECONDS = 0.5
#: prctl(2)'s option: the signal a process receives when its parent dies
_PR_SET_PDEATHSIG = 1


def _parent_death_signal(sig: int) -> bool:
    """Ask Linux to send ``sig`` to this process when its parent dies; False elsewhere
    or when the call fails."""
    if not sys.platform.startswith("linux"):
        return False
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6", use_errno=True)
        return libc.prctl(_PR_SET_PDEATHSIG, int(sig), 0, 0, 0) == 0
    except (OSError, AttributeError):
        return False


def _watch(parent: int, seconds: float) -> None:
    """The watchdog: end this process once its parent ``parent`` is gone (this process
    re-parented to another)."""
    event = threading.Event()
    while not event.wait(seconds):
        if os.getppid() != parent:
            os._exit(1)


def bind_to_parent(parent: int, seconds: float = WATCH_SECONDS) -> None:
    """Bind this process (a pool's worker, as it starts) to its parent ``parent`` (the
    pid that started it): it dies when the parent dies (Linux: at once, by the kernel's
    SIGKILL; elsewhere: within ``seconds``, by a watchdog thread). A parent already gone
    before the binding ends the worker at once.

    Examples
    --------
    >>> from concurrent.futures import ProcessPoolExecutor
    >>> with ProcessPoolExecutor(1, initializer=bind_to_parent, initargs=(os.getpid(),)) as p:
    ...     p.submit(abs, -3).result()
    3
    """
    _parent_death_signal(signal.SIGKILL)
    if os.getppid() != parent:  # died between the fork and the binding
        os._exit(1)
    threading.Thread(target=_watch, args=(parent, seconds), name="growsim-watchdog",
                     daemon=True).start()  # fmt: skip


class WorkerPool(ProcessPoolExecutor):
    """A process pool of ``workers`` processes bound to this process
    (:func:`bind_to_parent`): they end when it ends, however it ends. Otherwise a
    ``ProcessPoolExecutor`` (same start method, same results).

    Examples
    --------
    >>> with WorkerPool(2) as pool:
    ...     list(pool.map(abs, [-1, -2, 3]))
    [1, 2, 3]
    """

    def __init__(self, workers: int):
        super().__init__(int(workers), initializer=bind_to_parent, initargs=(os.getpid(),))

    def terminate(self) -> None:
        """End the pool now: its workers killed (what they were running is lost, the
        tasks not started cancelled), then shut down. What a stopped run does, instead
        of waiting for its workers' current tasks.

        Examples
        --------
        >>> pool = WorkerPool(1)
        >>> pool.submit(abs, -1).result()
        1
        >>> pool.terminate()
        """
        processes = list((self._processes or {}).values())
        for process in processes:
            if process.is_alive():
                process.kill()
        self.shutdown(wait=True, cancel_futures=True)
        for process in processes:
            process.join()
