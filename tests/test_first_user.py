"""What a new user met (issue 45, item 8), each fixed and kept so: the hormones numbered
the same in ``grow hormone --help`` and ``docs/models/hormone.md``; ``grow --json``'s leaves
are the leaves drawn; Honda's unit stated; ``.mp4`` says it needs the video extra; the
tube options show their defaults; ``grow`` and ``show`` the same default view; the README
gives the Python version and the tests' time; ``compare --help`` opens short."""

from __future__ import annotations

import json
import re
import sys
import tomllib

import pytest
from conftest import ROOT

from growsim.cli import build_parser, main
from growsim.errors import UserInputError


def _help(argv: list[str], capsys) -> str:
    with pytest.raises(SystemExit):
        main(argv)
    return capsys.readouterr().out


def test_hormones_are_numbered_alike_in_help_and_docs(capsys):
    """(a) The paper names no numbers; the genes are ``h0_*`` .. ``h9_*``: from 0."""
    from growsim.kernels.hormone import HORMONES

    page = (ROOT / "docs" / "models" / "hormone.md").read_text()
    listed = re.search(r"for each of the ten hormones `k` \((.*?)\):", page, flags=re.S)
    numbered = dict(re.findall(r"(\d) (\w+)", listed.group(1)))
    assert numbered == {str(k): name for k, name in enumerate(HORMONES)}
    text = _help(["grow", "hormone", "--help"], capsys)
    for k, name in enumerate(HORMONES):
        assert re.search(rf"^  h{k}_bias .* {name}: synthesis bias$", text, flags=re.M)
    # every "hormone N" a parameter's help names is that parameter's own hormone
    for param, k in re.findall(r"^  (\w+) .*\bhormone (\d)\b", text, flags=re.M):
        assert param.startswith(numbered[k][:6]), (param, k, numbered[k])


@pytest.mark.parametrize(("model", "preset"), [("hormone", "demo_3d"), ("honda", "zelkova")])
def test_grow_counts_the_leaves_it_draws(model, preset, capsys):
    """(b) A hormone plant's green modules are drawn as leaf blades: counted as leaves."""
    from growsim.kernels.mesh import LEAF_VERTS

    assert main(["grow", model, "--preset", preset, "--json"]) == 0
    counts = json.loads(capsys.readouterr().out)["counts"]
    assert counts["leaves"] > 0
    assert counts["leaves"] * LEAF_VERTS == counts["leaf_vertices"]
    assert counts["leaf_modules"] == (counts["leaves"] if model == "hormone" else 0)


def test_honda_states_its_unit(capsys):
    """(c) Honda's lengths are metres, as the stand and environment pages read them."""
    text = _help(["grow", "honda", "--help"], capsys)
    for name in ("bd", "b0", "b_max", "radius", "leaf_radius"):
        assert re.search(rf"^  {name} +real +[\d.]+ \.\. [\d.]+ m, default", text, flags=re.M)
    page = (ROOT / "docs" / "models" / "honda.md").read_text()
    assert re.search(r"\*\*Units\.\*\* Lengths .* are metres", page)


def test_mp4_says_it_needs_the_video_extra(capsys, monkeypatch, tmp_path):
    """(d) Wherever ``.mp4`` is offered, the ``video`` extra is named."""
    assert (
        "video"
        in tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["optional-dependencies"]
    )
    text = _help(["grow", "--help"], capsys)
    gif = re.search(r"--gif PATH +(.*?)\n  --", text, flags=re.S).group(1)
    assert ".mp4" in gif and "growsim[video]" in gif
    plant_page = (ROOT / "docs" / "plant.md").read_text()
    for line in plant_page.splitlines():
        if "MP4" in line or ".mp4" in line:
            assert "video extra" in line, line
    from growsim.render import frames_writer

    monkeypatch.setitem(sys.modules, "imageio_ffmpeg", None)  # not installed
    with pytest.raises(UserInputError, match=r'pip install "growsim\[video\]"'):
        frames_writer(tmp_path / "a.mp4", fps=4)


def test_tube_options_show_their_defaults(capsys):
    """(e)"""
    text = _help(["grow", "--help"], capsys)
    assert re.search(r"--sides SIDES +tube polygon sides \(default 6\)", text)
    assert re.search(r"--segments SEGMENTS +tube pieces per segment \(default 1\)", text)


def test_grow_and_show_have_the_same_default_view():
    """(f) Front (docs/plant.md's pictures; a 2D plant face on), in both."""
    from growsim.cli.arguments import DEFAULT_VIEW

    grow = build_parser().parse_args(["grow", "honda"])
    show = build_parser().parse_args(["show", "runs/a"])
    assert grow.view == show.view == DEFAULT_VIEW == "front"


def test_readme_gives_python_version_and_test_time():
    """(g)"""
    readme = (ROOT / "README.md").read_text()
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert project["requires-python"] == ">=3.11"
    assert "Python 3.11 or newer" in readme
    setup = readme[readme.index("## Set-up") : readme.index("## Headline")]
    assert re.search(r"tests \(the whole suite: about \d+ minutes on 2 cores\)", setup)


def test_compare_help_opens_short(capsys):
    """(h) Two or three lines; the details in docs/compare.md."""
    text = _help(["compare", "--help"], capsys)
    description = text.split("\n\n")[1]
    assert len(description.splitlines()) <= 3, description
    assert "docs/compare.md" in description


def test_fit_image_has_one_way_to_keep_the_setups_leaves(capsys):
    """``--no-leaves`` meant ``--leaves keep``: dropped, ``--leaves keep`` is the one way."""
    parser = build_parser()
    assert (
        parser.parse_args(["fit-image", "t.png", "--out", "o", "--leaves", "keep"]).leaves == "keep"
    )
    with pytest.raises(SystemExit) as stop:
        parser.parse_args(["fit-image", "t.png", "--out", "o", "--no-leaves"])
    assert stop.value.code == 2
    assert "--no-leaves" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        parser.parse_args(["fit-image", "--help"])
    assert "--no-leaves" not in capsys.readouterr().out
