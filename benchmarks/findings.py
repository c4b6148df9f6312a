"""The findings table of the hormone experiments: every shipped hormone and stand
experiment under both physics (``growsim``, ``paper``), its declared primary tests on the
discovery block (seeds 1-8) and their replication on the confirmation block (seeds 9-16),
the spread of the best fitness and the largest best plant, as ``docs/models/findings.md``
gives it (between its ``<!-- findings -->`` markers).

Read from the files ``benchmarks/hormone_replication.py`` wrote
(``benchmarks/results/<file>.json``, :data:`EXPERIMENTS`); a file not yet written is
a row "not run".

    python benchmarks/findings.py            # print the table
    python benchmarks/findings.py --write    # and put it into docs/models/findings.md
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results"
PAGE = ROOT / "docs" / "models" / "findings.md"
START, END = "<!-- findings -->", "<!-- /findings -->"

#: (config, physics, result file stem), in the page's order
EXPERIMENTS = [
    ("hormone_2d", "growsim", "hormone_2d_replication"),
    ("hormone_2d", "paper", "hormone_2d_paper_physics_replication"),
    ("hormone_3d", "growsim", "hormone_3d_replication"),
    ("hormone_3d", "paper", "hormone_3d_paper_physics_replication"),
    ("water_supply_2d", "growsim", "water_supply_2d_replication"),
    ("water_supply_2d", "paper", "water_supply_2d_paper_physics"),
    ("hormone_2d_paper_ga", "growsim", "hormone_2d_seed_ga_replication"),
    ("hormone_2d_paper_ga", "paper", "hormone_2d_seed_ga_paper_physics"),
    ("hormone_3d_paper_ga", "growsim", "hormone_3d_seed_ga_replication"),
    ("hormone_3d_paper_ga", "paper", "hormone_3d_seed_ga_paper_physics"),
    ("stand_density_2d", "growsim", "stand_density_2d"),
    ("stand_density_2d", "paper", "stand_density_2d_paper_physics"),
    ("stand_density_3d", "growsim", "stand_density_3d"),
    ("stand_density_3d", "paper", "stand_density_3d_paper_physics"),
    ("stand_mixture_2d", "growsim", "stand_mixture_2d"),
    ("stand_mixture_2d", "paper", "stand_mixture_2d_paper_physics"),
    ("stand_mixture_3d", "growsim", "stand_mixture_3d"),
    ("stand_mixture_3d", "paper", "stand_mixture_3d_paper_physics"),
]


def label(row: dict) -> str:
    """A primary test in a few words: ``wood_volume: ample > half_water``; a contrast of
    fitness within a common garden ``garden half_water: half_water > ample`` (origins grown
    side by side there).

    Examples
    --------
    >>> label({"measure": "height", "expect": "dense > alone", "garden": None})
    'height: dense > alone'
    >>> label({"measure": "fitness", "expect": "a > b", "garden": "a"})
    'garden a: a > b'
    """
    if row.get("garden"):
        what = "" if row["measure"] == "fitness" else f"{row['measure']} "
        return f"garden {row['garden']}: {what}{row['expect']}"
    return f"{row['measure']}: {row['expect']}"


def summary(data: dict) -> dict:
    """One experiment's figures from its ``hormone_replication.py`` file: the declared
    tests, those past Holm on the discovery block, those replicated on the confirmation
    block, the range of the CV of the best fitness over both blocks' groups, and the
    largest best plant against its cap.

    Examples
    --------
    >>> row = {"measure": "height", "expect": "a > b", "garden": None,
    ...        "discovery_finding": True, "replicated": False}
    >>> s = summary({"replication": [row], "spread": {"discovery": {"a": {"best_fitness": 0.1}},
    ...              "confirmation": {"a": {"best_fitness": 0.2}}},
    ...              "sizes": {"discovery": {"max_modules": 9, "cap": [100]},
    ...                        "confirmation": {"max_modules": 12, "cap": [100]}}})
    >>> s["tests"], s["found"], s["replicated"], s["cv"], s["largest"], s["cap"]
    (1, ['height: a > b'], [], (0.1, 0.2), 12, 100)
    """
    rows = data["replication"]
    cvs = [
        g["best_fitness"]
        for block in ("discovery", "confirmation")
        for g in data["spread"].get(block, {}).values()
        if not math.isnan(g["best_fitness"])
    ]
    sizes = [data["sizes"][b] for b in ("discovery", "confirmation") if data["sizes"].get(b)]
    return {
        "tests": len(rows),
        "found": [label(r) for r in rows if r["discovery_finding"]],
        "replicated": [label(r) for r in rows if r["replicated"]],
        "cv": (min(cvs), max(cvs)),
        "largest": max(s["max_modules"] for s in sizes),
        "cap": max(max(s["cap"]) for s in sizes),
    }


def render() -> str:
    """The findings table (Markdown), one row per experiment and physics."""
    lines = [
        "| experiment | physics | declared tests | past Holm, seeds 1-8 | replicated, seeds 9-16 "
        "| CV of the best fitness | largest best plant (cap) |",
        "|---|---|---|---|---|---|---|",
    ]
    for config, physics, stem in EXPERIMENTS:
        path = RESULTS / f"{stem}.json"
        if not path.exists():
            lines.append(f"| `{config}` | `{physics}` | not run | | | | |")
            continue
        s = summary(json.loads(path.read_text()))
        held = "; ".join(s["replicated"]) if s["replicated"] else "none"
        lines.append(
            f"| `{config}` | `{physics}` | {s['tests']} | {len(s['found'])} "
            f"| {len(s['replicated'])}: {held} | {s['cv'][0]:.2f}-{s['cv'][1]:.2f} "
            f"| {s['largest']:,} ({s['cap']:,}) |"
        )
    return "\n".join(lines) + "\n"


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--write", action="store_true", help=f"put the table into {PAGE}")
    args = ap.parse_args(argv)
    table = render()
    print(table, end="")
    if args.write:
        text = PAGE.read_text()
        a, b = text.index(START) + len(START), text.index(END)
        PAGE.write_text(text[:a] + "\n" + table + text[b:])


if __name__ == "__main__":
    main()
