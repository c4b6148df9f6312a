"""Compare results directories: a table, statistics over repeats, curves, renders, HTML.

:func:`compare` takes run directories, sweep directories or any directory holding runs
(found by their ``summary.json``), groups the runs that share a config up to the seed
(the repeats of one variant), and reports per group:

- best, mean +/- 95 % confidence half-width (Student t) of the runs' best fitness,
  generations, evaluations, wall time;
- shape measures of the group's best plant: height, crown width, segments, light
  captured (leaf area seen from the light, times the light intensity);
- between every pair of groups with at least two runs each: Welch's t-test and the
  Mann-Whitney U test of the best fitness (``scipy.stats``);
- ``curves.png``: best-so-far fitness per generation (mean over repeats, min-max band);
  ``renders.png``: the groups' best plants side by side; ``report.html``: all of it in
  one self-contained file (PNGs embedded as base64).
"""

from __future__ import annotations

import base64
import dataclasses
import html
import itertools
import json
import logging
import math
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from growsim.errors import UserInputError
from growsim.results import RunRecord, find_runs

__all__ = ["Comparison", "compare", "group_runs", "run_key", "run_label"]

log = logging.getLogger(__name__)


def run_key(run: RunRecord) -> str:
    """The config without its seed: runs with the same key are repeats."""
    cfg = json.loads(json.dumps(run.config))
    cfg.get("experiment", {}).pop("seed", None)
    return json.dumps(cfg, sort_keys=True)


def run_label(run: RunRecord) -> str:
    """``variant`` for ``.../variant/seed-N``, else the directory name."""
    if run.path.name.startswith("seed-"):
        return run.path.parent.name
    return run.path.name


@dataclasses.dataclass
class Comparison:
    """What :func:`compare` returns: ``table`` (one row per group), ``stats`` (one row per
    pair of groups), ``runs`` (one row per run) and the paths of the files written."""

    table: Any
    stats: Any
    runs: Any
    files: dict[str, Path]


def group_runs(runs: Sequence[RunRecord]) -> dict[str, list[RunRecord]]:
    """Group runs by config up to the seed; name each group by its runs' common label.

    Examples
    --------
    >>> group_runs([])
    {}
    """
    by_key: dict[str, list[RunRecord]] = {}
    for r in runs:
        by_key.setdefault(run_key(r), []).append(r)
    groups: dict[str, list[RunRecord]] = {}
    for members in by_key.values():
        labels = {run_label(r) for r in members}
        name = labels.pop() if len(labels) == 1 else members[0].summary.get("experiment", "run")
        base, k = name, 2
        while name in groups:
            name = f"{base}#{k}"
            k += 1
        groups[name] = sorted(members, key=lambda r: r.summary.get("seed", 0))
    return groups


def _ci95(x: np.ndarray) -> float:
    """Half-width of the 95 % Student-t confidence interval of the mean (NaN for n < 2)."""
    from scipy import stats

    n = len(x)
    if n < 2:
        return float("nan")
    return float(stats.t.ppf(0.975, n - 1) * np.std(x, ddof=1) / math.sqrt(n))


def _curve(history) -> tuple[np.ndarray, np.ndarray]:
    """(generation, best-so-far) of one run, islands merged (max over islands)."""
    h = history.groupby("generation", sort=True)
    col = "best_so_far" if "best_so_far" in history else "best"
    best = h[col].max().to_numpy(dtype=np.float64)
    best = np.maximum.accumulate(best)
    return h[col].max().index.to_numpy(), best


def _plot_curves(groups: dict[str, list[RunRecord]], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from growsim.files import atomic_path

    fig, ax = plt.subplots(figsize=(7, 4.2), dpi=100)
    for name, members in groups.items():
        curves = [_curve(r.history) for r in members]
        n = min(len(c[1]) for c in curves)
        if n == 0:
            continue
        gen = curves[0][0][:n]
        ys = np.array([c[1][:n] for c in curves])
        (line,) = ax.plot(gen, ys.mean(axis=0), label=f"{name} (n={len(members)})")
        if len(members) > 1:
            ax.fill_between(gen, ys.min(axis=0), ys.max(axis=0), alpha=0.2, color=line.get_color())
    ax.set_xlabel("generation")
    ax.set_ylabel("best-so-far fitness (mean, min-max band)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png")
    plt.close(fig)


def _stats_table(groups: dict[str, list[RunRecord]]):
    import pandas as pd
    from scipy import stats

    rows = []
    eligible = {k: v for k, v in groups.items() if len(v) >= 2}
    for (a, ra), (b, rb) in itertools.combinations(eligible.items(), 2):
        x = np.array([r.best_fitness for r in ra])
        y = np.array([r.best_fitness for r in rb])
        if np.ptp(np.concatenate([x, y])) == 0:
            t_p, u_p = 1.0, 1.0
        else:
            t_p = float(stats.ttest_ind(x, y, equal_var=False).pvalue)
            u_p = float(stats.mannwhitneyu(x, y, alternative="two-sided").pvalue)
            if not math.isfinite(t_p):  # zero variance in both groups, different means
                t_p = 0.0
        rows.append(
            {
                "group_a": a,
                "group_b": b,
                "n_a": len(x),
                "n_b": len(y),
                "mean_a": float(x.mean()),
                "mean_b": float(y.mean()),
                "difference": float(x.mean() - y.mean()),
                "welch_t_p": t_p,
                "mann_whitney_p": u_p,
            }
        )
    return pd.DataFrame(
        rows,
        columns=[
            "group_a",
            "group_b",
            "n_a",
            "n_b",
            "mean_a",
            "mean_b",
            "difference",
            "welch_t_p",
            "mann_whitney_p",
        ],
    )


def _png_b64(path: Path) -> str:
    return base64.b64encode(path.read_bytes()).decode("ascii")


def _html(table, stats_df, runs_df, images: dict[str, Path], title: str) -> str:
    def df_html(df):
        return df.to_html(
            index=False, float_format=lambda v: f"{v:.6g}", border=0, classes="t", na_rep="-"
        )

    parts = [
        "<!DOCTYPE html><html><head><meta charset='utf-8'>",
        f"<title>{html.escape(title)}</title>",
        "<style>body{font-family:sans-serif;margin:2em;max-width:1200px}"
        "table.t{border-collapse:collapse;font-size:13px}"
        "table.t td,table.t th{border-bottom:1px solid #ddd;padding:3px 8px;text-align:right}"
        "img{max-width:100%;border:1px solid #eee}</style></head><body>",
        f"<h1>{html.escape(title)}</h1>",
        f"<p>Generated {html.escape(time.strftime('%Y-%m-%d %H:%M:%S'))} by growsim compare. "
        "Best fitness per group: best of the runs, and mean &plusmn; 95&nbsp;% confidence "
        "half-width (Student t) over the repeats (seeds). Shape measures are those of the "
        "group's best plant.</p>",
        "<h2>Groups</h2>",
        df_html(table),
    ]
    if len(stats_df):
        parts += [
            "<h2>Tests between groups</h2>",
            "<p>Best fitness of the runs: Welch's t-test and the Mann-Whitney U test "
            "(two-sided).</p>",
            df_html(stats_df),
        ]
    for name, caption in (("curves", "Fitness curves"), ("renders", "Best plants")):
        if name in images:
            parts += [
                f"<h2>{caption}</h2>",
                f"<img alt='{name}' src='data:image/png;base64,{_png_b64(images[name])}'>",
            ]
    parts += ["<h2>Runs</h2>", df_html(runs_df), "</body></html>"]
    return "\n".join(parts)


def compare(
    dirs: Sequence[str | Path],
    out: str | Path | None = None,
    *,
    renders: bool = True,
    html_report: bool = True,
) -> Comparison:
    """Compare runs: write ``compare.csv``, ``stats.csv``, ``runs.csv``, ``curves.png``,
    ``renders.png`` and ``report.html`` to ``out`` (default ``runs/compare-<time>``).

    Examples
    --------
    >>> c = compare(["runs/sweep-light"], out="runs/cmp")  # doctest: +SKIP
    >>> list(c.table.columns)[:4]  # doctest: +SKIP
    ['group', 'runs', 'best', 'mean']
    """
    import pandas as pd

    from growsim.files import atomic_write

    runs = find_runs(dirs)
    groups = group_runs(runs)
    out = Path(out) if out is not None else Path("runs") / time.strftime("compare-%Y%m%d-%H%M%S")
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise UserInputError(f"--out {out}: cannot create ({exc.strerror})") from None

    rows, run_rows, best_plants = [], [], {}
    for name, members in groups.items():
        fit = np.array([r.best_fitness for r in members])
        best_run = members[int(np.argmax(fit))]
        meas = best_run.summary.get("measures", {}) or {}
        rows.append(
            {
                "group": name,
                "runs": len(members),
                "best": float(fit.max()),
                "mean": float(fit.mean()),
                "ci95": _ci95(fit),
                "std": float(fit.std(ddof=1)) if len(fit) > 1 else float("nan"),
                "generations": float(np.mean([r.summary["generations"] for r in members])),
                "evaluations": float(np.mean([r.summary["evaluations"] for r in members])),
                "seconds": float(np.mean([r.summary["wall_seconds"] for r in members])),
                "height": meas.get("height", float("nan")),
                "width": meas.get("crown_width", float("nan")),
                "segments": meas.get("segments", meas.get("n_segments", float("nan"))),
                "light_captured": meas.get("light_captured", float("nan")),
                "best_run": str(best_run.path),
            }
        )
        for r in members:
            run_rows.append(
                {
                    "group": name,
                    "seed": r.summary.get("seed"),
                    "best_fitness": r.best_fitness,
                    "generations": r.summary["generations"],
                    "evaluations": r.summary["evaluations"],
                    "seconds": r.summary["wall_seconds"],
                    "stop_reason": r.summary.get("stop_reason", ""),
                    "path": str(r.path),
                }
            )
        if renders:
            try:
                best_plants[name] = best_run.phenotype()
            except Exception as exc:  # a missing plant must not lose the table
                log.warning("%s: no best plant to render (%s)", best_run.path, exc)
    table = pd.DataFrame(rows)
    stats_df = _stats_table(groups)
    runs_df = pd.DataFrame(run_rows)
    files = {
        "table": atomic_write(out / "compare.csv", table.to_csv(index=False)),
        "stats": atomic_write(out / "stats.csv", stats_df.to_csv(index=False)),
        "runs": atomic_write(out / "runs.csv", runs_df.to_csv(index=False)),
    }
    _plot_curves(groups, out / "curves.png")
    files["curves"] = out / "curves.png"
    if renders and best_plants:
        from growsim import viz
        from growsim.files import atomic_path

        try:
            with atomic_path(out / "renders.png") as tmp:
                viz.render_grid(list(best_plants.values()), tmp, titles=list(best_plants))
            files["renders"] = out / "renders.png"
        except Exception as exc:
            log.warning("renders.png failed: %s", exc)
    if html_report:
        text = _html(
            table.drop(columns=["best_run"]),
            stats_df,
            runs_df,
            files,
            f"growsim compare: {', '.join(groups)}",
        )
        files["html"] = atomic_write(out / "report.html", text)
    return Comparison(table=table, stats=stats_df, runs=runs_df, files=files)
