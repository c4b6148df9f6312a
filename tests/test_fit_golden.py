"""A small fit of a picture gives the pinned result (``tests/golden/fits/<name>.json``,
made by ``python -m tests.golden.make NAME``): ``fit_image`` on the Table 1 tree drawn
front and side, a 300-evaluation search. A change meant to keep behaviour (a refactor of
the fit, its options or its stages) keeps it bit for bit on one machine: ``fit.json``'s
numbers (but the seconds), the run's ``best.json`` and the pixels of every mask picture
written; the numbers compared to their last bits (``LAST_BITS``: another CPU's)."""

import json

import pytest
from golden.make import FIT_PINS, FITS, differences, golden_fit


def test_every_fit_pin_has_its_fit():
    assert {p.stem for p in FIT_PINS.glob("*.json")} == set(FITS)


@pytest.mark.parametrize("name", sorted(FITS))
def test_small_fit_is_pinned(name, tmp_path):
    pinned = json.loads((FIT_PINS / f"{name}.json").read_text())
    now = json.loads(json.dumps(golden_fit(name, tmp_path), sort_keys=True))
    assert now["options"] == pinned["options"]
    assert not (d := differences(pinned["fit"], now["fit"], "fit.json")), f"{name}: {d[:5]}"
    assert not (d := differences(pinned["best"], now["best"], "best")), f"{name}: {d[:5]}"
    assert now["pixels"] == pinned["pixels"]
