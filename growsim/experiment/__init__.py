"""Experiment configs, runs and sweeps: the user's way into growsim.

An experiment is a TOML file (see ``docs/configs.md``, generated from the schema by
``python -m growsim.experiment --docs``) with the sections ``[experiment]``, ``[model]``
(+ ``[model.evolve]``), ``[environment]``, ``[[objective]]``, ``[ga]`` and ``[output]``.
The package holds one concept per module:

- :mod:`~growsim.experiment.schema`: the sections and :class:`Config`;
- :mod:`~growsim.experiment.load`: reading, ``--set`` overrides, validation
  (:func:`load_config`, :func:`parse_overrides`) and :func:`load_plan`, the one way into
  a plan (from a path, dict, :class:`Config` or plan);
- :mod:`~growsim.experiment.plan`: :class:`ExperimentPlan`, a config compiled once
  (model, parameters, genome, objectives built once, environment, GA options, outputs);
- :mod:`~growsim.experiment.fitness`: :class:`Fitness`, the unit shipped to workers, and
  :meth:`Fitness.phenotype_of`, the one way to rebuild an individual;
- :mod:`~growsim.experiment.runner`: :func:`run` into a results directory;
- :mod:`~growsim.experiment.results`: the results directory, written (``best.json``,
  ``summary.json``) and read back: :class:`RunRecord` (also named :data:`RunResult`), the
  one description of a run, which :func:`run` returns and :func:`load_run` reads;
  :func:`best_phenotype`;
- :mod:`~growsim.experiment.executors`: serial, process-pool or Dask evaluation
  (:class:`DaskPool`: a Dask client's :class:`DaskExecutor`, of the cluster's size);
- :mod:`~growsim.experiment.sweep`: :func:`sweep`, a grid of variants x repeats;
- :mod:`~growsim.experiment.species`: :func:`~growsim.experiment.species.evolve_species`;
- :mod:`~growsim.experiment.docs`: ``docs/configs.md``.

Inside the package the modules import downwards only (import-linter checks it):
species | sweep > runner > results > load > plan > fitness > schema | executors.

Randomness: one seed per run (``experiment.seed``, or ``--seed``). The GA spawns its own
generator and one seed per evaluation (by the evaluation's global index) from it, so the
history does not depend on ``--workers`` or ``--scheduler``. Models are developed with
``model.noise = "fixed"`` (default): every evaluation of a genome grows the same
phenotype (a model's own ``seed`` parameter is used when it has one, fixed or evolved,
else the run seed), so a genome's fitness is a function of the genome; or
``"per-evaluation"``: each evaluation grows with its own seed, so the GA selects for
shapes that are good whatever the random draws (a noisy fitness).

Examples
--------
>>> from growsim.experiment import load_plan
>>> plan = load_plan("experiments/quickstart.toml", ["ga.generations=2"])
>>> plan.config.ga.generations, plan.model.name
(2, 'honda')
"""

from growsim.experiment.docs import config_docs
from growsim.experiment.executors import DaskExecutor, DaskPool
from growsim.experiment.fitness import Fitness
from growsim.experiment.load import build_fitness, load_config, load_plan, parse_overrides
from growsim.experiment.plan import ExperimentPlan, ModelPlan, compile_plan
from growsim.experiment.results import (
    RunRecord,
    RunResult,
    best_phenotype,
    best_plant,
    load_run,
    read_run,
)
from growsim.experiment.runner import default_out, run
from growsim.experiment.schema import (
    Config,
    ExperimentConfig,
    GAConfig,
    ModelConfig,
    ObjectiveConfig,
    OutputConfig,
)
from growsim.experiment.sweep import parse_vary, sweep

__all__ = [
    "Config",
    "DaskExecutor",
    "DaskPool",
    "ExperimentConfig",
    "ExperimentPlan",
    "Fitness",
    "GAConfig",
    "ModelConfig",
    "ModelPlan",
    "ObjectiveConfig",
    "OutputConfig",
    "RunRecord",
    "RunResult",
    "best_phenotype",
    "best_plant",
    "build_fitness",
    "compile_plan",
    "config_docs",
    "default_out",
    "load_config",
    "load_plan",
    "load_run",
    "parse_overrides",
    "parse_vary",
    "read_run",
    "run",
    "sweep",
]
