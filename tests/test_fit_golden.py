"""A small fit of a picture gives the pinned result (``tests/golden/fits/<name>.json``,
made by ``python -m tests.golden.make NAME``): ``fit_image`` on the Table 1 tree drawn
front and side, a 300-evaluation search. A change meant to keep behaviour (a refactor of
the fit, its options or its stages) keeps it bit for bit: ``fit.json``'s numbers (but the
seconds), the run's ``best.json`` and the pixels of every mask picture written."""

import json

import pytest
from golden.make import FIT_PINS, FITS, golden_fit


def test_every_fit_pin_has_its_fit():
    assert {p.stem for p in FIT_PINS.glob("*.json")} == set(FITS)


@pytest.mark.parametrize("name", sorted(FITS))
def test_small_fit_is_pinned(name, tmp_path):
    pinned = json.loads((FIT_PINS / f"{name}.json").read_text())
    now = json.loads(json.dumps(golden_fit(name, tmp_path), sort_keys=True))
    assert now["options"] == pinned["options"]
    for key in sorted(pinned["fit"]):
        assert now["fit"][key] == pinned["fit"][key], f"{name}: fit.json's {key!r}"
    assert now["fit"] == pinned["fit"]
    assert now["best"] == pinned["best"]
    assert now["pixels"] == pinned["pixels"]
