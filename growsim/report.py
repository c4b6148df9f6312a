"""Compare results directories: groups, families, statistics over repeats, curves, HTML.

:func:`compare` takes run directories, sweep directories or any directory holding runs
(found by their ``summary.json``) and:

- **groups** the runs whose resolved configs are equal up to the seed (the repeats of
  one variant; the experiment's name, description and repeat count and the ``[output]``
  table do not change a result and are ignored), and labels each group by what differs
  between the groups' configs, with the shortest unambiguous key paths
  (``light.intensity=0.5``, ``model.preset=cherry, ga.population=100``);
- counts **one run per seed**: runs of a group with the same seed are the same run
  again, not independent repeats; they are flagged (a warning, the ``duplicates`` and
  ``duplicate_of`` columns) and only the latest finished one is counted;
- sorts the groups into **families**: same model and same objectives (kinds and every
  option that defines the score). Fitness is only comparable within a family, so tests
  are only made within one and the report has one block per family;
- reports per group (``n`` = distinct seeds): best fitness (best of the runs, mean +/-
  95 % confidence half-width, Student t) and the mean +/- 95 % CI of every numeric
  measure of the runs' best phenotypes (``summary.json`` ``measures``) and of every
  objective's score and terms (``terms``: ``light.leaf_area``, ...);
- tests, for every such quantity and every pair of groups of a family with at least two
  distinct-seed runs each: Welch's t-test and the Mann-Whitney U test (two-sided), with
  effect sizes (difference of means and its Welch 95 % CI, Cohen's d, Cliff's delta) and
  p-values adjusted with Holm-Bonferroni (:func:`holm`) over all the family's
  hypotheses (quantities x pairs), separately for each of the two tests;
- writes ``compare.csv`` (groups), ``stats.csv`` (tests), ``runs.csv`` (runs),
  ``curves.png`` (best-so-far fitness against evaluations, one panel per family),
  ``renders.png`` (each group's best phenotype, one row per family) and a self-contained
  ``report.html``, by default beside the runs (:func:`default_out`).
"""

from __future__ import annotations

import base64
import dataclasses
import html
import io
import itertools
import json
import logging
import math
import os
import textwrap
import time
import warnings
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from growsim.errors import UserInputError
from growsim.results import RunRecord, find_runs

__all__ = [
    "Comparison",
    "compare",
    "default_out",
    "format_mean_ci",
    "group_runs",
    "holm",
    "run_key",
    "run_label",
]

log = logging.getLogger(__name__)

#: config keys that do not change a run's result: ignored when grouping (the seed is
#: what tells repeats apart, and is checked for duplicates separately)
IGNORED_KEYS = (
    "experiment.seed",
    "experiment.name",
    "experiment.description",
    "experiment.repeats",
    "output",
)

Path_ = tuple[str, ...]  # a key path, one component per table level ("objective[0]", "kind")
_MISSING = "\0unset"
_MAX_LABEL_ITEMS = 4


# --- configs: flattening, keys, labels -------------------------------------------------


def _flatten(obj: Any, prefix: Path_ = ()) -> dict[Path_, Any]:
    """Leaves of a nested config: ``{("environment", "light", "intensity"): 0.5, ...}``.
    Lists of tables are indexed (``objective[0]``); other lists are values."""
    out: dict[Path_, Any] = {}
    if isinstance(obj, dict):
        for k, v in obj.items():
            if isinstance(v, list) and v and all(isinstance(e, dict) for e in v):
                for i, e in enumerate(v):
                    out.update(_flatten(e, (*prefix, f"{k}[{i}]")))
            else:
                out.update(_flatten(v, (*prefix, str(k))))
    else:
        out[prefix] = obj
    return out


def _ignored(path: Path_) -> bool:
    dotted = ".".join(path)
    return any(dotted == k or dotted.startswith(k + ".") for k in IGNORED_KEYS)


def _result_config(run: RunRecord) -> dict[Path_, Any]:
    """The flattened config of a run without the keys that do not change its result."""
    return {p: v for p, v in _flatten(run.config).items() if not _ignored(p)}


def _canon(v: Any) -> str:
    return v if v is _MISSING else json.dumps(v, sort_keys=True)


def run_key(run: RunRecord) -> str:
    """The config up to the seed (and the keys of :data:`IGNORED_KEYS`): runs with the
    same key are repeats of one variant."""
    flat = _result_config(run)
    return json.dumps({".".join(p): flat[p] for p in sorted(flat)}, sort_keys=True)


def _family_key(run: RunRecord) -> str:
    """Model kind and objectives (every option): runs whose fitness is comparable."""
    return json.dumps(
        [run.config.get("model", {}).get("kind"), run.config.get("objective", [])],
        sort_keys=True,
    )


def run_label(run: RunRecord) -> str:
    """``variant`` for ``.../variant/seed-N``, else the directory name."""
    if run.path.name.startswith("seed-"):
        return run.path.parent.name
    return run.path.name


def _fmt_value(v: Any) -> str:
    """A config value in a label: strings bare, the rest as JSON (``true``, ``[0, 1]``).

    Examples
    --------
    >>> _fmt_value("cherry"), _fmt_value(0.5), _fmt_value([1.0, -1.0]), _fmt_value(True)
    ('cherry', '0.5', '[1.0, -1.0]', 'true')
    """
    if v is _MISSING:
        return "unset"
    if isinstance(v, str):
        return v
    return json.dumps(v)


def _short_names(
    paths: Sequence[Path_], universe: set[Path_], min_parts: int = 2
) -> dict[Path_, str]:
    """The shortest suffix of each path (``min_parts`` components at least: two gives
    ``light.intensity``, ``ga.population``) that no other path of ``universe`` ends with.

    Examples
    --------
    >>> u = {("environment", "light", "intensity"), ("ga", "population"),
    ...      ("ga", "polish", "evaluations"), ("ga", "evaluations")}
    >>> sorted(_short_names(sorted(u), u).values())
    ['ga.evaluations', 'ga.population', 'light.intensity', 'polish.evaluations']
    """
    out = {}
    for p in paths:
        for k in range(min(min_parts, len(p)), len(p) + 1):
            suffix = p[-k:]
            if not any(q != p and q[-k:] == suffix for q in universe):
                break
        out[p] = ".".join(suffix)
    return out


def _differing(configs: Sequence[dict[Path_, Any]]) -> list[Path_]:
    """The paths whose value (or presence) is not the same in every config, in order."""
    order: dict[Path_, None] = {}
    for c in configs:
        order.update(dict.fromkeys(c))
    return [p for p in order if len({_canon(c.get(p, _MISSING)) for c in configs}) > 1]


def _from_preset(configs: Sequence[dict[Path_, Any]], diff: Sequence[Path_]) -> set[Path_]:
    """``model.params.*`` that differ only because ``model.preset`` differs (each value is
    the one the group's preset gives): left out of the labels."""
    params = [p for p in diff if p[:2] == ("model", "params") and len(p) == 3]
    if ("model", "preset") not in diff or not params:
        return set()
    try:
        from growsim.models import get_model

        expected = []
        for c in configs:
            m = get_model(c[("model", "kind")])
            preset = c.get(("model", "preset"), _MISSING)
            values = m.preset(preset) if preset is not _MISSING else {}
            expected.append(m.resolve(values))
    except Exception:  # an unknown model or preset: every parameter follows the preset
        return set(params)
    return {
        p
        for p in params
        if all(
            isinstance(c.get(p), (int, float)) and float(c[p]) == float(e.get(p[2], math.nan))
            for c, e in zip(configs, expected)
        )
    }


def _diff_labels(
    configs: Sequence[dict[Path_, Any]], universe: set[Path_], min_parts: int = 2
) -> tuple[list[str], list[Path_]]:
    """One label per config naming what differs between them (``path=value, ...``) and
    the differing paths (all of them, for the report's table of differences).

    Examples
    --------
    >>> a = {("environment", "light", "intensity"): 1.0, ("ga", "population"): 8}
    >>> b = {("environment", "light", "intensity"): 0.5, ("ga", "population"): 8}
    >>> _diff_labels([a, b], set(a))[0]
    ['light.intensity=1.0', 'light.intensity=0.5']
    """
    diff = _differing(configs)
    hidden = _from_preset(configs, diff)
    shown = [p for p in diff if p not in hidden]
    shown.sort(key=lambda p: (p != ("model", "preset"), p[-1] != "kind"))  # stable
    names = _short_names(shown, universe, min_parts)
    items = [[f"{names[p]}={_fmt_value(c.get(p, _MISSING))}" for p in shown] for c in configs]
    k = min(len(shown), _MAX_LABEL_ITEMS)
    while k < len(shown) and len({tuple(i[:k]) for i in items}) < len(items):
        k += 1
    more = len(shown) - k
    labels = [", ".join(i[:k]) + (f", ... (+{more})" if more > 0 else "") for i in items]
    return labels, diff


def _sort_value(v: Any) -> tuple:
    if isinstance(v, bool) or v is _MISSING:
        return (2, str(v))
    if isinstance(v, (int, float)):
        return (0, float(v))
    return (1, _canon(v))


# --- groups and families ----------------------------------------------------------------


@dataclasses.dataclass
class Group:
    """The runs of one config up to the seed: ``runs`` (one per seed, the ones counted),
    ``duplicates`` (``(dropped, kept)`` pairs: the same seed again)."""

    label: str
    runs: list[RunRecord]
    duplicates: list[tuple[RunRecord, RunRecord]]
    config: dict[Path_, Any]

    @property
    def members(self) -> list[RunRecord]:
        """Every run of the group, duplicates included, by seed then path."""
        allr = self.runs + [d for d, _ in self.duplicates]
        return sorted(allr, key=lambda r: (_sort_value(_seed(r)), str(r.path)))


@dataclasses.dataclass
class Family:
    """Groups whose fitness is comparable: same model, same objectives."""

    label: str
    model: str
    objectives: list[dict[str, Any]]
    groups: list[Group]
    differences: list[Path_]  # the config paths that differ between its groups


def _seed(run: RunRecord) -> Any:
    seed = (run.summary or {}).get("seed")
    if seed is None:
        seed = run.config.get("experiment", {}).get("seed")
    return seed if seed is not None else f"?{run.path}"  # unknown: never a duplicate


def _dedupe(label: str, members: list[RunRecord], notes: list[str]) -> Group:
    """Keep one run per seed (the latest finished; ties: the first path), note the rest."""
    by_seed: dict[str, list[RunRecord]] = {}
    for r in sorted(members, key=lambda r: str(r.path)):
        by_seed.setdefault(str(_seed(r)), []).append(r)
    kept, dups = [], []
    for rs in by_seed.values():
        keep = max(rs, key=lambda r: str((r.summary or {}).get("finished", "")))
        kept.append(keep)
        if len(rs) == 1:
            continue
        dups += [(r, keep) for r in rs if r is not keep]
        fits = sorted({r.best_fitness for r in rs})
        msg = (
            f"{label}: seed {_seed(keep)} appears in {len(rs)} runs "
            f"({', '.join(str(r.path) for r in rs)}): the same run again, not independent "
            f"repeats; counted once, keeping {keep.path} (the latest finished)"
        )
        if len(fits) > 1:
            msg += (
                f"; their best fitness differ ({', '.join(f'{f:.6g}' for f in fits)}): "
                "same config and seed should give the same run (growsim versions?)"
            )
        notes.append(msg)
        log.warning("%s", msg)
    kept.sort(key=lambda r: _sort_value(_seed(r)))
    return Group(label, kept, dups, {})


def _by_kind(objectives: Sequence[dict[str, Any]]) -> dict[str, dict[str, Any]]:
    """Objectives keyed by kind (``kind#i``, from 1, when a kind repeats)."""
    kinds = [str(o.get("kind")) for o in objectives]
    return {
        (k if kinds.count(k) == 1 else f"{k}#{i + 1}"): o
        for i, (k, o) in enumerate(zip(kinds, objectives))
    }


def _families(runs: Sequence[RunRecord], notes: list[str]) -> list[Family]:
    """Group the runs, label the groups, dedupe seeds, sort the groups into families."""
    by_family: dict[str, dict[str, list[RunRecord]]] = {}
    for r in runs:
        by_family.setdefault(_family_key(r), {}).setdefault(run_key(r), []).append(r)
    universe: set[Path_] = set()
    for r in runs:
        universe.update(_result_config(r))

    # family labels: model and objective kinds, plus the objective options that differ
    # between families of the same model and kinds
    heads = []
    for fkey in by_family:
        model, objectives = json.loads(fkey)
        kinds = " + ".join(str(o.get("kind", "?")) for o in objectives)
        heads.append((fkey, model, objectives, f"{model} / {kinds}"))
    fam_labels = {}
    for base in {h[3] for h in heads}:
        same = [h for h in heads if h[3] == base]
        if len(same) == 1:
            fam_labels[same[0][0]] = base
            continue
        # options named by their objective's kind (kind#i if repeated), as short as
        # unambiguous: "light (wood_cost=1.0)"
        cfgs = [_flatten(_by_kind(h[2])) for h in same]
        labels, _ = _diff_labels(cfgs, set().union(*cfgs), min_parts=1)
        for h, lab in zip(same, labels):
            fam_labels[h[0]] = f"{base} ({lab})"

    labelled = []  # (family key, [(label, config, runs)])
    for fkey, *_ in heads:
        members = list(by_family[fkey].values())
        configs = [_result_config(m[0]) for m in members]
        if len(members) > 1:
            labels, diff = _diff_labels(configs, universe)
        else:
            names = dict.fromkeys(
                str(r.config.get("experiment", {}).get("name") or run_label(r)) for r in members[0]
            )
            labels, diff = ["/".join(names)], []
        for i, lab in enumerate(labels):  # (a safeguard: labels name one group each)
            if labels.index(lab) != i:
                labels[i] = f"{lab} #{i + 1}"
        preset = _from_preset(configs, diff)
        shown = [p for p in diff if p not in preset]
        order = sorted(
            range(len(members)),
            key=lambda i: (
                tuple(_sort_value(configs[i].get(p, _MISSING)) for p in shown),
                labels[i],
            ),
        )
        labelled.append((fkey, diff, [(labels[i], configs[i], members[i]) for i in order]))

    # a label must name one group: the same label in two families gets the family's
    counts: dict[str, int] = {}
    for _, _, gs in labelled:
        for lab, _, _ in gs:
            counts[lab] = counts.get(lab, 0) + 1
    families = []
    for (fkey, model, objectives, _), (_, diff, gs) in zip(heads, labelled):
        groups = []
        for lab, cfg, members in gs:
            if counts[lab] > 1:
                lab = f"{lab} [{fam_labels[fkey]}]"
            g = _dedupe(lab, members, notes)
            g.config = cfg
            groups.append(g)
        families.append(Family(fam_labels[fkey], model, objectives, groups, diff))
    return families


def group_runs(runs: Sequence[RunRecord]) -> dict[str, list[RunRecord]]:
    """Group runs by config up to the seed; ``{label: runs}`` (every run, duplicated seeds
    included), each label naming what differs between the groups' configs.

    Examples
    --------
    >>> group_runs([])
    {}
    """
    if not runs:
        return {}
    return {g.label: g.members for f in _families(runs, []) for g in f.groups}


# --- statistics ---------------------------------------------------------------------------


def holm(pvalues: Sequence[float]) -> np.ndarray:
    """Holm-Bonferroni adjusted p-values (NaN entries stay NaN and do not count).

    Sorted ascending, the i-th smallest of m p-values is multiplied by m - i (i from 0),
    made monotone (running maximum) and capped at 1, as R's ``p.adjust(p, "holm")``.

    Examples
    --------
    >>> holm([0.01, 0.04, 0.03, 0.005]).round(6).tolist()  # R: 0.03 0.06 0.06 0.02
    [0.03, 0.06, 0.06, 0.02]
    """
    p = np.asarray(pvalues, dtype=np.float64)
    out = np.full(p.shape, np.nan)
    ok = np.isfinite(p)
    q = p[ok]
    m = len(q)
    order = np.argsort(q, kind="stable")
    adjusted = np.minimum(1.0, np.maximum.accumulate((m - np.arange(m)) * q[order]))
    res = np.empty(m)
    res[order] = adjusted
    out[ok] = res
    return out


def _flat(v: np.ndarray) -> bool:
    """True when the values are equal up to rounding (no variance to speak of)."""
    return bool(np.ptp(v) <= 1e-12 * np.max(np.abs(v))) if len(v) else True


def _ci95(x: np.ndarray) -> float:
    """Half-width of the 95 % Student-t confidence interval of the mean (NaN for n < 2)."""
    from scipy import stats

    x = np.asarray(x, dtype=np.float64)
    x = x[np.isfinite(x)]
    n = len(x)
    if n < 2:
        return float("nan")
    if _flat(x):
        return 0.0
    return float(stats.t.ppf(0.975, n - 1) * np.std(x, ddof=1) / math.sqrt(n))


def _pair_test(x: np.ndarray, y: np.ndarray) -> dict[str, Any]:
    """Welch's t and Mann-Whitney U (two-sided) of x against y, with effect sizes:
    difference of means (and its Welch 95 % CI), Cohen's d (pooled SD), Cliff's delta.
    Zero variance is handled here, so scipy never warns."""
    from scipy import stats

    nx, ny = len(x), len(y)
    mx, my = float(np.mean(x)), float(np.mean(y))
    vx = 0.0 if _flat(x) else float(np.var(x, ddof=1))
    vy = 0.0 if _flat(y) else float(np.var(y, ddof=1))
    diff = mx - my
    same = _flat(np.concatenate([x, y]))
    notes = []
    row: dict[str, Any] = {
        "n_a": nx,
        "n_b": ny,
        "mean_a": mx,
        "mean_b": my,
        "difference": diff,
        "diff_ci_low": math.nan,
        "diff_ci_high": math.nan,
        "cohen_d": math.nan,
        "cliffs_delta": float(np.mean(np.sign(x[:, None] - y[None, :]))),
        "welch_t": math.nan,
        "welch_df": math.nan,
        "welch_t_p": math.nan,
        "mann_whitney_u": math.nan,
        "mann_whitney_p": math.nan,
    }
    se2 = vx / nx + vy / ny
    if same:
        row.update(welch_t=0.0, welch_t_p=1.0, mann_whitney_p=1.0, cohen_d=0.0)
        row["mann_whitney_u"] = nx * ny / 2.0
        notes.append("no variation")
        return {**row, "note": "; ".join(notes)}
    if se2 == 0.0:
        notes.append("zero variance in both groups: Welch's t undefined")
    else:
        se = math.sqrt(se2)
        df = se2**2 / ((vx / nx) ** 2 / (nx - 1) + (vy / ny) ** 2 / (ny - 1))
        t = diff / se
        half = float(stats.t.ppf(0.975, df)) * se
        row.update(
            welch_t=t,
            welch_df=df,
            welch_t_p=float(2.0 * stats.t.sf(abs(t), df)),
            diff_ci_low=diff - half,
            diff_ci_high=diff + half,
        )
    pooled = math.sqrt(((nx - 1) * vx + (ny - 1) * vy) / (nx + ny - 2))
    if pooled > 0:
        row["cohen_d"] = diff / pooled
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        u = stats.mannwhitneyu(x, y, alternative="two-sided")
    row.update(mann_whitney_u=float(u.statistic), mann_whitney_p=float(u.pvalue))
    notes += [f"scipy: {w.message}" for w in caught]
    return {**row, "note": "; ".join(notes)}


STATS_COLUMNS = [
    "family",
    "measure",
    "group_a",
    "group_b",
    "n_a",
    "n_b",
    "mean_a",
    "mean_b",
    "difference",
    "diff_ci_low",
    "diff_ci_high",
    "cohen_d",
    "cliffs_delta",
    "welch_t",
    "welch_df",
    "welch_t_p",
    "welch_t_p_holm",
    "mann_whitney_u",
    "mann_whitney_p",
    "mann_whitney_p_holm",
    "note",
]


def _quantities(run: RunRecord) -> dict[str, float]:
    """Best fitness, the numeric measures and every objective's score and terms."""

    def num(v):
        return isinstance(v, (int, float)) and not isinstance(v, bool)

    out = {"best_fitness": run.best_fitness}
    s = run.summary or {}
    for k, v in (s.get("measures") or {}).items():
        if num(v):
            out[str(k)] = float(v)
    for obj, terms in (s.get("terms") or {}).items():
        for k, v in (terms or {}).items() if isinstance(terms, dict) else ():
            if num(v):
                out[f"{obj}.{k}"] = float(v)
    return out


@dataclasses.dataclass
class _FamilyStats:
    quantities: list[str]  # shown in the tables (duplicates of another left out)
    tested: list[str]
    skipped: dict[str, str]  # quantity -> why not tested
    untested_groups: list[str]
    values: dict[tuple[str, str], np.ndarray]  # (group, quantity) -> values of its runs


def _family_stats(fam: Family, notes: list[str]) -> tuple[_FamilyStats, list[dict[str, Any]]]:
    qs = {id(r): _quantities(r) for g in fam.groups for r in g.runs}
    names = list(dict.fromkeys(k for q in qs.values() for k in q))
    allruns = [r for g in fam.groups for r in g.runs]
    col = {n: np.array([qs[id(r)].get(n, math.nan) for r in allruns]) for n in names}
    shown, tested, skipped = [], [], {}
    for n in names:
        v = col[n]
        if not np.isfinite(v).any():
            continue
        constant = _flat(v[np.isfinite(v)]) and bool(np.isfinite(v).all())
        twin = next((m for m in tested if np.array_equal(col[m], v, equal_nan=True)), None)
        if twin is not None and (not constant or twin == "best_fitness"):  # measured twice
            skipped[n] = f"same values as {twin}"
            continue
        shown.append(n)
        if constant and n != "best_fitness":  # the primary outcome is always tested
            skipped[n] = "the same in every run"
        else:
            tested.append(n)
    values = {
        (g.label, n): np.array([qs[id(r)].get(n, math.nan) for r in g.runs])
        for g in fam.groups
        for n in names
    }
    eligible = [g for g in fam.groups if len(g.runs) >= 2]
    untested = [g.label for g in fam.groups if len(g.runs) < 2]
    if len(fam.groups) > 1:
        for g in fam.groups:
            if len(g.runs) < 2:
                msg = (
                    f"{fam.label}: {g.label} has {len(g.runs)} run(s) with distinct seeds: "
                    "not tested (a test needs at least 2 per group)"
                )
                notes.append(msg)
                log.info("%s", msg)
    rows = []
    for n in tested:
        for ga, gb in itertools.combinations(eligible, 2):
            x, y = values[(ga.label, n)], values[(gb.label, n)]
            x, y = x[np.isfinite(x)], y[np.isfinite(y)]
            if len(x) < 2 or len(y) < 2:
                continue
            rows.append(
                {"family": fam.label, "measure": n, "group_a": ga.label, "group_b": gb.label}
                | _pair_test(x, y)
            )
    for c in ("welch_t_p", "mann_whitney_p"):
        adj = holm([r[c] for r in rows])
        for r, a in zip(rows, adj):
            r[f"{c}_holm"] = float(a)
    return _FamilyStats(shown, tested, skipped, untested, values), rows


# --- pictures -------------------------------------------------------------------------


def _curve(history) -> tuple[np.ndarray, np.ndarray, bool]:
    """(x, best-so-far, x is evaluations) of one run, islands merged (max over islands);
    x is the evaluations done by the end of each generation when the history has them."""
    h = history.groupby("generation", sort=True)
    col = "best_so_far" if "best_so_far" in history else "best"
    best = np.maximum.accumulate(h[col].max().to_numpy(dtype=np.float64))
    if "evaluations" in history:
        return h["evaluations"].max().to_numpy(dtype=np.float64), best, True
    return h[col].max().index.to_numpy(dtype=np.float64), best, False


def _group_curve(runs: Sequence[RunRecord], use_evals: bool):
    """Mean, min and max over the runs of their best-so-far step functions on the union
    of their x values (a run that stopped keeps its last best-so-far)."""
    curves = []
    for r in runs:
        if r.history is None or not len(r.history):
            continue
        x, y, has_evals = _curve(r.history)
        if not use_evals or not has_evals:
            x = np.arange(len(y), dtype=np.float64)
        curves.append((x, y))
    if not curves:
        return None
    start = max(c[0][0] for c in curves)
    grid = np.unique(np.concatenate([c[0] for c in curves]))
    grid = grid[grid >= start]
    ys = np.array([y[np.searchsorted(x, grid, side="right") - 1] for x, y in curves])
    return grid, ys.mean(axis=0), ys.min(axis=0), ys.max(axis=0), len(curves)


def _curves_figure(families: Sequence[Family]):
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    n = len(families)
    cols = 1 if n == 1 else 2
    rows = -(-n // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(7 * cols, 4.2 * rows), dpi=100, squeeze=False)
    for ax in axes.flat[n:]:
        ax.set_visible(False)
    for ax, fam in zip(axes.flat, families):
        runs = [r for g in fam.groups for r in g.runs if r.history is not None]
        use_evals = bool(runs) and all("evaluations" in r.history for r in runs)
        for g in fam.groups:
            c = _group_curve(g.runs, use_evals)
            if c is None:
                continue
            x, mean, lo, hi, k = c
            (line,) = ax.step(x, mean, where="post", label=f"{g.label} (n={k})")
            if k > 1:
                ax.fill_between(x, lo, hi, step="post", alpha=0.2, color=line.get_color())
        ax.set_title(fam.label, fontsize=10)
        ax.set_xlabel("evaluations" if use_evals else "generation")
        ax.set_ylabel("best-so-far fitness\n(mean over seeds, min-max band)")
        ax.grid(alpha=0.3)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=7)
    fig.tight_layout()
    return fig


def _renders_figure(rows: Sequence[tuple[str, list[tuple[str, np.ndarray]]]], per_row: int = 5):
    """A grid of pictures: for each (row title, [(title, image)]), one or more rows."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    lines = []
    for head, cells in rows:
        for i in range(0, len(cells), per_row):
            lines.append((head if i == 0 else "", cells[i : i + per_row]))
    cols = max(len(c) for _, c in lines)
    fig, axes = plt.subplots(
        len(lines), cols, figsize=(2.6 * cols, 3.0 * len(lines)), dpi=100, squeeze=False
    )
    for (head, cells), axrow in zip(lines, axes):
        for ax in axrow:
            ax.axis("off")
        for ax, (title, img) in zip(axrow, cells):
            ax.imshow(img)
            ax.set_title("\n".join(textwrap.fill(t, 30) for t in title.splitlines()), fontsize=7)
        if head and len(rows) > 1:
            axrow[0].text(
                -0.05, 0.5, textwrap.fill(head, 25), transform=axrow[0].transAxes,
                rotation=90, ha="right", va="center", fontsize=8,
            )  # fmt: skip
    fig.tight_layout()
    return fig


def _save(fig, path: Path | None = None) -> bytes:
    """PNG bytes of a figure (and the file ``path``, written atomically); closes it."""
    import matplotlib.pyplot as plt

    from growsim.files import atomic_write

    buf = io.BytesIO()
    fig.savefig(buf, format="png")
    plt.close(fig)
    data = buf.getvalue()
    if path is not None:
        atomic_write(path, data)
    return data


# --- HTML -------------------------------------------------------------------------------


def format_mean_ci(mean: float, ci: float) -> str:
    """``mean +/- ci`` rounded to the CI's second significant digit.

    Examples
    --------
    >>> format_mean_ci(1293.87, 19.2), format_mean_ci(0.95312, 0.0123)
    ('1294 ± 19', '0.953 ± 0.012')
    >>> format_mean_ci(3.0, float("nan")), format_mean_ci(2.0, 0.0)
    ('3', '2 ± 0')
    """
    if not math.isfinite(mean):
        return "-"
    if not math.isfinite(ci):
        return f"{mean:.4g}"
    if ci == 0:
        return f"{mean:.4g} ± 0"
    d = max(0, 1 - math.floor(math.log10(ci)))
    return f"{mean:.{d}f} ± {ci:.{d}f}"


def _p(p: float) -> str:
    """A p-value: three decimals, or two significant digits below 0.001.

    Examples
    --------
    >>> _p(0.0412), _p(3.2e-05), _p(1.0), _p(float("nan"))
    ('0.041', '3.2e-05', '1.000', '-')
    """
    if not math.isfinite(p):
        return "-"
    return f"{p:.3f}" if p >= 0.001 else f"{p:.2g}"


def _g(v: float) -> str:
    return f"{v:.4g}" if isinstance(v, (int, float)) and math.isfinite(v) else "-"


def _e(s: Any) -> str:
    return html.escape(str(s))


def _table(head: Sequence[str], body: Sequence[Sequence[str]], caption: str = "") -> str:
    """An HTML table; cells are already escaped HTML."""
    cap = f"<caption>{caption}</caption>" if caption else ""
    th = "".join(f"<th>{h}</th>" for h in head)
    tr = "".join("<tr>" + "".join(f"<td>{c}</td>" for c in row) + "</tr>" for row in body)
    return f"<table class='t'>{cap}<thead><tr>{th}</tr></thead><tbody>{tr}</tbody></table>"


def _img(data: bytes, alt: str) -> str:
    b64 = base64.b64encode(data).decode("ascii")
    return f"<img alt='{_e(alt)}' src='data:image/png;base64,{b64}'>"


_METHODS = (
    "Runs were grouped by their resolved configuration up to the random seed (the "
    "experiment's name, description, repeat count and output settings ignored); runs of a "
    "group with the same seed were counted once. Groups were sorted into families of "
    "runs with the same model and the same objectives (every option defining the score), "
    "whose fitness values are comparable; no test was made across families. For each "
    "group, n is the number of runs with distinct seeds; values are mean &plusmn; "
    "half-width of the 95&nbsp;% confidence interval of the mean (Student t, n&minus;1 "
    "degrees of freedom) of the runs' best fitness and of the measures of each run's best "
    "phenotype. Between every two groups of a family with n &ge; 2 each, the best fitness "
    "and every other quantity varying across the family's runs were compared with Welch's "
    "two-sided t-test and the two-sided Mann-Whitney U test. Effect sizes: the "
    "difference of means with its Welch "
    "95&nbsp;% confidence interval, Cohen's d (pooled standard deviation) and Cliff's "
    "&delta; (P(a &gt; b) &minus; P(a &lt; b) over all pairs of runs). p-values were "
    "adjusted for multiple testing with the Holm-Bonferroni method over all the "
    "family's hypotheses (quantities &times; pairs of groups), separately for each test; "
    "<b>bold</b>: adjusted p &lt; 0.05."
)


def _significant(r: dict[str, Any]) -> bool:
    return any(
        math.isfinite(r[c]) and r[c] < 0.05 for c in ("welch_t_p_holm", "mann_whitney_p_holm")
    )


def _tests_table(rows: Sequence[dict[str, Any]], caption: str) -> str:
    """The tests as an HTML table: effect sizes, raw and adjusted p (bold below 0.05)."""

    def adjusted(p: float) -> str:
        return f"<b>{_p(p)}</b>" if math.isfinite(p) and p < 0.05 else _p(p)

    body = []
    for r in rows:
        ci = (
            f" [{_g(r['diff_ci_low'])}, {_g(r['diff_ci_high'])}]"
            if math.isfinite(r["diff_ci_low"])
            else ""
        )
        body.append(
            [
                _e(r["measure"].replace("best_fitness", "best fitness")),
                _e(r["group_a"]),
                _e(r["group_b"]),
                f"{r['n_a']}, {r['n_b']}",
                _g(r["difference"]) + ci,
                _g(r["cohen_d"]),
                _g(r["cliffs_delta"]),
                _p(r["welch_t_p"]),
                adjusted(r["welch_t_p_holm"]),
                _p(r["mann_whitney_p"]),
                adjusted(r["mann_whitney_p_holm"]),
                _e(r["note"]),
            ]
        )
    head = [
        "quantity",
        "group a",
        "group b",
        "n",
        "a &minus; b [95&nbsp;% CI]",
        "Cohen's d",
        "Cliff's &delta;",
        "Welch p",
        "Welch p (Holm)",
        "Mann-Whitney p",
        "M-W p (Holm)",
        "note",
    ]
    return _table(head, body, caption)


def _family_html(
    k: int,
    fam: Family,
    fs: _FamilyStats,
    rows: list[dict[str, Any]],
    images: dict[str, bytes],
) -> list[str]:
    n_runs = sum(len(g.runs) for g in fam.groups)
    objs = "; ".join(
        ", ".join(f"{a}={_fmt_value(v)}" for a, v in o.items()) for o in fam.objectives
    )
    parts = [
        f"<h2>{k}. {_e(fam.label)}</h2>",
        f"<p>Model <code>{_e(fam.model)}</code>; objective(s): <code>{_e(objs)}</code>. "
        f"{len(fam.groups)} group(s), {n_runs} run(s) counted.</p>",
    ]
    groups = fam.groups
    if fam.differences:
        preset = _from_preset([g.config for g in groups], fam.differences)
        body = [
            [f"<code>{_e('.'.join(p))}</code>" + (" (from the preset)" if p in preset else "")]
            + [_e(_fmt_value(g.config.get(p, _MISSING))) for g in groups]
            for p in fam.differences
        ]
        parts.append(
            _table(
                ["key"] + [_e(g.label) for g in groups],
                body,
                f"Table {k}.1. What differs between the groups' configurations.",
            )
        )
    head = ["", *(_e(g.label) for g in groups)]
    body = [
        ["n (distinct seeds)"] + [str(len(g.runs)) for g in groups],
        ["duplicated seeds dropped"] + [str(len(g.duplicates)) for g in groups],
        ["best fitness (best run)"] + [_g(max(r.best_fitness for r in g.runs)) for g in groups],
    ]
    label = {"best_fitness": "best fitness"}
    for q in fs.quantities:
        cells = []
        for g in groups:
            v = fs.values[(g.label, q)]
            v = v[np.isfinite(v)]
            cells.append(format_mean_ci(float(v.mean()), _ci95(v)) if len(v) else "-")
        name = _e(label.get(q, q))
        if q == "best_fitness":
            name = f"<b>{name}</b>"
        if q in fs.skipped and n_runs > 1:
            name += " <sup>&dagger;</sup>"
        body.append([name, *cells])
    for key, lab in (("generations", "generations"), ("evaluations", "evaluations")):
        body.append(
            [lab]
            + [_g(float(np.mean([r.summary.get(key, math.nan) for r in g.runs]))) for g in groups]
        )
    body.append(
        ["wall time (s)"]
        + [_g(float(np.mean([r.summary.get("wall_seconds", math.nan) for r in g.runs])))
           for g in groups]
    )  # fmt: skip
    parts.append(
        _table(
            head,
            body,
            f"Table {k}.2. Groups: n runs with distinct seeds; mean &plusmn; 95&nbsp;% CI "
            "half-width over the runs (one value: n = 1)."
            + (" &dagger;: the same in every run of the family, not tested." * (n_runs > 1)),
        )
    )
    dropped = {q: why for q, why in fs.skipped.items() if q not in fs.quantities}
    if dropped:
        parts.append(
            "<p class='n'>Not shown (repeat another quantity): "
            + "; ".join(f"{_e(q)} ({_e(w)})" for q, w in dropped.items())
            + ".</p>"
        )
    if rows:
        best = [r for r in rows if r["measure"] == "best_fitness"]
        other = [r for r in rows if r["measure"] != "best_fitness"]
        na, nb = min(((r["n_a"], r["n_b"]) for r in rows), key=lambda n: math.comb(sum(n), n[0]))
        floor = 2.0 / math.comb(na + nb, na)
        small = (
            f" With n = {na} and {nb} runs, the smallest two-sided Mann-Whitney p (exact) "
            f"is {floor:.2g}: that test cannot detect anything here, more seeds are needed."
            if floor >= 0.05
            else ""
        )
        parts.append(
            f"<p>{len(rows)} hypotheses tested in this family (quantities &times; pairs of "
            "groups); every adjusted p-value is Holm-Bonferroni over all of them, separately "
            f"for each test.{small}</p>"
        )
        if best:
            parts.append(_tests_table(best, f"Table {k}.3. Best fitness: tests between groups."))
        if other:
            n_sig = sum(_significant(r) for r in other)
            table = _tests_table(
                other,
                f"Table {k}.4. Measures of the best phenotypes and objective terms: tests "
                "between groups.",
            )
            parts.append(
                f"<details{' open' if len(other) <= 40 else ''}><summary>{len(other)} tests "
                f"of the measures and terms, {n_sig} with an adjusted p &lt; 0.05</summary>"
                f"{table}</details>"
            )
    elif len(groups) == 1:
        parts.append(
            "<p class='n'>One group: no other group has the same model and objectives, so "
            "there is nothing to test it against.</p>"
        )
    else:
        parts.append(
            "<p class='n'>No tests: a test needs two groups with at least two runs with "
            "distinct seeds each.</p>"
        )
    if fs.untested_groups and len(groups) > 1 and rows:
        parts.append(
            "<p class='n'>Not tested (fewer than 2 runs with distinct seeds): "
            + ", ".join(_e(g) for g in fs.untested_groups)
            + ".</p>"
        )
    parts.append(f"<h3>Figure {k}.1. Best-so-far fitness</h3>")
    parts.append(_img(images["curves"], f"curves {fam.label}"))
    if "renders" in images:
        parts.append(f"<h3>Figure {k}.2. Best phenotype of each group (front view)</h3>")
        parts.append(_img(images["renders"], f"renders {fam.label}"))
    return parts


def _html(families, fam_stats, fam_rows, fam_images, runs_df, notes, title) -> str:
    parts = [
        "<!DOCTYPE html><html><head><meta charset='utf-8'>",
        f"<title>{_e(title)}</title>",
        "<style>body{font-family:sans-serif;margin:2em;max-width:1250px;line-height:1.4}"
        "table.t{border-collapse:collapse;font-size:13px;margin:1em 0}"
        "table.t caption{caption-side:top;text-align:left;font-size:13px;padding:4px 0}"
        "table.t td,table.t th{border-bottom:1px solid #ddd;padding:3px 8px;text-align:right}"
        "table.t td:first-child,table.t th:first-child{text-align:left}"
        "p.n{font-size:13px;color:#444}img{max-width:100%;border:1px solid #eee}</style>"
        "</head><body>",
        f"<h1>{_e(title)}</h1>",
        f"<p>Generated {_e(time.strftime('%Y-%m-%d %H:%M:%S'))} by growsim compare: "
        f"{len(runs_df)} run(s) in {sum(len(f.groups) for f in families)} group(s), "
        f"{len(families)} famil{'y' if len(families) == 1 else 'ies'}.</p>",
        f"<h2>Methods</h2><p>{_METHODS}</p>",
    ]
    if notes:
        parts.append("<h2>Notes</h2><ul>" + "".join(f"<li>{_e(n)}</li>" for n in notes) + "</ul>")
    for k, fam in enumerate(families, 1):
        parts += _family_html(k, fam, fam_stats[k - 1], fam_rows[k - 1], fam_images[k - 1])
    cols = [
        c
        for c in (
            "family", "group", "seed", "counted", "duplicate_of", "best_fitness",
            "generations", "evaluations", "seconds", "stop_reason", "path",
        )
        if c in runs_df
    ]  # fmt: skip
    body = [[_e(_g(v) if isinstance(v, float) else v) for v in row] for row in runs_df[cols].values]
    parts += ["<h2>Runs</h2>", _table([_e(c) for c in cols], body), "</body></html>"]
    return "\n".join(parts)


# --- where, and the whole ---------------------------------------------------------------


def default_out(dirs: Sequence[str | Path], runs: Sequence[RunRecord]) -> Path:
    """Where a comparison goes by default: ``<dir>/compare-<time>`` beside the runs when
    they are all under one directory (the runs' common parent, when it is a directory
    given, inside one, the parent of one, or a run's own parent), else
    ``runs/compare-<time>``.

    Examples
    --------
    >>> from growsim.results import RunRecord
    >>> rs = [RunRecord(Path(f"/x/sw/v{i}/seed-0"), {}, {}) for i in (1, 2)]
    >>> default_out(["/x/sw"], rs).parent
    PosixPath('/x/sw')
    >>> default_out(["/a/r1", "/b/r2"], [RunRecord(Path("/a/r1"), {}, {}),
    ...     RunRecord(Path("/b/r2"), {}, {})]).parent
    PosixPath('runs')
    """
    name = time.strftime("compare-%Y%m%d-%H%M%S")
    parents = [Path(os.path.abspath(r.path)).parent for r in runs]
    given = [Path(os.path.abspath(d)) for d in dirs]
    if parents:
        common = Path(os.path.commonpath([str(p) for p in parents]))
        ok = (
            common in parents
            or any(common == d or d in common.parents for d in given)
            or any(common == d.parent for d in given)
        )
        if ok and common != Path(common.anchor):
            try:
                return common.relative_to(Path.cwd()) / name
            except ValueError:
                return common / name
    return Path("runs") / name


@dataclasses.dataclass
class Comparison:
    """What :func:`compare` returns: ``table`` (one row per group), ``stats`` (one row per
    test: quantity x pair of groups of a family), ``runs`` (one row per run), the paths of
    the files written and ``notes`` (duplicated seeds, tests not made)."""

    table: Any
    stats: Any
    runs: Any
    files: dict[str, Path]
    notes: list[str] = dataclasses.field(default_factory=list)


def compare(
    dirs: Sequence[str | Path],
    out: str | Path | None = None,
    *,
    renders: bool = True,
    html_report: bool = True,
) -> Comparison:
    """Compare runs: write ``compare.csv``, ``stats.csv``, ``runs.csv``, ``curves.png``,
    ``renders.png`` and ``report.html`` to ``out`` (default: :func:`default_out`).

    Examples
    --------
    >>> c = compare(["runs/sweep-light"], out="runs/cmp")  # doctest: +SKIP
    >>> list(c.table.columns)[:5]  # doctest: +SKIP
    ['family', 'group', 'dirs', 'runs', 'duplicates']
    """
    import pandas as pd

    from growsim.files import atomic_write

    runs = find_runs(dirs)
    notes: list[str] = []
    families = _families(runs, notes)
    out = Path(out) if out is not None else default_out(dirs, runs)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise UserInputError(f"--out {out}: cannot create ({exc.strerror})") from None

    rows, run_rows, fam_stats, fam_rows, stat_rows = [], [], [], [], []
    for fam in families:
        fs, frows = _family_stats(fam, notes)
        fam_stats.append(fs)
        fam_rows.append(frows)
        stat_rows += frows
        for g in fam.groups:
            fit = np.array([r.best_fitness for r in g.runs])
            best_run = g.runs[int(np.argmax(fit))]
            labels = sorted(dict.fromkeys(run_label(r) for r in g.members))
            more = f", ... (+{len(labels) - 3})" if len(labels) > 3 else ""
            row = {
                "family": fam.label,
                "group": g.label,
                "dirs": ", ".join(labels[:3]) + more,
                "runs": len(g.runs),
                "duplicates": len(g.duplicates),
                "best": float(fit.max()),
                "mean": float(fit.mean()),
                "ci95": _ci95(fit),
                "std": float(fit.std(ddof=1)) if len(fit) > 1 else float("nan"),
                "generations": float(np.mean([r.summary["generations"] for r in g.runs])),
                "evaluations": float(np.mean([r.summary["evaluations"] for r in g.runs])),
                "seconds": float(np.mean([r.summary["wall_seconds"] for r in g.runs])),
            }
            for q in fs.quantities:
                if q == "best_fitness":
                    continue
                v = fs.values[(g.label, q)]
                v = v[np.isfinite(v)]
                row[q] = float(v.mean()) if len(v) else float("nan")
                row[f"{q}_ci95"] = _ci95(v)
            row["best_run"] = str(best_run.path)
            rows.append(row)
            dup_of = {id(d): k for d, k in g.duplicates}
            for r in g.members:
                q = _quantities(r)
                run_rows.append(
                    {
                        "family": fam.label,
                        "group": g.label,
                        "seed": r.summary.get("seed"),
                        "counted": id(r) not in dup_of,
                        "duplicate_of": str(dup_of[id(r)].path) if id(r) in dup_of else "",
                        "best_fitness": r.best_fitness,
                        "generations": r.summary["generations"],
                        "evaluations": r.summary["evaluations"],
                        "seconds": r.summary["wall_seconds"],
                        "stop_reason": r.summary.get("stop_reason", ""),
                        "path": str(r.path),
                    }
                    | {k: v for k, v in q.items() if k != "best_fitness"}
                )
    table = pd.DataFrame(rows)
    table = table[[c for c in table.columns if c != "best_run"] + ["best_run"]]
    stats_df = pd.DataFrame(stat_rows, columns=STATS_COLUMNS)
    runs_df = pd.DataFrame(run_rows)
    files = {
        "table": atomic_write(out / "compare.csv", table.to_csv(index=False)),
        "stats": atomic_write(out / "stats.csv", stats_df.to_csv(index=False)),
        "runs": atomic_write(out / "runs.csv", runs_df.to_csv(index=False)),
    }
    _save(_curves_figure(families), out / "curves.png")
    files["curves"] = out / "curves.png"
    fam_images: list[dict[str, bytes]] = [
        {"curves": _save(_curves_figure([f]))} if html_report else {} for f in families
    ]
    if renders:
        cells = _render_cells(families)
        if any(cells):
            try:
                rows_ = [(f.label, c) for f, c in zip(families, cells) if c]
                _save(_renders_figure(rows_), out / "renders.png")
                files["renders"] = out / "renders.png"
                if html_report:
                    for imgs, c in zip(fam_images, cells):
                        if c:
                            imgs["renders"] = _save(_renders_figure([("", c)]))
            except Exception as exc:  # a picture must not lose the tables
                log.warning("renders.png failed: %s", exc)
    if html_report:
        title = "growsim compare: " + "; ".join(f.label for f in families)
        text = _html(families, fam_stats, fam_rows, fam_images, runs_df, notes, title)
        files["html"] = atomic_write(out / "report.html", text)
    return Comparison(table=table, stats=stats_df, runs=runs_df, files=files, notes=notes)


def _render_cells(families: Sequence[Family]) -> list[list[tuple[str, np.ndarray]]]:
    """Per family, (title, picture) of each group's best phenotype."""
    cells = []
    for fam in families:
        row = []
        for g in fam.groups:
            best = max(g.runs, key=lambda r: r.best_fitness)
            try:
                img = best.phenotype().render_image(view="front", size=(300, 300))
            except Exception as exc:  # a missing phenotype must not lose the table
                log.warning("%s: no best phenotype to render (%s)", best.path, exc)
                continue
            row.append((f"{g.label}\nbest {best.best_fitness:.4g}", np.asarray(img)))
        cells.append(row)
    return cells
