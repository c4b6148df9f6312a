"""Experiment configs: schema, defaults, overrides, error messages, fuzzing, docs."""

from __future__ import annotations

import copy
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest
from conftest import ROOT
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from growsim.errors import ConfigError, GrowsimError, UserInputError
from growsim.experiment import (
    Config,
    build_fitness,
    config_docs,
    load_config,
    parse_overrides,
    parse_vary,
)
from growsim.objectives import OBJECTIVES, get_objective
from growsim.options import fields_of

QUICK = ROOT / "experiments" / "quickstart.toml"

BASE = {
    "model": {"kind": "honda", "evolve": {"f": True, "theta0": [5.0, 30.0]}},
    "objective": [{"kind": "light", "wood_cost": 0.5}],
    "ga": {"population": 10, "generations": 3},
}


def cfg_with(**changes):
    d = copy.deepcopy(BASE)
    for path, value in changes.items():
        node = d
        parts = path.split("__")
        for p in parts[:-1]:
            node = node.setdefault(p, {})
        node[parts[-1]] = value
    return d


def test_defaults_are_filled_and_model_resolved():
    cfg = load_config(BASE)
    assert cfg.experiment.seed == 0 and cfg.experiment.name == "experiment"
    assert cfg.ga.coding == "real" and cfg.ga.elite == 1
    assert cfg.environment.light.direction == [0.0, -1.0, 0.0]
    # every fixed honda parameter is written out, the evolved ones are ranges
    from growsim.models.honda import PARAMS

    names = {p.name for p in PARAMS}
    assert set(cfg.model.params) == names - {"f", "theta0"}
    assert cfg.model.evolve == {"f": [0.0, 1.0], "theta0": [5.0, 30.0]}
    # the resolved config round-trips through TOML unchanged
    again = load_config(tomllib.loads(cfg.to_toml()))
    assert again.to_dict() == cfg.to_dict()


def test_preset_values_are_used_and_params_override_them():
    from growsim.models.honda import PRESETS

    cfg = load_config(cfg_with(model__preset="cherry", model__params={"thr": 0.25}))
    assert cfg.model.params["thq"] == PRESETS["cherry"]["thq"]
    assert cfg.model.params["thr"] == 0.25


@pytest.mark.parametrize(
    ("data", "needle"),
    [
        (cfg_with(ga__populaton=5), "ga.populaton: unknown key; allowed: population,"),
        (cfg_with(ga__population=1), "ga.population: Input should be greater than or equal to 2"),
        (cfg_with(ga__population="50"), "ga.population: Input should be a valid integer"),
        (cfg_with(ga__population=True), "ga.population"),
        (cfg_with(ga__coding="floats"), "ga.coding: Input should be 'real' or 'bits'"),
        (cfg_with(ga__bit_coding="x"), "'binary', 'gray', 'weighted' or 'fraction'"),
        (cfg_with(ga__generations=None), "no budget"),
        (cfg_with(ga__elite=10), "elite (10) must be smaller than population (10)"),
        (cfg_with(experiment__name="a b"), "experiment.name: String should match pattern"),
        (cfg_with(experiment__seed=-1), "experiment.seed"),
        (cfg_with(environment__light=-1.0), "environment.light.intensity: Input should be greater"),
        (cfg_with(environment__light_direction=[0, 0, 0]), "environment.light.direction"),
        (cfg_with(environment__light_direction=[0, 1]), "environment.light.direction"),
        (cfg_with(environment__light={"direction": [0, 1]}), "environment.light.direction"),
        (cfg_with(environment__water={"supply": -1}), "environment.water.supply"),
        (cfg_with(environment__gravity={"gee": 1}), "environment.gravity.gee: unknown key"),
        (
            cfg_with(environment__tank={"size": [10, 10, 10], "obstacles": [{"shape": "egg"}]}),
            "environment.tank.obstacles[0].shape",
        ),
        (cfg_with(output__mesh=["stl"]), "output.mesh[0]: Input should be 'vtp', 'ply'"),
        (cfg_with(output__size=[8, 8]), "output.size"),
        (cfg_with(model__kind="oak"), "model.kind: unknown model 'oak'; available: fish, honda"),
        (cfg_with(model__preset="oak"), "model.preset: unknown preset 'oak' of model 'honda'"),
        (
            cfg_with(model__params={"zz": 1.0}),
            "model.params.zz: unknown parameter of model 'honda'; allowed: generations",
        ),
        (cfg_with(model__params={"f": 1.5}), "model.params.f: 1.5 is out of range [0, 1]"),
        (cfg_with(model__params={"f": "x"}), "model.params.f: expected a number (got 'x')"),
        (cfg_with(model__evolve={}), "model.evolve: nothing to evolve"),
        (cfg_with(model__evolve={"zz": True}), "model.evolve.zz: unknown parameter"),
        (cfg_with(model__evolve={"f": [0.5, 2.0]}), "outside the model's range [0, 1]"),
        (cfg_with(model__evolve={"f": [0.9, 0.5]}), "expected finite low < high"),
        (cfg_with(model__evolve={"f": False}), "f = false"),
        (cfg_with(model__evolve={"f": [1]}), "f: expected true or [low, high], got [1]"),
        (cfg_with(objective=[]), "objective: List should have at least 1 item"),
        (cfg_with(objective=[{"kind": "sun"}]), "objective[0].kind: unknown objective 'sun'"),
        (cfg_with(objective=[{"kind": "light", "wood": 1}]), "objective[0].wood: unknown key"),
        (cfg_with(objective=[{"kind": "light", "wood_cost": -1}]), "objective[0].wood_cost"),
        (cfg_with(objective=[{"weight": 2.0}]), "objective[0].kind: required key missing"),
        (cfg_with(objective=[{"kind": "light", "weight": 0}]), "objective[0].weight"),
        (cfg_with(objective=[{"weight": 1.0}]), "objective[0].kind: required key missing"),
        ({"objective": [{"kind": "light"}]}, "model: required key missing"),
        (cfg_with(extra={"a": 1}), "extra: unknown key; allowed: experiment, model"),
    ],
)
def test_bad_configs_name_the_key_path(data, needle):
    with pytest.raises(ConfigError) as info:
        load_config(data)
    msg = str(info.value)
    assert needle in msg, msg
    assert "\n" not in msg


def test_unknown_operator_is_rejected():
    from growsim.ga import SELECTION  # first-party: an import error fails, never skips

    with pytest.raises(
        ConfigError, match=r"ga.selection: unknown selection operator 'nope'; available: "
    ) as info:
        load_config(cfg_with(ga__selection="nope"))
    assert ", ".join(sorted(SELECTION)) in str(info.value)


def test_overrides_parse_toml_values_and_aliases():
    got = parse_overrides(
        [
            "ga.population=50",
            "env.light=0.5",
            "model.preset=cherry",
            "objective.0.weight=2",
            "model.evolve.f=[0.5, 0.9]",
            "ga.extinction=false",
            'experiment.name="x y"',
        ]
    )
    assert got == [
        (["ga", "population"], 50),
        (["environment", "light"], 0.5),
        (["model", "preset"], "cherry"),
        (["objective", 0, "weight"], 2),
        (["model", "evolve", "f"], [0.5, 0.9]),
        (["ga", "extinction"], False),
        (["experiment", "name"], "x y"),
    ]


def test_overrides_apply_before_validation():
    cfg = load_config(
        BASE,
        [
            "ga.population=12",
            "env.light=0.25",
            "objective[0].weight=3",
            "model.evolve.thq=true",
            "objective[1].kind=light",
            "model.params.generations=5",
        ],
    )
    assert cfg.ga.population == 12 and cfg.environment.light.intensity == 0.25
    assert cfg.objective[0].weight == 3.0 and len(cfg.objective) == 2
    assert "thq" in cfg.model.evolve and cfg.model.params["generations"] == 5
    with pytest.raises(ConfigError, match=r"ga.population: Input should be greater"):
        load_config(BASE, ["ga.population=0"])
    with pytest.raises(ConfigError, match=r"index out of range"):
        load_config(BASE, ["objective[5].weight=1"])
    with pytest.raises(ConfigError, match=r"expected key.path=value"):
        load_config(BASE, ["ga.population"])
    with pytest.raises(ConfigError, match=r"ga.population is not a table"):
        load_config(BASE, ["ga.population.x=1"])


def test_vary_parsing():
    assert parse_vary(["env.light=1.0,0.5", "ga.population=[10, 20]"]) == {
        "environment.light": [1.0, 0.5],
        "ga.population": [10, 20],
    }
    with pytest.raises(UserInputError, match="given twice"):
        parse_vary(["env.light=1", "environment.light=2"])
    with pytest.raises(UserInputError, match="no values"):
        parse_vary(["env.light="])


def test_config_files_errors(tmp_path):
    with pytest.raises(UserInputError, match="no such config file"):
        load_config(tmp_path / "nope.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("[ga\npopulation = 3\n")
    with pytest.raises(ConfigError, match=r"bad.toml: invalid TOML"):
        load_config(bad)
    bad.write_bytes(b"\xff\xfe[ga]")
    with pytest.raises(ConfigError, match="not UTF-8"):
        load_config(bad)
    with pytest.raises(UserInputError, match="is a directory"):
        load_config(tmp_path)


@pytest.mark.parametrize(
    "path", sorted((ROOT / "experiments").glob("*.toml")), ids=lambda p: p.name
)
def test_every_shipped_experiment_validates(path):
    cfg = load_config(path)
    assert isinstance(cfg, Config)
    f = build_fitness(cfg)
    assert f.model.name == cfg.model.kind and len(f.evolved) >= 1
    # the resolved copy a run saves loads back to the same config
    assert load_config(tomllib.loads(cfg.to_toml())).to_dict() == cfg.to_dict()


def test_fitness_is_picklable_and_deterministic():
    import pickle

    import numpy as np

    f = build_fitness(load_config(QUICK))
    g = pickle.loads(pickle.dumps(f))
    x = np.array([[0.8, 20.0, 20.0, 0.3, 5.0, 2.0], [0.6, 10.0, 40.0, 0.1, 8.0, 1.0]])
    assert x.shape[1] == len(f.evolved)
    a, b = f(x), g(x, seeds=np.array([1, 2], dtype=np.uint64))
    assert np.array_equal(a, b) and np.all(np.isfinite(a)) and a[0] != a[1]


def test_docs_configs_md_is_generated_from_the_schema():
    from growsim.experiment.docs import config_pages

    pages = config_pages()  # docs/configs.md and one page per large section
    assert pages["configs.md"] == config_docs()
    for name, text in pages.items():
        page = (ROOT / "docs" / name).read_text()
        assert page == text, f"regenerate: python -m growsim.experiment --docs docs ({name})"
    doc = "".join(pages.values())
    for section, cls in Config.model_fields.items():
        subs = [cls.annotation]
        if section == "objective":  # one options class per registered objective
            subs = [get_objective(name).Options for name in OBJECTIVES]
        for sub in subs:
            for key in fields_of(sub):
                assert f"`{section}.{key}`" in doc
    for key in ("environment.light.direction", "environment.tank.obstacles.shape"):
        assert f"`{key}`" in doc


def test_docs_entry_point():
    out = subprocess.run(
        [sys.executable, "-m", "growsim.experiment", "--docs"],
        capture_output=True,
        text=True,
        check=True,
    )
    assert out.stdout == config_docs()


# ---- fuzzing: no traceback for any malformed config, always a GrowsimError ----------


_WORDS = ["ga", "model", "population", "objective", "kind", "honda", "light", "true", "inf"]
_WORDS += ["nan", "1e999", "[[", "]]", '"""']
_toml_chars = st.sampled_from([*"[]{}=.\"'#,\n -_0123456789abcdefgxyz", *_WORDS])


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(_toml_chars, max_size=40).map("".join))
def test_fuzz_random_text_never_crashes(tmp_path_factory, text):
    p = tmp_path_factory.mktemp("fz") / "c.toml"
    p.write_text(text)
    try:
        load_config(p)
    except GrowsimError as exc:
        assert str(exc) and "\n" not in str(exc).strip()


_leaf = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(-5, 10**20),
    st.floats(allow_nan=True),
    st.text(max_size=8),
    st.lists(st.integers(-3, 3), max_size=4),
)
_paths = st.sampled_from(
    [
        ("ga", "population"),
        ("ga", "generations"),
        ("ga", "coding"),
        ("ga", "elite"),
        ("ga", "polish"),
        ("ga", "islands"),
        ("model", "kind"),
        ("model", "preset"),
        ("model", "params"),
        ("model", "evolve"),
        ("model", "evolve", "f"),
        ("model", "params", "f"),
        ("environment", "light_direction"),
        ("environment",),
        ("objective",),
        ("objective", 0),
        ("objective", 0, "kind"),
        ("objective", 0, "wood_cost"),
        ("objective", 0, "resolution"),
        ("output", "mesh"),
        ("output", "size"),
        ("experiment", "seed"),
        ("experiment", "name"),
        ("experiment",),
        ("zz",),
    ]
)


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(_paths, _leaf), min_size=1, max_size=4))
def test_fuzz_structured_mutations_never_crash(mutations):
    data = copy.deepcopy(BASE)
    for path, value in mutations:
        node = data
        for p in path[:-1]:
            if isinstance(node, dict):
                node = node.setdefault(p, {})
            elif isinstance(node, list) and isinstance(p, int) and p < len(node):
                node = node[p]
            else:
                break
        else:
            if isinstance(node, dict) and isinstance(path[-1], str):
                node[path[-1]] = value
            elif isinstance(node, list) and isinstance(path[-1], int) and path[-1] < len(node):
                node[path[-1]] = value
    try:
        load_config(data)
    except GrowsimError as exc:
        assert str(exc) and "\n" not in str(exc).strip()


def test_relative_image_paths_resolve_next_to_the_config(tmp_path, monkeypatch):
    from PIL import Image, ImageDraw

    d = tmp_path / "exp"
    d.mkdir()
    for name in ("front.png", "side.png"):
        im = Image.new("L", (64, 64), 255)
        ImageDraw.Draw(im).polygon([(32, 5), (10, 50), (54, 50)], fill=0)
        ImageDraw.Draw(im).rectangle([30, 50, 34, 62], fill=0)
        im.save(d / name)
    (d / "fit.toml").write_text(
        '[model]\nkind = "honda"\nevolve = { f = true }\n'
        '[[objective]]\nkind = "silhouette"\nfront = "front.png"\nside = "side.png"\n'
    )
    monkeypatch.chdir(tmp_path)  # not the config's directory
    cfg = load_config("exp/fit.toml")
    opts = cfg.objective[0]
    assert opts.front == str((d / "front.png").resolve())
    assert Path(opts.side).is_absolute()
    # the saved copy loads from anywhere
    monkeypatch.chdir(d)
    assert load_config(tomllib.loads(cfg.to_toml())).to_dict() == cfg.to_dict()
    # a path that exists nowhere is left to the objective, which names it
    with pytest.raises(GrowsimError, match=r"nope\.png"):
        load_config("fit.toml", ["objective[0].front=nope.png"])


def test_commands_in_the_shipped_configs_name_directories_they_make():
    """A config's comments say how to run and compare it: every directory a commented
    ``growsim compare DIR`` reads is the ``--out DIR`` of a commented run or sweep."""
    import re

    for path in sorted((ROOT / "experiments").glob("*.toml")):
        lines = [ln.lstrip("# ").strip() for ln in path.read_text().splitlines()]
        made = {m for ln in lines if ln.startswith("growsim ")
                for m in re.findall(r"--out (\S+)", ln)}  # fmt: skip
        for ln in lines:
            if ln.startswith("growsim compare "):
                dirs = [a for a in ln.split("#")[0].split()[2:] if not a.startswith("-")]
                assert dirs and set(dirs) <= made, (path.name, ln, made)
