"""Statistics over repeats: confidence intervals, tests between groups, Holm correction.

Per group, the mean and the half-width of its 95 % Student-t confidence interval
(:func:`ci95`) of every quantity of the runs (:func:`quantities`: best fitness, measures
of the best phenotype, objective scores and terms). Between every two groups of a family
with at least two distinct-seed runs each (:func:`family_stats`): Welch's t-test and the
Mann-Whitney U test (two-sided), with effect sizes (difference of means and its Welch
95 % CI, Cohen's d, Cliff's delta) and p-values adjusted with Holm-Bonferroni
(:func:`holm`) over all the family's hypotheses, one row per test
(:data:`STATS_COLUMNS`).
"""

from __future__ import annotations

import dataclasses
import itertools
import logging
import math
import warnings
from collections.abc import Sequence
from typing import Any

import numpy as np

from growsim.experiment.results import RunRecord
from growsim.files import number
from growsim.report.groups import Family

__all__ = [
    "STATS_COLUMNS",
    "FamilyStats",
    "ci95",
    "family_stats",
    "holm",
    "is_flat",
    "pair_test",
    "quantities",
]

log = logging.getLogger(__name__)

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


def is_flat(v: np.ndarray) -> bool:
    """True when the values are equal up to rounding (no variance to speak of).

    Examples
    --------
    >>> is_flat(np.array([1.0, 1.0 + 1e-15])), is_flat(np.array([1.0, 1.1]))
    (True, False)
    """
    return bool(np.ptp(v) <= 1e-12 * np.max(np.abs(v))) if len(v) else True


def ci95(x: np.ndarray) -> float:
    """Half-width of the 95 % Student-t confidence interval of the mean (NaN for n < 2);
    NaN values are left out.

    Examples
    --------
    >>> round(ci95(np.array([10.0, 12.0, 11.0])), 4), ci95(np.array([1.0, 1.0]))
    (2.4841, 0.0)
    >>> ci95(np.array([3.0, np.nan]))
    nan
    """
    from scipy import stats

    x = np.asarray(x, dtype=np.float64)
    x = x[np.isfinite(x)]
    n = len(x)
    if n < 2:
        return float("nan")
    if is_flat(x):
        return 0.0
    return float(stats.t.ppf(0.975, n - 1) * np.std(x, ddof=1) / math.sqrt(n))


def pair_test(x: np.ndarray, y: np.ndarray) -> dict[str, Any]:
    """Welch's t and Mann-Whitney U (two-sided) of x against y, with effect sizes:
    difference of means (and its Welch 95 % CI), Cohen's d (pooled SD), Cliff's delta.
    Zero variance is handled here, so scipy never warns.

    Examples
    --------
    >>> r = pair_test(np.array([1.0, 2.0, 3.0]), np.array([4.0, 5.0, 6.0]))
    >>> r["difference"], r["cliffs_delta"]
    (-3.0, -1.0)
    """
    from scipy import stats

    nx, ny = len(x), len(y)
    mx, my = float(np.mean(x)), float(np.mean(y))
    vx = 0.0 if is_flat(x) else float(np.var(x, ddof=1))
    vy = 0.0 if is_flat(y) else float(np.var(y, ddof=1))
    diff = mx - my
    same = is_flat(np.concatenate([x, y]))
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


def quantities(run: RunRecord) -> dict[str, float]:
    """Best fitness, the numeric measures and every objective's score and terms.

    Examples
    --------
    >>> from pathlib import Path
    >>> summary = {"measures": {"height": 12, "shape": "tall"},
    ...            "terms": {"light": {"score": 3.5, "leaf_area": 2.0}}}
    >>> quantities(RunRecord(Path("r"), {}, {"fitness": 3.5}, summary))
    {'best_fitness': 3.5, 'height': 12.0, 'light.score': 3.5, 'light.leaf_area': 2.0}

    A measure undefined for the run's plant (``"nan"`` in its JSON, e.g. an unbranched
    plant's branch angle) stays a measure, as NaN; the tests leave it out:

    >>> unbranched = {"measures": {"branch_angle": "nan"}}
    >>> quantities(RunRecord(Path("r"), {}, {"fitness": 1.0}, unbranched))
    {'best_fitness': 1.0, 'branch_angle': nan}
    """

    def num(v):
        return isinstance(v, (int, float)) and not isinstance(v, bool)

    out = {"best_fitness": run.best_fitness}
    s = run.summary or {}
    for k, v in (s.get("measures") or {}).items():
        v = number(v)
        if num(v):
            out[str(k)] = float(v)
    for obj, terms in (s.get("terms") or {}).items():
        for k, v in (terms or {}).items() if isinstance(terms, dict) else ():
            if num(v):
                out[f"{obj}.{k}"] = float(v)
    return out


@dataclasses.dataclass
class FamilyStats:
    """The quantities of one family's runs, and which of them are tested."""

    quantities: list[str]  # shown in the tables (duplicates of another left out)
    tested: list[str]
    skipped: dict[str, str]  # quantity -> why not tested
    untested_groups: list[str]
    values: dict[tuple[str, str], np.ndarray]  # (group, quantity) -> values of its runs


def family_stats(fam: Family, notes: list[str]) -> tuple[FamilyStats, list[dict[str, Any]]]:
    """The quantities of a family's runs and the tests between its groups: one row (a dict
    with the keys of :data:`STATS_COLUMNS`) per quantity and pair of groups with two runs
    or more each, p-values Holm-adjusted over all the rows. ``notes`` gets a line for each
    group left untested.

    Examples
    --------
    >>> from pathlib import Path
    >>> from growsim.report.groups import Group
    >>> groups = [Group(g, [RunRecord(Path(f"{g}{f}"), {}, {"fitness": f}) for f in fits], [], {})
    ...           for g, fits in (("a", [1.0, 2.0, 3.0]), ("b", [5.0, 6.0, 7.0]), ("c", [9.0]))]
    >>> notes = []
    >>> fs, rows = family_stats(Family("honda / light", "honda", [], groups, []), notes)
    >>> fs.tested, fs.untested_groups, len(notes)
    (['best_fitness'], ['c'], 1)
    >>> [(r["group_a"], r["group_b"], round(r["welch_t_p"], 4)) for r in rows]
    [('a', 'b', 0.008)]
    """
    qs = {id(r): quantities(r) for g in fam.groups for r in g.runs}
    names = list(dict.fromkeys(k for q in qs.values() for k in q))
    allruns = [r for g in fam.groups for r in g.runs]
    col = {n: np.array([qs[id(r)].get(n, math.nan) for r in allruns]) for n in names}
    shown, tested, skipped = [], [], {}
    for n in names:
        v = col[n]
        if not np.isfinite(v).any():
            continue
        constant = is_flat(v[np.isfinite(v)]) and bool(np.isfinite(v).all())
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
                | pair_test(x, y)
            )
    for c in ("welch_t_p", "mann_whitney_p"):
        adj = holm([r[c] for r in rows])
        for r, a in zip(rows, adj):
            r[f"{c}_holm"] = float(a)
    return FamilyStats(shown, tested, skipped, untested, values), rows
