"""The common garden: every evolved genome grown in every environment of its family.

Plants evolved in different environments may differ because their genes differ
(adaptation) or only because the same genes grow differently in another environment
(plasticity). A common garden tells them apart: the best genome of every run is grown
again in the environment of every group of its family (the "gardens"), and each
quantity (fitness, the objectives' scores and terms, the phenotype's numeric measures)
is compared

- **between origins within one garden** (contrast ``genetic``): genomes evolved in
  different environments, grown side by side in the same one;
- **between gardens within one origin** (contrast ``plastic``): the same genomes grown
  in two environments;

each pair with Welch's t-test and the Mann-Whitney U test and the effect sizes of
:mod:`growsim.report.statistics`, Holm-adjusted over all the family's garden tests. A
two-way decomposition of each quantity's sum of squares over origin, garden, their
interaction and the residual (:func:`variance_shares`) says how much of the variation is
genetic and how much plastic.

A family takes part when its groups differ in the ``[environment]`` table (and possibly
in nothing else that changes the model's growth); its gardens are the groups'
environments.
"""

from __future__ import annotations

import itertools
import logging
from typing import Any

import numpy as np
import pandas as pd

from growsim.experiment.load import load_plan
from growsim.phenotypes.plant import Plant
from growsim.report.groups import Family
from growsim.report.statistics import holm, is_flat, pair_test

__all__ = [
    "GARDEN_STATS_COLUMNS",
    "garden_stats",
    "grow_in_gardens",
    "stop_reasons",
    "variance_shares",
]

log = logging.getLogger(__name__)

#: the columns of the garden tests (:func:`garden_stats`)
GARDEN_STATS_COLUMNS = [
    "family", "contrast", "within", "measure", "group_a", "group_b", "n_a", "n_b", "mean_a",
    "mean_b", "difference", "diff_ci_low", "diff_ci_high", "cohen_d", "cliffs_delta",
    "welch_t", "welch_df", "welch_t_p", "welch_t_p_holm", "mann_whitney_u", "mann_whitney_p",
    "mann_whitney_p_holm", "note",
]  # fmt: skip


def _env_family(fam: Family) -> bool:
    return len(fam.groups) > 1 and any(p and p[0] == "environment" for p in fam.differences)


def grow_in_gardens(families: list[Family], notes: list[str]):
    """One row per counted run and garden: ``family``, ``origin`` (the run's group),
    ``seed``, ``garden`` (the group whose environment it is grown in), ``fitness`` (the
    weighted sum of the objectives, as the GA saw it), every objective's score and terms
    (``<kind>.score``, ``<kind>.<term>``), the phenotype's numeric measures in that
    environment and, for a plant whose model says why it stopped growing (the hormone
    model), ``stopped`` (``"end of steps"``, ``"cap"``, ``"broken"``, ...). Families
    whose groups do not differ in ``[environment]`` are left out (with a note). In a
    mixture garden (``environment.stand.mode = "mixture"``) every genome grows among
    neighbours drawn from the family's evolved genomes (all origins; one set of draws for
    every genome, :meth:`Fitness.prepare`): ``fitness`` is the mean over the draws, the
    terms and measures are the focal plant's among the first draw.

    Examples
    --------
    >>> grow_in_gardens([], []).empty
    True
    """

    rows: list[dict[str, Any]] = []
    for fam in families:
        if not _env_family(fam):
            if len(fam.groups) > 1:
                notes.append(f"{fam.label}: no common garden (its groups share one environment)")
            continue
        gardens = [(g.label, g.runs[0].config["environment"]) for g in fam.groups if g.runs]
        pool = [r.best["params"] for g in fam.groups for r in g.runs]  # a mixture's neighbours
        for g in fam.groups:
            for r in g.runs:
                for garden, env in gardens:
                    data = {**r.config, "environment": env}
                    fitness = load_plan(data).fitness()
                    if fitness.mixture:
                        x = np.array([[p[n] for n in fitness.evolved] for p in pool])
                        fitness.prepare(x, np.arange(len(pool), dtype=np.uint64))
                    phenotype = fitness.phenotype_of(r.best["params"]).phenotype
                    terms = fitness.terms(phenotype)
                    total = 0.0
                    for (_, t), w, s in zip(terms.items(), fitness.weights, fitness.signs):
                        total += float(w * s * t["score"])
                    if fitness.mixture:  # the mean over the draws
                        mine = np.array([[r.best["params"][n] for n in fitness.evolved]])
                        total = float(fitness(mine)[0])
                    row = {
                        "family": fam.label,
                        "origin": g.label,
                        "seed": r.summary.get("seed") if r.summary else None,
                        "garden": garden,
                        "fitness": total,
                    }
                    for kind, t in terms.items():
                        row.update({f"{kind}.{k}": float(v) for k, v in t.items()})
                    for k, v in phenotype.measures(fitness.env).items():
                        if isinstance(v, (int, float)) and not isinstance(v, bool):
                            row[str(k)] = float(v)
                    if isinstance(phenotype, Plant) and "stopped" in phenotype.meta:
                        row["stopped"] = str(phenotype.meta["stopped"]) or "end of steps"
                    row["path"] = str(r.path)
                    rows.append(row)
    return pd.DataFrame(rows)


def stop_reasons(table):
    """Why the plants of each garden cell stopped growing: one row per family, origin and
    garden with ``n`` and the count of each reason (``end of steps``, ``cap``,
    ``broken``, ``starved``, ``nan``); empty when no model of the table says.

    Examples
    --------
    >>> t = pd.DataFrame({"family": "f", "origin": ["a", "a", "b", "b"], "garden": "a",
    ...                   "stopped": ["end of steps", "cap", "cap", "cap"]})
    >>> stop_reasons(t).to_dict("records")[0]
    {'family': 'f', 'origin': 'a', 'garden': 'a', 'n': 2, 'cap': 1, 'end of steps': 1}
    """
    if not len(table) or "stopped" not in table.columns:
        return pd.DataFrame(columns=["family", "origin", "garden", "n"])
    keys = ["family", "origin", "garden"]
    counts = table.groupby(keys, sort=False)["stopped"].value_counts().unstack(fill_value=0)
    counts = counts[sorted(counts.columns)].astype(int)
    counts.columns.name = None
    out = counts.reset_index()
    out.insert(3, "n", counts.sum(axis=1).to_numpy())
    return out


def _quantities(table) -> list[str]:
    """The numeric columns that vary, each once (a column equal to an earlier one, e.g. an
    objective's score that is the fitness, is left out: it would only add tests)."""
    skip = {"family", "origin", "seed", "garden", "path"}
    out, seen = [], []
    for c in table.columns:
        if c in skip or table[c].dtype.kind not in "fi":
            continue
        v = table[c].to_numpy(np.float64)
        finite = v[np.isfinite(v)]
        if not len(finite) or is_flat(finite):
            continue
        if any(np.array_equal(v, w, equal_nan=True) for w in seen):
            continue
        seen.append(v)
        out.append(c)
    return out


def garden_stats(table):
    """The garden's tests (:data:`GARDEN_STATS_COLUMNS`): for each family and varying
    quantity, every pair of origins within each garden (``genetic``) and every pair of
    gardens within each origin (``plastic``), Holm-adjusted over all of a family's rows.

    Examples
    --------
    >>> import pandas as pd
    >>> t = pd.DataFrame({"family": "f", "origin": ["a"] * 4 + ["b"] * 4,
    ...                   "garden": ["a", "b"] * 4, "seed": [0, 0, 1, 1] * 2,
    ...                   "fitness": [1.0, 0.5, 1.1, 0.6, 2.0, 1.5, 2.2, 1.4]})
    >>> s = garden_stats(t)
    >>> s[["contrast", "within", "group_a", "group_b"]].values.tolist()[:2]
    [['genetic', 'a', 'a', 'b'], ['genetic', 'b', 'a', 'b']]
    """

    rows = []
    for fam, ft in table.groupby("family", sort=False) if len(table) else []:
        qs = _quantities(ft)
        origins = list(dict.fromkeys(ft["origin"]))
        gardens = list(dict.fromkeys(ft["garden"]))
        frows = []
        for q in qs:
            for contrast, within_all, pair_all, wcol, pcol in (
                ("genetic", gardens, origins, "garden", "origin"),
                ("plastic", origins, gardens, "origin", "garden"),
            ):
                for w in within_all:
                    sub = ft[ft[wcol] == w]
                    for a, b in itertools.combinations(pair_all, 2):
                        x = sub.loc[sub[pcol] == a, q].to_numpy(np.float64)
                        y = sub.loc[sub[pcol] == b, q].to_numpy(np.float64)
                        x, y = x[np.isfinite(x)], y[np.isfinite(y)]
                        if len(x) < 2 or len(y) < 2:
                            continue
                        frows.append(
                            {"family": fam, "contrast": contrast, "within": w, "measure": q,
                             "group_a": a, "group_b": b, **pair_test(x, y)}
                        )  # fmt: skip
        for col in ("welch_t_p", "mann_whitney_p"):
            adj = holm([r[col] for r in frows])
            for r, p in zip(frows, adj):
                r[f"{col}_holm"] = float(p)
        rows += frows
    return pd.DataFrame(rows, columns=GARDEN_STATS_COLUMNS)


def variance_shares(table):
    """For each family and varying quantity, the shares of its total sum of squares
    explained by ``origin`` (genetic), ``garden`` (plastic), their ``interaction`` and the
    ``residual`` (the runs within a cell): a two-way decomposition of cell means, exact
    for a balanced design (every run grown in every garden, the same number of runs per
    origin).

    Examples
    --------
    >>> import pandas as pd
    >>> t = pd.DataFrame({"family": "f", "origin": ["a"] * 4 + ["b"] * 4,
    ...                   "garden": ["a", "b"] * 4, "fitness": [1, 0, 1, 0, 3, 2, 3, 2.0]})
    >>> variance_shares(t)[["origin", "garden", "interaction", "residual"]].round(3).values.tolist()
    [[0.8, 0.2, 0.0, 0.0]]
    """

    rows = []
    for fam, ft in table.groupby("family", sort=False) if len(table) else []:
        for q in _quantities(ft):
            d = ft[["origin", "garden", q]].dropna()
            y = d[q].to_numpy(np.float64)
            grand = y.mean()
            total = float(((y - grand) ** 2).sum())
            if not total > 0:
                continue
            cell = d.groupby(["origin", "garden"])[q].transform("mean").to_numpy()
            om = d.groupby("origin")[q].transform("mean").to_numpy()
            gm = d.groupby("garden")[q].transform("mean").to_numpy()
            ss_o = float(((om - grand) ** 2).sum())
            ss_g = float(((gm - grand) ** 2).sum())
            ss_cell = float(((cell - grand) ** 2).sum())
            ss_res = float(((y - cell) ** 2).sum())
            ss_int = max(0.0, ss_cell - ss_o - ss_g)
            rows.append({"family": fam, "measure": q, "origin": ss_o / total,
                         "garden": ss_g / total, "interaction": ss_int / total,
                         "residual": ss_res / total, "n": len(y)})  # fmt: skip
    cols = ["family", "measure", "origin", "garden", "interaction", "residual", "n"]
    return pd.DataFrame(rows, columns=cols)
