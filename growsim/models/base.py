"""The model contract: what every model publishes so the GA can evolve it and every later
step can use what it grows.

A model is a :class:`Model` (one instance per model, registered by name in
:data:`growsim.models.MODELS`) with

- :attr:`Model.name` and :attr:`Model.phenotype` (the kind of phenotype it returns, see
  :mod:`growsim.phenotypes`);
- its parameters, a tuple of :class:`Param` (:meth:`Model.param_spec`, which may depend
  on fixed parameters: the IFS tree's parameters depend on its number of maps);
- named parameter sets (:attr:`Model.presets`, :meth:`Model.preset`);
- :meth:`Model.develop` ``(params, *, seed, env) -> phenotype``;
- for step-wise models, :meth:`Model.grow`, yielding the phenotype after each step
  (growth animations use it; a one-shot model yields once);
- the optional capabilities it implements, declared by name in :attr:`Model.capabilities`
  (one of :data:`CAPABILITIES` each; the base methods refuse): :meth:`Model.population`,
  :meth:`Model.map_groups`, :meth:`Model.collisions`, :meth:`Model.draws`,
  :meth:`Model.mixture`, :meth:`Model.grow_stand`. Callers ask
  ``"population" in model.capabilities``, never ``getattr``. The conformance suite
  (``tests/test_conformance.py``) checks that a model overrides exactly the methods it
  declares and that each gives what its docstring says.
"""

from __future__ import annotations

import abc
import copy
import warnings
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, ClassVar, Literal

import numpy as np

from growsim.errors import UserInputError
from growsim.phenotypes.stand import place

__all__ = ["CAPABILITIES", "Model", "Param", "resolve_params"]

#: the optional capabilities a model may declare (:attr:`Model.capabilities`), each the
#: name of the :class:`Model` method that implements it
CAPABILITIES = ("population", "map_groups", "collisions", "draws", "mixture", "grow_stand")


@dataclass(frozen=True)
class Param:
    """One model parameter: its name, range ``[low, high]``, kind and default.

    ``kind`` is ``"real"`` or ``"int"``. A GA-codable field: :func:`growsim.ga.genome_from_params`
    turns a list of them into a :class:`growsim.ga.Genome`. An ``"int"`` parameter may
    name its values (``labels``, value ``i`` the ``i``-th label, ``low`` 0): a config,
    preset or ``--set`` gives it by name (``physics = "paper"``), and it stays a number
    everywhere else.

    Examples
    --------
    >>> p = Param("f", 0.0, 1.0, default=0.95, doc="lateral nutrient ratio")
    >>> p.check(0.5)
    0.5
    >>> Param("physics", 0, 1, 0, kind="int", labels=("growsim", "paper")).check("paper")
    1.0
    """

    name: str
    low: float
    high: float
    default: float
    kind: Literal["real", "int"] = "real"
    doc: str = ""
    unit: str = ""
    labels: tuple[str, ...] = ()

    def check(self, value, where: str = "") -> float:
        """Return ``value`` as a float (int-valued for ``kind="int"``; a label's index for
        a named value) or raise :class:`UserInputError` naming the parameter and its
        range."""
        label = f"{where}{self.name}"
        if isinstance(value, str) and self.labels:
            if value not in self.labels:
                raise UserInputError(
                    f"{label}: {value!r} is not one of {', '.join(map(repr, self.labels))}"
                )
            return float(self.labels.index(value))
        if isinstance(value, str):
            raise UserInputError(f"{label}: expected a number (got {value!r})")
        if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
            raise UserInputError(f"{label}: expected a number, got {value!r}")
        v = float(value)
        if not np.isfinite(v):
            raise UserInputError(f"{label}: {value!r} is not a finite number")
        if v < self.low or v > self.high:
            raise UserInputError(
                f"{label}: {value!r} is out of range [{self.low:g}, {self.high:g}]"
            )
        if self.kind == "int":
            if v != round(v):
                raise UserInputError(f"{label}: expected an integer, got {value!r}")
            v = float(round(v))
        return v


def resolve_params(
    spec: Sequence[Param], values: Mapping[str, float] | None = None, where: str = ""
) -> dict[str, float]:
    """Fill defaults from ``spec``, check every value, reject unknown names.

    Examples
    --------
    >>> spec = (Param("a", 0, 1, 0.5), Param("n", 1, 9, 3, kind="int"))
    >>> resolve_params(spec, {"n": 4})
    {'a': 0.5, 'n': 4.0}
    """
    by_name = {p.name: p for p in spec}
    values = dict(values or {})
    unknown = sorted(set(values) - set(by_name))
    if unknown:
        raise UserInputError(
            f"{where}unknown parameter(s) {', '.join(unknown)}; allowed: {', '.join(by_name)}"
        )
    return {p.name: p.check(values.get(p.name, p.default), where) for p in spec}


class Model(abc.ABC):
    """Base of every model (see the module docstring for the contract).

    Subclasses set :attr:`name`, :attr:`phenotype`, :attr:`params` (the spec for the
    default fixed values) and :attr:`presets`, and implement :meth:`develop`; a model
    whose spec depends on fixed parameters overrides :meth:`param_spec`; a step-wise
    model overrides :meth:`grow` and sets :attr:`stepwise`. Instances hold no state, so
    they pickle to process pools and Dask workers.

    Examples
    --------
    >>> from growsim.models import get_model
    >>> m = get_model("honda")
    >>> m.name, m.phenotype, m.preset("zelkova")["f"]
    ('honda', 'plant', 0.95)
    >>> [type(p).__name__ for p in m.grow(m.preset("zelkova"))]
    ['Plant']
    """

    #: registry name
    name: ClassVar[str] = ""
    #: kind of phenotype :meth:`develop` returns (a name in :data:`growsim.phenotypes.PHENOTYPES`)
    phenotype: ClassVar[str] = "plant"
    #: the parameter spec for default fixed values
    params: ClassVar[tuple[Param, ...]] = ()
    #: named parameter sets
    presets: ClassVar[Mapping[str, Mapping[str, float]]] = {}
    #: the ``[environment]`` table a preset is shown in (``growsim grow --preset``), if any;
    #: an experiment naming the preset keeps its own ``[environment]``
    preset_environments: ClassVar[Mapping[str, Mapping[str, Any]]] = {}
    #: deprecated preset names and their new names: :meth:`preset` still takes them for one
    #: version, with a :class:`DeprecationWarning` (``growsim`` prints it as a note)
    preset_aliases: ClassVar[Mapping[str, str]] = {}
    #: True when :meth:`grow` yields one phenotype per growth step
    stepwise: ClassVar[bool] = False
    #: the optional capabilities implemented (names in :data:`CAPABILITIES`)
    capabilities: ClassVar[frozenset[str]] = frozenset()

    def param_spec(self, fixed: Mapping[str, float] | None = None) -> tuple[Param, ...]:
        """The parameters of the model given the ``fixed`` values (default: :attr:`params`)."""
        return tuple(self.params)

    def preset(self, name: str) -> dict[str, float]:
        """The parameter values of preset ``name``; :class:`UserInputError` naming the
        model and the presets available if there is no such preset. A deprecated name
        (:attr:`preset_aliases`) gives its new preset, with a :class:`DeprecationWarning`.

        Examples
        --------
        >>> import warnings
        >>> from growsim.models import get_model
        >>> with warnings.catch_warnings(record=True) as caught:
        ...     warnings.simplefilter("always")
        ...     old = get_model("ifs3d").preset("seed_ga")
        >>> old == get_model("ifs3d").preset("paper_ga"), str(caught[0].message)
        (True, "preset 'seed_ga' is now 'paper_ga'; the old name goes in 0.3")
        """
        if isinstance(name, str) and name in self.preset_aliases:
            new = self.preset_aliases[name]
            warnings.warn(
                f"preset {name!r} is now {new!r}; the old name goes in 0.3",
                DeprecationWarning,
                stacklevel=2,
            )
            name = new
        if not isinstance(name, str) or name not in self.presets:
            raise UserInputError(
                f"unknown preset {name!r} of model {self.name!r}; "
                f"available: {', '.join(sorted(self.presets)) or '(none)'}"
            )
        return dict(self.presets[name])

    def preset_environment(self, name: str) -> dict[str, Any]:
        """The ``[environment]`` table preset ``name`` is grown in by ``growsim grow``
        (:attr:`preset_environments`; empty: the default environment).

        Examples
        --------
        >>> from growsim.models import get_model
        >>> get_model("hormone").preset_environment("demo_3d")["light"]["diffuse"]
        0.5
        >>> get_model("honda").preset_environment("zelkova")
        {}
        """
        if isinstance(name, str):
            name = self.preset_aliases.get(name, name)  # preset() says it is deprecated
        self.preset(name)  # an unknown preset is refused the same way
        return copy.deepcopy(dict(self.preset_environments.get(name, {})))

    def resolve(
        self, values: Mapping[str, float] | None = None, where: str = ""
    ) -> dict[str, float]:
        """Every parameter's value: ``values`` over the defaults, checked against
        :meth:`param_spec` of ``values`` (see :func:`resolve_params`)."""
        values = dict(values or {})
        return resolve_params(self.param_spec(values), values, where=where)

    @abc.abstractmethod
    def develop(self, params: Mapping[str, float], *, seed: int | None = None, env=None) -> Any:
        """Grow one phenotype from ``params`` (any subset of the spec; the rest default).

        ``seed``: the randomness of this growth (a model whose randomness is itself a
        parameter uses that when ``seed`` is None; deterministic models ignore it).
        ``env``: the :class:`growsim.env.Environment` (None: the default environment).
        """

    def grow(
        self, params: Mapping[str, float], *, seed: int | None = None, env=None
    ) -> Iterator[Any]:
        """Yield the phenotype after each growth step (a one-shot model: once, grown)."""
        yield self.develop(params, seed=seed, env=env)

    def grow_in_stand(
        self, params, *, seed: int | None = None, env, every_step: bool = True
    ) -> Iterator[Any]:
        """Grow the plants of ``env``'s explicit stand (``env.stand.xz()``): copies of
        ``params`` (a mapping) or one plant per position (a sequence of mappings),
        yielding the stand (one phenotype, as :func:`growsim.phenotypes.stand.place`
        builds it) after every step, or only the last (``every_step=False``).

        A model with the ``"grow_stand"`` capability grows them together, each shading
        the others (:meth:`grow_stand`); any other grows each plant alone and places it,
        the stand lit by ``env.light`` (one plant per position: grown once, one stand).

        Examples
        --------
        >>> from growsim.env import Environment
        >>> from growsim.models import get_model
        >>> env = Environment.parse({"stand": {"mode": "explicit", "layout": "row", "count": 2}})
        >>> honda = get_model("honda")
        >>> *_, s = honda.grow_in_stand(honda.resolve({}), env=env, every_step=False)
        >>> sorted(set(s.data["plant"].tolist())), s.meta["stand"]
        ([0, 1], [[-0.5, 0.0], [0.5, 0.0]])
        """
        xz = env.stand.xz()
        if "grow_stand" in self.capabilities:
            steps = self.grow_stand(params, env=env)
        elif not isinstance(params, Mapping):
            grown = [self.develop(q, seed=seed, env=env) for q in params]
            yield place(grown, xz, light=env.light)
            return
        else:
            steps = self.grow(params, seed=seed, env=env)
        if not every_step:
            *_, last = steps
            steps = [last]
        for plant in steps:
            yield plant if "grow_stand" in self.capabilities else place(plant, xz, light=env.light)

    def _missing(self, capability: str):
        raise NotImplementedError(
            f"model {self.name!r} has no {capability!r} capability "
            f"(it declares: {', '.join(sorted(self.capabilities)) or 'none'})"
        )

    def population(self, params: np.ndarray, names: Sequence[str], seeds=None, env=None):
        """Capability ``"population"``: grow every row of full parameters ``(n, p)``
        (columns ``names``) in one call, keeping no phenotype; a ``pandas.DataFrame`` of
        per-plant totals (one row per individual), or None when this population cannot
        take the path (the caller then develops one by one)."""
        self._missing("population")

    def map_groups(self, params: np.ndarray, names: Sequence[str]):
        """Capability ``"map_groups"``: the population split into groups that share their
        discrete parameters, each ``(rows, maps, depth)`` (the IFS tree's population
        kernel of the silhouette objective)."""
        self._missing("map_groups")

    def collisions(self, params: np.ndarray, names: Sequence[str], seeds=None, env=None):
        """Capability ``"collisions"``: ``(n,)`` collision counts of every row of full
        parameters, no phenotype kept (the fish's population kernel), or None when the
        population cannot take the path."""
        self._missing("collisions")

    def draws(self, params: Mapping[str, float] | None = None, *, seed=None) -> np.ndarray:
        """Capability ``"draws"``: the random draws of the phenotype's arrangement (one
        row per branching), which ``develop(params, draws=...)`` takes back, so a fit can
        search them (:func:`growsim.fitting.setups.arrange`)."""
        self._missing("draws")

    def mixture(self, params, neighbours, *, seed=None, env=None):
        """Capability ``"mixture"``: the phenotype of ``params`` grown together with
        ``neighbours`` (a sequence of parameter mappings, ``env.stand.neighbours`` of them;
        None: copies of ``params``) in ``env``'s mixed stand (``environment.stand.mode =
        "mixture"``), scored as the focal plant among them."""
        self._missing("mixture")

    def grow_stand(self, params, *, seed=None, env=None) -> Iterator[Any]:
        """Capability ``"grow_stand"``: grow the plants of ``env``'s explicit stand together
        (``environment.stand.mode = "explicit"``, at ``env.stand.xz()``), each shading the
        others, yielding the stand after every step (one phenotype: ``data["plant"]`` each
        segment's plant, ``meta["stand"]`` the positions, as
        :func:`growsim.phenotypes.stand.place` builds one of plants grown alone): copies
        of ``params`` (a mapping), or one plant per position (a sequence of mappings).
        A model without it grows each plant alone (:meth:`grow`) and places them."""
        self._missing("grow_stand")

    def __repr__(self) -> str:
        return f"<growsim model {self.name!r} ({self.phenotype})>"
