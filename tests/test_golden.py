"""Every shipped experiment, at a small budget, gives the pinned history and best.

The pins (``tests/golden/<name>.json``) were made by ``python -m tests.golden.make``;
a change meant to keep behaviour (a refactor, a faster kernel) must keep them bit for
bit. History columns are compared as text (a float's shortest round-trip repr).
"""

import json
from pathlib import Path

import pytest

from tests.golden.make import BUDGETS, golden

HERE = Path(__file__).resolve().parent / "golden"


@pytest.mark.parametrize("name", sorted(BUDGETS))
def test_shipped_experiment_is_pinned(name, tmp_path):
    pinned = json.loads((HERE / f"{name}.json").read_text())
    now = json.loads(json.dumps(golden(name, tmp_path / name), sort_keys=True))
    assert now["overrides"] == pinned["overrides"]
    assert now["history_columns"] == pinned["history_columns"]
    for column, values in pinned["history"].items():
        assert now["history"][column] == values, f"{name}: history column {column!r}"
    assert now["best"] == pinned["best"]
