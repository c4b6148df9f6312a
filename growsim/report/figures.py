"""Pictures of a comparison: best-so-far curves and the groups' best phenotypes.

:func:`curves_figure` draws one panel per family, one curve per group (the mean over its
runs of the best-so-far fitness against evaluations, with the min-max band);
:func:`render_cells` renders each group's best phenotype and :func:`renders_figure` lays
them out one row per family; :func:`save_png` writes a figure and closes it.
"""

from __future__ import annotations

import io
import logging
import textwrap
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from growsim.experiment.results import RunRecord
from growsim.report.groups import Family

__all__ = ["curves_figure", "render_cells", "renders_figure", "save_png"]

log = logging.getLogger(__name__)


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


def curves_figure(families: Sequence[Family]):
    """Best-so-far fitness against evaluations (generations when a history has no
    evaluations): one panel per family, one curve per group (mean over its runs, min-max
    band), as a matplotlib figure.

    Examples
    --------
    >>> import pandas as pd
    >>> from growsim.report.groups import Group
    >>> h = pd.DataFrame({"generation": [0, 1], "evaluations": [4, 8], "best": [1.0, 2.0]})
    >>> run = RunRecord(Path("r"), {}, {"fitness": 2.0}, {}, history=h)
    >>> fig = curves_figure([Family("honda / light", "honda", [], [Group("a", [run], [], {})], [])])
    >>> fig.axes[0].get_title(), fig.axes[0].get_xlabel()
    ('honda / light', 'evaluations')
    >>> png = save_png(fig)
    """
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


def renders_figure(rows: Sequence[tuple[str, list[tuple[str, np.ndarray]]]], per_row: int = 5):
    """A grid of pictures: for each (row title, [(title, image)]), one or more rows.

    Examples
    --------
    >>> cells = [(f"group {i}", np.zeros((8, 8, 3), np.uint8)) for i in range(7)]
    >>> fig = renders_figure([("honda / light", cells)])
    >>> len(fig.axes), fig.axes[6].get_title()  # two rows of five
    (10, 'group 6')
    >>> png = save_png(fig)
    """
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


def save_png(fig, path: Path | None = None) -> bytes:
    """PNG bytes of a figure (and the file ``path``, written atomically); closes it.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> save_png(plt.figure(figsize=(1, 1)))[:4]
    b'\\x89PNG'
    """
    import matplotlib.pyplot as plt

    from growsim.files import atomic_write

    buf = io.BytesIO()
    fig.savefig(buf, format="png", bbox_inches="tight")  # titles of any length kept
    plt.close(fig)
    data = buf.getvalue()
    if path is not None:
        atomic_write(path, data)
    return data


def render_cells(families: Sequence[Family]) -> list[list[tuple[str, np.ndarray]]]:
    """Per family, (title, picture) of each group's best phenotype; a group whose best
    run has no phenotype to render is left out (with a warning).

    Examples
    --------
    >>> from growsim.report.groups import Group
    >>> run = RunRecord(Path("/nonexistent/run"), {}, {"fitness": 1.0})
    >>> render_cells([Family("f", "honda", [], [Group("a", [run], [], {})], [])])
    [[]]
    """
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
