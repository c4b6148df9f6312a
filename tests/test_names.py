"""A seed in growsim is a random seed (issue 45, item 3): nothing a user reads calls a
source paper a "seed" (the README, every page of ``docs/``, the comments of every shipped
config, every ``--help``), and the names of 0.1 that did (``seed_ga``, ``seed_gradient``,
``hormone_*_seed_ga.toml``, ``ifs2d.seed_form``) are renamed after the paper and still
taken, with a note, until 0.3."""

from __future__ import annotations

import re
import warnings

import pytest
from conftest import ROOT
from golden.make import BUDGETS

from growsim.cli import build_parser, main
from growsim.models import MODELS, get_model

#: wording that calls a source paper a seed, and what to write instead
PAPER_AS_SEED = {
    r"seed_(?:ga|gradient|form)\b": "a name of 0.1: paper_ga, paper_gradient, paper_form",
    r"\bthe\s+(?:#\s*)?seed's\b": "the paper's (the report's: Endo; the thesis's: Okusa)",
    r"\bseed papers?\b": "the source paper",
    r"\bseed 00\d\b": "the paper by its authors (Kuwahara, Okusa, Liu & Zhang, Endo, Uehara)",
    r"\b(?:beyond|as|in|of) the seed\b(?![-\w])": "the paper",
    r"\bthe seed (?:says|gives|writes|summed|draws|uses|leaves|keeps)\b": "the paper",
    r"\bseed mode\b": "the report's mode",
}


def _comments(toml_text: str) -> str:
    """The comment part of each line of a TOML file (a ``#`` outside a string)."""
    out = []
    for line in toml_text.splitlines():
        quote = None
        for i, ch in enumerate(line):
            if quote:
                quote = None if ch == quote else quote
            elif ch in "'\"":
                quote = ch
            elif ch == "#":
                out.append(line[i:])
                break
    return "\n".join(out)


def _help(argv: list[str], capsys) -> str:
    with pytest.raises(SystemExit):
        main(argv)
    return capsys.readouterr().out


def _help_texts(capsys) -> dict[str, str]:
    parser = build_parser()
    subcommands = next(a for a in parser._actions if a.choices and "grow" in a.choices)
    texts = {"growsim --help": _help(["--help"], capsys)}
    for cmd in subcommands.choices:
        texts[f"growsim {cmd} --help"] = _help([cmd, "--help"], capsys)
    for model in MODELS:
        texts[f"growsim grow {model} --help"] = _help(["grow", model, "--help"], capsys)
    return texts


def _found(text: str) -> list[str]:
    return [
        f"{m.group(0)!r} ({instead})"
        for pattern, instead in PAPER_AS_SEED.items()
        for m in re.finditer(pattern, text, flags=re.IGNORECASE)
    ]


def test_the_patterns_catch_what_0_1_said():
    said = [
        "hormone_2d_seed_ga.toml is the\n# seed's GA.",
        "The seed writes each map as ... the seed's Fig. 2-3",
        "Presets: `table1`, `seed_ga` and `seed_gradient`",
        '# Seed 000, "Fitting a 3D fractal tree ..."',
        "random seed (the seed's set_rnd)",
        "beyond the seed: bending under sub-tree weight",
        "**Radius.** Seed mode (`pipe = 0`)",
        'model = "generational"  # the seed: elite kept (the seed keeps the best)',
    ]
    assert all(_found(s) for s in said), [s for s in said if not _found(s)]
    fine = [
        "random seed (overrides the preset's)",
        "seeds 1-8 (discovery), then 9-16; the seed of the run (overrides experiment.seed)",
        "the same config up to the seed, one run per seed; Seed 0: the first picture",
        "seed = 1\nrepeats = 8  # seeds per variant (seed, seed + 1, ...)",
    ]
    assert not any(_found(s) for s in fine), [_found(s) for s in fine]


def test_no_user_text_calls_a_paper_a_seed(capsys):
    texts = {p.relative_to(ROOT).as_posix(): p.read_text() for p in [
        ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]}  # fmt: skip
    for p in sorted((ROOT / "experiments").glob("*.toml")):
        texts[f"{p.relative_to(ROOT).as_posix()} (comments)"] = _comments(p.read_text())
    texts.update(_help_texts(capsys))
    assert len(texts) > 40
    found = {where: hits for where, text in texts.items() if (hits := _found(text))}
    assert not found, found


def test_the_configs_and_their_pins_are_named_after_the_paper():
    for dims in ("2d", "3d"):
        new = f"hormone_{dims}_paper_ga"
        assert (ROOT / "experiments" / f"{new}.toml").is_file()
        assert not (ROOT / "experiments" / f"hormone_{dims}_seed_ga.toml").exists()
        assert f'name = "{new}"' in (ROOT / "experiments" / f"{new}.toml").read_text()
        assert (ROOT / "tests" / "golden" / f"{new}.json").is_file() and new in BUDGETS
    presets = get_model("ifs3d").presets
    assert {"paper_ga", "paper_gradient"} <= set(presets) and "seed_ga" not in presets


def test_old_preset_names_work_with_a_deprecation_warning():
    ifs3d = get_model("ifs3d")
    for old, new in (("seed_ga", "paper_ga"), ("seed_gradient", "paper_gradient")):
        with pytest.warns(DeprecationWarning, match=f"preset '{old}' is now '{new}'"):
            assert ifs3d.preset(old) == ifs3d.preset(new)
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            assert ifs3d.preset_environment(old) == ifs3d.preset_environment(new)
            ifs3d.preset(new)  # the new name: no warning


def test_old_function_name_works_with_a_deprecation_warning():
    from growsim.models import ifs2d

    abcd = [[0.0, -0.5, 0.5, 0.0]]
    with pytest.warns(DeprecationWarning, match="seed_form is now ifs2d.paper_form"):
        old = ifs2d.seed_form(abcd)
    assert old.tolist() == ifs2d.paper_form(abcd).tolist()


def test_the_command_line_notes_an_old_preset_once(capsys):
    assert main(["grow", "ifs3d", "--preset", "seed_ga", "--json"]) == 0
    err = capsys.readouterr().err
    note = "growsim: note: preset 'seed_ga' is now 'paper_ga'; the old name goes in 0.3"
    assert err.splitlines() == [note]


@pytest.mark.parametrize("command", ["run", "sweep"])
def test_a_renamed_config_is_named(command, capsys):
    old = ROOT / "experiments" / "hormone_2d_seed_ga.toml"
    assert main([command, str(old)]) == 2
    err = capsys.readouterr().err
    assert "no such file; it was renamed" in err and "hormone_2d_paper_ga.toml" in err
