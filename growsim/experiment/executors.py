"""Where evaluations run: serially, in local processes, or on a Dask cluster.

Results never depend on the choice: the GA seeds every evaluation by its global index.
An executor with a known size is a :class:`growsim.ga.evaluate.Pool`; a Dask client's is
a :class:`DaskPool`, which holds the client and asks it for the cluster's threads.
"""

from __future__ import annotations

import concurrent.futures as cf
import os
import re
import threading

import numpy as np

from growsim.errors import UserInputError
from growsim.ga.evaluate import Pool

__all__ = [
    "QUIET_CLUSTER",
    "SCHEDULER_ADDRESS",
    "DaskExecutor",
    "DaskPool",
    "check_executor_args",
    "executor_workers",
    "local_cluster",
    "make_executor",
]

#: a Dask scheduler address
SCHEDULER_ADDRESS = re.compile(r"^(tcp|tls|ws|wss|inproc)://\S+$")


def check_executor_args(workers, scheduler) -> None:
    """Refuse a bad ``--workers`` or ``--scheduler`` before anything runs.

    Examples
    --------
    >>> check_executor_args(2, "tcp://10.0.0.1:8786")
    >>> check_executor_args(0, None)
    Traceback (most recent call last):
    ...
    growsim.errors.UserInputError: --workers: expected an integer >= 1, got 0
    """
    if workers is not None and (
        isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or workers < 1
    ):
        raise UserInputError(f"--workers: expected an integer >= 1, got {workers!r}")
    if scheduler is not None and not (
        scheduler == "local" or SCHEDULER_ADDRESS.match(str(scheduler))
    ):
        raise UserInputError(
            f"--scheduler: {scheduler!r} is not 'local' or an address like tcp://host:8786"
        )


#: Dask settings of :func:`local_cluster`: its periodic work made rarer or off, for a
#: cluster that runs a GA's evaluations on the machine's own cores, where every
#: millisecond a worker's event loop takes is taken from an evaluation. Each process's
#: event-loop health tick (20 ms by default), its system monitor for the dashboard
#: (500 ms), the nanny's memory monitor (100 ms), the workers' statistical profiler and
#: the scheduler's work stealing (the GA's tasks are alike and given out evenly).
#: Measured (docs/cluster.md): 2 workers' GA loop 3.80 / 4.08 s against 4.10 / 4.30 s
#: with Dask's defaults, their CPU 11.6 / 12.2 s against 12.5 / 12.9 s.
QUIET_CLUSTER = {
    "distributed.admin.tick.interval": "500ms",
    "distributed.admin.system-monitor.interval": "5s",
    "distributed.worker.memory.monitor-interval": "1s",
    "distributed.worker.profile.enabled": False,
    "distributed.scheduler.work-stealing": False,
}


def local_cluster(workers: int = 2):
    """A Dask ``LocalCluster`` of ``workers`` single-threaded worker processes, without
    Dask's default ``MALLOC_TRIM_THRESHOLD_=65536`` in the workers' environment and with
    its periodic work made rarer (:data:`QUIET_CLUSTER`).

    That setting (``distributed.nanny.pre-spawn-environ``) fixes glibc's thresholds, so
    every array over 128 KB is a fresh ``mmap`` whose pages fault again at every
    allocation: 300 allocations of 2 MB cost 146,700 page faults in such a worker
    against 880 in a plain process, and a light evaluation at 1024 pixels about 10 %
    more time. A ``MALLOC_TRIM_THRESHOLD_`` the user set in the environment is kept,
    unless it is Dask's own value: a cluster started earlier with Dask's defaults leaves
    that in this process's ``os.environ`` (the Nanny writes its variables there).

    Examples
    --------
    >>> from dask.distributed import Client
    >>> with local_cluster(1) as cluster, Client(cluster) as client:  # doctest: +SKIP
    ...     client.submit(sum, [1, 2]).result()
    3
    """
    import dask
    from dask.distributed import LocalCluster

    key = "MALLOC_TRIM_THRESHOLD_"
    dasks = dask.config.get("distributed.nanny.pre-spawn-environ", {}).get(key)
    if dasks is not None and os.environ.get(key) == str(dasks):
        del os.environ[key]
    with dask.config.set({"distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None,
                          **QUIET_CLUSTER}):  # fmt: skip
        return LocalCluster(
            n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None
        )


def _follow(task, future: cf.Future) -> None:
    """Give ``future`` the outcome of the Dask future ``task`` once Dask is done with it
    (``task.result()``: a result lost with its worker is recomputed and waited for)."""
    try:
        result, error = task.result(), None
    except BaseException as exc:  # the task's own error, or Dask's (a killed worker)
        result, error = None, exc
    if task.cancelled():
        future.cancel()
    try:
        if not future.cancelled():
            if error is None:
                future.set_result(result)
            else:
                future.set_exception(error)
            return
    except cf.InvalidStateError:  # cancelled meanwhile
        pass
    future.set_running_or_notify_cancel()  # a cancelled future: wakes wait(), as_completed()


class DaskExecutor(cf.Executor):
    """A ``concurrent.futures`` executor running each task on a Dask ``client``
    (``client.submit(fn, *args, pure=False)``), its future following Dask's own: done
    when ``result()`` of Dask's future returns or raises. Unlike Dask's adapter
    (``client.get_executor()``, distributed 2026.8), a result lost with its worker after
    it finished is recomputed and delivered, not reported as the executor failing (that
    adapter reads the task's status after fetching its result: "lost" there is taken for
    an error). Cancelling the future cancels the task; ``shutdown`` leaves the client
    open.

    Examples
    --------
    >>> from dask.distributed import Client
    >>> with local_cluster(1) as cluster, Client(cluster) as client:  # doctest: +SKIP
    ...     DaskExecutor(client).submit(sum, [1, 2]).result()
    3
    """

    def __init__(self, client):
        #: the ``dask.distributed.Client``
        self.client = client
        self._tasks: dict = {}
        self._lock = threading.Lock()
        self._closed = False

    def submit(self, fn, /, *args, **kwargs) -> cf.Future:
        """``fn(*args, **kwargs)`` on the cluster."""
        with self._lock:
            if self._closed:
                raise RuntimeError("cannot schedule new futures after shutdown")
            task = self.client.submit(fn, *args, pure=False, **kwargs)
            future: cf.Future = cf.Future()
            self._tasks[future] = task
        # cancelling the future cancels the task; done, it is no longer held
        future.add_done_callback(self._settled)
        task.add_done_callback(lambda t: _follow(t, future))
        return future

    def _settled(self, future: cf.Future) -> None:
        with self._lock:
            task = self._tasks.pop(future, None)
        if task is not None and future.cancelled() and not task.done():
            task.cancel()

    def shutdown(self, wait: bool = True, *, cancel_futures: bool = False) -> None:
        """No more tasks; ``cancel_futures``: cancel those not done; ``wait``: wait for
        the rest."""
        with self._lock:
            self._closed = True
            futures = list(self._tasks)
        if cancel_futures:
            for future in futures:
                future.cancel()
        if wait:
            cf.wait(futures)


class DaskPool(Pool):
    """A Dask ``client``'s :class:`DaskExecutor` as a :class:`growsim.ga.evaluate.Pool`:
    its :attr:`workers` are the cluster's worker threads, asked of the client each time
    (None when the scheduler cannot say). Pass one as ``executor=`` to
    :func:`growsim.experiment.run` (or ``GA.run``) so a generation is split by the
    cluster's size. Shutting it down leaves the client open.

    Examples
    --------
    >>> from dask.distributed import Client
    >>> with local_cluster(1) as cluster, Client(cluster) as client:  # doctest: +SKIP
    ...     pool = DaskPool(client)
    ...     pool.submit(sum, [1, 2]).result(), pool.workers
    (3, 1)
    """

    def __init__(self, client):
        super().__init__(DaskExecutor(client))
        #: the ``dask.distributed.Client``
        self.client = client

    @property
    def workers(self) -> int | None:
        """The cluster's worker threads (None: the scheduler did not answer)."""
        try:
            workers = self.client.scheduler_info()["workers"].values()
            return max(1, sum(int(w.get("nthreads", 1)) for w in workers))
        except Exception:  # an unreachable or odd scheduler: fall back to the GA's default
            return None


def make_executor(workers: int | None, scheduler: str | None):
    """``(executor, close)`` for :meth:`growsim.ga.GA.run`: None (serial), a process
    count, or a :class:`DaskPool` (``scheduler``: ``"local"`` starts a LocalCluster of
    ``workers`` processes; an address connects to a running scheduler); ``close()``
    releases what was started."""
    if scheduler is None:
        if workers is None or workers <= 1:
            return None, lambda: None
        return int(workers), lambda: None
    try:
        from dask.distributed import Client
    except ImportError:
        raise UserInputError(
            "--scheduler needs dask.distributed: pip install 'growsim[dask]'"
        ) from None
    if scheduler == "local":
        cluster = local_cluster(workers or 2)
        client = Client(cluster)

        def close():
            client.close()
            cluster.close()

    else:
        check_executor_args(None, scheduler)
        try:
            client = Client(scheduler, timeout="10s")
        except (OSError, TimeoutError) as exc:
            raise UserInputError(f"--scheduler: cannot reach {scheduler}: {exc}") from None
        close = client.close
    return DaskPool(client), close


def executor_workers(executor) -> int | None:
    """How many evaluations an executor runs at once, when it says: a
    :class:`~growsim.ga.evaluate.Pool`'s :attr:`~growsim.ga.evaluate.Pool.workers` (a
    :class:`DaskPool`: the cluster's threads); None for anything else (None, a process
    count, a bare ``concurrent.futures.Executor``).

    Examples
    --------
    >>> from concurrent.futures import ThreadPoolExecutor
    >>> executor_workers(Pool(ThreadPoolExecutor(1), 3)), executor_workers(4)
    (3, None)
    """
    return executor.workers if isinstance(executor, Pool) else None
