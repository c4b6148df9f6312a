"""Views: off-screen renders are not blank, differ by view, keep the LOD silhouette."""

from __future__ import annotations

import os

import numpy as np
import pandas as pd
import pytest
from conftest import growsim
from PIL import Image

from growsim.errors import UserInputError
from growsim.experiment.results import plot_fitness
from growsim.models import honda
from growsim.phenotypes.plant import views as viz
from growsim.phenotypes.plant.mesh import lod_meshes


@pytest.fixture(scope="module")
def tree():
    return honda.develop(honda.PRESETS["plane"])


def _mask(img):
    return np.any(img < 200, axis=2)  # anything not near-white background


def test_render_not_blank_and_views_differ(tree):
    front = viz.render_image(tree, view="front", size=(128, 128))
    top = viz.render_image(tree, view="top", size=(128, 128))
    mf, mt = _mask(front), _mask(top)
    assert 0.02 < mf.mean() < 0.9 and 0.02 < mt.mean() < 0.9
    assert (mf ^ mt).mean() > 0.05
    # the tree stands: in the front view its lowest pixels are the trunk, in the middle
    rows = np.flatnonzero(mf.any(1))
    bottom = np.flatnonzero(mf[rows[-1]])
    assert abs(bottom.mean() - 64) < 20
    # bark and leaf colours both show
    greenish = (front[..., 1].astype(int) - front[..., 0] > 20) & mf
    assert greenish.sum() > 20 and (mf & ~greenish).sum() > 20
    with pytest.raises(UserInputError, match="view"):
        viz.render_image(tree, view="nadir")


def test_lod_silhouettes_agree(tree):
    def blocks(img):  # 4x4 blocks touched by the plant: the silhouette at 1/4 resolution
        return _mask(img).reshape(40, 4, 40, 4).any(axis=(1, 3))

    masks = [blocks(viz.render_image(m, size=(160, 160))) for m in lod_meshes(tree)]
    for m in masks[1:]:
        iou = (m & masks[0]).sum() / (m | masks[0]).sum()
        assert iou > 0.8, iou


def test_screenshot_grid_and_plot(tmp_path, tree):
    f = viz.screenshot(tree, tmp_path / "t.png", size=(96, 80), view="iso")
    assert Image.open(f).size == (96, 80)
    g = viz.render_grid(
        [tree, tree, tree], tmp_path / "g.png", titles=["a", "b", "c"], cell=(64, 64), columns=2
    )
    assert Image.open(g).size == (128, 2 * (64 + 18))
    h = pd.DataFrame(
        {
            "generation": [0, 0, 1, 1],
            "island": [0, 1, 0, 1],
            "best": [1.0, 2.0, 3.0, 2.5],
            "mean": [0.5, 1, 2, 2],
        }
    )
    p = plot_fitness(h, tmp_path / "f.png", title="run")
    assert Image.open(p).size[0] > 100
    with pytest.raises(UserInputError, match="generation"):
        plot_fitness(pd.DataFrame({"x": [1]}), tmp_path / "x.png")
    with pytest.raises(UserInputError, match="png"):
        viz.screenshot(tree, tmp_path / "t.jpg")
    with pytest.raises(UserInputError, match="titles"):
        viz.render_grid([tree], tmp_path / "g2.png", titles=["a", "b"])
    assert sorted(os.listdir(tmp_path)) == ["f.png", "g.png", "t.png"]


def test_turntable_and_growth_animation(tmp_path, tree):
    f = viz.turntable(tree, tmp_path / "t.gif", frames=5, size=(48, 48))
    im = Image.open(f)
    assert im.n_frames == 5
    frames = []
    for i in range(im.n_frames):
        im.seek(i)
        frames.append(np.asarray(im.convert("RGB")))
    assert not np.array_equal(frames[0], frames[1])  # it turns
    ps = [honda.develop({**honda.PRESETS["plane"], "generations": g}) for g in (2, 5, 8)]
    a = viz.growth_animation(ps, tmp_path / "g.gif", size=(48, 48))
    im = Image.open(a)
    assert im.n_frames == 3
    sizes = []
    for i in range(3):
        im.seek(i)
        sizes.append(_mask(np.asarray(im.convert("RGB"))).sum())
    assert sizes[0] < sizes[1] < sizes[2]  # fixed framing: the tree grows in the frame
    with pytest.raises(UserInputError, match="gif"):
        viz.turntable(tree, tmp_path / "t.avi")
    with pytest.raises(UserInputError, match="no plants"):
        viz.growth_animation([], tmp_path / "e.gif")


def test_show_without_display(monkeypatch, tree):
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    with pytest.raises(UserInputError, match="display"):
        viz.show(tree)


def test_turntable_mp4(tmp_path, tree):
    pytest.importorskip("imageio_ffmpeg")
    import imageio.v2 as imageio

    f = viz.turntable(tree, tmp_path / "t.mp4", frames=6, size=(64, 64))
    r = imageio.get_reader(f)
    try:
        assert r.count_frames() == 6
    finally:
        r.close()
    assert os.listdir(tmp_path) == ["t.mp4"]


def test_offscreen_rendering_prints_nothing_on_stderr(tmp_path, tree):
    """Without a display VTK used to print a coloured "bad X server connection" warning on
    every render (every screenshot of grow, show, run, fit-image): renders are quiet, and
    VTK's warning switch is left as it was."""
    import subprocess
    import sys

    from vtkmodules.vtkCommonCore import vtkObject

    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    png = tmp_path / "t.png"
    code = (
        "import sys; from growsim.models import honda; "
        "from growsim.phenotypes.plant.views import screenshot; "
        "screenshot(honda.develop({'generations': 3}), sys.argv[1], size=(64, 64))"
    )
    r = subprocess.run([sys.executable, "-c", code, str(png)], capture_output=True, text=True,
                       env=env)  # fmt: skip
    assert r.returncode == 0 and png.is_file()
    assert r.stderr == ""
    r = growsim("grow", "honda", "--set", "generations=3", "--screenshot", tmp_path / "g.png",
                "--size", "64", env=env)  # fmt: skip
    assert r.returncode == 0 and r.stderr == ""
    before = vtkObject.GetGlobalWarningDisplay()
    viz.render_image(tree, size=(32, 32))
    assert vtkObject.GetGlobalWarningDisplay() == before
