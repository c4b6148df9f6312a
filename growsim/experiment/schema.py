"""The experiment config schema: one class per TOML section, the whole :class:`Config`.

Sections: ``[experiment]``, ``[model]`` (+ ``[model.evolve]``), ``[environment]``
(:class:`growsim.env.Environment`), ``[[objective]]`` (each objective's own options
class, chosen by ``kind``), ``[ga]`` and ``[output]``. Every field carries its
description and limits: ``docs/configs.md`` is generated from them
(:mod:`growsim.experiment.docs`).
"""

from __future__ import annotations

import dataclasses
import math
import re
from typing import Annotated, Any, Literal, Union

import tomli_w
from pydantic import Field, StrictFloat, StrictInt, field_validator, model_validator
from pydantic.dataclasses import dataclass as pydantic_dataclass

from growsim.env import Environment
from growsim.ga import GAOptions, PolishOptions
from growsim.ga.options import GA_OPTIONS_CONFIG
from growsim.objectives import OBJECTIVES
from growsim.options import Options
from growsim.render import MAX_SIZE, MIN_SIZE, VIEWS

__all__ = [
    "SECTIONS",
    "CompareConfig",
    "Config",
    "ExperimentConfig",
    "GAConfig",
    "ModelConfig",
    "ObjectiveConfig",
    "OutputConfig",
    "PrimaryMeasure",
    "SweepConfig",
    "SweepVariant",
]


class ExperimentConfig(Options):
    """``[experiment]``: what this experiment is called and how it is seeded."""

    name: str = Field(
        "experiment",
        pattern=r"^[A-Za-z0-9][A-Za-z0-9_.-]{0,63}$",
        description="name of the experiment; used in the default results directory "
        "runs/<name>-<timestamp> (letters, digits, _ . -; at most 64)",
    )
    description: str = Field("", description="free text, copied to summary.json")
    seed: int = Field(0, ge=0, le=2**63 - 1, description="seed of the run (--seed overrides)")
    repeats: int = Field(
        1,
        ge=1,
        le=1000,
        description="seeds per variant (seed, seed + 1, ...) when growsim sweep is given no "
        "--repeats; used by growsim sweep only: growsim run always runs one seed",
    )


class ModelConfig(Options):
    """``[model]``: which model, its fixed parameters and the parameters the GA evolves."""

    kind: str = Field(description="registered model name (growsim.models.MODELS)")
    preset: str | None = Field(None, description="named parameter set of the model to start from")
    params: dict[str, int | float | str] = Field(
        default_factory=dict,
        description="fixed parameter values (over the preset, over the model's defaults); a "
        'parameter with named values takes its name (hormone: physics = "paper")',
    )
    evolve: dict[str, Any] = Field(
        default_factory=dict,
        description="parameters the GA evolves: name = true (the model's range) or "
        "[low, high] (a range inside the model's range); a name may be a shell-style "
        'pattern ("h*_w?" = true: every parameter it matches); at least one',
    )
    noise: Literal["fixed", "per-evaluation"] = Field(
        "fixed",
        description="'fixed': a genome always grows the same phenotype (the model's seed "
        "parameter, else the run seed); 'per-evaluation': every evaluation grows with its "
        "own seed (noisy fitness, selects robust shapes)",
    )

    @field_validator("evolve")
    @classmethod
    def _check_evolve(cls, v):
        for name, spec in v.items():
            if spec is False:
                raise ValueError(f"{name} = false: leave it out instead (or set true)")
            if spec is True:
                continue
            ok = (
                isinstance(spec, list)
                and len(spec) == 2
                and all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in spec)
            )
            if not ok:
                raise ValueError(f"{name}: expected true or [low, high], got {spec!r}")
            if not all(math.isfinite(x) for x in spec) or not spec[0] < spec[1]:
                raise ValueError(f"{name}: expected finite low < high, got {spec!r}")
        return {k: (True if x is True else [float(x[0]), float(x[1])]) for k, x in v.items()}

    @field_validator("params")
    @classmethod
    def _check_params(cls, v):
        for name, x in v.items():
            if not isinstance(x, str) and not math.isfinite(x):
                raise ValueError(f"{name}: {x!r} is not a finite number")
        return v


def _objective_union():
    """Every registered objective's options class, told apart by ``kind``."""
    classes = tuple(OBJECTIVES.get(name).Options for name in OBJECTIVES)
    if len(classes) == 1:
        return classes[0]
    return Annotated[Union[classes], Field(discriminator="kind")]  # noqa: UP007


#: one ``[[objective]]`` table: the options class of its ``kind``
ObjectiveConfig = _objective_union()


@pydantic_dataclass(frozen=True, config=GA_OPTIONS_CONFIG)
class GAConfig(GAOptions):
    """``[ga]``: the genetic algorithm (see docs/ga.md for the operators): every option of
    :class:`growsim.ga.GAOptions` (population, operators, generation model, elite,
    islands...), plus the genome's coding and the run's budget."""

    generations: StrictInt | None = Field(
        20,
        ge=1,
        le=10_000_000,
        description="stop after this many generations (generation 0, the random population, "
        "counts as one)",
    )
    evaluations: StrictInt | None = Field(
        None, ge=1, description="stop after this many evaluations"
    )
    target: StrictFloat | None = Field(None, description="stop when the best fitness reaches it")
    stagnation: StrictInt | None = Field(
        None, ge=1, description="stop after this many generations without improvement"
    )
    wall_time: StrictFloat | None = Field(None, gt=0.0, description="stop after this many seconds")
    coding: Literal["real", "bits"] = Field("real", description="genome coding")
    bits: StrictInt = Field(8, ge=1, le=32, description="bits per parameter when coding = 'bits'")
    bit_coding: Literal["binary", "gray", "weighted", "fraction"] = Field(
        "binary", description="how bits map to a value when coding = 'bits'"
    )
    polish: PolishOptions | None = Field(
        None,
        description="local refinement of the best at the end (a table: evaluations, sigma, "
        'batch, min_sigma, method "es" or "cmaes"), e.g. {evaluations = 500, sigma = 0.02}; '
        "its evaluations come out of ga.evaluations and must leave the GA at least one",
    )

    @model_validator(mode="after")
    def _budget(self):
        if self.generations is None and self.evaluations is None and self.wall_time is None:
            raise ValueError("no budget: set at least one of generations, evaluations or wall_time")
        # what GA.run refuses is refused here, before a run writes anything
        if self.evaluations is not None and self.polish is not None:
            if self.evaluations - self.polish.evaluations < 1:
                raise ValueError(
                    f"polish.evaluations ({self.polish.evaluations}) leaves no evaluations of "
                    f"the budget (evaluations = {self.evaluations}) for the GA"
                )
        return self

    def stop_options(self) -> dict[str, Any]:
        """The keyword options of :meth:`growsim.ga.GA.run` (budget, stops, polish)."""
        return {
            "generations": self.generations,
            "evaluations": self.evaluations,
            "target": self.target,
            "stagnation": self.stagnation,
            "wall_time": self.wall_time,
            "polish": None if self.polish is None else dataclasses.asdict(self.polish),
        }


class OutputConfig(Options):
    """``[output]``: which artefacts a run writes besides history, best and summary."""

    mesh: list[Literal["vtp", "ply", "obj", "glb"]] = Field(
        default_factory=lambda: ["vtp", "glb"],
        description="mesh formats of the best phenotype (plants)",
    )
    screenshots: list[Literal[tuple(VIEWS)]] = Field(  # type: ignore[valid-type]
        default_factory=lambda: ["front", "iso"], description="views rendered to best_<view>.png"
    )
    size: list[int] = Field(
        default_factory=lambda: [800, 800],
        min_length=2,
        max_length=2,
        description=f"screenshot size [width, height] in pixels ({MIN_SIZE}..{MAX_SIZE})",
    )
    plot: bool = Field(True, description="write fitness.png")
    phenotype: bool = Field(
        True, description="write best_<kind>.npz, the best phenotype (best_plant.npz for plants)"
    )

    @model_validator(mode="before")
    @classmethod
    def _legacy_plant(cls, data: Any) -> Any:
        # ``plant`` was the name of ``phenotype`` before models could grow other things
        if isinstance(data, dict) and "plant" in data:
            data = dict(data)
            if "phenotype" in data:
                raise ValueError("plant: the old name of phenotype; give only phenotype")
            data["phenotype"] = data.pop("plant")
        return data

    @field_validator("size")
    @classmethod
    def _check_size(cls, v):
        if not all(MIN_SIZE <= s <= MAX_SIZE for s in v):
            raise ValueError(
                f"each of width, height must be in [{MIN_SIZE}, {MAX_SIZE}], got {v!r}"
            )
        return v


class SweepVariant(Options):
    """One named variant of ``[[sweep.variants]]``: its name and the config keys it sets.

    Examples
    --------
    >>> SweepVariant(name="half_water", set={"environment.water.supply": 0.5}).name
    'half_water'
    """

    name: str = Field(
        pattern=r"^[A-Za-z0-9_.+-]{1,60}$",
        description="the variant's name (its directory in a sweep): letters, digits, _ . + -",
    )
    set: dict[str, Any] = Field(
        default_factory=dict,
        description="config keys (dotted paths, as --set) and their values in this variant",
    )


class SweepConfig(Options):
    """``[sweep]``: named variants for ``growsim sweep`` (e.g. the environments compared).

    ``growsim sweep`` runs each variant (crossed with ``--vary``) for every repeat; a
    variant's name is its directory.

    Examples
    --------
    >>> s = SweepConfig(variants=[{"name": "ample"}, {"name": "dark",
    ...                           "set": {"environment.light.intensity": 0.5}}])
    >>> [v.name for v in s.variants]
    ['ample', 'dark']
    """

    variants: list[SweepVariant] = Field(
        default_factory=list,
        description="named variants (`[[sweep.variants]]` with `name` and `set`) that "
        "`growsim sweep` runs, each for every --vary value and repeat",
    )

    @field_validator("variants")
    @classmethod
    def _unique(cls, v):
        names = [x.name for x in v]
        twice = sorted({n for n in names if names.count(n) > 1})
        if twice:
            raise ValueError(f"variant names must differ: {', '.join(twice)} given twice")
        return v


#: ``expect`` of a primary measure: ``"A > B"``, ``"A < B"`` or ``"A != B"`` (either way)
EXPECT_RE = re.compile(r"^\s*([A-Za-z0-9_.+=,-]+)\s*(>|<|!=)\s*([A-Za-z0-9_.+=,-]+)\s*$")


class PrimaryMeasure(Options):
    """One primary test of ``[compare] primary``: a measure and the difference expected
    between two groups (sweep variants), declared before the runs. With ``garden``, a
    contrast within a common garden: the best genomes evolved in the two groups (their
    origins) grown side by side in that group's environment (``growsim compare``
    grows the garden for it).

    Examples
    --------
    >>> PrimaryMeasure(measure="height", expect="ample > half_water").groups()
    ('ample', '>', 'half_water')
    >>> PrimaryMeasure(measure="fitness", expect="half_water > ample", garden="half_water").garden
    'half_water'
    """

    measure: str = Field(
        min_length=1,
        max_length=200,
        description="a quantity of growsim compare: best_fitness, a measure of the best "
        "phenotype (height, wood_volume, ...) or an objective term (nutrient.score)",
    )
    expect: str = Field(
        description='the groups and the direction expected: "A > B" (A\'s mean higher), '
        '"A < B", or "A != B" (a difference either way); A and B are sweep variant names '
        "(or group labels of growsim compare)",
    )
    garden: str | None = Field(
        None,
        min_length=1,
        max_length=200,
        description="a contrast within one common garden: the genomes evolved in A and B grown "
        "side by side in this group's environment (measure: fitness or a measure of the "
        "plant grown there); unset: each group in its own environment",
    )

    @field_validator("expect")
    @classmethod
    def _check_expect(cls, v):
        m = EXPECT_RE.match(v)
        if not m:
            raise ValueError(f'expected "A > B", "A < B" or "A != B" (group names), got {v!r}')
        if m.group(1) == m.group(3):
            raise ValueError(f"{v!r}: a group against itself")
        return f"{m.group(1)} {m.group(2)} {m.group(3)}"

    def groups(self) -> tuple[str, str, str]:
        """``(group a, direction, group b)``, direction one of ``>``, ``<``, ``!=``."""
        m = EXPECT_RE.match(self.expect)
        assert m is not None  # validated
        return m.group(1), m.group(2), m.group(3)


class CompareConfig(Options):
    """``[compare]``: what ``growsim compare`` tests as confirmatory (docs/compare.md).

    The primary tests are corrected (Holm) over themselves alone; every other test is
    reported as exploratory. Without ``[compare]``, compare corrects over every test.

    Examples
    --------
    >>> c = CompareConfig(primary=[{"measure": "height", "expect": "ample > half_water"}])
    >>> c.primary[0].groups(), c.alpha, c.test
    (('ample', '>', 'half_water'), 0.05, 'welch')
    """

    primary: list[PrimaryMeasure] = Field(
        default_factory=list,
        max_length=100,
        description='primary tests, declared before the runs: [{measure = "height", '
        'expect = "ample > half_water"}, ...]; Holm-corrected over these alone',
    )
    alpha: float = Field(
        0.05,
        gt=0.0,
        lt=1.0,
        description="threshold of the primary tests (Holm-adjusted p below it: a finding; "
        "the two-sided alpha of the power calculation)",
    )
    test: Literal["welch", "mann_whitney"] = Field(
        "welch", description="the test whose p decides a primary finding"
    )
    power: float = Field(
        0.8,
        gt=0.0,
        lt=1.0,
        description="power for which compare reports the seeds per group a replication needs",
    )

    @field_validator("primary")
    @classmethod
    def _unique(cls, v):
        seen = set()
        for i, p in enumerate(v):
            a, _, b = p.groups()
            key = (p.measure, frozenset((a, b)), p.garden)
            if key in seen:
                where = f" in garden {p.garden}" if p.garden else ""
                raise ValueError(f"[{i}]: {p.measure} between {a} and {b}{where} declared twice")
            seen.add(key)
        return v


class Config(Options):
    """A whole, validated experiment config (the TOML file as objects).

    Examples
    --------
    >>> cfg = Config.model_validate({"model": {"kind": "honda", "evolve": {"f": True}},
    ...                              "objective": [{"kind": "light"}]})
    >>> cfg.ga.population, cfg.objective[0].wood_cost
    (50, 0.02)
    """

    experiment: ExperimentConfig = Field(default_factory=ExperimentConfig)
    model: ModelConfig
    environment: Environment = Field(default_factory=Environment)
    objective: list[ObjectiveConfig] = Field(min_length=1, max_length=64)
    ga: GAConfig = Field(default_factory=GAConfig)
    output: OutputConfig = Field(default_factory=OutputConfig)
    sweep: SweepConfig = Field(default_factory=SweepConfig)
    compare: CompareConfig | None = Field(
        None, description="primary measures of growsim compare (docs/compare.md)"
    )

    @model_validator(mode="after")
    def _primary_groups(self):
        # a primary test names sweep variants: when the config has named variants, an
        # unknown name is a typo (without variants, compare checks the group labels)
        names = [v.name for v in self.sweep.variants]
        if self.compare is None or not names:
            return self
        for i, p in enumerate(self.compare.primary):
            for g in (p.groups()[0], p.groups()[2]):
                if g not in names:
                    raise ValueError(
                        f"compare.primary[{i}].expect: unknown variant {g!r}; the sweep's "
                        f"variants: {', '.join(names)}"
                    )
        return self

    def to_dict(self) -> dict[str, Any]:
        """The config as plain TOML-able data (``None`` values left out: TOML has no null).

        Examples
        --------
        >>> from growsim.experiment import load_config
        >>> load_config("experiments/quickstart.toml").to_dict()["model"]["kind"]
        'honda'
        """
        return self.model_dump(mode="json", exclude_none=True)

    def to_toml(self) -> str:
        """The config as TOML text (what ``config.toml`` of a run holds)."""

        return tomli_w.dumps(self.to_dict())

    def with_seed(self, seed: int) -> Config:
        """A copy with ``experiment.seed = seed`` (no re-validation of the rest).

        Examples
        --------
        >>> cfg = Config.model_validate({"model": {"kind": "honda", "evolve": {"f": True}},
        ...                              "objective": [{"kind": "light"}]})
        >>> cfg.with_seed(7).experiment.seed, cfg.experiment.seed
        (7, 0)
        """
        exp = ExperimentConfig.model_validate({**self.experiment.model_dump(), "seed": seed})
        return self.model_copy(update={"experiment": exp})


#: section name -> its class (docs and 'unknown key' messages walk these)
SECTIONS: dict[str, Any] = {
    "experiment": ExperimentConfig,
    "model": ModelConfig,
    "environment": Environment,
    "objective": ObjectiveConfig,
    "ga": GAConfig,
    "output": OutputConfig,
    "sweep": SweepConfig,
    "compare": CompareConfig,
}
