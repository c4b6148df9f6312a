"""A fitness that raises in a worker only fails its individuals (counted, given the
worst fitness, as in a serial run); a worker that dies stops the run with a clear
:class:`~growsim.ga.EvaluationError` (or, on Dask, is retried), never hangs; the
checkpoint then resumes the run to the uninterrupted result.

The faults come from :class:`growsim.ga.problems.Faulty` (picklable, so pools and Dask
workers import it): a batch holding a row whose first parameter is above ``above``
raises, calls ``os._exit`` or is ``SIGKILL``-ed."""

from __future__ import annotations

import os
from concurrent.futures import Executor, Future
from concurrent.futures.process import BrokenProcessPool

import numpy as np
import pandas as pd
import pytest
from conftest import _restore_environ

from growsim.experiment.executors import DaskExecutor
from growsim.ga import GA, HISTORY_COLUMNS, EvaluationError, Genome, Real
from growsim.ga.problems import Faulty, sphere

COLS = [c for c in HISTORY_COLUMNS if c != "seconds"]
G = Genome([Real("x", -3, 3, size=4)])
#: about 1 row in 12 of a random population is above it
ABOVE = 2.5
RUN = dict(generations=5, polish={"evaluations": 48, "batch": 8, "sigma": 0.5})


def _ga(fitness, maximize=False, **kw):
    return GA(G, fitness, population=20, maximize=maximize, seed=1, **kw)


def _same(a, b):
    pd.testing.assert_frame_equal(a.history[COLS], b.history[COLS])
    assert a.best.fitness == b.best.fitness
    assert np.array_equal(a.best.params, b.best.params)
    assert np.array_equal(a.fitness, b.fitness)


def _nan_above(x):
    """The sphere, NaN (a failure) on the rows ``Faulty(sphere, ABOVE)`` raises on."""
    return np.where(x[:, 0] > ABOVE, np.nan, sphere(x))


@pytest.fixture(scope="module")
def serial_with_failures():
    """The serial run whose fitness raises on the rows above ``ABOVE``: each such row,
    and only it, fails as a NaN does."""
    r = _ga(Faulty(sphere, ABOVE)).run(**RUN)
    failures = r.history["failures"]
    assert failures.sum() > 0  # the fault fires ...
    assert (r.history.groupby("phase")["failures"].sum() > 0).all()  # ... in GA and polish
    _same(r, _ga(_nan_above).run(**RUN))
    return r


@pytest.mark.timeout(60)
def test_a_fitness_raising_in_a_pool_worker_fails_its_rows_and_the_run_goes_on(
    serial_with_failures, process_pool
):
    r = _ga(Faulty(sphere, ABOVE), batch_size=3).run(executor=process_pool, **RUN)
    _same(r, serial_with_failures)  # the same rows failed, counted in the history
    assert np.isfinite(r.best.fitness) and r.best.params[0] <= ABOVE


@pytest.mark.timeout(60)
def test_a_fitness_raising_in_a_dask_worker_fails_its_rows_and_the_run_goes_on(
    serial_with_failures, dask_client
):
    ex = DaskExecutor(dask_client)
    r = _ga(Faulty(sphere, ABOVE), batch_size=4).run(executor=ex, **RUN)
    _same(r, serial_with_failures)


@pytest.mark.timeout(60)
@pytest.mark.parametrize("fault", ["exit", "kill"])
def test_a_pool_worker_that_dies_stops_the_run_with_the_cause(fault, tmp_path):
    ck = tmp_path / "ck.npz"
    with pytest.raises(EvaluationError) as err:
        _ga(Faulty(sphere, ABOVE, fault=fault)).run(executor=2, checkpoint=ck, **RUN)
    msg = str(err.value)
    assert msg.startswith("generation 0, evaluations 1-20: a worker process died")
    assert "BrokenProcessPool" in msg
    assert isinstance(err.value.__cause__, BrokenProcessPool)
    assert err.value.exit_code == 1


@pytest.mark.timeout(60)
def test_a_pool_worker_dying_once_then_resume_gives_the_uninterrupted_run(tmp_path):
    """Maximising, generation 0's rows stay below 2.9 and generation 1 has rows above: the
    worker dies there; the checkpoint (generation 0) resumes the run on a new pool, where
    the fault, once only, does not fire again."""
    ck = tmp_path / "ck.npz"
    once = tmp_path / "fired"
    dies = Faulty(sphere, 2.9, fault="exit", once=str(once))
    with pytest.raises(EvaluationError, match=r"^generation 1, evaluations 21-40: a worker"):
        _ga(dies, maximize=True).run(executor=2, checkpoint=ck, **RUN)
    assert once.exists()
    resumed = _ga(dies, maximize=True).run(executor=2, checkpoint=ck, resume=True, **RUN)
    _same(resumed, _ga(sphere, maximize=True).run(**RUN))


class DiesAfter(Executor):
    """An executor running tasks inline whose worker "dies" at task ``n`` (0-based): that
    task's and every later task's future holds ``BrokenProcessPool``."""

    def __init__(self, n):
        self.n, self.tasks = n, 0

    def submit(self, fn, /, *args, **kwargs):
        f = Future()
        if self.tasks >= self.n:
            f.set_exception(BrokenProcessPool("A process in the process pool was terminated"))
        else:
            f.set_result(fn(*args, **kwargs))
        self.tasks += 1
        return f


@pytest.mark.timeout(120)
def test_a_run_whose_worker_dies_names_the_cause_and_resumes(tmp_path):
    from conftest import ROOT

    from growsim.experiment import run

    config = ROOT / "experiments" / "quickstart.toml"
    overrides = [
        "ga.population=8",
        "ga.generations=4",
        "ga.batch_size=2",
        "output.mesh=[]",
        "output.screenshots=[]",
        "output.plot=false",
    ]
    out = tmp_path / "run"
    # tasks of 2 rows: 4 a generation (8 rows, then 7 children); it dies in generation 3
    with pytest.raises(EvaluationError) as err:
        run(config, out=out, overrides=overrides, progress=False, executor=DiesAfter(13))
    msg = str(err.value)
    assert msg.startswith("generation 3, evaluations 23-29: a worker process died")
    assert msg.endswith(f"to continue: growsim run --resume {out}")
    assert not (out / "summary.json").exists()
    resumed = run(out=out, resume=True, progress=False)
    whole = run(config, out=tmp_path / "whole", overrides=overrides, progress=False)
    h1 = resumed.history.drop(columns="seconds")
    pd.testing.assert_frame_equal(h1, whole.history.drop(columns="seconds"))
    assert resumed.best == whole.best


# -- Dask: a worker process of a cluster of its own dies --------------------------------
@pytest.fixture(scope="module")
def one_worker_cluster():
    """A Dask cluster of one worker (its nanny restarts it when it dies) whose scheduler
    gives a task up after its second worker death (``allowed-failures``: 1)."""
    import dask
    from dask.distributed import Client

    from growsim.experiment.executors import local_cluster

    before = dict(os.environ)
    with dask.config.set({"distributed.scheduler.allowed-failures": 1}):  # read at its start
        cluster = local_cluster(1)
    with cluster, Client(cluster) as client:
        yield client
    # its Nanny writes its worker's variables into os.environ each time it starts one (a
    # worker killed by the tests above is restarted, maybe after the last test's own
    # check): put back, once the cluster is closed, before the next module's tests run
    _restore_environ(before)


@pytest.mark.timeout(90)
@pytest.mark.filterwarnings("ignore:Port 8787 is already in use")
def test_a_dask_worker_dying_once_is_retried_to_the_same_result(one_worker_cluster, tmp_path):
    once = tmp_path / "fired"
    ex = DaskExecutor(one_worker_cluster)
    r = _ga(Faulty(sphere, ABOVE, fault="kill", once=str(once))).run(executor=ex, **RUN)
    assert once.exists()
    _same(r, _ga(sphere).run(**RUN))


@pytest.mark.timeout(90)
@pytest.mark.filterwarnings("ignore:Port 8787 is already in use")
def test_a_dask_worker_dying_every_time_stops_the_run(one_worker_cluster):
    ex = DaskExecutor(one_worker_cluster)
    with pytest.raises(EvaluationError, match=r"^generation 0, .*Dask gave up on a task"):
        _ga(Faulty(sphere, ABOVE, fault="exit")).run(executor=ex, **RUN)


def _exits(x):
    raise SystemExit(3)


@pytest.mark.timeout(60)
def test_a_fitness_calling_sys_exit_in_a_pool_worker_stops_the_run_not_the_caller(
    process_pool,
):
    """``SystemExit`` from a worker's task is the worker's, not this process's: the run
    stops with the cause named instead of exiting the caller."""
    with pytest.raises(EvaluationError, match=r"^generation 0, .*executor failed.*SystemExit"):
        _ga(_exits).run(executor=process_pool, **RUN)


class _LostAfterResult:
    """A Dask future whose result was fetched, then lost with its worker: ``status``
    says "lost" (Dask is recomputing it) though ``result()`` returned."""

    status = "lost"

    def __init__(self, value):
        self.value = value

    def result(self):
        return self.value

    def cancelled(self):
        return False


def test_a_dask_result_lost_after_it_was_fetched_is_delivered_not_an_error():
    """Dask's own adapter read such a task's status after fetching it and, finding
    "lost", unpacked the result as an error triple: the run stopped as if the executor
    had failed (one CI run of the killed-worker test above). The executor's future
    follows ``result()`` alone."""
    from growsim.experiment.executors import _follow

    future = Future()
    _follow(_LostAfterResult(np.arange(3)), future)
    assert future.result().tolist() == [0, 1, 2]


@pytest.mark.timeout(60)
def test_a_dask_executor_cancels_and_shuts_down_like_any_executor(dask_client):
    import time
    from concurrent.futures import CancelledError, wait

    ex = DaskExecutor(dask_client)
    assert ex.submit(sum, [1, 2]).result() == 3
    with pytest.raises(ZeroDivisionError):
        ex.submit(divmod, 1, 0).result()
    slow = ex.submit(time.sleep, 30)  # runs until cancelled
    assert slow.cancel()
    done, _ = wait([slow], timeout=20)  # the waiters are told
    assert slow in done
    with pytest.raises(CancelledError):
        slow.result()
    ex.shutdown(wait=True)
    with pytest.raises(RuntimeError, match="after shutdown"):
        ex.submit(sum, [1])
