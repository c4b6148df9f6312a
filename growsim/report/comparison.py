"""The comparison itself: :func:`compare` finds the runs, groups them, makes the tests,
writes the tables, figures and HTML report, and returns a :class:`Comparison`; by default
beside the runs (:func:`default_out`).
"""

from __future__ import annotations

import dataclasses
import logging
import os
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from growsim.errors import UserInputError
from growsim.experiment.results import RunRecord, find_runs
from growsim.files import atomic_write
from growsim.report import primary as prim
from growsim.report.figures import curves_figure, render_cells, renders_figure, save_png
from growsim.report.garden import garden_stats, grow_in_gardens, stop_reasons, variance_shares
from growsim.report.groups import families as find_families
from growsim.report.groups import run_label
from growsim.report.html import garden_html, primary_html, replication_html, report_html
from growsim.report.statistics import STATS_COLUMNS, ci95, family_stats, quantities

__all__ = ["Comparison", "compare", "default_out"]

log = logging.getLogger(__name__)


def default_out(dirs: Sequence[str | Path], runs: Sequence[RunRecord]) -> Path:
    """Where a comparison goes by default: ``<dir>/compare-<time>`` beside the runs when
    they are all under one directory (the runs' common parent, when it is a directory
    given, inside one, the parent of one, or a run's own parent), else
    ``runs/compare-<time>``.

    Examples
    --------
    >>> from growsim.experiment.results import RunRecord
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
    #: with ``[compare] primary``: the primary tests, the exploratory tests and (with a
    #: confirmation block) the replication table; ``None`` otherwise
    primary: Any = None
    exploratory: Any = None
    replication: Any = None


def compare(
    dirs: Sequence[str | Path],
    out: str | Path | None = None,
    *,
    renders: bool = True,
    html_report: bool = True,
    garden: bool = False,
    primary: Any = None,
    confirm: Sequence[str | Path] | None = None,
) -> Comparison:
    """Compare runs: write ``compare.csv``, ``stats.csv``, ``runs.csv``, ``curves.png``,
    ``renders.png`` and ``report.html`` to ``out`` (default: :func:`default_out`); with
    ``garden``, also the common garden (:mod:`growsim.report.garden`): ``garden.csv``,
    ``garden_stats.csv``, ``garden_variance.csv`` and (for a model that says why its
    plants stopped growing) ``garden_stops.csv``, and its section of the report
    (grown too when a primary test is declared within a garden).

    When the runs' configs declare ``[compare] primary`` (or ``primary`` gives an
    experiment TOML that does, :func:`growsim.report.primary.read_spec`), also
    ``primary.csv`` (the primary tests, Holm over them alone, effect sizes and the seeds
    a replication needs) and ``exploratory.csv`` (every other test, Holm over those
    alone); with ``confirm`` (the directories of the same sweep on a fresh block of
    seeds), the primary tests again on those runs and ``replication.csv``.
    ``stats.csv`` is unchanged: every test, Holm over all of them.

    Examples
    --------
    >>> c = compare(["runs/sweep-light"], out="runs/cmp")  # doctest: +SKIP
    >>> list(c.table.columns)[:5]  # doctest: +SKIP
    ['family', 'group', 'dirs', 'runs', 'duplicates']
    """

    runs = find_runs(dirs)
    notes: list[str] = []
    families = find_families(runs, notes)
    spec = prim.read_spec(runs, primary)
    confirmation = None
    if confirm:
        if spec is None:
            raise UserInputError(
                "--confirm: no primary tests declared ([compare] primary in the runs' config, "
                "or --primary CONFIG): nothing to replicate"
            )
        c_runs = find_runs(confirm)
        c_spec = prim.read_spec(c_runs, primary)
        if primary is None and c_spec is not None and c_spec != spec:
            raise UserInputError(
                "--confirm: the confirmation runs declare other [compare] primary tests than "
                "the discovery runs; choose one with --primary CONFIG"
            )
        c_notes: list[str] = []
        confirmation = (find_families(c_runs, c_notes), c_notes)
        prim.check_fresh_seeds(families, confirmation[0])
    out = Path(out) if out is not None else default_out(dirs, runs)
    rows, run_rows, fam_stats, fam_rows, stat_rows = [], [], [], [], []
    for fam in families:
        fs, frows = family_stats(fam, notes)
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
                "ci95": ci95(fit),
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
                row[f"{q}_ci95"] = ci95(v)
            row["best_run"] = str(best_run.path)
            rows.append(row)
            dup_of = {id(d): k for d, k in g.duplicates}
            for r in g.members:
                q = quantities(r)
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
    primary_df = exploratory_df = replication_df = None
    top = ""
    in_garden = spec is not None and any(p.garden for p in spec.primary)
    grown = grow_in_gardens(families, notes) if (garden or in_garden) else None
    if spec is not None:  # primary tests first: a bad name fails before anything is written
        p_rows = prim.primary_rows(families, fam_stats, spec, grown)
        e_rows = prim.exploratory_rows(stat_rows, p_rows)
        primary_df = pd.DataFrame(p_rows, columns=prim.PRIMARY_COLUMNS)
        exploratory_df = pd.DataFrame(e_rows, columns=prim.EXPLORATORY_COLUMNS)
        fam_rows = [[r for r in e_rows if r["family"] == f.label] for f in families]
        top = primary_html(p_rows, "Primary tests" + (" (discovery block)" if confirm else ""))
        if confirmation is not None:
            c_fams, c_notes = confirmation
            c_stats = [family_stats(f, c_notes)[0] for f in c_fams]
            c_grown = grow_in_gardens(c_fams, c_notes) if in_garden else None
            c_rows = prim.primary_rows(c_fams, c_stats, spec, c_grown)
            r_rows = prim.replication_rows(p_rows, c_rows)
            replication_df = pd.DataFrame(r_rows, columns=prim.REPLICATION_COLUMNS)
            top += replication_html(r_rows)
            notes += [f"confirmation block: {n}" for n in c_notes]
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise UserInputError(f"--out {out}: cannot create ({exc.strerror})") from None
    files = {
        "table": atomic_write(out / "compare.csv", table.to_csv(index=False)),
        "stats": atomic_write(out / "stats.csv", stats_df.to_csv(index=False)),
        "runs": atomic_write(out / "runs.csv", runs_df.to_csv(index=False)),
    }
    for key, df in (
        ("primary", primary_df),
        ("exploratory", exploratory_df),
        ("replication", replication_df),
    ):
        if df is not None:
            files[key] = atomic_write(out / f"{key}.csv", df.to_csv(index=False))
    save_png(curves_figure(families), out / "curves.png")
    files["curves"] = out / "curves.png"
    fam_images: list[dict[str, bytes]] = [
        {"curves": save_png(curves_figure([f]))} if html_report else {} for f in families
    ]
    if renders:
        cells = render_cells(families)
        if any(cells):
            try:
                rows_ = [(f.label, c) for f, c in zip(families, cells) if c]
                save_png(renders_figure(rows_), out / "renders.png")
                files["renders"] = out / "renders.png"
                if html_report:
                    for imgs, c in zip(fam_images, cells):
                        if c:
                            imgs["renders"] = save_png(renders_figure([("", c)]))
            except Exception as exc:  # a picture must not lose the tables
                log.warning("renders.png failed: %s", exc)
    extra = ""
    if grown is not None:
        g_stats, shares = garden_stats(grown), variance_shares(grown)
        files["garden"] = atomic_write(out / "garden.csv", grown.to_csv(index=False))
        files["garden_stats"] = atomic_write(out / "garden_stats.csv", g_stats.to_csv(index=False))
        files["garden_variance"] = atomic_write(
            out / "garden_variance.csv", shares.to_csv(index=False)
        )
        stops = stop_reasons(grown)
        if len(stops):
            files["garden_stops"] = atomic_write(
                out / "garden_stops.csv", stops.to_csv(index=False)
            )
        extra = garden_html(g_stats, shares, stops)
    if html_report:
        title = "growsim compare: " + "; ".join(f.label for f in families)
        text = report_html(
            families, fam_stats, fam_rows, fam_images, runs_df, notes, title, primary=top
        )
        if extra:
            text = text.replace("<h2>Runs</h2>", extra + "\n<h2>Runs</h2>", 1)
        files["html"] = atomic_write(out / "report.html", text)
    return Comparison(
        table=table,
        stats=stats_df,
        runs=runs_df,
        files=files,
        notes=notes,
        primary=primary_df,
        exploratory=exploratory_df,
        replication=replication_df,
    )
