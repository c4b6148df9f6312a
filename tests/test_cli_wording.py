"""The small wording items of issue 28 (item 9): the end of a run says what ``show``
opens for the model; a missing picture names the key the user wrote; the "in use" refusal
on ``--resume`` does not say "choose another --out"; resuming a finished run says so and
rewrites nothing; the viewer window has a title and a key hint; the garden table prints 0
where it means 0 and no empty table."""

from __future__ import annotations

import types

import pandas as pd
import pytest
from conftest import ROOT
from test_report import fake_run

from growsim.cli import main
from growsim.errors import ConfigError, UserInputError
from growsim.experiment.results import RunDir


def test_the_end_of_a_run_says_what_show_opens(monkeypatch, tmp_path, capsys):
    import growsim.experiment

    summary = {"experiment": "fish", "best_fitness": 1.0, "best_generation": 0,
               "evaluations": 4, "wall_seconds": 0.1, "stop_reason": "generations"}  # fmt: skip
    for kind, said in (("trajectory", "fish's swim"), ("plant", "best plant")):
        result = types.SimpleNamespace(summary=summary, out=tmp_path, best={"phenotype": kind})
        monkeypatch.setattr(growsim.experiment, "run", lambda *a, r=result, **k: r)
        fish = ROOT / "experiments" / "fish_tank.toml"
        assert main(["run", str(fish), "--out", str(tmp_path)]) == 0
        out = capsys.readouterr().out
        assert said in out and "tree" not in out, out


def test_a_missing_picture_names_the_key_written(tmp_path):
    from growsim.experiment.load import load_plan

    cfg = tmp_path / "fit.toml"
    cfg.write_text(
        '[model]\nkind = "ifs3d"\nevolve = { s_1 = true }\n'
        '[[objective]]\nkind = "silhouette"\nfront = "nothere.png"\nviews = "front"\n'
    )
    with pytest.raises(ConfigError) as info:
        load_plan(cfg)
    assert str(info.value).startswith("objective.front: nothere.png")


def test_resuming_a_finished_run_rewrites_nothing(tmp_path, capsys):
    run_dir = tmp_path / "done"
    fake_run(run_dir, 0, 5.0)
    before = {p.name: p.stat().st_mtime_ns for p in run_dir.iterdir()}
    assert main(["run", "--resume", str(run_dir)]) == 0
    out = capsys.readouterr().out
    assert "finished" in out and "nothing to resume" in out
    assert {p.name: p.stat().st_mtime_ns for p in run_dir.iterdir()} == before
    from growsim.experiment import run

    again = run(None, run_dir, resume=True, progress=False)  # read back, not run again
    assert again.summary["best_fitness"] == 5.0
    assert {p.name: p.stat().st_mtime_ns for p in run_dir.iterdir()} == before


def test_in_use_on_resume_does_not_say_choose_another_out(tmp_path):
    from growsim.experiment import run

    run_dir = tmp_path / "busy"
    fake_run(run_dir, 0, 5.0)
    RunDir(run_dir).summary_path.unlink()  # an interrupted run
    with RunDir(run_dir).lock(), pytest.raises(UserInputError) as info:
        run(None, run_dir, resume=True, progress=False)
    assert "in use" in str(info.value) and "--out" not in str(info.value)
    with RunDir(run_dir).lock(), pytest.raises(UserInputError) as info:
        with RunDir(run_dir).lock():
            pass
    assert "choose another --out" in str(info.value)  # a fresh run may go elsewhere


def test_the_viewer_has_a_title_and_a_key_hint(monkeypatch, tmp_path):
    import pyvista as pv

    from growsim.cli.show import window_title
    from growsim.models import honda
    from growsim.phenotypes.plant import views
    from growsim.render import VIEWER_KEYS

    shown = {}

    class Plotter(pv.Plotter):
        def __init__(self, *a, **k):
            super().__init__(*a, off_screen=True, window_size=(64, 64))

        def add_text(self, text, *a, **k):
            shown.setdefault("texts", []).append(text)
            return super().add_text(text, *a, **k)

        def show(self, *a, title=None, **k):
            shown["title"] = title
            self.close()

    monkeypatch.setattr(pv, "Plotter", Plotter)
    monkeypatch.setenv("DISPLAY", ":99")
    views.show(honda.develop({"generations": 3}), title=window_title("runs/a", "plant", 3.5))
    assert shown["title"] == "growsim show runs/a: the best plant (fitness 3.5)"
    assert VIEWER_KEYS in shown["texts"] and "q: close" in VIEWER_KEYS
    shown.clear()
    from growsim.models.fish import develop

    develop({"frames": 100}).show(title="a swim")
    assert shown["title"] == "a swim" and VIEWER_KEYS in shown["texts"]


def test_the_garden_table_prints_zero_and_no_empty_table():
    from growsim.report.html import garden_html

    row = {"family": "f", "measure": "height", "origin": 2.8e-30, "garden": 0.75,
           "interaction": 0.0, "residual": 0.25, "n": 8}  # fmt: skip
    shares = pd.DataFrame([row])
    test = {"family": "f", "measure": "height", "within": "ample", "group_a": "a",
            "group_b": "b", "n_a": 4, "n_b": 4, "difference": 1.0, "diff_ci_low": 0.5,
            "diff_ci_high": 1.5, "cohen_d": 2.0, "cliffs_delta": 1.0, "welch_t_p": 0.001,
            "welch_t_p_holm": 0.002, "mann_whitney_p": 0.01, "mann_whitney_p_holm": 0.02,
            "contrast": "plastic", "note": ""}  # fmt: skip
    html = garden_html(pd.DataFrame([test]), shares)
    assert "e-30" not in html and "<td>0</td>" in html
    assert "genetic: origins in one garden, Holm p &lt; 0.05 (0)" not in html
    assert "genetic: origins in one garden, Holm p < 0.05 (0)" not in html
    assert "no test with Holm p &lt; 0.05" in html and "(1)" in html


def test_groups_are_named_by_the_sweeps_variant_names(tmp_path):
    from test_report import BASE

    from growsim.experiment.results import find_runs
    from growsim.report.groups import families

    base = {**BASE, "sweep": {"variants": [
        {"name": "ample"}, {"name": "half_water", "set": {"environment.water.supply": 0.5}},
    ]}}  # fmt: skip
    for name, supply in (("ample", 1.0), ("half_water", 0.5)):
        for seed in range(2):
            fake_run(tmp_path / "sw" / name / f"seed-{seed}", seed, 5.0 + seed, base=base,
                     overrides=[f"environment.water.supply={supply}"])  # fmt: skip
    (fam,) = families(find_runs([tmp_path / "sw"]), [])
    assert sorted(g.label for g in fam.groups) == ["ample", "half_water"]
    # runs of no named variant keep the labels of what differs
    for light in (1.0, 0.5):
        fake_run(tmp_path / "plain" / f"light={light}" / "seed-0", 0, 3.0, light=light)
    (fam,) = families(find_runs([tmp_path / "plain"]), [])
    assert sorted(g.label for g in fam.groups) == ["light.intensity=0.5", "light.intensity=1.0"]
