"""Every shipped experiment, at a small budget, gives the pinned history and best.

The pins (``tests/golden/<name>.json``) were made by ``python -m tests.golden.make``;
a change meant to keep behaviour (a refactor, a faster kernel) must keep them bit for
bit on one machine (check before and after there). History columns are stored as text (a
float's shortest round-trip repr); compared to their last bits (``LAST_BITS``), as a
machine of another CPU computes them.
"""

import json

import pytest
from conftest import ROOT
from golden.make import BUDGETS, HERE, differences, golden


def test_every_shipped_experiment_has_a_budget_and_a_pin():
    """A new ``experiments/*.toml`` fails here until it gets a budget in
    ``tests/golden/make.py`` and its pin (``python -m tests.golden.make NAME``)."""
    shipped = {p.stem for p in (ROOT / "experiments").glob("*.toml")}
    assert set(BUDGETS) == shipped
    assert {p.stem for p in HERE.glob("*.json")} == shipped


@pytest.mark.parametrize("name", sorted(BUDGETS))
def test_shipped_experiment_is_pinned(name, tmp_path):
    pinned = json.loads((HERE / f"{name}.json").read_text())
    now = json.loads(json.dumps(golden(name, tmp_path / name), sort_keys=True))
    assert now["overrides"] == pinned["overrides"]
    assert now["history_columns"] == pinned["history_columns"]
    for column, values in pinned["history"].items():
        assert not (d := differences(values, now["history"][column], column)), f"{name}: {d[:5]}"
    assert not (d := differences(pinned["best"], now["best"], "best")), f"{name}: {d[:5]}"
