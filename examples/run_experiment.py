"""Run an experiment config from Python and read its results.

What it shows: ``growsim.run(config, out, overrides=[...])`` is ``growsim run CONFIG
--set KEY=VALUE --out DIR``; it returns a record with the history (a pandas DataFrame,
one row per generation), the best fitness, the best parameters and the best plant, and
the results directory holds the same files as the command's (``docs/quickstart.md``).
``callback(ga, row)`` is called after every generation (return True to stop).

    python examples/run_experiment.py                      # the quickstart, in full
    python examples/run_experiment.py --generations 5 --population 20
"""

from __future__ import annotations

import argparse
from pathlib import Path

import growsim

EXPERIMENTS = Path(__file__).resolve().parents[1] / "experiments"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--config", default=str(EXPERIMENTS / "quickstart.toml"))
    parser.add_argument("--out", default="runs/examples/run")
    parser.add_argument("--generations", type=int, help="ga.generations (default: the config's)")
    parser.add_argument("--population", type=int, help="ga.population (default: the config's)")
    args = parser.parse_args(argv)
    overrides = []
    if args.generations:
        overrides.append(f"ga.generations={args.generations}")
    if args.population:
        overrides.append(f"ga.population={args.population}")

    def watch(ga, row):
        print(f"generation {row['generation']:3d}: best {row['best']:.4g}")
        return False  # True would stop the run here

    result = growsim.run(
        args.config, out=args.out, overrides=overrides, progress=False, callback=watch
    )
    print(result.history[["generation", "evaluations", "best", "mean"]].tail())
    print("best fitness", result.best_fitness)
    print("best parameters", result.best_params)
    print("height of the best plant", result.best_plant.measures()["height"])
    print("results in", result.out)
    return result


if __name__ == "__main__":
    main()
