"""Runs' configs compared: flattened, keyed up to the seed, labelled by what differs.

A config is flattened to its leaves (:func:`growsim.experiment.load.flatten_config`),
without the keys that do not change a result (:data:`IGNORED_KEYS`,
:func:`result_config`); runs with the same flattened config (:func:`run_key`) are
repeats of one variant. Variants are labelled by the paths whose
values differ, named by their shortest unambiguous suffix (:func:`short_names`,
:func:`diff_labels`), leaving out the model parameters a preset sets
(:func:`from_preset`).
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from typing import Any

from growsim.experiment.load import flatten_config
from growsim.experiment.results import RunRecord
from growsim.models import get_model

__all__ = [
    "IGNORED_KEYS",
    "MISSING",
    "Path_",
    "diff_labels",
    "fmt_value",
    "from_preset",
    "result_config",
    "run_key",
    "short_names",
    "sort_value",
]

#: config keys that do not change a run's result: ignored when grouping (the seed is
#: what tells repeats apart, and is checked for duplicates separately; ``[compare]``
#: only says what compare tests)
IGNORED_KEYS = (
    "experiment.seed",
    "experiment.name",
    "experiment.description",
    "experiment.repeats",
    "output",
    "compare",
)

Path_ = tuple[str, ...]  # a key path, one component per table level ("objective[0]", "kind")
#: the value of a path a config does not have ("unset" in labels)
MISSING = "\0unset"
_MAX_LABEL_ITEMS = 4


def _ignored(path: Path_) -> bool:
    dotted = ".".join(path)
    return any(dotted == k or dotted.startswith(k + ".") for k in IGNORED_KEYS)


def result_config(run: RunRecord) -> dict[Path_, Any]:
    """The flattened config of a run without the keys that do not change its result.

    Examples
    --------
    >>> from pathlib import Path
    >>> cfg = {"experiment": {"seed": 3, "name": "a"}, "ga": {"population": 8}}
    >>> result_config(RunRecord(Path("r"), cfg, {}))
    {('ga', 'population'): 8}
    """
    return {p: v for p, v in flatten_config(run.config).items() if not _ignored(p)}


def _canon(v: Any) -> str:
    return v if v is MISSING else json.dumps(v, sort_keys=True)


def run_key(run: RunRecord) -> str:
    """The config up to the seed (and the keys of :data:`IGNORED_KEYS`): runs with the
    same key are repeats of one variant.

    Examples
    --------
    >>> from pathlib import Path
    >>> cfg = {"experiment": {"seed": 3}, "ga": {"population": 8}, "output": {"plot": False}}
    >>> run_key(RunRecord(Path("r"), cfg, {}))
    '{"ga.population": 8}'
    """
    flat = result_config(run)
    return json.dumps({".".join(p): flat[p] for p in sorted(flat)}, sort_keys=True)


def fmt_value(v: Any) -> str:
    """A config value in a label: strings bare, the rest as JSON (``true``, ``[0, 1]``).

    Examples
    --------
    >>> fmt_value("cherry"), fmt_value(0.5), fmt_value([1.0, -1.0]), fmt_value(True)
    ('cherry', '0.5', '[1.0, -1.0]', 'true')
    >>> fmt_value(MISSING)
    'unset'
    """
    if v is MISSING:
        return "unset"
    if isinstance(v, str):
        return v
    return json.dumps(v)


def short_names(
    paths: Sequence[Path_], universe: set[Path_], min_parts: int = 2
) -> dict[Path_, str]:
    """The shortest suffix of each path (``min_parts`` components at least: two gives
    ``light.intensity``, ``ga.population``) that no other path of ``universe`` ends with.

    Examples
    --------
    >>> u = {("environment", "light", "intensity"), ("ga", "population"),
    ...      ("ga", "polish", "evaluations"), ("ga", "evaluations")}
    >>> sorted(short_names(sorted(u), u).values())
    ['ga.evaluations', 'ga.population', 'light.intensity', 'polish.evaluations']
    """
    out = {}
    for p in paths:
        for k in range(min(min_parts, len(p)), len(p) + 1):
            suffix = p[-k:]
            if not any(q != p and q[-k:] == suffix for q in universe):
                break
        out[p] = ".".join(suffix)
    return out


def _differing(configs: Sequence[dict[Path_, Any]]) -> list[Path_]:
    """The paths whose value (or presence) is not the same in every config, in order."""
    order: dict[Path_, None] = {}
    for c in configs:
        order.update(dict.fromkeys(c))
    return [p for p in order if len({_canon(c.get(p, MISSING)) for c in configs}) > 1]


def from_preset(configs: Sequence[dict[Path_, Any]], diff: Sequence[Path_]) -> set[Path_]:
    """``model.params.*`` that differ only because ``model.preset`` differs (each value is
    the one the group's preset gives): left out of the labels.

    Examples
    --------
    >>> cfgs = [{("model", "kind"): "honda", ("model", "preset"): p,
    ...          ("model", "params", "f"): f, ("model", "params", "bd"): 15.0}
    ...         for p, f in (("cherry", 0.99), ("zelkova", 0.95))]
    >>> diff = [("model", "preset"), ("model", "params", "f"), ("model", "params", "bd")]
    >>> from_preset(cfgs, diff)  # zelkova's bd is 20, not 15: not the preset's
    {('model', 'params', 'f')}
    """
    params = [p for p in diff if p[:2] == ("model", "params") and len(p) == 3]
    if ("model", "preset") not in diff or not params:
        return set()
    try:
        expected = []
        for c in configs:
            m = get_model(c[("model", "kind")])
            preset = c.get(("model", "preset"), MISSING)
            values = m.preset(preset) if preset is not MISSING else {}
            expected.append(m.resolve(values))
    except Exception:  # an unknown model or preset: every parameter follows the preset
        return set(params)
    return {
        p
        for p in params
        if all(
            isinstance(c.get(p), (int, float)) and float(c[p]) == float(e.get(p[2], math.nan))
            for c, e in zip(configs, expected)
        )
    }


def diff_labels(
    configs: Sequence[dict[Path_, Any]], universe: set[Path_], min_parts: int = 2
) -> tuple[list[str], list[Path_]]:
    """One label per config naming what differs between them (``path=value, ...``) and
    the differing paths (all of them, for the report's table of differences).

    Examples
    --------
    >>> a = {("environment", "light", "intensity"): 1.0, ("ga", "population"): 8}
    >>> b = {("environment", "light", "intensity"): 0.5, ("ga", "population"): 8}
    >>> diff_labels([a, b], set(a))[0]
    ['light.intensity=1.0', 'light.intensity=0.5']
    """
    diff = _differing(configs)
    hidden = from_preset(configs, diff)
    shown = [p for p in diff if p not in hidden]
    shown.sort(key=lambda p: (p != ("model", "preset"), p[-1] != "kind"))  # stable
    names = short_names(shown, universe, min_parts)
    items = [[f"{names[p]}={fmt_value(c.get(p, MISSING))}" for p in shown] for c in configs]
    k = min(len(shown), _MAX_LABEL_ITEMS)
    while k < len(shown) and len({tuple(i[:k]) for i in items}) < len(items):
        k += 1
    more = len(shown) - k
    labels = [", ".join(i[:k]) + (f", ... (+{more})" if more > 0 else "") for i in items]
    return labels, diff


def sort_value(v: Any) -> tuple:
    """A sort key for config values of any type: numbers (by value), then the rest, then
    booleans and unset values.

    Examples
    --------
    >>> sorted([True, "b", 2, 0.5], key=sort_value)
    [0.5, 2, 'b', True]
    """
    if isinstance(v, bool) or v is MISSING:
        return (2, str(v))
    if isinstance(v, (int, float)):
        return (0, float(v))
    return (1, _canon(v))
