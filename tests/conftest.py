"""What the tests share: the repository's root, the command line in a subprocess, and one
Dask cluster and one process pool for the whole session.

Test modules import the plain helpers (``from conftest import ROOT, growsim``: pytest puts
``tests/`` on ``sys.path``) and ask for the executors as fixtures:

- ``dask_cluster`` / ``dask_client``: one Dask ``LocalCluster`` of two single-threaded
  worker processes, started by growsim's own :func:`growsim.experiment.executors.
  local_cluster` (the settings a user's ``--scheduler local`` gets), and a ``Client`` on
  it; started at the first test that asks, closed at the end of the session. A worker
  process costs an interpreter start and growsim's imports (a few seconds), so tests
  share it. A test that needs a cluster of its own on purpose (a worker killed, the
  environment it starts with) starts its own.
- ``process_pool``: one local process pool of two workers, as ``GA.run(executor=2)``
  opens it (:func:`growsim.ga.evaluate.open_executor`).

Every test leaves ``os.environ`` as it found it (an autouse fixture puts it back; a Dask
Nanny writes its workers' variables there), and Ctrl-C's handler too (another puts it back).

Paths are taken from :data:`ROOT`, never from the working directory, so
``cd /tmp && python -m pytest /path/to/tests/test_x.py`` runs the same tests.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

#: the repository's root (``experiments/``, ``docs/``, ``README.md``)
ROOT = Path(__file__).resolve().parents[1]


def benchmark_module(name: str):
    """The script ``benchmarks/<name>.py`` imported as module ``name`` (registered in
    ``sys.modules``: its dataclasses look their module up)."""
    import importlib.util

    spec = importlib.util.spec_from_file_location(name, ROOT / "benchmarks" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


def growsim(*args, cwd=None, timeout=240, env=None) -> subprocess.CompletedProcess:
    """Run ``python -m growsim ARGS`` as a user types it; its exit code and text output.

    ``args`` are turned into strings (paths welcome); ``env`` replaces the environment
    (default: this process's), always with ``MPLBACKEND=Agg``. E.g.
    ``growsim("grow", "nosuch").returncode == 2``.
    """
    return subprocess.run(
        [sys.executable, "-m", "growsim", *map(str, args)],
        capture_output=True,
        text=True,
        cwd=cwd,
        timeout=timeout,
        env={**(os.environ if env is None else env), "MPLBACKEND": "Agg"},
    )


def _restore_environ(before: dict) -> None:
    """Put ``os.environ`` back to ``before`` (keys added since removed, changed ones reset)."""
    if dict(os.environ) != before:
        os.environ.clear()
        os.environ.update(before)


@pytest.fixture(autouse=True)
def _no_environment_leak():
    """Every test leaves ``os.environ`` as it found it: a Dask Nanny writes its workers'
    variables (``OMP_NUM_THREADS``, ``PYTHONHASHSEED``, ...) into the starting process's
    environment, where later tests and their subprocesses would inherit them. A test's own
    settings go through ``monkeypatch.setenv``."""
    before = dict(os.environ)
    yield
    _restore_environ(before)


@pytest.fixture(autouse=True)
def _ctrl_c_put_back():
    """Ctrl-C's handler (SIGINT) is put back as it was after every test: one left ignored
    is inherited by every process later tests start, which Ctrl-C then cannot stop.
    (``tests/test_cli.py`` checks that an interrupted command called from Python puts it
    back itself.)"""
    import signal

    before = signal.getsignal(signal.SIGINT)
    yield
    if before is not None:
        signal.signal(signal.SIGINT, before)


@pytest.fixture(scope="session")
def dask_cluster():
    """The session's Dask ``LocalCluster`` (two single-threaded worker processes). Dask is
    in the ``[test]`` extra: a missing Dask fails the tests that ask, never skips them."""
    from growsim.experiment.executors import local_cluster

    before = dict(os.environ)
    with local_cluster(2) as cluster:
        _restore_environ(before)  # the workers have started: the Nanny's variables go
        yield cluster


@pytest.fixture(scope="session")
def dask_client(dask_cluster):
    """A Dask ``Client`` on :func:`dask_cluster`."""
    from dask.distributed import Client

    with Client(dask_cluster) as client:
        yield client


@pytest.fixture(scope="session")
def process_pool():
    """The session's local process pool of two workers."""
    from growsim.ga.evaluate import open_executor

    pool, _ = open_executor(2)
    with pool:
        yield pool
