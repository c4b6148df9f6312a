"""``growsim grow``: outputs, JSON, and bad input -> exit code 2 with nothing written; the
help of ``grow``, ``show`` and ``fit-image``; views and sizes shared by the commands."""

from __future__ import annotations

import argparse
import json
import os

import pytest
from conftest import growsim

from growsim.cli import main
from growsim.errors import UserInputError
from growsim.phenotypes.plant import Plant


def test_grow_zelkova_outputs(tmp_path, capsys):
    glb, png, npz = tmp_path / "tree.glb", tmp_path / "tree.png", tmp_path / "tree.npz"
    rc = main(
        [
            "grow",
            "honda",
            "--preset",
            "zelkova",
            "--set",
            "f=0.8",
            "--export",
            str(glb),
            "--screenshot",
            str(png),
            "--save",
            str(npz),
            "--size",
            "64",
            "--json",
        ]
    )
    assert rc == 0
    info = json.loads(capsys.readouterr().out)
    c = info["counts"]
    assert info["params"]["f"] == 0.8 and info["seed"] == 3
    p = Plant.load(npz)
    assert c["stems"] == p.n_stems and c["tips"] == p.n_tips
    assert c["branch_points"] == p.n_branch_points and c["generations"] == 10
    assert c["mesh_vertices"] == p.n_stems * 12 + p.n_leaves * 7
    assert c["leaf_vertices"] == p.n_leaves * 7
    assert info["measures"]["height"] == pytest.approx(p.height())
    assert glb.read_bytes()[:4] == b"glTF" and png.stat().st_size > 0


def test_seed_overrides_preset(capsys):
    main(["grow", "honda", "--preset", "plane", "--json"])
    a = json.loads(capsys.readouterr().out)
    main(["grow", "honda", "--preset", "plane", "--seed", "11", "--json"])
    b = json.loads(capsys.readouterr().out)
    assert b["seed"] == 11 and a["counts"] == b["counts"]  # topology from (f, steps) only
    assert a["measures"]["height"] != b["measures"]["height"]


@pytest.mark.parametrize(
    "args,msg",
    [
        (["--preset", "oak"], "unknown preset 'oak'"),
        (["--set", "f=1.5"], "honda.f"),
        (["--set", "colour=3"], "colour"),
        (["--set", "f"], "NAME=VALUE"),
        (["--set", "f=1", "--set", "generations=26"], "would need|needs"),
        (["--export", "{d}/missing/t.glb"], "does not exist"),
        (["--export", "{d}/t.stl"], ".stl"),
        (["--screenshot", "{d}/t.jpg"], "png"),
    ],
)
def test_bad_input_exit_2(tmp_path, capsys, args, msg):
    args = [a.replace("{d}", str(tmp_path)) for a in args]
    assert main(["grow", "honda", *args]) == 2
    err = capsys.readouterr().err
    assert err.startswith("growsim: error:") and "Traceback" not in err
    assert any(m in err for m in msg.split("|")), err
    assert os.listdir(tmp_path) == []


def test_unknown_model_and_console_script(tmp_path):
    r = growsim("grow", "nosuch")
    assert r.returncode == 2 and "unknown model 'nosuch'" in r.stderr


def test_grow_other_registered_model(capsys):
    # the command is generic over growsim.models.MODELS: grow the IFS tree the same way
    from growsim.models import get_model

    preset = sorted(get_model("ifs3d").presets)
    args = ["grow", "ifs3d", "--json"] + (["--preset", preset[0]] if preset else [])
    assert main(args) == 0
    info = json.loads(capsys.readouterr().out)
    assert info["model"] == "ifs3d" and info["counts"]["stems"] > 0
    assert main(["grow", "ifs3d", "--set", "no_such_param=1"]) == 2


def _help(capsys, *argv) -> str:
    with pytest.raises(SystemExit) as exc:
        main(list(argv))
    assert exc.value.code == 0
    return capsys.readouterr().out


def test_grow_help_lists_every_models_parameters_and_presets(capsys):
    """docs/configs.md sends readers to ``growsim grow MODEL --help`` for a model's
    parameters: ``grow --help`` lists every registered model (one line each, with its
    presets) and stays short; ``grow MODEL --help`` lists that model's parameters (range,
    default) and presets."""
    from growsim.models import MODELS

    text = _help(capsys, "grow", "--help")
    assert len(text.splitlines()) < 80
    assert "growsim grow MODEL --help" in text
    for name in MODELS:
        model = MODELS.get(name)
        assert f"\n  {name} (" in text
        for preset in model.presets:
            assert preset in text
        one = _help(capsys, "grow", name, "--help")
        for p in model.params:
            assert f"\n  {p.name} " in one, p.name
    assert "0 .. 1, default 0.95" in _help(capsys, "grow", "honda", "--help")  # honda's f
    one = _help(capsys, "grow", "ifs3d", "--help")
    assert "theta_y_5" in one and "table1" in one
    assert "e_wandering_bush" not in one and "\n  theta0 " not in one


def test_fit_image_help_describes_every_option(capsys):
    from growsim.cli import build_parser

    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    for command in ("fit-image", "grow", "show"):
        sub.choices[command].fill_now()  # fit-image's options are added when first used
        for action in sub.choices[command]._actions:
            assert action.help, (command, action.dest)
    text = " ".join(_help(capsys, "fit-image", "--help").split())
    assert "between 0 (black) and 1 (white)" in text and "--line-width" in text


def test_fit_image_threshold_range(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["fit-image", "a.png", "b.png", "--out", "o", "--threshold", "128"])
    assert exc.value.code == 2
    assert "between 0 (black) and 1 (white), got '128'" in capsys.readouterr().err


def test_views_and_sizes_are_the_same_in_every_command(tmp_path, capsys):
    """``grow`` and ``show`` take the same views (VIEWS, ``back`` included) and the
    same ``--size`` (``W H``, or ``N`` for ``N x N``), checked against one limit
    (growsim.render.MAX_SIZE)."""
    from growsim.cli import build_parser
    from growsim.render import MAX_SIZE, MIN_SIZE, VIEWS, check_size

    parse = build_parser().parse_args
    for view in VIEWS:
        assert parse(["grow", "honda", "--view", view]).view == view
        assert parse(["show", "runs/a", "--view", view]).view == view
    for argv in (["grow", "honda"], ["show", "runs/a"]):
        assert tuple(parse([*argv, "--size", "64"]).size) == (64, 64)
        assert tuple(parse([*argv, "--size", "64", "48"]).size) == (64, 48)
        assert tuple(parse(argv).size) == (800, 800)
        with pytest.raises(SystemExit):
            parse([*argv, "--view", "nadir"])
        with pytest.raises(SystemExit):
            parse([*argv, "--size", "1", "2", "3"])
    capsys.readouterr()
    for command in ("grow", "show"):  # the help states the one limit
        text = " ".join(_help(capsys, command, "--help").split())
        assert f"each {MIN_SIZE}..{MAX_SIZE}" in text
        assert ", ".join(VIEWS) in text
    png = tmp_path / "t.png"
    assert main(["grow", "honda", "--set", "generations=3", "--screenshot", str(png),
                 "--size", "64", "48", "--view", "back"]) == 0  # fmt: skip
    from PIL import Image

    assert Image.open(png).size == (64, 48)
    big = str(MAX_SIZE + 1)
    for argv in (["grow", "honda"], ["show", str(tmp_path / "no_run")]):
        assert main([*argv, "--screenshot", str(tmp_path / "big.png"), "--size", big]) == 2
        err = capsys.readouterr().err
        assert f"[{MIN_SIZE}, {MAX_SIZE}]" in err, err
    with pytest.raises(UserInputError, match=str(MAX_SIZE)):
        check_size((int(big), 64))
