"""The generic GA every growsim model uses.

- :mod:`growsim.ga.genome`: codings (:class:`Real`, :class:`Integer`, :class:`Categorical`,
  :class:`Bits` with binary / Gray / weighted / fraction coding, diploid) and
  :func:`genome_from_params`;
- :mod:`growsim.ga.selection`, :mod:`growsim.ga.crossover`, :mod:`growsim.ga.mutation`:
  operators, registered by name in :data:`SELECTION`, :data:`CROSSOVER`, :data:`MUTATION`;
- :mod:`growsim.ga.evaluate`: serial / process-pool / ``Executor`` (Dask) evaluation, and
  the GA's contracts with what it is given: :class:`GAFitness` (a fitness with a
  ``prepare`` per batch) and :class:`Pool` (an executor that says its size);
- :mod:`growsim.ga.options`: :class:`GAOptions`, every option of the GA, declared once;
- :mod:`growsim.ga.engine`: :class:`GA` (ask/tell, islands, termination, the ``run()``
  loop) and :class:`Result`;
- :mod:`growsim.ga.generation`: the generation models (:data:`GENERATION_MODELS`) and
  the ring migration;
- :mod:`growsim.ga.state`: :class:`GAState`, everything a run changes, which is also the
  checkpoint;
- :mod:`growsim.ga.history`: the history rows (:data:`HISTORY_COLUMNS`);
- :mod:`growsim.ga.polish`: the local refinement ``GA.run(polish=...)`` uses;
- :mod:`growsim.ga.problems`: test problems as picklable fitnesses (:func:`onemax`,
  :func:`sphere`, :func:`noisy_sphere`, :func:`rastrigin`).

See ``docs/ga.md``.

Examples
--------
>>> from growsim.ga import GA, Genome, Real
>>> genome = Genome([Real("x", -5.12, 5.12, size=3)])
>>> ga = GA(genome, lambda x: (x**2).sum(axis=1), population=30, maximize=False, seed=1)
>>> result = ga.run(generations=20)
>>> result.best.params.shape
(3,)
"""

from growsim.ga.crossover import CROSSOVER, Crossover
from growsim.ga.engine import GA
from growsim.ga.evaluate import EvaluationError, Evaluator, GAFitness, Pool, evaluation_seeds
from growsim.ga.generation import GENERATION_MODELS, GenerationModel
from growsim.ga.genome import (
    OKUSA_WEIGHTS,
    Bits,
    Categorical,
    Genome,
    Integer,
    Real,
    genome_from_params,
)
from growsim.ga.history import HISTORY_COLUMNS, Individual, Result
from growsim.ga.mutation import MUTATION, Mutation
from growsim.ga.operator import Operator
from growsim.ga.options import GAOptions
from growsim.ga.polish import PolishOptions
from growsim.ga.problems import noisy_sphere, onemax, rastrigin, sphere
from growsim.ga.selection import SELECTION, Selection
from growsim.ga.state import GAState
from growsim.ga.workers import WorkerPool, bind_to_parent

__all__ = [
    "CROSSOVER",
    "GA",
    "GENERATION_MODELS",
    "HISTORY_COLUMNS",
    "MUTATION",
    "OKUSA_WEIGHTS",
    "SELECTION",
    "Bits",
    "Categorical",
    "Crossover",
    "EvaluationError",
    "Evaluator",
    "GAFitness",
    "GAOptions",
    "GAState",
    "GenerationModel",
    "Genome",
    "Individual",
    "Integer",
    "Mutation",
    "Operator",
    "PolishOptions",
    "Pool",
    "Real",
    "Result",
    "Selection",
    "WorkerPool",
    "bind_to_parent",
    "evaluation_seeds",
    "genome_from_params",
    "noisy_sphere",
    "onemax",
    "rastrigin",
    "sphere",
]
