"""``growsim grow MODEL --preset P`` grows the plant the docs show (issue 28, item 1): every
preset of every plant model grows a plant of more than one segment; a preset may carry its
environment (hormone's demo genomes: the sun a little from the side and a sky); ``grow``
and ``show`` take an experiment's environment (``--config FILE``, ``--environment FILE``).
Also ``grow --help`` is short, a model's parameters are in ``grow MODEL --help`` (item 8).
"""

from __future__ import annotations

import json

import pytest
from conftest import ROOT

from growsim.cli import main
from growsim.models import MODELS

PLANT_PRESETS = [
    (name, preset)
    for name in MODELS
    if MODELS.get(name).phenotype == "plant"
    for preset in sorted(MODELS.get(name).presets)
]


def _grow(capsys, *argv) -> dict:
    assert main(["grow", *argv, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_every_plant_model_is_covered():
    assert {"hormone", "honda", "ifs3d"} <= {name for name, _ in PLANT_PRESETS}


@pytest.mark.parametrize(("model", "preset"), PLANT_PRESETS)
def test_every_preset_grows_a_plant(capsys, model, preset):
    """Conformance: a plain ``grow MODEL --preset P`` gives more than one segment."""
    counts = _grow(capsys, model, "--preset", preset)["counts"]
    assert counts["segments"] > 1, (model, preset, counts)
    assert counts["branch_points"] >= 1, (model, preset, counts)


def test_hormone_demo_3d_is_a_branched_plant(capsys):
    """The bar of issue 28: >= 100 modules and branch points, in the preset's own
    environment (the docs' 300-module plant); the default light alone gives a stick."""
    info = _grow(capsys, "hormone", "--preset", "demo_3d")
    assert info["counts"]["segments"] >= 100 and info["counts"]["branch_points"] > 0
    assert info["environment"] == "preset demo_3d"
    demo_2d = _grow(capsys, "hormone", "--preset", "demo_2d")["counts"]
    assert demo_2d["segments"] == 140  # docs/models/hormone.md
    stick = _grow(capsys, "hormone", "--preset", "demo_3d", "--environment", "/dev/null")
    assert stick["counts"]["segments"] <= 2  # a stick: walls that see no sun


def test_preset_environment_under_an_option(capsys):
    """Options set keys over the preset's environment (its sky stays)."""
    from growsim.models import get_model

    env = get_model("hormone").preset_environment("demo_3d")
    assert env["light"]["diffuse"] == 0.5
    get_model("hormone").preset_environment("demo_3d")["light"]["diffuse"] = 0  # a copy
    assert get_model("hormone").preset_environment("demo_3d")["light"]["diffuse"] == 0.5
    info = _grow(capsys, "hormone", "--preset", "demo_3d", "--set", "steps=8",
                 "--light-intensity", "0.5")  # fmt: skip
    assert info["counts"]["segments"] > 1


def test_presets_do_not_change_experiments():
    """An experiment naming a preset keeps its own [environment] (the golden pins hold)."""
    from growsim.experiment.load import read_config

    cfg = read_config(
        {"model": {"kind": "hormone", "preset": "demo_3d"}, "objective": [{"kind": "nutrient"}]}
    )
    assert cfg.environment.light.diffuse == 0.0


def test_config_and_environment_files(capsys, tmp_path):
    config = ROOT / "experiments" / "hormone_2d.toml"  # from the test file, not the cwd
    a = _grow(capsys, "hormone", "--preset", "demo_2d", "--config", str(config))
    assert a["environment"] == f"--config {config}"
    assert a["counts"]["segments"] > 1
    env = tmp_path / "env.toml"
    env.write_text("[light]\ndirection = [0.3, -1.0, 0.2]\ndiffuse = 0.5\n")
    b = _grow(capsys, "hormone", "--preset", "demo_2d", "--environment", str(env))
    assert b["counts"] == _grow(capsys, "hormone", "--preset", "demo_2d")["counts"]
    # an [environment] table in the file works the same
    env.write_text("[environment.light]\ndirection = [0.3, -1.0, 0.2]\ndiffuse = 0.5\n")
    c = _grow(capsys, "hormone", "--preset", "demo_2d", "--environment", str(env))
    assert c["counts"] == b["counts"]


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("[light]\ncolour = 1\n", "environment.light.colour: unknown key"),
        ("[light]\ndirection = [0, 0, 0]\n", "environment.light.direction:"),
        ("[light\n", "invalid TOML"),
    ],
)
def test_bad_environment_file_is_refused(capsys, tmp_path, text, message):
    env = tmp_path / "env.toml"
    env.write_text(text)
    png = tmp_path / "p.png"
    assert main(["grow", "honda", "--environment", str(env), "--screenshot", str(png)]) != 0
    err = capsys.readouterr().err
    assert message in err and str(env) in err and len(err.strip().splitlines()) == 1
    assert not png.exists()


def test_bad_config_is_refused_naming_the_option(capsys, tmp_path):
    cfg = tmp_path / "c.toml"
    cfg.write_text('[model]\nkind = "honda"\n[[objective]]\nkind = "light"\n[ga]\npopulaton = 3\n')
    assert main(["grow", "honda", "--config", str(cfg)]) != 0
    err = capsys.readouterr().err
    assert f"--config {cfg}" in err and "ga.populaton" in err
    assert main(["grow", "honda", "--config", str(tmp_path / "none.toml")]) != 0
    assert "no such config file" in capsys.readouterr().err


def test_config_and_environment_exclude_each_other(capsys):
    with pytest.raises(SystemExit):
        main(["grow", "honda", "--config", "a.toml", "--environment", "b.toml"])
    assert "not allowed with" in capsys.readouterr().err


def test_grow_help_is_short_and_per_model(capsys):
    """Item 8: ``grow --help`` is one screen; ``grow MODEL --help`` that model's."""
    with pytest.raises(SystemExit):
        main(["grow", "--help"])
    text = capsys.readouterr().out
    assert len(text.splitlines()) <= 70 and "h0_bias" not in text
    with pytest.raises(SystemExit):
        main(["grow", "hormone", "--help"])
    one = capsys.readouterr().out
    assert "h0_bias" in one and "cherry" not in one


def test_show_colours_by_another_environment(capsys, tmp_path):
    from test_report import fake_run

    from growsim.experiment.results import RunDir
    from growsim.models import honda

    run_dir = tmp_path / "run"
    fake_run(run_dir, 0, 5.0)
    honda.develop({"generations": 4}).save(RunDir(run_dir).phenotype_path("plant"))
    env = tmp_path / "env.toml"
    env.write_text("[light]\ndirection = [1, 0, 0]\ndiffuse = 0.5\n")
    png = tmp_path / "lit.png"
    argv = ["show", str(run_dir), "--color", "light", "--size", "64", "--screenshot", str(png)]
    assert main([*argv, "--environment", str(env)]) == 0
    assert png.is_file()
    png.unlink()
    env.write_text("[light]\ncolour = 1\n")
    assert main([*argv, "--environment", str(env)]) != 0
    assert "environment.light.colour: unknown key" in capsys.readouterr().err
    assert not png.exists()
    config = ROOT / "experiments" / "hormone_3d.toml"
    assert main([*argv, "--config", str(config)]) == 0 and png.is_file()
