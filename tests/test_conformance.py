"""Conformance: every registered model, phenotype and objective honours its contract.

Parametrised over the registries, so a new model or objective is tested the day it is
registered (docs/extending.md). The optional capabilities are declared, not probed: a
model or phenotype overrides exactly the capability methods it declares, and each
declared one, called on a small example, gives what its contract documents.
"""

from __future__ import annotations

import pickle

import numpy as np
import pytest

from growsim.env import Environment
from growsim.models import MODELS, get_model
from growsim.models.base import CAPABILITIES as MODEL_CAPABILITIES
from growsim.models.base import Model
from growsim.objectives import OBJECTIVES, get_objective
from growsim.objectives.base import Objective
from growsim.phenotypes import PHENOTYPES, Phenotype, load_phenotype
from growsim.phenotypes.base import CAPABILITIES as PHENOTYPE_CAPABILITIES

MODEL_NAMES = sorted(MODELS)
OBJECTIVE_NAMES = sorted(OBJECTIVES)


def _arrays(path) -> dict[str, np.ndarray]:
    with np.load(path, allow_pickle=False) as z:
        return {k: z[k] for k in z.files}


def same_phenotype(a, b, tmp_path) -> bool:
    """Two phenotypes are the same when their saved files hold the same arrays."""
    fa, fb = a.save(tmp_path / "a.npz"), b.save(tmp_path / "b.npz")
    xa, xb = _arrays(fa), _arrays(fb)
    return xa.keys() == xb.keys() and all(np.array_equal(xa[k], xb[k]) for k in xa)


def _cases(name):
    """(label, params) to grow: the model's defaults and each preset."""
    model = get_model(name)
    return [("defaults", {})] + [(p, model.preset(p)) for p in sorted(model.presets)]


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_model_declares_the_contract(name):
    model = get_model(name)
    assert isinstance(model, Model) and model.name == name
    assert model.phenotype in PHENOTYPES
    spec = model.param_spec()
    assert spec and len({p.name for p in spec}) == len(spec)
    for p in spec:
        assert p.low <= p.default <= p.high and p.kind in ("real", "int")
    assert pickle.loads(pickle.dumps(model)).name == name


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_every_preset_resolves(name):
    model = get_model(name)
    for preset in model.presets:
        values = model.resolve(model.preset(preset))
        assert set(values) == {p.name for p in model.param_spec(values)}


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_develop_gives_a_valid_phenotype_the_same_for_the_same_seed(name, tmp_path):
    model = get_model(name)
    cls = PHENOTYPES.get(model.phenotype)
    env = Environment()
    for label, params in _cases(name):
        a = model.develop(params, seed=5, env=env)
        assert isinstance(a, cls) and isinstance(a, Phenotype), label
        b = model.develop(params, seed=5, env=env)
        assert same_phenotype(a, b, tmp_path), f"{name} {label}: same seed, other phenotype"
        # it survives a round trip through its file and through pickle
        back = load_phenotype(a.save(tmp_path / "p.npz"))
        assert same_phenotype(a, back, tmp_path)
        assert same_phenotype(a, pickle.loads(pickle.dumps(a)), tmp_path)
        m = a.measures(env)
        # finite, or NaN where the measure is undefined (an unbranched plant's branch angle)
        assert m and all(isinstance(v, (int, float)) for v in m.values())
        assert all(np.isfinite(v) or (k == "branch_angle" and np.isnan(v)) for k, v in m.items())


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_grow_ends_at_the_developed_phenotype(name, tmp_path):
    model = get_model(name)
    params = _cases(name)[-1][1]
    steps = list(model.grow(params, seed=2))
    assert steps and all(isinstance(s, Phenotype) for s in steps)
    assert same_phenotype(steps[-1], model.develop(params, seed=2), tmp_path)
    assert model.stepwise or len(steps) == 1


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_pickled_model_develops_the_same(name, tmp_path):
    model = get_model(name)
    params = _cases(name)[-1][1]
    clone = pickle.loads(pickle.dumps(model))
    assert same_phenotype(model.develop(params, seed=1), clone.develop(params, seed=1), tmp_path)


# --------------------------------------------------------------------------- capabilities


def _rows(model, params, n=2):
    """``n`` copies of the full parameter row of ``params`` and the column names."""
    values = model.resolve(params)
    names = list(values)
    return np.array([[float(values[k]) for k in names]] * n), names


def _overrides(cls, base, method: str) -> bool:
    return getattr(cls, method) is not getattr(base, method)


@pytest.mark.parametrize("name", MODEL_NAMES)
def test_model_overrides_exactly_the_capabilities_it_declares(name):
    model = get_model(name)
    caps = model.capabilities
    assert isinstance(caps, frozenset) and caps <= set(MODEL_CAPABILITIES), caps
    for cap in MODEL_CAPABILITIES:
        assert _overrides(type(model), Model, cap) == (cap in caps), f"{name}: {cap}"
    rows, names = _rows(model, {})
    args = {"draws": (), "grow_stand": ({},)}  # the others take (rows, names, ...)
    for cap in sorted(set(MODEL_CAPABILITIES) - caps):
        method = getattr(model, cap)
        with pytest.raises(NotImplementedError, match=cap):
            method(*args.get(cap, (rows, names)))


#: every (model, capability) it declares
MODEL_CAPABILITY_PAIRS = [
    (m, c) for m in MODEL_NAMES for c in sorted(get_model(m).capabilities)
]  # fmt: skip


@pytest.mark.parametrize(("name", "cap"), MODEL_CAPABILITY_PAIRS)
def test_declared_model_capability_gives_its_documented_type(name, cap, tmp_path):
    import pandas as pd

    model = get_model(name)
    params = _cases(name)[-1][1]
    rows, names = _rows(model, params)
    seeds = np.array([0, 3], dtype=np.uint64)
    if cap == "population":  # a DataFrame of per-plant totals, one row per individual
        table = model.population(rows, names, seeds, env=Environment())
        assert isinstance(table, pd.DataFrame) and len(table) == len(rows)
    elif cap == "map_groups":  # (rows, maps (k, N, 4), depth) groups of the population
        groups = list(model.map_groups(rows, names))
        assert groups
        for idx, maps, depth in groups:
            assert isinstance(idx, np.ndarray) and idx.dtype.kind == "i"
            assert set(idx.tolist()) <= set(range(len(rows)))
            assert maps.ndim == 3 and maps.shape[0] == len(idx) and maps.shape[2] == 4
            assert isinstance(depth, int) and depth >= 0
    elif cap == "collisions":  # (n,) counts, each as the developed phenotype's
        counts = model.collisions(rows, names, seeds, env=Environment())
        assert isinstance(counts, np.ndarray) and counts.shape == (len(rows),)
        for c, s in zip(counts, seeds):
            assert c == model.develop(params, seed=int(s)).collisions
    elif cap == "draws":  # a 2D float array that develop(..., draws=) takes back
        d = model.draws(params, seed=4)
        assert isinstance(d, np.ndarray) and d.ndim == 2 and d.dtype == np.float64
        again = model.develop(params, seed=4, draws=d)
        assert same_phenotype(again, model.develop(params, seed=4), tmp_path)
    elif cap == "mixture":  # the focal phenotype among neighbours; None: among copies
        env = Environment.model_validate(
            {"stand": {"mode": "mixture", "neighbours": 2, "spacing": 1.0}}
        )
        copies = model.mixture(params, None, env=env)
        again = model.mixture(params, [params, params], env=env)
        assert same_phenotype(copies, again, tmp_path)
        assert same_phenotype(copies, model.develop(params, env=env), tmp_path)
    elif cap == "grow_stand":  # the stand after each step, every position's plant in it
        env = Environment.model_validate(
            {"stand": {"mode": "explicit", "layout": "row", "count": 2, "spacing": 1.0}}
        )
        steps = list(model.grow_stand(params, env=env))
        assert steps and all(isinstance(s, Phenotype) for s in steps)
        stand = steps[-1]
        assert stand.meta["stand"] == env.stand.xz().tolist()
        assert set(stand.data["plant"].tolist()) == {0, 1}
        *_, each = model.grow_stand([params, params], env=env)  # one plant a position
        assert same_phenotype(stand, each, tmp_path)
    else:  # pragma: no cover - a capability added to CAPABILITIES needs its check here
        pytest.fail(f"no conformance check for model capability {cap!r}")


def _example(kind):
    """A small phenotype of ``kind``, grown by the first model that grows that kind."""
    model = next(get_model(m) for m in MODEL_NAMES if get_model(m).phenotype == kind)
    return model.develop(_cases(model.name)[-1][1], seed=0)


@pytest.mark.parametrize("name", sorted(PHENOTYPES))
def test_phenotype_overrides_exactly_the_capabilities_it_declares(name):
    cls = PHENOTYPES.get(name)
    caps = cls.capabilities
    assert isinstance(caps, frozenset) and caps <= set(PHENOTYPE_CAPABILITIES), caps
    for cap in PHENOTYPE_CAPABILITIES:
        assert _overrides(cls, Phenotype, cap) == (cap in caps), f"{name}: {cap}"
    ph = _example(name)
    for cap in sorted(set(PHENOTYPE_CAPABILITIES) - caps):
        with pytest.raises(NotImplementedError, match=cap):
            getattr(ph, cap)()
    for cap in sorted(caps):
        if cap == "front_view":  # (size, size) uint8, 1 where the phenotype is
            view = ph.front_view(16)
            assert isinstance(view, np.ndarray) and view.shape == (16, 16)
            assert view.dtype == np.uint8 and set(np.unique(view)) <= {0, 1} and view.any()
        else:  # pragma: no cover
            pytest.fail(f"no conformance check for phenotype capability {cap!r}")


@pytest.mark.parametrize("name", sorted(PHENOTYPES))
def test_phenotype_renders_and_lists_artefacts(name, tmp_path):
    from growsim.experiment.schema import OutputConfig

    model = next(get_model(m) for m in MODEL_NAMES if get_model(m).phenotype == name)
    ph = model.develop(_cases(model.name)[-1][1], seed=0)
    img = ph.render_image(view="front", size=(48, 32))
    assert img.shape == (32, 48, 3) and img.dtype == np.uint8 and img.std() > 0
    out = OutputConfig(mesh=["vtp"], screenshots=["side"], size=[32, 32])
    files = ph.artefacts(out)
    assert "best_side.png" in files
    for fname, writer in files.items():
        writer(tmp_path / fname)
        assert (tmp_path / fname).stat().st_size > 0


@pytest.mark.parametrize("name", OBJECTIVE_NAMES)
def test_objective_declares_the_contract(name):
    cls = get_objective(name)
    assert issubclass(cls, Objective) and cls.name == name
    assert cls.accepts and all(k in PHENOTYPES for k in cls.accepts)
    assert cls.Options.model_fields["kind"].default == name
    obj = cls(**cls.example)
    assert obj.options.kind == name
    back = pickle.loads(pickle.dumps(obj))
    assert back.options == obj.options
    with pytest.raises(Exception, match="no_such_option"):
        cls(**cls.example, no_such_option=1)


#: every (objective, model) whose phenotype the objective scores
SCORED_PAIRS = [
    (o, m) for o in OBJECTIVE_NAMES for m in MODEL_NAMES
    if get_model(m).phenotype in get_objective(o).accepts
]  # fmt: skip


@pytest.mark.parametrize("obj_name", OBJECTIVE_NAMES)
def test_every_objective_scores_some_registered_model(obj_name):
    assert any(o == obj_name for o, _ in SCORED_PAIRS), f"no model grows what {obj_name} scores"


@pytest.mark.parametrize(("obj_name", "model_name"), SCORED_PAIRS)
def test_objective_scores_every_phenotype_it_accepts(obj_name, model_name):
    cls = get_objective(obj_name)
    model = get_model(model_name)
    obj = cls(**cls.example)
    cases = _cases(model_name)
    phenotypes = [model.develop(p, seed=0) for _, p in cases]
    scores = np.array([obj(ph) for ph in phenotypes], dtype=np.float64)
    assert np.all(np.isfinite(scores))
    for ph, s in zip(phenotypes, scores):
        terms = obj.terms(ph)
        assert all(np.isfinite(v) for v in terms.values())
        assert obj(ph) == s  # deterministic
    # the population fast path, where there is one, agrees with scoring one by one
    names = [p.name for p in model.param_spec(model.resolve(cases[-1][1]))]
    rows = [model.resolve(p) for _, p in cases]
    same_spec = [r for r in rows if list(r) == names]
    params = np.array([[r[n] for n in names] for r in same_spec])
    fast = obj.batch(model, params, names, np.zeros(len(params), np.uint64))
    if fast is not None:
        slow = [obj(model.develop(r, seed=0)) for r in same_spec]
        np.testing.assert_allclose(fast, slow, rtol=0, atol=1e-12)
