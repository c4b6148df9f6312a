"""The self-contained HTML report of a comparison: methods, notes, one block per family.

Each family's block has the table of what differs between its groups' configs, the
groups (n, mean +/- 95 % CI of each quantity, :func:`format_mean_ci`), the tests between
them and its figures, embedded as PNG data URIs; last, the table of the runs. Built by
:func:`report_html`.
"""

from __future__ import annotations

import base64
import html
import math
import time
from collections.abc import Sequence
from typing import Any

import numpy as np

from growsim.report.configs import MISSING, fmt_value, from_preset
from growsim.report.groups import Family
from growsim.report.statistics import FamilyStats, ci95

__all__ = [
    "format_mean_ci",
    "garden_html",
    "primary_html",
    "replication_html",
    "report_html",
]


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
    fs: FamilyStats,
    rows: list[dict[str, Any]],
    images: dict[str, bytes],
    exploratory: bool = False,
) -> list[str]:
    n_runs = sum(len(g.runs) for g in fam.groups)
    objs = "; ".join(", ".join(f"{a}={fmt_value(v)}" for a, v in o.items()) for o in fam.objectives)
    parts = [
        f"<h2>{k}. {_e(fam.label)}</h2>",
        f"<p>Model <code>{_e(fam.model)}</code>; objective(s): <code>{_e(objs)}</code>. "
        f"{len(fam.groups)} group(s), {n_runs} run(s) counted.</p>",
    ]
    groups = fam.groups
    if fam.differences:
        preset = from_preset([g.config for g in groups], fam.differences)
        body = [
            [f"<code>{_e('.'.join(p))}</code>" + (" (from the preset)" if p in preset else "")]
            + [_e(fmt_value(g.config.get(p, MISSING))) for g in groups]
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
            cells.append(format_mean_ci(float(v.mean()), ci95(v)) if len(v) else "-")
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
        if exploratory:
            parts.append(
                f"<p><b>Exploratory.</b> {len(rows)} tests besides the primary ones "
                "(quantities &times; pairs of groups); their adjusted p-values are "
                "Holm-Bonferroni over these exploratory tests alone, separately for each "
                f"test: leads for a next experiment, not findings.{small}</p>"
            )
        else:
            parts.append(
                f"<p>{len(rows)} hypotheses tested in this family (quantities &times; pairs "
                "of groups); every adjusted p-value is Holm-Bonferroni over all of them, "
                f"separately for each test.{small}</p>"
            )
        what = "Exploratory: " if exploratory else ""
        if best:
            parts.append(
                _tests_table(best, f"Table {k}.3. {what}Best fitness: tests between groups.")
            )
        if other:
            n_sig = sum(_significant(r) for r in other)
            table = _tests_table(
                other,
                f"Table {k}.4. {what}Measures of the best phenotypes and objective terms: "
                "tests between groups.",
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


def report_html(
    families, fam_stats, fam_rows, fam_images, runs_df, notes, title, primary: str = ""
) -> str:
    """The whole report as one HTML page: for each family (in order) its
    :class:`~growsim.report.statistics.FamilyStats`, its tests (the rows of
    :func:`~growsim.report.statistics.family_stats`) and its PNG images (``"curves"``, and
    ``"renders"`` when there are any); then the notes and the runs (a DataFrame). With
    ``primary`` (the HTML of :func:`primary_html`, and :func:`replication_html`), that
    section comes first and the families' tests are marked exploratory.

    Examples
    --------
    >>> import pandas as pd
    >>> text = report_html([], [], [], [], pd.DataFrame({"path": ["runs/a"]}), ["a note"], "t")
    >>> "<h1>t</h1>" in text, "<li>a note</li>" in text, "<td>runs/a</td>" in text
    (True, True, True)
    """
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
        f"<h2>Methods</h2><p>{_METHODS}"
        + (
            " The primary tests the experiment declared (<code>[compare] primary</code>) "
            "were adjusted over themselves alone, and every other test, exploratory, over "
            "the other tests of its family alone."
            if primary
            else ""
        )
        + "</p>",
    ]
    if notes:
        parts.append("<h2>Notes</h2><ul>" + "".join(f"<li>{_e(n)}</li>" for n in notes) + "</ul>")
    parts.append(primary)
    for k, fam in enumerate(families, 1):
        parts += _family_html(
            k, fam, fam_stats[k - 1], fam_rows[k - 1], fam_images[k - 1], bool(primary)
        )
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


def garden_html(stats, shares, stops=None) -> str:
    """The garden's section of ``report.html``: why each cell's plants stopped growing
    (``stops``, :func:`growsim.report.garden.stop_reasons`), the variance shares, then
    the tests whose Holm-adjusted p is below 0.05 (all of them are in
    ``garden_stats.csv``)."""
    if not len(shares) and not len(stats):
        return ""
    parts = ["<h2>Common garden</h2>", f"<p class='n'>{_e_doc()}</p>"]
    if stops is not None and len(stops):
        head = [str(c) for c in stops.columns]
        body = [[_e(str(v)) for v in row] for row in stops.itertuples(index=False)]
        parts.append(_table(head, body, "Why the plants stopped growing, per garden cell"))
    body = [[r.family, r.measure, _share(r.origin), _share(r.garden), _share(r.interaction),
             _share(r.residual), str(r.n)] for r in shares.itertuples()]  # fmt: skip
    head = ["family", "quantity", "origin (genetic)", "garden (plastic)", "interaction",
            "residual", "n"]  # fmt: skip
    parts.append(_table(head, body, "Shares of each quantity's sum of squares"))
    sig = stats[(stats.welch_t_p_holm < 0.05) | (stats.mann_whitney_p_holm < 0.05)]
    for contrast in ("genetic", "plastic"):
        sub = sig[sig.contrast == contrast]
        recs = [
            {**r, "measure": f"{r['measure']} (in {r['within']})"} for r in sub.to_dict("records")
        ]
        what = "origins in one garden" if contrast == "genetic" else "gardens for one origin"
        if recs:
            parts.append(_tests_table(recs, f"{contrast}: {what}, Holm p < 0.05 ({len(recs)})"))
        else:  # no empty table with headers only
            parts.append(f"<p class='n'>{contrast} ({what}): no test with Holm p &lt; 0.05</p>")
    return "\n".join(parts)


def _share(v) -> str:
    """A share of a sum of squares (in [0, 1]): 3 decimals, so a rounding-error share
    reads 0, not 2.8e-30.

    Examples
    --------
    >>> _share(2.8e-30), _share(0.41666), _share(1.0), _share(float("nan"))
    ('0', '0.417', '1', '-')
    """
    if not isinstance(v, (int, float)) or not math.isfinite(v):
        return "-"
    text = f"{round(float(v), 3):.3f}".rstrip("0").rstrip(".")
    return "0" if text in ("0", "-0") else text


def _e_doc() -> str:
    return (
        "Every run's best genome grown again in the environment of every group of its "
        "family. <i>genetic</i>: genomes from different origins grown in the same garden; "
        "<i>plastic</i>: the same genomes grown in two gardens. Welch and Mann-Whitney "
        "tests, Holm-adjusted over all of a family's garden tests."
    )


def _yes(v: Any) -> str:
    return "<b>yes</b>" if bool(v) and v == v else "no"


def _expect(row: dict[str, Any]) -> str:
    """A primary test's declared expectation, with its common garden when it has one."""
    garden = row.get("garden")
    return (
        f"{row['expect']} grown in {garden}"
        if isinstance(garden, str) and garden
        else row["expect"]
    )


def primary_html(rows: Sequence[dict[str, Any]], title: str = "Primary tests") -> str:
    """The primary tests (rows of :func:`growsim.report.primary.primary_rows`) as a section
    of the report: the declared expectation, the effect, raw and Holm p (over the primary
    tests alone), whether it is a finding and the seeds a replication needs.

    Examples
    --------
    >>> r = {"family": "f", "measure": "height", "expect": "a > b", "group_a": "a",
    ...      "group_b": "b", "n_a": 8, "n_b": 8, "difference": 1.0, "diff_ci_low": 0.5,
    ...      "diff_ci_high": 1.5, "hedges_g": 1.2, "cliffs_delta": 0.6, "test": "welch",
    ...      "p": 0.01, "p_holm": 0.02, "alpha": 0.05, "as_expected": True,
    ...      "finding": True, "power": 0.8, "seeds_for_power": 12, "note": ""}
    >>> "<td>height</td>" in primary_html([r])
    True
    """
    if not rows:
        return ""
    body = []
    for r in rows:
        ci = (
            f" [{_g(r['diff_ci_low'])}, {_g(r['diff_ci_high'])}]"
            if math.isfinite(r["diff_ci_low"])
            else ""
        )
        n_need = r["seeds_for_power"]
        need = "&infin;" if n_need == math.inf else _g(n_need)
        body.append(
            [
                _e(r["measure"]),
                _e(_expect(r)),
                f"{r['n_a']}, {r['n_b']}",
                _g(r["difference"]) + ci,
                _g(r["hedges_g"]),
                _g(r["cliffs_delta"]),
                _p(r["p"]),
                f"<b>{_p(r['p_holm'])}</b>" if r["finding"] else _p(r["p_holm"]),
                "yes" if r["as_expected"] else "no",
                _yes(r["finding"]),
                need,
                _e(r["note"]),
            ]
        )
    r0 = rows[0]
    test = "Welch's t" if r0["test"] == "welch" else "Mann-Whitney U"
    head = ["quantity", "expected", "n", "a &minus; b [95&nbsp;% CI]", "Hedges' g",
            "Cliff's &delta;", "p", "p (Holm)", "direction as expected", "finding",
            f"seeds per group for {r0['power']:.0%} power", "note"]  # fmt: skip
    families = sorted({r["family"] for r in rows})
    text = (
        f"<h2>{_e(title)}</h2><p>Declared in the experiment's <code>[compare] primary</code> "
        f"before the runs{' (' + _e(', '.join(families)) + ')' if families else ''}. "
        f"Two-sided {test} test of group a against group b; p-values Holm-Bonferroni "
        f"adjusted over these {len(rows)} primary tests alone. A <b>finding</b>: adjusted p "
        f"&lt; {r0['alpha']:g} with the difference in the expected direction. Hedges' g: "
        "Cohen's d with the small-sample correction; the seeds per group a replication "
        f"needs for {r0['power']:.0%} power at that g (two-sided two-sample t-test at alpha "
        f"= {r0['alpha']:g}, noncentral t; an observed effect that passed a threshold "
        "overstates the true one, so treat it as a lower bound). Every other test below is "
        "<b>exploratory</b>.</p>"
    )
    return text + _table(head, body, "Primary tests.")


def replication_html(rows: Sequence[dict[str, Any]]) -> str:
    """The replication table (rows of :func:`growsim.report.primary.replication_rows`):
    each primary test on the discovery block beside the confirmation block.

    Examples
    --------
    >>> r = {"measure": "height", "expect": "a > b", "discovery_n": "8, 8",
    ...      "discovery_difference": 1.0, "discovery_hedges_g": 1.1, "discovery_p_holm": 0.01,
    ...      "discovery_finding": True, "confirmation_n": "8, 8",
    ...      "confirmation_difference": 0.2, "confirmation_hedges_g": 0.1,
    ...      "confirmation_p_holm": 0.6, "replicated": False, "verdict": "not replicated"}
    >>> "not replicated" in replication_html([r])
    True
    """
    if not rows:
        return ""
    body = [
        [
            _e(r["measure"]),
            _e(_expect(r)),
            _e(r["discovery_n"]),
            _g(r["discovery_difference"]),
            _g(r["discovery_hedges_g"]),
            _p(r["discovery_p_holm"]),
            _yes(r["discovery_finding"]),
            _e(r["confirmation_n"]),
            _g(r["confirmation_difference"]),
            _g(r["confirmation_hedges_g"]),
            _p(r["confirmation_p_holm"]),
            _yes(r["replicated"]),
            _e(r["verdict"]),
        ]
        for r in rows
    ]
    head = ["quantity", "expected", "n (discovery)", "a &minus; b", "g", "p (Holm)", "finding",
            "n (confirmation)", "a &minus; b", "g", "p (Holm)", "replicated",
            "verdict"]  # fmt: skip
    n_rep = sum(bool(r["replicated"]) for r in rows)
    n_find = sum(bool(r["discovery_finding"]) for r in rows)
    return (
        "<h2>Replication</h2><p>The same primary tests on a fresh block of seeds (the "
        "confirmation runs), Holm-adjusted over the primary tests of that block. A finding "
        "<b>replicated</b> when the confirmation block shows the same direction with an "
        f"adjusted p below the threshold: {n_rep} of {n_find} discovery finding(s).</p>"
        + _table(head, body, "Discovery and confirmation.")
    )
