"""Where evaluations run: serially, in local processes, or on a Dask cluster.

Results never depend on the choice: the GA seeds every evaluation by its global index.
"""

from __future__ import annotations

import re

import numpy as np

from growsim.errors import UserInputError

__all__ = ["SCHEDULER_ADDRESS", "check_executor_args", "executor_workers", "make_executor"]

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


def make_executor(workers: int | None, scheduler: str | None):
    """``(executor, close)`` for :meth:`growsim.ga.GA.run`: None (serial), a process
    count, or a Dask executor (``scheduler``: ``"local"`` starts a LocalCluster of
    ``workers`` processes; an address connects to a running scheduler); ``close()``
    releases what was started."""
    if scheduler is None:
        if workers is None or workers <= 1:
            return None, lambda: None
        return int(workers), lambda: None
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError:
        raise UserInputError(
            "--scheduler needs dask.distributed: pip install 'growsim[dask]'"
        ) from None
    if scheduler == "local":
        cluster = LocalCluster(
            n_workers=workers or 2,
            threads_per_worker=1,
            processes=True,
            dashboard_address=None,
        )
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
    return client.get_executor(pure=False), close


def executor_workers(executor) -> int | None:
    """How many evaluations an executor runs at once (Dask: the cluster's threads)."""
    client = getattr(executor, "_client", None)
    if client is not None:
        try:
            workers = client.scheduler_info()["workers"].values()
            return max(1, sum(int(w.get("nthreads", 1)) for w in workers))
        except Exception:  # an unreachable or odd scheduler: fall back to the GA's default
            return None
    n = getattr(executor, "_max_workers", None)
    return int(n) if n else None
