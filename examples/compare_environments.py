"""Evolve the quickstart tree under two lights and test the difference.

What it shows: ``growsim.sweep(config, vary, repeats=..., out=...)`` is ``growsim sweep
CONFIG --vary KEY=V1,V2 --repeats N --out DIR``: every variant (here the light from
straight above, and at 45 degrees) runs the same seeds, and the returned table (pandas)
has one row per run. ``growsim.report.compare([dir])`` is ``growsim compare DIR``: it
groups the runs by what differs, tests the groups against each other (Welch t,
Mann-Whitney U, Holm-adjusted) and writes ``report.html``, ``curves.png``,
``renders.png`` and the CSV tables (``docs/compare.md``).

    python examples/compare_environments.py                       # 2 lights x 3 seeds, full
    python examples/compare_environments.py --generations 5 --population 20
"""

from __future__ import annotations

import argparse
from pathlib import Path

import growsim
from growsim.report import compare

EXPERIMENTS = Path(__file__).resolve().parents[1] / "experiments"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--config", default=str(EXPERIMENTS / "quickstart.toml"))
    parser.add_argument("--out", default="runs/examples/lights")
    parser.add_argument("--repeats", type=int, default=3, help="seeds per light")
    parser.add_argument("--generations", type=int, help="ga.generations (default: the config's)")
    parser.add_argument("--population", type=int, help="ga.population (default: the config's)")
    parser.add_argument("--no-renders", action="store_true", help="skip renders.png")
    args = parser.parse_args(argv)
    overrides = []
    if args.generations:
        overrides.append(f"ga.generations={args.generations}")
    if args.population:
        overrides.append(f"ga.population={args.population}")

    out = Path(args.out)
    table = growsim.sweep(
        args.config,
        {"env.light.direction": [[0, -1, 0], [1, -1, 0]]},  # from above; at 45 degrees
        repeats=args.repeats,
        out=out / "sweep",
        overrides=overrides,
        progress=False,
    )
    print(table[["environment.light.direction", "seed", "best_fitness"]])
    result = compare([out / "sweep"], out / "compare", renders=not args.no_renders)
    print(result.table[["group", "runs", "best", "mean"]])
    print("report:", out / "compare" / "report.html")
    return result


if __name__ == "__main__":
    main()
