"""The fit's options are one schema (:class:`growsim.fitting.FitOptions`): the keywords of
``fit_image``, the flags of ``growsim fit-image`` and the saved state
(:class:`growsim.fitting.FitState`, what ``--resume`` reads) take their names from it;
a bad option is refused naming its flag before any work; a state written before states
had a version is still resumed, to the same fit."""

from __future__ import annotations

import argparse
import json

import pytest
from golden.make import table1_drawing

from growsim.cli import build_parser, main
from growsim.errors import UserInputError
from growsim.fitting import FitOptions, FitState, fit_image
from growsim.fitting.options import flag
from growsim.fitting.state import FIT_STATE, STATE_VERSION

#: the command's own arguments: how the fit runs, not what it fits
RUNNING = {"help", "out", "resume", "workers", "quiet"}


def _actions():
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    fit = sub.choices["fit-image"]
    fit.fill_now()  # its options are added when it is first used (fill_later)
    return {a.dest: a for a in fit._actions}


def test_the_flags_are_the_schema():
    """Every option of the schema is a flag of the command (or its positional picture),
    with the field's default and a help text; the command has no other option but how
    it runs."""
    actions = _actions()
    assert set(actions) == set(FitOptions.model_fields) | RUNNING
    for name, form in FitOptions.cli().items():
        action = actions[name]
        assert action.default == form["default"] and action.help, name
        if form["flag"] is None:
            assert not action.option_strings, name
        else:
            assert action.option_strings == [flag(name)], name
        if form["choices"] is not None:
            assert tuple(action.choices) == form["choices"], name
    args = build_parser().parse_args(["fit-image", "t.png", "--out", "o", "--box", "1,2,3,4"])
    options = FitOptions.parse({k: getattr(args, k) for k in FitOptions.model_fields})
    assert options.box == [1.0, 2.0, 3.0, 4.0] and options == FitOptions(
        front="t.png", box=[1, 2, 3, 4]
    )


@pytest.mark.parametrize(
    "bad, message",
    [
        ({"restarts": 0}, "--restarts: at least 1, got 0"),
        ({"evaluations": 10}, "--evaluations: at least 100, got 10"),
        ({"budget": 1000}, "--budget: expected 0.01..100, got 1000"),
        ({"size": 4}, "--size: expected 8..1024, got 4"),
        ({"sizes": (64, 32)}, "--sizes: expected increasing raster sizes"),
        ({"box": (1, 2)}, "--box: expected 4 numbers, got (1, 2)"),
        ({"box_side": (10, 20, 5, 40)}, "--box-side: expected x0,y0,x1,y1 with x0 < x1"),
        ({"point": ("a", 2)}, "--point: expected 2 numbers"),
        ({"threshold": 128}, "--threshold: expected 'otsu' or a grey level between 0"),
        ({"segmentation": "otsu"}, "--segmentation: expected one of auto, photo, threshold"),
        ({"leaves": "some"}, "--leaves: expected one of auto, fit, bare, keep, got 'some'"),
        ({"line_width": "fat"}, "--line-width: expected one of thin, radius, got 'fat'"),
        ({"seed": 1.5}, "--seed: Input should be a valid integer"),
        ({"colour": "red"}, "unknown option 'colour'; the options: front, side, model"),
    ],
)
def test_a_bad_option_is_refused_naming_its_flag_before_any_work(bad, message, tmp_path):
    with pytest.raises(UserInputError, match="^" + message.replace("(", r"\(").replace(")", r"\)")):
        fit_image("tree.jpg", out=tmp_path / "never", **bad)
    assert not (tmp_path / "never").exists()


def test_options_and_keywords_are_one_set(tmp_path):
    """``options=`` and keywords give the same options (the keywords over ``options``);
    paths are kept as given, and made absolute in the saved state only."""
    options = FitOptions(front="tree.jpg", model="honda", sizes=[32, 64])
    with pytest.raises(UserInputError, match="--restarts: at least 1"):
        fit_image(options=options, out=tmp_path / "never", restarts=0)
    with pytest.raises(UserInputError, match="--resume: give the fit's directory alone"):
        fit_image(options=options, out=tmp_path / "never", resume=True)
    with pytest.raises(UserInputError, match="no picture given"):
        fit_image(out=tmp_path / "never", model="honda")
    state = FitState(options=options.absolute())
    assert state.options.front.endswith("/tree.jpg") and state.options.front != "tree.jpg"
    assert state.options.model_copy(update={"front": "tree.jpg"}) == options


def test_the_state_is_read_back_and_refused_when_it_cannot_be(tmp_path):
    """The state round-trips; an old state (no version) is read as the new one; a newer
    version, a damaged file, options no longer valid and a finished fit are refused with
    one line saying why."""
    options = FitOptions(front="/pics/tree.jpg", model="honda", point=[150, 120])
    decided = {"first_size": {"honda bare": {"ncc": 0.8, "score": 0.7}},
               "judged": {"honda/bare": 0.7}, "kept": ["honda", "bare"],
               "carried": [["honda", "bare", 0]]}  # fmt: skip
    state = FitState(options=options).done("choose", "segment").updated(decided=decided)
    assert FitState.read(state.write(tmp_path).parent) == state
    written = json.loads((tmp_path / FIT_STATE).read_text())
    assert written["version"] == STATE_VERSION and written["options"]["point"] == [150.0, 120.0]
    old = {"options": {k: written["options"][k] for k in written["options"]}, "decided": decided}
    (tmp_path / FIT_STATE).write_text(json.dumps(old))
    read = FitState.read(tmp_path)
    assert read.options == options and read.decided.carried == [("honda", "bare", 0)]
    for data, message in (
        ({**old, "version": STATE_VERSION + 1}, "a fit state of version 3; this growsim reads"),
        ({"decided": decided}, "not a fit's state"),
        (
            {"options": {**old["options"], "restarts": 0}},
            "cannot resume it, its options: --restarts",
        ),
        ({"options": {**old["options"], "colour": 1}}, "its options: unknown option 'colour'"),
        ({**old, "decided": {"kept": "honda"}}, "cannot resume it: decided"),
    ):
        (tmp_path / FIT_STATE).write_text(json.dumps(data))
        with pytest.raises(UserInputError, match=message):
            FitState.read(tmp_path)
    (tmp_path / FIT_STATE).write_text("{")
    with pytest.raises(UserInputError, match="not a fit's state"):
        FitState.read(tmp_path)
    (tmp_path / "fit.json").write_text("{}")
    with pytest.raises(UserInputError, match="this fit is finished"):
        FitState.read(tmp_path)


def test_a_fit_saved_by_the_old_state_is_resumed_to_the_same_fit(tmp_path, capsys):
    """A fit whose state has no version (as fit-image wrote it before FitOptions: the
    options under their names, the decision) is resumed to the same fit; its new state
    names every stage finished."""
    pictures = table1_drawing(tmp_path / "pictures")
    out = tmp_path / "fit"
    kw = dict(model="ifs3d", evaluations=100, workers=1, progress=False)
    whole = fit_image(*pictures, out=out, **kw)
    state = json.loads((out / FIT_STATE).read_text())
    assert state["finished"] == ["choose", "segment", "search", "grow", "judge", "write"]
    old = {"options": state["options"], "decided": state["decided"]}
    (out / FIT_STATE).write_text(json.dumps(old))
    fit = json.loads((out / "fit.json").read_text())
    (out / "fit.json").unlink()
    assert main(["fit-image", "--resume", str(out), "-q"]) == 0
    again = json.loads((out / "fit.json").read_text())
    drop = lambda x: {k: v for k, v in x.items() if k not in ("seconds", "stages", "pictures")}  # noqa: E731
    assert drop(again) == drop(fit) and again["params"] == whole.params
    assert [s["ncc"] for s in again["stages"]] == [s["ncc"] for s in fit["stages"]]
    assert json.loads((out / FIT_STATE).read_text())["version"] == STATE_VERSION
    assert "fitted ifs3d" in capsys.readouterr().out
