"""Compare results directories: groups, families, statistics over repeats, curves, HTML.

:func:`compare` takes run directories, sweep directories or any directory holding runs
(found by their ``summary.json``) and:

- **groups** the runs whose resolved configs are equal up to the seed (the repeats of
  one variant; the experiment's name, description and repeat count and the ``[output]``
  table do not change a result and are ignored), and labels each group by what differs
  between the groups' configs, with the shortest unambiguous key paths
  (``light.intensity=0.5``, ``model.preset=cherry, ga.population=100``);
- counts **one run per seed**: runs of a group with the same seed are the same run
  again, not independent repeats; they are flagged (a warning, the ``duplicates`` and
  ``duplicate_of`` columns) and only the latest finished one is counted;
- sorts the groups into **families**: same model and same objectives (kinds and every
  option that defines the score). Fitness is only comparable within a family, so tests
  are only made within one and the report has one block per family;
- reports per group (``n`` = distinct seeds): best fitness (best of the runs, mean +/-
  95 % confidence half-width, Student t) and the mean +/- 95 % CI of every numeric
  measure of the runs' best phenotypes (``summary.json`` ``measures``) and of every
  objective's score and terms (``terms``: ``light.leaf_area``, ...);
- tests, for every such quantity and every pair of groups of a family with at least two
  distinct-seed runs each: Welch's t-test and the Mann-Whitney U test (two-sided), with
  effect sizes (difference of means and its Welch 95 % CI, Cohen's d, Cliff's delta) and
  p-values adjusted with Holm-Bonferroni (:func:`holm`) over all the family's
  hypotheses (quantities x pairs), separately for each of the two tests;
- with ``[compare] primary`` in the runs' config (declared before the runs): makes those
  tests Holm-corrected over themselves alone, with Hedges' g and the seeds per group a
  replication needs, and marks every other test exploratory (Holm over those alone);
  with a confirmation block of fresh seeds (``confirm``), says which primary findings
  replicated (:mod:`growsim.report.primary`);
- writes ``compare.csv`` (groups), ``stats.csv`` (tests), ``runs.csv`` (runs),
  ``curves.png`` (best-so-far fitness against evaluations, one panel per family),
  ``renders.png`` (each group's best phenotype, one row per family) and a self-contained
  ``report.html``, by default beside the runs (:func:`default_out`); with primary tests
  also ``primary.csv``, ``exploratory.csv`` and (with ``confirm``) ``replication.csv``.

What lives where:

- :mod:`growsim.report.configs`: configs flattened, keyed up to the seed (:func:`run_key`,
  :data:`IGNORED_KEYS`) and labelled by what differs between them;
- :mod:`growsim.report.groups`: groups (:class:`Group`), seed duplicates, families
  (:class:`Family`), :func:`group_runs`, :func:`run_label`;
- :mod:`growsim.report.statistics`: confidence intervals, Welch and Mann-Whitney tests,
  effect sizes, :func:`holm`, the tests table (:data:`STATS_COLUMNS`);
- :mod:`growsim.report.primary`: primary and exploratory tests, power, replication;
- :mod:`growsim.report.figures`: best-so-far curves and renders of the best phenotypes;
- :mod:`growsim.report.html`: the HTML report (:func:`format_mean_ci`);
- :mod:`growsim.report.comparison`: :func:`compare`, :class:`Comparison`,
  :func:`default_out`.

Everything a user needs is imported from here: ``from growsim.report import compare``.
"""

from __future__ import annotations

from growsim.report.comparison import Comparison, compare, default_out
from growsim.report.configs import IGNORED_KEYS as IGNORED_KEYS
from growsim.report.configs import Path_ as Path_
from growsim.report.configs import run_key
from growsim.report.groups import Family as Family
from growsim.report.groups import Group as Group
from growsim.report.groups import group_runs, run_label
from growsim.report.html import format_mean_ci
from growsim.report.statistics import STATS_COLUMNS as STATS_COLUMNS
from growsim.report.statistics import holm

# the same names as the single module growsim/report.py had (its other public names,
# IGNORED_KEYS, STATS_COLUMNS, Family, Group and Path_, are importable from here too)
__all__ = [
    "Comparison",
    "compare",
    "default_out",
    "format_mean_ci",
    "group_runs",
    "holm",
    "run_key",
    "run_label",
]
