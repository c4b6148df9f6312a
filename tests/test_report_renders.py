"""``compare``'s renders draw a family's best plants at one scale (issue 28, item 6): a
one-module stick must not stand as tall as a branched tree beside it."""

from __future__ import annotations

import numpy as np
from test_report import fake_run

from growsim.experiment.results import RunDir, find_runs
from growsim.models import honda
from growsim.phenotypes.plant import Plant
from growsim.report.figures import render_cells, renders_figure, save_png
from growsim.report.groups import families as find_families


def _runs(tmp_path):
    tree = honda.develop(honda.PRESETS["zelkova"])
    stick = Plant.from_points([[0, 0, 0], [0, 4, 0]], [-1], [-1, 0], meta={"model": "honda"})
    assert stick.n_segments == 1 and stick.height() < tree.height() / 5
    for light, plant, best in ((1.0, tree, 10.0), (0.5, stick, 5.0)):
        for seed in range(2):
            path = tmp_path / "sw" / f"light={light}" / f"seed-{seed}"
            fake_run(path, seed, best + seed, light=light)
            plant.save(RunDir(path).phenotype_path("plant"))
    return find_runs([tmp_path / "sw"]), tree, stick


def _ink_height(img: np.ndarray) -> int:
    """Rows of ``img`` holding anything but white."""
    rows = np.flatnonzero((np.asarray(img)[..., :3] < 200).any(axis=(1, 2)))
    return int(rows[-1] - rows[0] + 1) if rows.size else 0


def test_best_plants_are_drawn_at_one_scale(tmp_path):
    runs, tree, stick = _runs(tmp_path)
    tall = f"height {tree.height():.3g}"
    short = f"height {stick.height():.3g}"
    families = find_families(runs, [])
    cells = render_cells(families)
    assert [len(c) for c in cells] == [2]
    row = cells[0]
    assert all(len(c) == 3 and c[2] is not None for c in row)  # plants carry their frame
    assert any("height" in c[0] for c in row)
    fig = renders_figure([("", row)])
    limits = [(ax.get_xlim(), ax.get_ylim()) for ax in fig.axes[:2]]
    spans = {round(float(np.diff(lim)[0]), 9) for pair in limits for lim in pair}
    assert len(spans) == 1  # the same window size in every panel
    fig.savefig(tmp_path / "renders.png", dpi=100)
    # each panel as drawn: the stick stands a small part of the tree's height
    fig.canvas.draw()
    buf = np.asarray(fig.canvas.buffer_rgba())
    heights = []
    for ax in fig.axes[:2]:
        bb = ax.get_window_extent()
        h = buf.shape[0]
        panel = buf[int(h - bb.y1) + 1 : int(h - bb.y0) - 1, int(bb.x0) + 1 : int(bb.x1) - 1]
        # leave out the scale bar (bottom left); the plant stands in the middle
        heights.append(_ink_height(panel[:, int(panel.shape[1] * 0.35) :]))
    save_png(fig)
    by_title = dict(zip([c[0] for c in row], heights))
    tree_h = next(v for k, v in by_title.items() if tall in k)
    stick_h = next(v for k, v in by_title.items() if short in k)
    assert 0 < stick_h < tree_h / 5, by_title


def test_other_phenotypes_still_fill_their_panel():
    cells = [("a", np.zeros((8, 8, 3), np.uint8)), ("b", np.zeros((8, 8, 3), np.uint8))]
    fig = renders_figure([("", cells)])
    assert [ax.get_xlim() for ax in fig.axes] == [(-0.5, 7.5)] * 2
    save_png(fig)
