"""Primary tests declared in ``[compare]``, exploratory tests, power and replication.

An experiment config declares its primary tests before the runs (``[compare] primary``,
:class:`growsim.experiment.schema.CompareConfig`): a measure and the direction expected
between two groups (sweep variants), each in its own environment or, with ``garden``,
both origins grown in one common garden. :func:`primary_rows` makes exactly those tests,
Holm-adjusted over themselves alone, each with its effect size (Hedges' g) and the seeds
per group a replication needs for the declared power (:func:`seeds_for_power`);
:func:`exploratory_rows` is every other test, Holm-adjusted separately within each
family and labelled exploratory. :func:`replication_rows` sets the primary tests of a
discovery block of seeds beside the same tests on a fresh confirmation block.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
from pydantic import ValidationError

from growsim.errors import ConfigError, UserInputError
from growsim.experiment.load import read_config
from growsim.experiment.results import RunRecord
from growsim.experiment.schema import CompareConfig
from growsim.options import validation_message
from growsim.report.groups import Family
from growsim.report.statistics import STATS_COLUMNS, FamilyStats, holm, pair_test

__all__ = [
    "EXPLORATORY_COLUMNS",
    "PRIMARY_COLUMNS",
    "REPLICATION_COLUMNS",
    "check_fresh_seeds",
    "exploratory_rows",
    "hedges_g",
    "primary_rows",
    "read_spec",
    "replication_rows",
    "seeds_for_power",
]

#: columns of ``primary.csv``: one row per primary test (per family holding both groups)
PRIMARY_COLUMNS = [
    "family",
    "measure",
    "expect",
    "garden",
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
    "hedges_g",
    "cliffs_delta",
    "welch_t_p",
    "mann_whitney_p",
    "test",
    "p",
    "p_holm",
    "alpha",
    "as_expected",
    "finding",
    "power",
    "seeds_for_power",
    "note",
]

#: columns of ``exploratory.csv``: ``role`` then those of ``stats.csv``
EXPLORATORY_COLUMNS = ["role", *STATS_COLUMNS]

#: columns of ``replication.csv``: one row per primary test, discovery beside confirmation
REPLICATION_COLUMNS = [
    "family",
    "measure",
    "expect",
    "garden",
    "group_a",
    "group_b",
    "discovery_n",
    "discovery_difference",
    "discovery_hedges_g",
    "discovery_p_holm",
    "discovery_finding",
    "confirmation_n",
    "confirmation_difference",
    "confirmation_hedges_g",
    "confirmation_p",
    "confirmation_p_holm",
    "same_direction",
    "replicated",
    "verdict",
]


def read_spec(runs: Sequence[RunRecord], source: Any = None) -> CompareConfig | None:
    """The ``[compare]`` section that applies: the one ``source`` (an experiment TOML, a
    config mapping or a :class:`CompareConfig`) gives, else the one the runs' configs
    share (``None`` when none declares one); runs declaring different ones are refused.

    Examples
    --------
    >>> from pathlib import Path
    >>> cmp = {"primary": [{"measure": "height", "expect": "a > b"}]}
    >>> runs = [RunRecord(Path(f"r{i}"), {"compare": cmp}, {}) for i in range(2)]
    >>> read_spec(runs).primary[0].expect
    'a > b'
    >>> read_spec([RunRecord(Path("r"), {}, {})]) is None
    True
    """

    if isinstance(source, CompareConfig):
        return source
    if source is not None:
        cfg = read_config(source)
        if cfg.compare is None or not cfg.compare.primary:
            raise UserInputError(f"--primary {source}: the config declares no [compare] primary")
        return cfg.compare
    found: dict[str, tuple[Any, RunRecord]] = {}
    for r in runs:
        data = r.config.get("compare")
        if data is None:
            continue
        key = repr(sorted(data.items())) if isinstance(data, dict) else repr(data)
        found.setdefault(key, (data, r))
    if not found:
        return None
    if len(found) > 1:
        paths = [str(r.path) for _, r in found.values()]
        raise UserInputError(
            f"the runs declare different [compare] sections ({paths[0]} and {paths[1]}); "
            "choose one with --primary CONFIG"
        )
    data, r = next(iter(found.values()))
    try:
        spec = CompareConfig.model_validate(data)
    except Exception as exc:
        if not isinstance(exc, ValidationError):
            raise
        raise ConfigError(
            f"{r.path / 'config.toml'}: {validation_message(exc, 'compare.', CompareConfig)}"
        ) from None
    return spec if spec.primary else None


def hedges_g(d: float, n_a: int, n_b: int) -> float:
    """Hedges' g: Cohen's d (pooled SD) times the small-sample correction
    ``1 - 3 / (4 (n_a + n_b) - 9)``.

    Examples
    --------
    >>> round(hedges_g(1.0, 8, 8), 4)
    0.9455
    """
    if not math.isfinite(d) or n_a + n_b < 4:
        return math.nan
    return d * (1.0 - 3.0 / (4.0 * (n_a + n_b) - 9.0))


def _power(n: int, g: float, alpha: float) -> float:
    """Power of the two-sided two-sample t-test (equal n, pooled SD) at effect g."""
    from scipy import stats

    df = 2 * n - 2
    nc = abs(g) * math.sqrt(n / 2.0)
    tc = float(stats.t.ppf(1.0 - alpha / 2.0, df))
    return float(stats.nct.sf(tc, df, nc) + stats.nct.cdf(-tc, df, nc))


def seeds_for_power(
    g: float, alpha: float = 0.05, power: float = 0.8, max_n: int = 1_000_000
) -> float:
    """The seeds per group a two-group replication needs to detect effect ``g`` (a
    standardized difference of means) with the given power: the smallest n whose
    two-sided two-sample t-test at ``alpha`` (equal n, noncentral t) has that power.
    ``inf`` when g is 0 or needs more than ``max_n``; NaN when g is unknown.

    Examples
    --------
    >>> seeds_for_power(0.5), seeds_for_power(1.0), seeds_for_power(2.0)  # G*Power: 64, 17, 6
    (64, 17, 6)
    >>> seeds_for_power(0.0), seeds_for_power(float("nan"))
    (inf, nan)
    """
    if not math.isfinite(g):
        return math.nan
    if g == 0.0:
        return math.inf
    lo, hi = 2, 2
    while _power(hi, g, alpha) < power:
        lo, hi = hi, hi * 2
        if hi > max_n:
            return math.inf
    while lo < hi:  # the smallest n with enough power (power grows with n)
        mid = (lo + hi) // 2
        if _power(mid, g, alpha) >= power:
            hi = mid
        else:
            lo = mid + 1
    return lo


def _direction(diff: float) -> str:
    if not math.isfinite(diff) or diff == 0.0:
        return "="
    return ">" if diff > 0 else "<"


def _between(families, fam_stats, i, item):
    """(family label, values of a, values of b) for each family holding both groups of a
    primary test between environments: each group's runs in their own environment."""
    a, _, b = item.groups()
    held = [(f, fs) for f, fs in zip(families, fam_stats) if {a, b} <= {g.label for g in f.groups}]
    if not held:
        labels = sorted({g.label for f in families for g in f.groups})
        missing = [x for x in (a, b) if x not in labels]
        what = f"no group {missing[0]!r}" if missing else f"{a!r} and {b!r} in no one family"
        raise ConfigError(f"compare.primary[{i}].expect: {what}; the groups: {', '.join(labels)}")
    known = sorted({q for _, fs in held for (_, q) in fs.values})
    if item.measure not in known:
        raise ConfigError(
            f"compare.primary[{i}].measure: unknown measure {item.measure!r}; "
            f"measured: {', '.join(known)}"
        )
    return [(f.label, fs.values[(a, item.measure)], fs.values[(b, item.measure)]) for f, fs in held]


def _in_garden(table, i, item):
    """(family label, values of a, values of b) for each family of the common garden
    ``table`` (:func:`growsim.report.garden.grow_in_gardens`) holding both origins and
    the garden: the two origins' genomes grown in the declared garden."""
    a, _, b = item.groups()
    where = f"compare.primary[{i}]"
    if table is None or table.empty:
        raise ConfigError(
            f"{where}.garden: no common garden was grown (its groups share one environment)"
        )
    measure = "fitness" if item.measure == "best_fitness" else item.measure
    out = []
    for fam, ft in table.groupby("family", sort=False):
        if {a, b} <= set(ft["origin"]) and item.garden in set(ft["garden"]):
            cell = ft[ft["garden"] == item.garden]
            if measure not in ft.columns:
                known = [
                    c for c in ft.columns if c not in ("family", "origin", "seed", "garden", "path")
                ]
                raise ConfigError(
                    f"{where}.measure: unknown measure {item.measure!r} in the garden; "
                    f"measured: {', '.join(known)}"
                )
            x, y = (cell.loc[cell["origin"] == o, measure].to_numpy(np.float64) for o in (a, b))
            out.append((str(fam), x, y))
    if not out:
        origins = sorted(set(table["origin"]))
        gardens = sorted(set(table["garden"]))
        raise ConfigError(
            f"{where}: no family grows origins {a!r} and {b!r} in garden {item.garden!r}; "
            f"origins: {', '.join(origins)}; gardens: {', '.join(gardens)}"
        )
    return out


def primary_rows(
    families: Sequence[Family],
    fam_stats: Sequence[FamilyStats],
    spec: CompareConfig,
    garden: Any = None,
) -> list[dict[str, Any]]:
    """The primary tests: for each ``spec.primary`` entry and each family holding both its
    groups, Welch and Mann-Whitney of group a against group b (the rows of
    :func:`~growsim.report.statistics.pair_test`), Hedges' g, the seeds per group for
    ``spec.power`` (:func:`seeds_for_power`), the declared test's p Holm-adjusted over the
    primary tests alone (``p_holm``), whether the difference has the expected sign
    (``as_expected``) and whether it is a finding (``p_holm < alpha`` and as expected).
    An entry with a ``garden`` compares the two origins grown in that garden, read from
    ``garden`` (the table of :func:`growsim.report.garden.grow_in_gardens`). A group,
    garden or measure no family has raises ``ConfigError`` naming the key.

    Examples
    --------
    >>> from pathlib import Path
    >>> from growsim.report.groups import Group
    >>> from growsim.report.statistics import family_stats
    >>> groups = [Group(g, [RunRecord(Path(f"{g}{f}"), {}, {"fitness": f}) for f in fits],
    ...                 [], {}) for g, fits in (("a", [5.0, 6, 7, 8]), ("b", [1.0, 2, 3, 2]))]
    >>> fam = Family("m / o", "m", [], groups, [])
    >>> fs, _ = family_stats(fam, [])
    >>> spec = CompareConfig(primary=[{"measure": "best_fitness", "expect": "a > b"}])
    >>> r = primary_rows([fam], [fs], spec)[0]
    >>> r["difference"], r["finding"], r["seeds_for_power"]
    (4.5, True, 3)
    >>> import pandas as pd
    >>> g = pd.DataFrame({"family": "m / o", "origin": ["a"] * 4 + ["b"] * 4, "garden": "b",
    ...                   "fitness": [5.0, 6, 7, 8, 1, 2, 3, 2]})
    >>> spec = CompareConfig(primary=[{"measure": "fitness", "expect": "a > b", "garden": "b"}])
    >>> r = primary_rows([fam], [fs], spec, g)[0]
    >>> r["garden"], r["difference"], r["finding"]
    ('b', 4.5, True)
    """
    rows: list[dict[str, Any]] = []
    for i, item in enumerate(spec.primary):
        a, op, b = item.groups()
        if item.garden is None:
            held = _between(families, fam_stats, i, item)
        else:
            held = _in_garden(garden, i, item)
        for label, x, y in held:
            x, y = x[np.isfinite(x)], y[np.isfinite(y)]
            row: dict[str, Any] = {
                "family": label,
                "measure": item.measure,
                "expect": item.expect,
                "garden": item.garden or "",
                "group_a": a,
                "group_b": b,
                "test": spec.test,
                "alpha": spec.alpha,
                "power": spec.power,
            }
            if len(x) < 2 or len(y) < 2:
                row.update({c: math.nan for c in PRIMARY_COLUMNS if c not in row})
                row.update(n_a=len(x), n_b=len(y), as_expected=False, finding=False)
                row["note"] = "fewer than 2 runs in a group: not tested"
                rows.append(row)
                continue
            row |= pair_test(x, y)
            g = hedges_g(row["cohen_d"], len(x), len(y))
            seen = _direction(row["difference"])
            row.update(
                hedges_g=g,
                p=row["welch_t_p" if spec.test == "welch" else "mann_whitney_p"],
                as_expected=seen != "=" and (op == "!=" or seen == op),
                seeds_for_power=seeds_for_power(g, spec.alpha, spec.power),
            )
            rows.append(row)
    adjusted = holm([r["p"] for r in rows])
    for r, p in zip(rows, adjusted):
        r["p_holm"] = float(p)
        r["finding"] = bool(math.isfinite(p) and p < r["alpha"] and r["as_expected"])
    return [{c: r.get(c, math.nan) for c in PRIMARY_COLUMNS} for r in rows]


def exploratory_rows(
    stat_rows: Sequence[dict[str, Any]], primary: Sequence[dict[str, Any]]
) -> list[dict[str, Any]]:
    """Every test of the families that is not a primary one, its p-values Holm-adjusted
    over the exploratory tests of its family alone (``welch_t_p_holm``,
    ``mann_whitney_p_holm``), each row marked ``role = "exploratory"``.

    Examples
    --------
    >>> rows = [{"family": "f", "measure": m, "group_a": "a", "group_b": "b",
    ...          "welch_t_p": p, "mann_whitney_p": p} for m, p in (("h", 0.01), ("w", 0.02))]
    >>> prim = [{"family": "f", "measure": "h", "group_a": "b", "group_b": "a"}]
    >>> [(r["measure"], r["role"], r["welch_t_p_holm"]) for r in exploratory_rows(rows, prim)]
    [('w', 'exploratory', 0.02)]
    """
    taken = {
        (r["family"], r["measure"], frozenset((r["group_a"], r["group_b"])))
        for r in primary
        if not r.get("garden")
    }
    rest = [
        {"role": "exploratory", **r}
        for r in stat_rows
        if (r["family"], r["measure"], frozenset((r["group_a"], r["group_b"]))) not in taken
    ]
    for fam in dict.fromkeys(r["family"] for r in rest):
        mine = [r for r in rest if r["family"] == fam]
        for c in ("welch_t_p", "mann_whitney_p"):
            for r, p in zip(mine, holm([r[c] for r in mine])):
                r[f"{c}_holm"] = float(p)
    return rest


def check_fresh_seeds(discovery: Sequence[Family], confirmation: Sequence[Family]) -> None:
    """Refuse (``UserInputError``) a confirmation block sharing a seed with the discovery
    block in a group of the same name: the same seed and config is the same run again.

    Examples
    --------
    >>> from pathlib import Path
    >>> from growsim.report.groups import Group
    >>> def fam(seeds):
    ...     runs = [RunRecord(Path(f"a/seed-{s}"), {}, {}, {"seed": s}) for s in seeds]
    ...     return [Family("f", "m", [], [Group("a", runs, [], {})], [])]
    >>> check_fresh_seeds(fam([1, 2]), fam([3, 4]))
    >>> check_fresh_seeds(fam([1, 2]), fam([2, 3]))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    growsim.errors.UserInputError: --confirm: group a has seed(s) 2 in the discovery runs ...
    """
    seeds: dict[tuple[str, str], set[str]] = {}
    for f in discovery:
        for g in f.groups:
            seeds[(f.label, g.label)] = {str((r.summary or {}).get("seed")) for r in g.runs}
    for f in confirmation:
        for g in f.groups:
            mine = {str((r.summary or {}).get("seed")) for r in g.runs}
            both = sorted(mine & seeds.get((f.label, g.label), set()) - {"None"})
            if both:
                raise UserInputError(
                    f"--confirm: group {g.label} has seed(s) {', '.join(both)} in the discovery "
                    "runs too; a confirmation needs fresh seeds (growsim sweep CONFIG --block 2)"
                )


def replication_rows(
    discovery: Sequence[dict[str, Any]], confirmation: Sequence[dict[str, Any]]
) -> list[dict[str, Any]]:
    """Each primary test of the discovery block beside the same test on the confirmation
    block (matched by family, measure and groups): ``replicated`` when the discovery
    found it (``finding``) and the confirmation shows the same direction with its
    Holm-adjusted p (over the confirmation's primary tests) below alpha; ``verdict``
    says which, or why not.

    Examples
    --------
    >>> d = [{"family": "f", "measure": "h", "expect": "a > b", "group_a": "a",
    ...       "group_b": "b", "n_a": 8, "n_b": 8, "difference": 2.0, "hedges_g": 1.5,
    ...       "p_holm": 0.01, "finding": True, "alpha": 0.05, "as_expected": True}]
    >>> c = [dict(d[0], difference=-0.5, hedges_g=-0.3, p=0.4, p_holm=0.4, finding=False,
    ...           as_expected=False)]
    >>> r = replication_rows(d, c)[0]
    >>> r["replicated"], r["verdict"]
    (False, 'not replicated: opposite direction (a - b = -0.5)')
    """

    def key(r):
        return (r["family"], r["measure"], r.get("garden", ""), r["group_a"], r["group_b"])

    conf = {key(r): r for r in confirmation}
    out = []
    for d in discovery:
        c = conf.get(key(d), {})
        alpha = d["alpha"]
        cd = c.get("difference", math.nan)
        same = (
            _direction(cd) != "="
            and _direction(cd) == _direction(d["difference"])
            and bool(c.get("as_expected", False))
        )
        cp = c.get("p_holm", math.nan)
        significant = math.isfinite(cp) and cp < alpha
        replicated = bool(d["finding"] and same and significant)
        if not c or not math.isfinite(cd):
            verdict = "not tested in the confirmation block"
        elif not d["finding"]:
            verdict = "no discovery finding to replicate" + (
                " (the confirmation block alone finds it)"
                if significant and c.get("as_expected")
                else ""
            )
        elif replicated:
            verdict = "replicated"
        elif not same:
            diff = f"{d['group_a']} - {d['group_b']} = {cd:.4g}"
            verdict = f"not replicated: opposite direction ({diff})"
        else:
            verdict = f"not replicated: p_holm = {cp:.3g} >= {alpha:g}"
        out.append(
            {
                "family": d["family"],
                "measure": d["measure"],
                "expect": d["expect"],
                "garden": d.get("garden", ""),
                "group_a": d["group_a"],
                "group_b": d["group_b"],
                "discovery_n": f"{d['n_a']}, {d['n_b']}",
                "discovery_difference": d["difference"],
                "discovery_hedges_g": d["hedges_g"],
                "discovery_p_holm": d["p_holm"],
                "discovery_finding": bool(d["finding"]),
                "confirmation_n": f"{c.get('n_a', 0)}, {c.get('n_b', 0)}",
                "confirmation_difference": cd,
                "confirmation_hedges_g": c.get("hedges_g", math.nan),
                "confirmation_p": c.get("p", math.nan),
                "confirmation_p_holm": cp,
                "same_direction": bool(same),
                "replicated": replicated,
                "verdict": verdict,
            }
        )
    return out
