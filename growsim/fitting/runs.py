"""One run of a fit on its way through the raster sizes (:class:`FitRun`): the first
stage's GA (:func:`evolve`), the searches at each size (:func:`size_stages`), and the
whole of one run as a job a process can take (:class:`RunJob`, :func:`run_job`,
:func:`run_jobs`: the runs of a photo's fit side by side on the machine's cores).

Each run keeps its state in its directory (:data:`RUN_STATE`, written after each size),
so an interrupted fit goes on from each run's last finished size, and a job run in
another process is read back from there.
"""

from __future__ import annotations

import json
import os
import sys
import time
from concurrent.futures import as_completed
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
from tqdm.auto import tqdm

from growsim.experiment import load_plan, read_run, run
from growsim.files import atomic_write, jsonable
from growsim.fitting.setups import arrange as search_arrangement
from growsim.fitting.setups import exact_score, fit_config, sweep_discrete
from growsim.fitting.setups import refine as refine_fit
from growsim.ga import WorkerPool

__all__ = ["RUN_STATE", "FitRun", "RunJob", "evolve", "run_job", "run_jobs", "size_stages"]

#: each run's state in its directory: the stages it finished, its values and draws
RUN_STATE = "fit-stages.json"


@dataclass
class FitRun:
    """One fit on its way through the sizes: its compiled plan (at the current size), the
    evolved values ``x``, the arrangement ``draws`` (``None``: the model's own), the stages
    so far and its run's directory.

    Examples
    --------
    >>> run = FitRun(None, np.zeros(2), Path("fit"), stages=[{"ncc": 0.7, "score": 0.6}])
    >>> run.ncc, run.score
    (0.7, 0.6)
    """

    plan: Any
    x: np.ndarray
    out: Path
    draws: np.ndarray | None = None
    stages: list[dict[str, Any]] = field(default_factory=list)

    @property
    def ncc(self) -> float:
        """The binary NCC at its last stage."""
        return self.stages[-1]["ncc"]

    def save(self, done: int) -> None:
        """Write its state after the searches of size ``done`` (an index into the sizes)."""
        state = {"done": done, "x": self.x.tolist(), "stages": self.stages,
                 "draws": None if self.draws is None else self.draws.tolist()}  # fmt: skip
        atomic_write(self.out / RUN_STATE, json.dumps(jsonable(state)))

    @classmethod
    def restore(cls, out: Path, config) -> tuple[FitRun, int] | None:
        """The fit saved in ``out`` (:meth:`save`) and the index of the last size done, its
        plan compiled by ``config(k)``; ``None`` if nothing was saved."""

        path = out / RUN_STATE
        if not path.is_file():
            return None
        state = json.loads(path.read_text())
        draws = None if state["draws"] is None else np.asarray(state["draws"], dtype=np.float64)
        fit = cls(load_plan(config(state["done"])), np.asarray(state["x"], dtype=np.float64),
                  out, draws, state["stages"])  # fmt: skip
        return fit, state["done"]

    @property
    def score(self) -> float:
        """The score searched at its last stage (the shape score, blurred or not; the
        binary NCC when the search scored that)."""
        return self.stages[-1].get("score", self.stages[-1]["ncc"])


def searched_apart(plan) -> bool:
    """Whether ``plan``'s searches score something else than the binary NCC (a blur, the
    shape terms)."""
    o = plan.objectives[0]
    return o.blur > 0 or o.has_shape_terms


class Bar:
    """A progress bar of one stage (tqdm on stderr, labelled; nothing when disabled)."""

    def __init__(self, label: str, total: int, enabled: bool, unit: str = "eval"):
        self.bar = None
        if enabled and total > 0:
            if sys.stderr.isatty():
                tqdm.monitor_interval = 0  # no monitor thread: runs fork side by side
                self.bar = tqdm(total=total, desc=label, unit=unit, file=sys.stderr,
                                dynamic_ncols=True, leave=False)  # fmt: skip

    def __call__(self, n: int) -> None:
        if self.bar is not None:
            self.bar.update(n)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()


def evolve(plan, size: int, out: Path, workers, progress, resume: bool = False) -> FitRun:
    """The first stage of one fit: the setup's GA on ``plan`` (compiled at the first size,
    ``size``), run into ``out`` (``progress``: ``False`` or the bar's label; ``resume``:
    continued from the run's checkpoint, or read back when it finished); its row: size,
    evaluations, seconds, binary NCC (and the ``score`` searched, when it differs).

    Examples
    --------
    >>> run = evolve(load_plan(config), 64, Path("fit/honda-bare-0"), None, False)  # doctest: +SKIP
    >>> run.stages[0]["stage"], run.stages[0]["size"]  # doctest: +SKIP
    ('ga', 64)
    """

    t0 = time.perf_counter()
    if resume and (out / "summary.json").is_file():
        result = read_run(out, history=False)
    elif resume and (out / "config.toml").is_file():
        result = run(None, out=out, workers=workers, progress=progress, resume=True)
    else:
        result = run(plan, out=out, workers=workers, progress=progress)
    fitness = plan.fitness()
    x = np.array([result.best_params[n] for n in fitness.evolved], dtype=np.float64)
    apart = searched_apart(plan)
    row = {
        "size": size,
        "stage": "ga",
        "evaluations": int(result.summary["evaluations"]),
        "seconds": round(time.perf_counter() - t0, 3),
        "ncc": exact_score(plan, x) if apart else float(result.best_fitness),
    }
    if apart:
        row["score"] = float(result.best_fitness)
    return FitRun(plan, x, Path(result.out), stages=[row])


def size_stages(fit: FitRun, k: int, config, sizes, setup, budgets, seed: int,
                 label: str | None = None) -> None:  # fmt: skip
    """The searches of ``fit`` at ``sizes[k]``, in place: a refinement (at every size but
    the first, on the fit's config at that size, ``config(size, blur)``), the sweep of the
    discrete parameters (:func:`~growsim.fitting.setups.sweep_discrete`) and the search for
    the branches' arrangement (:func:`~growsim.fitting.setups.arrange`, for a model with
    the ``draws`` capability). ``budgets`` ``(refine, arrange, blur)``: the evaluations of
    each refinement and of each arrangement search (0: none), and the blur at the first
    size (scaled with the size; the searches at the last size are on the binary NCC). Each
    search appends its row to ``fit.stages`` (size, evaluations, seconds, binary NCC);
    ``label``: a progress bar per search, labelled with it and the stage.

    Examples
    --------
    >>> size_stages(run, 1, job.config, (64, 128), setup, (600, 1000, 0.7), 0)  # doctest: +SKIP
    >>> [(s["size"], s["stage"]) for s in run.stages][-2:]  # doctest: +SKIP
    [(128, 'refine'), (128, 'arrange')]
    """

    refine_evaluations, arrange_evaluations, blur = budgets
    size = sizes[k]

    def stage(name, evaluations, search):
        plan, x, draws = fit.plan, fit.x, fit.draws
        t = time.perf_counter()
        bar = Bar(f"{label}: {size} px {name}", evaluations, label is not None)
        try:
            if name == "refine":
                x, score, start = search(plan, x, evaluations=evaluations,
                                         sigma=setup.refine_sigma, seed=seed * 1000 + k,
                                         draws=draws, tick=bar)  # fmt: skip
            elif name == "discrete":
                x, score, start, evaluations = search(plan, x, draws)
            else:
                draws, score, start = search(plan, x, draws, evaluations=evaluations,
                                             seed=seed * 1000 + 500 + k, tick=bar)  # fmt: skip
        finally:
            bar.close()
        fit.x, fit.draws = x, draws
        row = {"size": size, "stage": name, "evaluations": evaluations}
        row["seconds"] = round(time.perf_counter() - t, 3)
        if searched_apart(plan):
            row["score_start"], row["score"] = start, score
            row["ncc"] = exact_score(plan, x, draws)
        else:
            row["ncc_start"], row["ncc"] = start, score
        fit.stages.append(row)

    # blurred at every size but the last, whose searches are on the score reported
    sigma = blur * size / sizes[0] if k < len(sizes) - 1 else 0.0
    if k > 0:
        fit.plan = load_plan(config(size, sigma))
        stage("refine", refine_evaluations, refine_fit)
    elif blur > 0 and sigma == 0:  # one size: the GA's score was blurred
        fit.plan = load_plan(config(size, 0.0))
    # the discrete parameters (leaves per branch): every value tried at every size
    genome = fit.plan.genome
    if np.any(genome.discrete & (genome.param_high - genome.param_low >= 1)):
        stage("discrete", 0, sweep_discrete)
    if arrange_evaluations > 0 and "draws" in fit.plan.model.capabilities:
        stage("arrange", arrange_evaluations, search_arrangement)


@dataclass(frozen=True)
class RunJob:
    """One run of a fit as a job (plain values, so another process can take it): the
    pictures ``front``, ``side`` (paths), the ``model``, its leaves ``mode`` and GA
    ``seed``, its ``settings`` (:func:`~growsim.fitting.choices.fit_settings`), the
    ``pictures`` keywords of :func:`~growsim.fitting.setups.fit_config` (segmentation,
    threshold, ...), the run's directory ``out``, and ``last``, the index of the last size
    to reach. ``resume``: go on from the run's saved state (or its GA's checkpoint);
    ``workers``: the GA's local processes; ``label``: progress bars' label (``None``:
    none).

    Examples
    --------
    >>> from growsim.fitting.choices import fit_settings
    >>> st = fit_settings("honda", False, {}, 1.0)
    >>> job = RunJob("tree.jpg", None, "honda", "bare", 0, st, {}, Path("fit/honda-bare-0"), 0)
    >>> job.config(64)["model"]["params"]["leaves"]
    0
    """

    front: Any
    side: Any
    model: str
    mode: str
    seed: int
    settings: dict
    pictures: dict
    out: Path
    last: int
    resume: bool = False
    workers: int | None = None
    label: str | None = None

    def config(self, size: int, sigma: float = 0.0) -> dict:
        """The run's experiment config at raster ``size`` with blur ``sigma``."""
        st = self.settings
        return fit_config(self.front, self.side, model=self.model, size=size, leaves=self.mode,
                          seed=self.seed, blur=sigma, line_width=st["line_width"],
                          evaluations=st["evaluations"], score=st["score"],
                          **self.pictures)  # fmt: skip

    def plan_at(self, k: int):
        """The compiled plan of the run's searches at its ``k``-th size (blurred at every
        size but the last)."""

        sizes = self.settings["sizes"]
        sigma = 0.0 if k == len(sizes) - 1 else self.settings["blur"] * sizes[k] / sizes[0]
        return load_plan(self.config(sizes[k], sigma))


def run_job(job: RunJob, plan=None) -> FitRun:
    """Run ``job`` up to its last size: from its saved state when ``job.resume`` and there
    is one, else the GA at the first size (on ``plan`` when given: the first size's
    compiled plan) and the searches there; then the searches of each finer size, the
    state saved after each (:meth:`FitRun.save`). Returns the run.

    Examples
    --------
    >>> run = run_job(job)  # doctest: +SKIP
    >>> [s["stage"] for s in run.stages]  # doctest: +SKIP
    ['ga', 'arrange']
    """

    st = job.settings
    sizes, budgets = st["sizes"], (st["refine"], st["arrange"], st["blur"])
    restored = FitRun.restore(job.out, job.plan_at) if job.resume else None
    if restored is not None:
        run, done = restored
    else:
        plan = plan if plan is not None else load_plan(job.config(sizes[0], st["blur"]))
        label = f"{job.label}: {sizes[0]} px GA" if job.label else False
        run = evolve(plan, sizes[0], job.out, job.workers, label, job.resume)
        size_stages(run, 0, job.config, sizes, st["setup"], budgets, job.seed, job.label)
        run.save(0)
        done = 0
    for k in range(done + 1, job.last + 1):
        size_stages(run, k, job.config, sizes, st["setup"], budgets, job.seed, job.label)
        run.save(k)
    return run


def _run_apart(job: RunJob) -> None:
    """:func:`run_job` in a worker process (its run is read back from its directory)."""
    run_job(job)


def run_jobs(jobs: list[RunJob], processes: int | None, label: str | None) -> list[FitRun]:
    """Run ``jobs`` (:func:`run_job`), on ``processes`` local processes side by side
    (``None``: the machine's cores; 1: one after the other in this process, with a
    progress bar per search), each job's GA in its process; returns their runs, in order.
    A job's runs are the same on any number of processes. ``label``: a progress bar over
    the jobs (``None``: none).

    Examples
    --------
    >>> runs = run_jobs(jobs, None, "fits at 64 px")  # doctest: +SKIP
    >>> [r.out.name for r in runs]  # doctest: +SKIP
    ['honda-bare-0', 'honda-bare-1', 'honda-bare-2']
    """
    n = min(processes or os.cpu_count() or 1, len(jobs))
    if n <= 1:
        return [run_job(j) for j in jobs]

    with WorkerPool(n) as pool:
        # every worker forked at the first job, before the bar starts a thread
        futures = [pool.submit(_run_apart, replace(j, label=None, workers=None)) for j in jobs]
        bar = Bar(label or "", len(jobs), label is not None, unit="run")
        try:
            for future in as_completed(futures):
                future.result()
                bar(1)
        except BaseException:
            pool.terminate()  # its workers end now, not after the runs they hold
            raise
        finally:
            bar.close()
    return [FitRun.restore(j.out, j.plan_at)[0] for j in jobs]
