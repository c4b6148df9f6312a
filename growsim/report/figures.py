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
from growsim.files import atomic_write
from growsim.phenotypes.plant import Plant
from growsim.phenotypes.plant.mesh import plant_mesh
from growsim.phenotypes.plant.views import render_image
from growsim.render import view_vectors
from growsim.report.groups import Family

__all__ = [
    "Frame",
    "curves_figure",
    "render_cells",
    "render_frame",
    "renders_figure",
    "save_png",
]

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


def _nice_length(span: float) -> float:
    """A round length (1, 2 or 5 times a power of ten) of about a quarter of ``span``.

    Examples
    --------
    >>> _nice_length(4.0), _nice_length(84.0), _nice_length(0.3)
    (1.0, 20.0, 0.05)
    """
    target = max(span, 1e-12) / 4.0
    power = 10.0 ** np.floor(np.log10(target))
    return float(max(m * power for m in (1.0, 2.0, 5.0) if m * power <= target * 1.0001))


def renders_figure(rows: Sequence[tuple[str, list[tuple]]], per_row: int = 5):
    """A grid of pictures: for each (row title, cells), one or more rows. A cell is
    ``(title, image)``, drawn to fill its panel, or ``(title, image, frame)`` with ``frame``
    a :class:`Frame` (where the image lies in the plant's units): the framed cells of a row
    title are drawn at one scale, standing on one ground line, each with a scale bar.

    Examples
    --------
    >>> cells = [(f"group {i}", np.zeros((8, 8, 3), np.uint8)) for i in range(7)]
    >>> fig = renders_figure([("honda / light", cells)])
    >>> len(fig.axes), fig.axes[6].get_title()  # two rows of five
    (10, 'group 6')
    >>> png = save_png(fig)
    >>> tall = Frame((-5, 5, -1, 9), (-1, 1, 0, 8))
    >>> stick = Frame((-0.6, 0.6, -0.1, 1.1), (-0.1, 0.1, 0, 1))
    >>> fig = renders_figure([("", [("tree", cells[0][1], tall), ("stick", cells[1][1], stick)])])
    >>> [tuple(round(float(v), 2) for v in ax.get_ylim()) for ax in fig.axes]  # one scale
    [(-0.35, 8.45), (-0.35, 8.45)]
    >>> png = save_png(fig)
    """
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    lines = []
    for head, cells in rows:
        framed = [c[2] for c in cells if len(c) > 2 and c[2] is not None]
        span = None
        if framed:  # one window size for the row title's plants: the largest plant's box
            width = max(f.box[1] - f.box[0] for f in framed)
            height = max(f.box[3] - f.box[2] for f in framed)
            span = max(width, height, 1e-9) * 1.1
        for i in range(0, len(cells), per_row):
            lines.append((head if i == 0 else "", cells[i : i + per_row], span))
    cols = max(len(c) for _, c, _ in lines)
    fig, axes = plt.subplots(
        len(lines), cols, figsize=(2.6 * cols, 3.0 * len(lines)), dpi=100, squeeze=False
    )
    for (head, cells, span), axrow in zip(lines, axes):
        for ax in axrow:
            ax.axis("off")
        for ax, cell in zip(axrow, cells):
            title, img = cell[0], cell[1]
            frame = cell[2] if len(cell) > 2 else None
            if frame is None or span is None:
                ax.imshow(img)
            else:
                _draw_to_scale(ax, img, frame, span)
            ax.set_title("\n".join(textwrap.fill(t, 30) for t in title.splitlines()), fontsize=7)
        if head and len(rows) > 1:
            axrow[0].text(
                -0.05, 0.5, textwrap.fill(head, 25), transform=axrow[0].transAxes,
                rotation=90, ha="right", va="center", fontsize=8,
            )  # fmt: skip
    fig.tight_layout()
    return fig


class Frame(tuple):
    """Where a render lies in the plant's units: ``image`` (left, right, bottom, top of
    the picture) and ``box`` (left, right, bottom, top of the plant in it), as seen.

    Examples
    --------
    >>> Frame((0, 2, 0, 2), (0.5, 1.5, 0, 1)).box
    (0.5, 1.5, 0, 1)
    """

    def __new__(cls, image, box):
        return super().__new__(cls, (tuple(image), tuple(box)))

    @property
    def image(self) -> tuple:
        return self[0]

    @property
    def box(self) -> tuple:
        return self[1]


def _draw_to_scale(ax, img, frame: Frame, span: float) -> None:
    """``img`` in ``ax`` at its place in the plant's units, in a window ``span`` wide and
    high whose bottom is the plant's ground (a little below), with a scale bar."""
    x0, x1, y0, _ = frame.box
    cx, pad = (x0 + x1) / 2.0, 0.04 * span
    ax.imshow(img, extent=frame.image, interpolation="antialiased")
    ax.set_xlim(cx - span / 2.0, cx + span / 2.0)
    ax.set_ylim(y0 - pad, y0 - pad + span)
    length = _nice_length(span)
    left = cx - span / 2.0 + 0.06 * span
    ax.plot([left, left + length], [y0 - pad * 0.5] * 2, color="black", lw=2, solid_capstyle="butt")
    ax.text(left + length / 2.0, y0 - pad * 0.35, f"{length:g}", ha="center", va="bottom",
            fontsize=7)  # fmt: skip


def render_frame(mesh, view="front") -> Frame:
    """The :class:`Frame` of ``mesh`` rendered square with
    :func:`growsim.phenotypes.plant.views.render_image` (orthographic, framed on the bounding
    sphere of its bounds).

    Examples
    --------
    >>> import pyvista as pv
    >>> f = render_frame(pv.Line((0, 0, 0), (0, 2, 0)))
    >>> [round(v, 2) for v in f.image], [round(v, 2) for v in f.box]
    ([-1.02, 1.02, -0.02, 2.02], [0.0, 0.0, 0.0, 2.0])
    """

    d, up = view_vectors(view)
    b = np.asarray(mesh.bounds, float).reshape(3, 2)
    screen_up = np.asarray(up, float) - np.dot(up, d) * d
    screen_up /= np.linalg.norm(screen_up)
    right = np.cross(d, screen_up)
    centre = b.mean(1)
    half = max(float(np.linalg.norm(b[:, 1] - b[:, 0])) / 2.0, 1e-6) * 1.02
    corners = np.array(np.meshgrid(*b, indexing="ij")).reshape(3, -1).T
    x, y = corners @ right, corners @ screen_up
    cx, cy = float(centre @ right), float(centre @ screen_up)
    image = (cx - half, cx + half, cy - half, cy + half)
    return Frame(image, (float(x.min()), float(x.max()), float(y.min()), float(y.max())))


def save_png(fig, path: Path | None = None) -> bytes:
    """PNG bytes of a figure (and the file ``path``, written atomically); closes it.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> save_png(plt.figure(figsize=(1, 1)))[:4]
    b'\\x89PNG'
    """
    import matplotlib.pyplot as plt

    buf = io.BytesIO()
    fig.savefig(buf, format="png", bbox_inches="tight")  # titles of any length kept
    plt.close(fig)
    data = buf.getvalue()
    if path is not None:
        atomic_write(path, data)
    return data


def render_cells(families: Sequence[Family]) -> list[list[tuple[str, np.ndarray]]]:
    """Per family, (title, picture) of each group's best phenotype, and for a plant its
    :class:`Frame` (so that :func:`renders_figure` draws a family's plants at one scale);
    a group whose best run has no phenotype to render is left out (with a warning).

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
            title = f"{g.label}\nbest {best.best_fitness:.4g}"
            try:
                phenotype = best.phenotype()
                if isinstance(phenotype, Plant):  # plants: at one scale (renders_figure)
                    mesh = plant_mesh(phenotype)
                    img = render_image(mesh, view="front", size=(300, 300))
                    frame = render_frame(mesh) if mesh.n_points else None
                    title += f", height {phenotype.height():.3g}"
                    row.append((title, np.asarray(img), frame))
                    continue
                img = phenotype.render_image(view="front", size=(300, 300))
            except Exception as exc:  # a missing phenotype must not lose the table
                log.warning("%s: no best phenotype to render (%s)", best.path, exc)
                continue
            row.append((title, np.asarray(img)))
        cells.append(row)
    return cells
