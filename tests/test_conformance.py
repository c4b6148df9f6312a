"""Conformance: every registered model, phenotype and objective honours its contract.

Parametrised over the registries, so a new model or objective is tested the day it is
registered (docs/extending.md).
"""

from __future__ import annotations

import pickle

import numpy as np
import pytest

from growsim.env import Environment
from growsim.models import MODELS, get_model
from growsim.models.base import Model
from growsim.objectives import OBJECTIVES, get_objective
from growsim.objectives.base import Objective
from growsim.phenotypes import PHENOTYPES, Phenotype, load_phenotype

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
        assert m and all(isinstance(v, (int, float)) and np.isfinite(v) for v in m.values())


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
