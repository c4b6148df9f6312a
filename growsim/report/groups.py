"""Runs sorted into groups (repeats of one variant) and families (comparable fitness).

A **group** holds the runs whose configs are equal up to the seed
(:func:`growsim.report.configs.run_key`), labelled by what differs between the groups;
runs of a group with the same seed are the same run again: one is counted, the others
are noted as duplicates. A **family** holds the groups with the same model and the same
objectives (every option that defines the score): fitness is only comparable within one.
"""

from __future__ import annotations

import dataclasses
import json
import logging
from collections.abc import Sequence
from typing import Any

from growsim.experiment.load import flatten_config
from growsim.experiment.results import RunRecord
from growsim.report.configs import (
    MISSING,
    Path_,
    diff_labels,
    from_preset,
    result_config,
    run_key,
    sort_value,
)

__all__ = ["Family", "Group", "families", "group_runs", "run_label"]

log = logging.getLogger(__name__)


@dataclasses.dataclass
class Group:
    """The runs of one config up to the seed: ``runs`` (one per seed, the ones counted),
    ``duplicates`` (``(dropped, kept)`` pairs: the same seed again)."""

    label: str
    runs: list[RunRecord]
    duplicates: list[tuple[RunRecord, RunRecord]]
    config: dict[Path_, Any]

    @property
    def members(self) -> list[RunRecord]:
        """Every run of the group, duplicates included, by seed then path."""
        allr = self.runs + [d for d, _ in self.duplicates]
        return sorted(allr, key=lambda r: (sort_value(_seed(r)), str(r.path)))


@dataclasses.dataclass
class Family:
    """Groups whose fitness is comparable: same model, same objectives."""

    label: str
    model: str
    objectives: list[dict[str, Any]]
    groups: list[Group]
    differences: list[Path_]  # the config paths that differ between its groups


def run_label(run: RunRecord) -> str:
    """``variant`` for ``.../variant/seed-N``, else the directory name.

    Examples
    --------
    >>> from pathlib import Path
    >>> run_label(RunRecord(Path("runs/sweep/light=0.5/seed-2"), {}, {}))
    'light=0.5'
    >>> run_label(RunRecord(Path("runs/quickstart-20261122"), {}, {}))
    'quickstart-20261122'
    """
    if run.path.name.startswith("seed-"):
        return run.path.parent.name
    return run.path.name


def _variant_name(runs: Sequence[RunRecord]) -> str | None:
    """The name the config gives the group's sweep variant (``[[sweep.variants]] name``,
    the directory of ``.../half_water/seed-N``, or ``half_water_light=0.5`` with a
    ``--vary``), if all its runs share one; else ``None``.

    Examples
    --------
    >>> from pathlib import Path
    >>> cfg = {"sweep": {"variants": [{"name": "half_water"}]}}
    >>> _variant_name([RunRecord(Path("sw/half_water/seed-1"), cfg, {})])
    'half_water'
    >>> _variant_name([RunRecord(Path("sw/light=0.5/seed-1"), cfg, {})]) is None
    True
    """
    found = set()
    for r in runs:
        if not r.path.name.startswith("seed-"):
            return None
        label = run_label(r)
        variants = (r.config.get("sweep") or {}).get("variants") or []
        names = {str(v.get("name")) for v in variants if isinstance(v, dict) and v.get("name")}
        if not any(label == n or label.startswith(n + "_") for n in names):
            return None
        found.add(label)
    return found.pop() if len(found) == 1 else None


def _variant_order(groups: Sequence[Sequence[RunRecord]]) -> dict[str, int]:
    """The names of ``[[sweep.variants]]`` in the order the config gives them.

    Examples
    --------
    >>> from pathlib import Path
    >>> cfg = {"sweep": {"variants": [{"name": "ample"}, {"name": "dry"}]}}
    >>> _variant_order([[RunRecord(Path("sw/dry/seed-1"), cfg, {})]])
    {'ample': 0, 'dry': 1}
    """
    order: dict[str, int] = {}
    for runs in groups:
        for r in runs[:1]:
            for v in (r.config.get("sweep") or {}).get("variants") or []:
                if isinstance(v, dict) and v.get("name"):
                    order.setdefault(str(v["name"]), len(order))
    return order


def _family_key(run: RunRecord) -> str:
    """Model kind and objectives (every option): runs whose fitness is comparable."""
    return json.dumps(
        [run.config.get("model", {}).get("kind"), run.config.get("objective", [])],
        sort_keys=True,
    )


def _seed(run: RunRecord) -> Any:
    seed = (run.summary or {}).get("seed")
    if seed is None:
        seed = run.config.get("experiment", {}).get("seed")
    return seed if seed is not None else f"?{run.path}"  # unknown: never a duplicate


def _dedupe(label: str, members: list[RunRecord], notes: list[str]) -> Group:
    """Keep one run per seed (the latest finished; ties: the first path), note the rest."""
    by_seed: dict[str, list[RunRecord]] = {}
    for r in sorted(members, key=lambda r: str(r.path)):
        by_seed.setdefault(str(_seed(r)), []).append(r)
    kept, dups = [], []
    for rs in by_seed.values():
        keep = max(rs, key=lambda r: str((r.summary or {}).get("finished", "")))
        kept.append(keep)
        if len(rs) == 1:
            continue
        dups += [(r, keep) for r in rs if r is not keep]
        fits = sorted({r.best_fitness for r in rs})
        msg = (
            f"{label}: seed {_seed(keep)} appears in {len(rs)} runs "
            f"({', '.join(str(r.path) for r in rs)}): the same run again, not independent "
            f"repeats; counted once, keeping {keep.path} (the latest finished)"
        )
        if len(fits) > 1:
            msg += (
                f"; their best fitness differ ({', '.join(f'{f:.6g}' for f in fits)}): "
                "same config and seed should give the same run (growsim versions?)"
            )
        notes.append(msg)
        log.warning("%s", msg)
    kept.sort(key=lambda r: sort_value(_seed(r)))
    return Group(label, kept, dups, {})


def _by_kind(objectives: Sequence[dict[str, Any]]) -> dict[str, dict[str, Any]]:
    """Objectives keyed by kind (``kind#i``, from 1, when a kind repeats)."""
    kinds = [str(o.get("kind")) for o in objectives]
    return {
        (k if kinds.count(k) == 1 else f"{k}#{i + 1}"): o
        for i, (k, o) in enumerate(zip(kinds, objectives))
    }


def families(runs: Sequence[RunRecord], notes: list[str]) -> list[Family]:
    """Group the runs, label the groups, dedupe seeds, sort the groups into families;
    ``notes`` gets a line for each duplicated seed.

    Examples
    --------
    >>> from pathlib import Path
    >>> def run(seed, light, kind="honda"):
    ...     cfg = {"model": {"kind": kind}, "objective": [{"kind": "light"}],
    ...            "environment": {"light": {"intensity": light}}}
    ...     return RunRecord(Path(f"{kind}{light}-{seed}"), cfg, {"fitness": 1.0}, {"seed": seed})
    >>> runs = [run(0, 1.0), run(1, 1.0), run(0, 0.5), run(0, 1.0, "ifs3d")]
    >>> for f in families(runs, []):
    ...     print(f.label, [(g.label, len(g.runs)) for g in f.groups])
    honda / light [('light.intensity=0.5', 1), ('light.intensity=1.0', 2)]
    ifs3d / light [('ifs3d1.0-0', 1)]
    """
    by_family: dict[str, dict[str, list[RunRecord]]] = {}
    for r in runs:
        by_family.setdefault(_family_key(r), {}).setdefault(run_key(r), []).append(r)
    universe: set[Path_] = set()
    for r in runs:
        universe.update(result_config(r))

    # family labels: model and objective kinds, plus the objective options that differ
    # between families of the same model and kinds
    heads = []
    for fkey in by_family:
        model, objectives = json.loads(fkey)
        kinds = " + ".join(str(o.get("kind", "?")) for o in objectives)
        heads.append((fkey, model, objectives, f"{model} / {kinds}"))
    fam_labels = {}
    for base in {h[3] for h in heads}:
        same = [h for h in heads if h[3] == base]
        if len(same) == 1:
            fam_labels[same[0][0]] = base
            continue
        # options named by their objective's kind (kind#i if repeated), as short as
        # unambiguous: "light (wood_cost=1.0)"
        cfgs = [flatten_config(_by_kind(h[2])) for h in same]
        labels, _ = diff_labels(cfgs, set().union(*cfgs), min_parts=1)
        for h, lab in zip(same, labels):
            fam_labels[h[0]] = f"{base} ({lab})"

    labelled = []  # (family key, [(label, config, runs)])
    for fkey, *_ in heads:
        members = list(by_family[fkey].values())
        configs = [result_config(m[0]) for m in members]
        if len(members) > 1:
            labels, diff = diff_labels(configs, universe)
            named = [_variant_name(m) for m in members]
            if all(named) and len(set(named)) == len(named):  # the sweep's own names
                labels = named
                declared = _variant_order(members)
                rank = [
                    declared.get(
                        str(n),  # a variant's own name, else the variant it starts with
                        min(
                            (i for v, i in declared.items() if str(n).startswith(v + "_")),
                            default=len(declared),
                        ),
                    )
                    for n in named
                ]
            else:
                rank = [0] * len(members)
        else:
            names = dict.fromkeys(
                str(r.config.get("experiment", {}).get("name") or run_label(r)) for r in members[0]
            )
            labels, diff = ["/".join(names)], []
            rank = [0]
        for i, lab in enumerate(labels):  # (a safeguard: labels name one group each)
            if labels.index(lab) != i:
                labels[i] = f"{lab} #{i + 1}"
        preset = from_preset(configs, diff)
        shown = [p for p in diff if p not in preset]
        order = sorted(
            range(len(members)),
            key=lambda i: (
                rank[i],  # named variants in the config's order (ample first)
                tuple(sort_value(configs[i].get(p, MISSING)) for p in shown),
                labels[i],
            ),
        )
        labelled.append((fkey, diff, [(labels[i], configs[i], members[i]) for i in order]))

    # a label must name one group: the same label in two families gets the family's
    counts: dict[str, int] = {}
    for _, _, gs in labelled:
        for lab, _, _ in gs:
            counts[lab] = counts.get(lab, 0) + 1
    out = []
    for (fkey, model, objectives, _), (_, diff, gs) in zip(heads, labelled):
        groups = []
        for lab, cfg, members in gs:
            if counts[lab] > 1:
                lab = f"{lab} [{fam_labels[fkey]}]"
            g = _dedupe(lab, members, notes)
            g.config = cfg
            groups.append(g)
        out.append(Family(fam_labels[fkey], model, objectives, groups, diff))
    return out


def group_runs(runs: Sequence[RunRecord]) -> dict[str, list[RunRecord]]:
    """Group runs by config up to the seed; ``{label: runs}`` (every run, duplicated seeds
    included), each label naming what differs between the groups' configs.

    Examples
    --------
    >>> group_runs([])
    {}
    """
    if not runs:
        return {}
    return {g.label: g.members for f in families(runs, []) for g in f.groups}
