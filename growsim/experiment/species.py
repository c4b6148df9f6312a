"""Evolving a species with Ochoa's weighted fitness (Liu & Zhang), generation by generation.

:func:`evolve_species` runs an experiment whose objective is ``ochoa``
(:mod:`growsim.objectives.ochoa`) and records the best plant of every generation, its four
terms and pictures (the paper's Fig. 2-3); ``growsim species CONFIG`` is the command.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from growsim.errors import UserInputError
from growsim.experiment.load import load_plan
from growsim.experiment.runner import run
from growsim.files import atomic_path
from growsim.objectives.ochoa import TERMS

__all__ = ["GenerationBests", "evolve_species", "species_figure", "terms_figure"]


class GenerationBests:
    """A run callback (:func:`growsim.experiment.run`'s ``callback``) that records, after
    every GA generation, the best individual of that generation: ``rows`` of
    ``(generation, fitness, evolved parameters (k,))``.

    Examples
    --------
    >>> rec = GenerationBests()
    >>> rec.rows
    []
    """

    def __init__(self):
        self.rows: list[tuple[int, float, np.ndarray]] = []

    def __call__(self, ga, row) -> None:
        if row.get("phase", "ga") != "ga":
            return None
        best, where = -np.inf, None
        for raw, scores in zip(ga.state.pops, ga.state.scores):
            if raw is None or scores is None or not len(scores):
                continue
            i = int(np.argmax(scores))
            if where is None or scores[i] > best:
                best, where = float(scores[i]), raw[i : i + 1]
        if where is not None:
            self.rows.append((int(row["generation"]), best, ga.genome.decode(where)[0]))
        return None


def evolve_species(config, *, out=None, seed: int | None = None, overrides=(), progress=False):
    """Run an experiment whose first objective is ``ochoa`` and record its species'
    evolution: the best plant of every generation, its four terms, and pictures.

    Writes into the run directory (besides what :func:`growsim.experiment.run` writes):
    ``generations.parquet`` (per generation: ``generation``, ``fitness`` and the terms of
    :func:`growsim.objectives.ochoa.ochoa_terms` of that generation's best), ``generations.png``
    (the best plant of
    the first, middle and last generation side by side: the paper's Fig. 2-3) and
    ``terms.png`` (the four terms over generations). ``config``: anything
    :func:`~growsim.experiment.load.load_plan` takes. Returns ``(result, table)``: the
    run's :class:`~growsim.experiment.results.RunRecord` and the table.

    Examples
    --------
    >>> cfg = "experiments/ifs_species.toml"
    >>> result, table = evolve_species(cfg, out="runs/x")  # doctest: +SKIP
    >>> list(table.columns[:3])  # doctest: +SKIP
    ['generation', 'fitness', 'phototropism']
    """

    plan = load_plan(config, overrides)
    if seed is not None:
        plan = plan.with_seed(int(seed))
    objective = next((o for o in plan.objectives if o.name == "ochoa"), None)
    if objective is None:
        raise UserInputError("evolve_species: the experiment has no 'ochoa' objective")
    rec = GenerationBests()
    result = run(plan, out=out, callback=rec, progress=progress)
    fitness = plan.fitness()
    rows, plants = [], []
    for generation, score, x in rec.rows:
        params, _, plant = fitness.phenotype_of(x)
        plants.append(plant)
        rows.append({"generation": generation, "fitness": score, **objective.terms(plant),
                     **{f"param_{k}": params[k] for k in fitness.evolved}})  # fmt: skip
    table = pd.DataFrame(rows)
    path = result.out
    with atomic_path(path / "generations.parquet") as tmp:
        table.to_parquet(tmp, index=False)
    if plants:
        picks = sorted({0, len(plants) // 2, len(plants) - 1})
        species_figure([plants[i] for i in picks], [rows[i] for i in picks],
                       path / "generations.png")  # fmt: skip
        terms_figure(table, path / "terms.png")
    return result, table


def species_figure(plants, rows, path, size: int = 300):
    """A PNG of plants side by side, each titled with its generation, ``F`` and terms
    (``rows``: dicts with ``generation``, ``fitness`` and the four terms)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(plants), figsize=(3.2 * len(plants), 3.9), squeeze=False)
    for ax, plant, row in zip(axes[0], plants, rows):
        ax.imshow(plant.render_image(view="front", size=(size, size)))
        ax.set_axis_off()
        ax.set_title(
            f"generation {row['generation']}: F {row['fitness']:.3f}\n"
            f"a {row['phototropism']:.2f} b {row['light']:.2f} "
            f"c {row['stability']:.2f} d {row['symmetry']:.2f}",
            fontsize=9,
        )
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png", dpi=100)
    plt.close(fig)
    return path


def terms_figure(table, path):
    """A PNG of the fitness and the four terms of each generation's best."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 3.6))
    for name in ("fitness", *TERMS):
        ax.plot(table["generation"], table[name], marker="o", ms=3, label=name,
                lw=2.5 if name == "fitness" else 1.2)  # fmt: skip
    ax.set_xlabel("generation")
    ax.set_ylabel("best of the generation")
    ax.set_ylim(-0.02, 1.02)
    ax.legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png", dpi=100)
    plt.close(fig)
    return path
