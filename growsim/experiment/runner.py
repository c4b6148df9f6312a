"""Running one experiment into a results directory.

:func:`run` takes a config (anything :func:`~growsim.experiment.load.load_plan` takes: a
path, dict, :class:`Config` or compiled :class:`~growsim.experiment.plan.ExperimentPlan`),
evolves it with the GA, and writes history, best, the best phenotype and its artefacts,
and the summary (last) through :class:`growsim.experiment.results.RunDir`; it returns the
run's :class:`~growsim.experiment.results.RunRecord`, the type
:func:`~growsim.experiment.results.read_run` reads back.
"""

from __future__ import annotations

import contextlib
import logging
import math
import signal
import sys
import threading
import time
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from tqdm.auto import tqdm

from growsim.errors import ConfigError, UserInputError
from growsim.experiment.executors import check_executor_args, executor_workers, make_executor
from growsim.experiment.load import load_plan
from growsim.experiment.plan import ExperimentPlan
from growsim.experiment.results import RunDir, RunRecord, plot_fitness, read_run
from growsim.experiment.schema import Config
from growsim.ga.evaluate import EvaluationError, open_executor

__all__ = ["Progress", "default_out", "interrupts_deferred", "run"]

log = logging.getLogger("growsim.experiment")


@contextlib.contextmanager
def interrupts_deferred(replay: bool = True) -> Iterator[None]:
    """Hold Ctrl-C (SIGINT) until the block ends, then raise ``KeyboardInterrupt``.

    Native code must not be interrupted halfway: a ``KeyboardInterrupt`` raised inside
    pyvista/VTK (its off-screen renders, the import of its rendering modules) crashed the
    interpreter (segmentation fault), and one raised inside ``np.savez`` or a renderer
    came out as another exception, which an artefact's error handling took for a failed
    file. Inside the block a SIGINT is only recorded; at its end the previous handler is
    put back and, if one came, called (the default one raises ``KeyboardInterrupt``,
    even over an exception of the block); ``replay=False`` drops it (for code that is
    already handling an interrupt). Outside the main thread, or when SIGINT is ignored,
    the block runs as is.

    Examples
    --------
    >>> import signal
    >>> before = signal.signal(signal.SIGINT, signal.default_int_handler)  # Python's own
    >>> try:
    ...     with interrupts_deferred():
    ...         signal.raise_signal(signal.SIGINT)  # to this thread, as Ctrl-C would
    ...         print("the block ends")
    ... except KeyboardInterrupt:
    ...     print("then the interrupt")
    the block ends
    then the interrupt
    >>> _ = signal.signal(signal.SIGINT, before)
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.getsignal(signal.SIGINT)
    if previous in (signal.SIG_IGN, None):  # ignored, or a handler set outside Python
        yield
        return
    caught: list[object] = []
    signal.signal(signal.SIGINT, lambda signum, frame: caught.append(frame))
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
        if caught and replay:
            if not callable(previous):  # SIG_DFL: stop, as Python's own handler would
                raise KeyboardInterrupt
            previous(signal.SIGINT, caught[0])  # Python's default raises KeyboardInterrupt


def _interrupted(exc: BaseException) -> bool:
    """True when ``exc`` was raised while a ``KeyboardInterrupt`` was being handled (a
    library's clean-up failing under Ctrl-C, e.g. a ZIP file closed halfway)."""
    seen: set[int] = set()
    e: BaseException | None = exc
    while e is not None and id(e) not in seen:
        if isinstance(e, KeyboardInterrupt):
            return True
        seen.add(id(e))
        e = e.__cause__ or e.__context__
    return False


def default_out(cfg: Config, root: str | Path = "runs", kind: str = "") -> Path:
    """``runs/<name>[-<kind>]-<YYYYmmdd-HHMMSS>`` (with ``-2``, ``-3``... if it exists).

    Examples
    --------
    >>> from growsim.experiment import load_config
    >>> cfg = load_config({"model": {"kind": "honda", "evolve": {"f": True}},
    ...                    "objective": [{"kind": "light"}]})
    >>> default_out(cfg).name.startswith("experiment-")
    True
    """
    stamp = time.strftime("%Y%m%d-%H%M%S")
    base = Path(root) / "-".join(x for x in (cfg.experiment.name, kind, stamp) if x)
    out, k = base, 2
    while out.exists():
        out = base.with_name(f"{base.name}-{k}")
        k += 1
    return out


class Progress:
    """Per-generation callback: tqdm bar on stderr, a live history.parquet (at most every
    ``every`` seconds, so a long run can be watched; the checkpoint is what resumes), and
    the user's callback."""

    def __init__(
        self,
        total: int | None,
        enabled: bool,
        user_callback=None,
        rd=None,
        every: float = 5.0,
        label: str | None = None,
    ):
        self.user_callback = user_callback
        self.rd = rd
        self.every = every
        self.last_write = time.perf_counter()
        self.bar = None
        self.t0 = time.perf_counter()
        self.evals0: int | None = None
        if enabled:
            self.bar = tqdm(
                total=total, unit="gen", file=sys.stderr, dynamic_ncols=True, desc=label
            )

    def __call__(self, ga, row: Mapping[str, Any]):
        if self.bar is not None:
            evals = int(row.get("evaluations", 0))
            if self.evals0 is None:
                self.evals0 = evals
                self.t0 = time.perf_counter()
            dt = max(time.perf_counter() - self.t0, 1e-9)
            rate = (evals - self.evals0) / dt
            gen = int(row.get("generation", self.bar.n))
            self.bar.update(max(gen + 1 - self.bar.n, 0))
            self.bar.set_postfix(
                best=f"{row.get('best_so_far', row.get('best', float('nan'))):.4g}",
                mean=f"{row.get('mean', float('nan')):.4g}",
                evals_s=f"{rate:.0f}",
                refresh=False,
            )
        if self.rd is not None and time.perf_counter() - self.last_write > self.every:
            try:
                with interrupts_deferred():  # a Ctrl-C here stops the run after the file
                    self.rd.write_parquet("history.parquet", ga.history)
            except Exception as exc:  # only a live view: never stop a run for it
                log.warning("live history.parquet not written: %s", exc)
            self.last_write = time.perf_counter()
        if self.user_callback is not None:
            return self.user_callback(ga, row)
        return None

    def close(self):
        if self.bar is not None:
            self.bar.close()


def run(
    config: str | Path | Mapping[str, Any] | Config | ExperimentPlan | None = None,
    out: str | Path | None = None,
    *,
    seed: int | None = None,
    overrides: Sequence[str] = (),
    workers: int | None = None,
    scheduler: str | None = None,
    resume: bool = False,
    progress: bool | str = True,
    callback=None,
    executor=None,
) -> RunRecord:
    """Run one experiment into a results directory; return its
    :class:`~growsim.experiment.results.RunRecord` (also named ``RunResult``).

    ``config``: a TOML path, dict, :class:`Config` or compiled ``ExperimentPlan``
    (:func:`~growsim.experiment.load.load_plan`; ``None`` with ``resume=True``: the
    ``config.toml`` saved in ``out``). ``out``: the
    results directory (default ``runs/<name>-<timestamp>``); a fresh run refuses a
    directory that already holds a run, and a second run on a directory in use refuses
    at once; everything that can be checked (the config, the GA's options and budget,
    the directory) is checked before anything is written. ``seed`` overrides
    ``experiment.seed``. ``workers``: local process pool size;
    ``scheduler``: ``"local"`` (a Dask LocalCluster of ``workers`` processes) or a Dask
    scheduler address. ``resume=True`` continues from ``out/checkpoint.npz`` to the same
    history and best as an uninterrupted run (a finished run is read back as it is: nothing
    to resume, none of its outputs rewritten). ``progress``: a tqdm bar on stderr (only when
    stderr is a TTY; a text: the bar, labelled with it). ``callback(ga, row)`` is called
    after every generation (return True to stop). ``executor``: any
    ``concurrent.futures.Executor`` to evaluate on (instead of ``workers``/``scheduler``;
    not shut down here), e.g. a Dask client's as
    :class:`~growsim.experiment.DaskPool` ``(client)``, whose size splits a
    generation into 4 tasks per worker thread (a bare executor's size is unknown: the
    local CPUs are counted).

    Ctrl-C stops the run at once, except while a file is being written (the end-of-run
    artefacts: meshes, renders, plots), which is finished first; then it prints
    ``growsim: to continue: growsim run --resume DIR`` on stderr and raises
    ``KeyboardInterrupt``. The directory's ``.lock`` is removed when the run ends.
    A worker that dies (or a task the executor loses) stops the run with an
    :class:`~growsim.ga.EvaluationError` naming the cause and the same hint; a fitness
    that raises in a worker only fails its individuals, as in the main process.

    Examples
    --------
    >>> r = run("experiments/quickstart.toml", out="runs/doc", progress=False)  # doctest: +SKIP
    >>> sorted(p.name for p in r.out.iterdir())[:3]  # doctest: +SKIP
    ['best.json', 'best.vtp', 'best_front.png']
    """
    check_executor_args(workers, scheduler)
    if resume:
        if out is None:
            raise UserInputError("resume: give the results directory to resume (--resume DIR)")
        rd = RunDir(out)
        if not rd.config_path.is_file():
            raise UserInputError(f"{rd.path}: no config.toml here; nothing to resume")
        plan = load_plan(rd.config_path)
        if config is not None:
            given = load_plan(config, overrides)
            if seed is not None:
                given = given.with_seed(seed)
            if given.config.to_dict() != plan.config.to_dict():
                raise ConfigError(
                    f"{rd.path}: the config given differs from the run's config.toml; "
                    "resume with the directory alone (growsim run --resume DIR)"
                )
        elif seed is not None and seed != plan.seed:
            raise ConfigError(f"--seed {seed}: the run in {rd.path} has seed {plan.seed}")
        if rd.is_complete():  # finished: nothing to resume; its outputs stay as they are
            log.info("%s: the run is finished; nothing to resume", rd.path)
            return read_run(rd.path)
    else:
        if config is None:
            raise UserInputError("no config given")
        plan = load_plan(config, overrides)
        if seed is not None:
            plan = plan.with_seed(seed)
        rd = RunDir(out if out is not None else default_out(plan.config))

    # connect to the evaluators first: an unreachable scheduler writes nothing
    ext, close = (
        (executor, lambda: None) if executor is not None else make_executor(workers, scheduler)
    )
    try:
        # the fitness and the GA before the directory: what they refuse writes nothing
        fitness, ga = _build(plan, ext)
        try:
            try:
                with rd.lock(resume=resume):
                    if not resume:
                        rd.create_fresh()
                        rd.write_text("config.toml", plan.config.to_toml())
                    return _run_locked(
                        plan, rd, workers, scheduler, resume, progress, callback, ext, fitness, ga
                    )
            except EvaluationError as exc:  # a worker died: the checkpoint resumes the run
                raise EvaluationError(
                    f"{exc}; to continue: growsim run --resume {rd.path}"
                ) from exc.__cause__
            except Exception as exc:
                if _interrupted(exc):  # a clean-up failing under Ctrl-C: still an interrupt
                    raise KeyboardInterrupt from exc
                raise
        except KeyboardInterrupt:
            with interrupts_deferred(replay=False):  # a second Ctrl-C: the same stop
                if rd.config_path.is_file():
                    print(f"growsim: to continue: growsim run --resume {rd.path}", file=sys.stderr)
            raise
    finally:
        close()


def _build(plan: ExperimentPlan, executor):
    """The plan's fitness and its GA (evaluating on ``executor``)."""
    fitness = plan.fitness()
    g = plan.config.ga
    # Tasks per generation: the GA splits a population into 4 tasks per worker, counting
    # local CPUs when it cannot see the executor's size; give it the Dask cluster's size.
    # (Batching never changes results: seeds follow the evaluation index.)
    batch = None
    n_exec = executor_workers(executor) if executor is not None else None
    if g.batch_size is None and n_exec is not None:
        batch = max(1, math.ceil(g.population / (4 * n_exec)))
    return fitness, plan.build_ga(fitness, batch_size=batch)


def _stop_counts(fitness, params: np.ndarray) -> dict[str, int]:
    """``{reason: count}`` of why the plants of ``params`` (full rows) stopped growing, by
    the model's population path; ``{}`` when it reports no ``stopped`` column."""
    fast = fitness.model.population
    table = fast(params, fitness.names, None, env=fitness.env)
    if table is None or "stopped" not in table:
        return {}
    counts = table["stopped"].replace("", "growing").value_counts()
    return {str(k): int(v) for k, v in counts.items()}


def _census(fitness, result, warnings: list[str], executor=None) -> dict[str, int]:
    """Why the final population's individuals stopped growing, for a model with a
    population path that reports it (the hormone model: ``cap``, ``broken``, ``nan``;
    ``growing`` for the rest): ``{"population": n, reason: count}``, else ``{}``.

    The population is grown again in 4 tasks per worker of ``executor`` (None: serially;
    an int: a process pool of that size, as the GA's): it costs about as much as one or
    two generations' evaluations (the final population's plants are the grown ones)."""
    population = result.population
    if "population" not in fitness.model.capabilities or population is None:
        return {}
    if not len(population):
        return {}
    try:
        params = fitness.full_params(population)
        ex, owned = open_executor(executor)
        try:
            if ex is None:
                parts = [_stop_counts(fitness, params)]
            else:
                tasks = min(len(params), 4 * (ex.workers or 1))
                futures = [
                    ex.submit(_stop_counts, fitness, part) for part in np.array_split(params, tasks)
                ]
                parts = [f.result() for f in futures]
        finally:
            if owned:
                ex.shutdown(wait=True, cancel_futures=True)
    except Exception as exc:  # a census must not lose the run
        warnings.append(f"counting the final population's stops failed: {exc}")
        return {}
    if not any(parts):
        return {}
    counts: dict[str, int] = {}
    for part in parts:
        for k, v in part.items():
            counts[k] = counts.get(k, 0) + v
    ordered = sorted(counts.items(), key=lambda kv: (-kv[1], kv[0]))  # most common first
    return {"population": len(params), **dict(ordered)}


def _run_locked(
    plan, rd, workers, scheduler, resume, progress, callback, executor, fitness, ga
) -> RunRecord:
    cfg = plan.config
    g = cfg.ga
    show_bar = bool(progress) and sys.stderr.isatty()
    label = progress if isinstance(progress, str) else None
    bar = Progress(g.generations, show_bar, callback, rd=rd, label=label)
    started = time.strftime("%Y-%m-%dT%H:%M:%S%z")
    try:
        result = ga.run(
            **g.stop_options(),
            executor=executor,
            callback=bar,
            checkpoint=rd.checkpoint_path,
            resume=resume,
        )
    finally:
        bar.close()
    t_ga = time.perf_counter()
    ga_seconds = float(result.seconds)  # the GA's own clock covers every session

    x = result.best.params
    individual = fitness.phenotype_of(x, grow=False)
    best_params = {n: round(v) if n in plan.int_names else v for n, v in individual.params.items()}
    history = result.history
    # every file of the end of the run is finished before a Ctrl-C stops it
    with interrupts_deferred():
        rd.write_parquet("history.parquet", history)

    warnings: list[str] = []
    phenotype, terms = None, {}
    try:
        phenotype = fitness.phenotype_of(x).phenotype
        terms = fitness.terms(phenotype)
    except Exception as exc:  # the best genome scored, so this is a model bug: report it
        warnings.append(f"developing the best phenotype failed: {exc}")
        log.warning("developing the best phenotype failed: %s", exc)
    with interrupts_deferred():
        best = rd.write_best(
            fitness=result.best.fitness,
            generation=result.best.generation,
            params=best_params,
            evolved=fitness.evolved,
            model=cfg.model.kind,
            phenotype=plan.model.phenotype,
            plant_seed=individual.seed,
            terms=terms,
            genome=result.best.raw,
        )
    warnings += _artefacts(cfg, rd, phenotype, history)

    wall_seconds = ga_seconds + time.perf_counter() - t_ga
    stops = _census(fitness, result, warnings, executor)
    finished = time.strftime("%Y-%m-%dT%H:%M:%S%z")
    measures = _measures(phenotype, plan) if phenotype is not None else {}
    with interrupts_deferred():
        summary = rd.write_summary(
            cfg,
            best,
            history,
            evaluations=result.evaluations,
            wall_seconds=wall_seconds,
            ga_seconds=ga_seconds,
            stop_reason=result.stop_reason,
            stops=stops,
            resumed=resume,
            started=started,
            finished=finished,
            workers=workers,
            scheduler=scheduler,
            measures=measures,
            warnings=warnings,
        )
    return RunRecord.of_run(rd, best, summary, history, phenotype)


#: measures of the light on the leaves: left out of summaries for a phenotype without
#: leaves (``n_leaves == 0``, e.g. the IFS tree's), where they would read 0
LEAF_LIGHT_MEASURES = ("leaf_area_top", "light_captured")


def _measures(phenotype, plan) -> dict[str, float]:
    """The best phenotype's named measures (in its environment), for summaries; without
    :data:`LEAF_LIGHT_MEASURES` when it has no leaves."""
    try:
        out = {
            k: float(v) for k, v in phenotype.measures(plan.environment).items() if np.isscalar(v)
        }
    except Exception as exc:  # measures are informative; never lose a run for them
        log.warning("measures of the best phenotype failed: %s", exc)
        return {}
    if out.get("n_leaves") == 0:
        for k in LEAF_LIGHT_MEASURES:
            out.pop(k, None)
    return out


def _artefacts(cfg: Config, rd, phenotype, history) -> list[str]:
    """The best phenotype's file and artefacts, the fitness plot. Returns warnings.

    Each file is written with Ctrl-C held (:func:`interrupts_deferred`): an interrupt
    finishes the file being written (a VTK render must not be cut: it crashed), then
    stops the run."""
    warnings = []
    o = cfg.output

    def attempt(what, fn):
        try:
            with interrupts_deferred():
                fn()
        except Exception as exc:  # an artefact must not lose the run's results
            warnings.append(f"{what}: {exc}")
            log.warning("writing %s failed: %s", what, exc)

    if phenotype is not None:
        if o.phenotype:
            path = rd.phenotype_path(phenotype.phenotype)
            attempt(path.name, lambda: phenotype.save(path))
        try:
            with interrupts_deferred():
                files = phenotype.artefacts(o)
        except Exception as exc:
            files = {}
            warnings.append(f"artefacts: {exc}")
        for name, writer in files.items():
            attempt(name, lambda name=name, writer=writer: writer(rd.path / name))
    if o.plot and len(history):
        attempt("fitness.png", lambda: plot_fitness(history, rd.path / "fitness.png"))
    return warnings
