"""Sweeps: a grid of config variants x repeats, run into one directory, one table.

Every variant is compiled once (its objectives built once) and run for each seed. A run
directory already there is reused (finished) or resumed (interrupted) only when its
``config.toml`` is the config the sweep would run; otherwise the sweep refuses before
running or writing anything.
"""

from __future__ import annotations

import itertools
import json
import re
import sys
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import pandas as pd

from growsim.errors import GrowsimError, UserInputError
from growsim.experiment.executors import check_executor_args, make_executor
from growsim.experiment.load import (
    UNSET,
    config_difference,
    load_plan,
    parse_path,
    parse_value,
    read_config,
    set_path,
    validate,
)
from growsim.experiment.plan import ExperimentPlan
from growsim.experiment.results import RunDir, read_run, write_parquet
from growsim.experiment.runner import default_out, run
from growsim.experiment.schema import Config
from growsim.files import atomic_write, number
from growsim.options import key_path

__all__ = ["parse_vary", "sweep"]


def parse_vary(items: Sequence[str] | Mapping[str, Sequence[Any]]) -> dict[str, list[Any]]:
    """``["env.light=1.0,0.5", "ga.population=[10, 20]"]`` -> ``{path: [values]}``.

    A value list is comma-separated TOML values, or one TOML array.

    Examples
    --------
    >>> parse_vary(["env.light=1.0,0.5", "model.preset=zelkova,cherry"])
    {'environment.light': [1.0, 0.5], 'model.preset': ['zelkova', 'cherry']}
    """
    if isinstance(items, Mapping):
        out = {}
        for k, v in items.items():
            vals = list(v) if isinstance(v, (list, tuple)) else [v]
            if not vals:
                raise UserInputError(f"--vary {k}: no values")
            out[key_path(parse_path(k))] = vals
        return out
    out = {}
    for item in items:
        if "=" not in item:
            raise UserInputError(f"--vary {item!r}: expected key.path=v1,v2,...")
        key, text = item.split("=", 1)
        key = key_path(parse_path(key.strip()))
        text = text.strip()
        parsed = parse_value(text) if text.startswith("[") else None
        if isinstance(parsed, list):
            vals = parsed
        else:
            vals = [parse_value(t.strip()) for t in text.split(",") if t.strip()]
        if not vals:
            raise UserInputError(f"--vary {key}: no values")
        if key in out:
            raise UserInputError(f"--vary {key}: given twice")
        out[key] = vals
    return out


def _label(assign: Mapping[str, Any]) -> str:
    """A directory-safe name of one variant: ``light=0.5_light_direction=0,-1,0``."""
    if not assign:
        return "base"

    def text(v):
        if isinstance(v, (list, tuple)):
            return ",".join(text(x) for x in v)
        if isinstance(v, bool):
            return str(v).lower()
        return str(v)

    parts = [f"{k.split('.')[-1]}={text(v)}" for k, v in assign.items()]
    return re.sub(r"[^A-Za-z0-9_.=,+-]", "-", "_".join(parts))[:120]


def sweep(
    config: str | Path | Mapping[str, Any] | Config | ExperimentPlan,
    vary: Sequence[str] | Mapping[str, Sequence[Any]] = (),
    *,
    repeats: int | None = None,
    out: str | Path | None = None,
    overrides: Sequence[str] = (),
    workers: int | None = None,
    scheduler: str | None = None,
    progress: bool = True,
    block: int = 1,
):
    """Run the grid of variants x repeats; return one row per run as a DataFrame.

    ``vary`` maps key paths to value lists (or ``"path=v1,v2"`` strings). Every variant
    runs ``repeats`` seeds (``experiment.seed + r``, the same seeds for every variant, so
    variants are compared on common random numbers) into
    ``out/<variant label>/seed-<seed>/``. ``block`` k (from 1) runs the k-th block of
    ``repeats`` seeds instead: ``experiment.seed + (k - 1) * repeats + r``, seeds no other
    block uses (block 1 to discover, block 2 to confirm: ``growsim compare DIR1 --confirm
    DIR2``). The config's named ``[[sweep.variants]]`` (each a
    ``name`` and the keys it sets, e.g. the environments an experiment compares) are
    crossed with ``vary``; their names lead the labels. A finished run found there is reused and a
    killed one resumed, so re-running a sweep completes it; but only when its saved
    ``config.toml`` equals the config this sweep would run there: a run made with other
    settings (another ``--set``, another base config) is refused before anything runs or
    is written, naming its directory and the first key that differs (use another
    ``out``). The table (also written to
    ``out/sweep.csv`` and ``out/sweep.parquet``) has one column per varied key, then
    ``repeat``, ``seed``, ``best_fitness``, ``generations``, ``evaluations``,
    ``wall_seconds``, the best plant's measures and ``out``.

    Examples
    --------
    >>> df = sweep("experiments/quickstart.toml", ["env.light=1.0,0.5"], repeats=2,
    ...            out="runs/sw", overrides=["ga.generations=2"])  # doctest: +SKIP
    >>> len(df)  # doctest: +SKIP
    4
    """

    check_executor_args(workers, scheduler)
    base = read_config(config, overrides)  # each variant is compiled below, once
    grid = parse_vary(vary)
    n_rep = base.experiment.repeats if repeats is None else repeats
    if not isinstance(n_rep, int) or n_rep < 1:
        raise UserInputError(f"--repeats: expected an integer >= 1, got {n_rep!r}")
    if not isinstance(block, int) or isinstance(block, bool) or block < 1:
        raise UserInputError(f"--block: expected an integer >= 1, got {block!r}")
    skip = (block - 1) * n_rep  # the seeds of the blocks before this one
    # validate every variant before running any, so a typo fails at once
    variants, labels = [], []
    keys = list(grid)
    named = [(v.name, v.set, f"sweep.variants[{i}].set") for i, v in enumerate(base.sweep.variants)]
    for (name, sets, where), combo in itertools.product(
        named or [(None, {}, "")], itertools.product(*(grid[k] for k in keys))
    ):
        assign = dict(zip(keys, combo))
        data = base.to_dict()
        for k, v in sets.items():
            set_path(data, parse_path(k), v, f"{where}.{k}")
        for k, v in assign.items():
            set_path(data, parse_path(k), v, f"--vary {k}")
        variants.append((({"sweep_variant": name} if name else {}) | assign, load_plan(data)))
        parts = [name] if name else []
        labels.append("_".join(parts + ([_label(assign)] if assign or not name else [])))
    if len(set(labels)) != len(labels):
        labels = [f"v{i}-{lab}" for i, lab in enumerate(labels)]
    root = Path(out) if out is not None else default_out(base, kind="sweep")
    # every run directory already there must hold this sweep's run: check them all
    # before running (or writing) anything
    for (_, plan), label in zip(variants, labels):
        for r in range(n_rep):
            seed = plan.seed + skip + r
            if seed > 2**63 - 1:
                raise UserInputError(f"--block {block}: seed {seed} beyond 2**63 - 1")
            _check_run_dir(root / label / f"seed-{seed}", plan.with_seed(seed))
    root.mkdir(parents=True, exist_ok=True)
    executor, close = make_executor(workers, scheduler)  # one pool/cluster for every run
    try:
        rows = _sweep_runs(
            variants, labels, n_rep, root, executor, workers, scheduler, progress, skip
        )
    finally:
        close()
    df = pd.DataFrame(rows)
    atomic_write(root / "sweep.csv", df.to_csv(index=False))
    write_parquet(root / "sweep.parquet", df)
    return df


def _show(value: Any) -> str:
    text = value if value == UNSET else json.dumps(value, default=str)
    return text if len(text) <= 40 else text[:37] + "..."


def _check_run_dir(run_dir: Path, plan: ExperimentPlan) -> None:
    """Refuse (``UserInputError``, one line, nothing written) a run directory that holds
    a run whose saved resolved config is not ``plan``'s: neither reuse its results nor
    resume it with its old config."""
    rd = RunDir(run_dir)
    if not rd.config_path.is_file():
        if rd.path.exists():
            rd.create_fresh()  # a run's files without its config.toml: refused too
        return
    want = plan.config.to_dict()
    saved = rd.read_config()
    # [compare] says what compare tests, not how a run goes: declaring primary measures
    # after the runs does not make them other runs
    want.pop("compare", None)
    saved = {k: v for k, v in saved.items() if k != "compare"}
    diff = config_difference(saved, want)
    if diff is not None:
        try:  # saved by another growsim version: compare the configs as resolved now
            resolved = validate(saved, str(rd.config_path)).to_dict()
        except GrowsimError:
            resolved = None
        if resolved is not None:
            resolved.pop("compare", None)
        if resolved is not None and config_difference(resolved, want) is None:
            return
        key, there, here = diff
        raise UserInputError(
            f"{rd.path} holds a run made with another config ({key}: {_show(there)} there, "
            f"{_show(here)} in this sweep); choose another --out"
        )


def _sweep_runs(variants, labels, n_rep, root, executor, workers, scheduler, progress, skip):
    rows = []
    if isinstance(executor, int):  # a process-pool size: let each run make its pool
        executor = None
    total, k = len(variants) * n_rep, 0
    for (assign, plan), label in zip(variants, labels):
        for r in range(n_rep):
            seed = plan.seed + skip + r
            run_dir = root / label / f"seed-{seed}"
            rd = RunDir(run_dir)
            k += 1
            if progress and sys.stderr.isatty():
                print(f"sweep: run {k}/{total}: {label}/seed-{seed}", file=sys.stderr)
            if rd.summary_path.is_file():
                summary = read_run(run_dir, history=False).summary
            elif rd.config_path.is_file():
                summary = run(
                    None,
                    run_dir,
                    resume=True,
                    workers=workers,
                    scheduler=scheduler,
                    progress=progress,
                    executor=executor,
                ).summary
            else:
                summary = run(
                    plan.with_seed(seed),
                    run_dir,
                    workers=workers,
                    scheduler=scheduler,
                    progress=progress,
                    executor=executor,
                ).summary
            row = {k: v for k, v in assign.items()}
            row.update(
                variant=label,
                repeat=r,
                seed=seed,
                best_fitness=summary["best_fitness"],
                generations=summary["generations"],
                evaluations=summary["evaluations"],
                wall_seconds=summary["wall_seconds"],
            )
            row.update({f"best_{k}": number(v) for k, v in summary.get("measures", {}).items()})
            row["out"] = str(run_dir)
            rows.append(row)
    return rows
