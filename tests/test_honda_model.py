"""Honda model: kernel vs oracle, topology property, presets, switches, guards."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from naive.honda import grow_kernel as grow_oracle
from naive.honda import leaves_kernel as leaves_oracle
from naive.honda import sag_kernel as sag_oracle

from growsim.errors import ResourceError, UserInputError
from growsim.kernels.honda import (
    N_DRAWS,
    grow_kernel,
    leaves_kernel,
    sag_kernel,
    subtree_tips_kernel,
)
from growsim.models import get_model, honda
from growsim.phenotypes.plant import LEAF, STEM


def _geo(**kw):
    base = {q.name: q.default for q in honda.PARAMS}
    base.update(kw)
    return honda._geo(base)


def _grow(f, gens, geo, seed=0):
    n, _ = honda.count_topology(f, gens)
    U = np.random.default_rng(seed).random(((n - 1) // 2, N_DRAWS))
    return grow_kernel(f, gens, geo, U, n + 1), U


CASES = [
    (0.95, 6, {}),
    (1.0, 5, {}),
    (0.0, 5, {}),
    (0.45, 9, {"thq": 1.0, "theta0": 60.0, "theta_max": 30.0}),  # fold above 90 deg
    (0.6, 8, {"thr": 0.0, "theta_max": 0.0}),
    (0.78, 7, {"phi0": 30.0, "phi_max": 0.0, "avoid": 0.8}),
    (0.99, 7, {"avoid": 1.0, "b_max": 0.0}),
    (0.3, 10, {"thq": 0.0}),
]


@pytest.mark.parametrize("f,gens,kw", CASES)
def test_kernel_matches_oracle(f, gens, kw):
    geo = _geo(**kw)
    (pos, vpar, _depth, order, gen, _main, _t, _p), U = _grow(f, gens, geo, seed=7)
    opos, ovpar, oorder, ogen = grow_oracle(f, gens, geo, U)
    assert vpar.tolist() == ovpar.tolist()
    assert order.tolist() == oorder.tolist()
    assert gen.tolist() == ogen.tolist()
    np.testing.assert_allclose(pos, opos, rtol=1e-12, atol=1e-9)


@settings(max_examples=25, deadline=None)
@given(
    f=st.floats(0, 1),
    gens=st.integers(1, 9),
    seed=st.integers(0, 2**32 - 1),
    thq=st.floats(0, 1),
    thr=st.floats(0, 1),
    th0=st.floats(0, 90),
)
def test_kernel_matches_oracle_random(f, gens, seed, thq, thr, th0):
    geo = _geo(thq=thq, thr=thr, theta0=th0)
    (pos, vpar, *_), U = _grow(f, gens, geo, seed=seed)
    opos, ovpar, _, _ = grow_oracle(f, gens, geo, U)
    assert vpar.tolist() == ovpar.tolist()
    np.testing.assert_allclose(pos, opos, rtol=1e-12, atol=1e-9)


@settings(max_examples=30, deadline=None)
@given(f=st.floats(0, 1), gens=st.integers(1, 12), s1=st.integers(0, 999), s2=st.integers(0, 999))
def test_topology_depends_only_on_f_and_steps(f, gens, s1, s2):
    a = honda.develop({"f": f, "generations": gens, "seed": s1, "leaves": 0})
    b = honda.develop(
        {
            "f": f,
            "generations": gens,
            "seed": s2,
            "leaves": 0,
            "theta0": 50,
            "thq": 0.9,
            "thr": 0.1,
            "bd": 3,
            "b0": 1,
            "avoid": 0.5,
            "sag": 0.7,
        }
    )
    assert a.parent.tolist() == b.parent.tolist()
    assert a.order.tolist() == b.order.tolist()
    assert a.n_segments == honda.count_topology(f, gens)[0]


def test_seed_rules_by_hand():
    # f = 1: every tip branches every step: the full binary tree (2,047 segments at 10).
    assert honda.count_topology(1.0, 10) == (2047, 1024)
    # nutrients in float32 like the seed's C floats: ten rations of 0.1 reach 1 (in float64
    # they would not), so the trunk's first lateral branches at step 11
    assert honda.count_topology(0.1, 11) == (25, 13)
    assert honda.count_topology(0.1, 10) == (21, 11)
    # f = 0: only the trunk branches; laterals never grow.
    assert honda.count_topology(0.0, 10) == (21, 11)
    # the seed's Fig. 5 (f = 1/3, 4 steps): parents of vertices 1..11 are
    # 0,1,1,2,2,4,4,3,3,6,6 -- the lateral 3 reaches 1 at step 4 and, scanned before
    # the trunk tip 6, is numbered first.
    t = honda.develop({"f": 1 / 3, "generations": 4, "leaves": 0})
    assert (t.parent + 1).tolist() == [0, 1, 1, 2, 2, 4, 4, 3, 3, 6, 6]
    # f = 0.5, 3 steps: vertex 3 (0.5 + 0.5) branches before the trunk tip 4
    t = honda.develop({"f": 0.5, "generations": 3, "leaves": 0})
    assert (t.parent + 1).tolist() == [0, 1, 1, 2, 2, 3, 3, 4, 4]
    assert t.data["main"].tolist() == [True, True, False, True, False, False, False, True, False]
    assert t.order.tolist() == [0, 0, 1, 0, 1, 1, 2, 0, 1]
    assert t.data["generation"].tolist() == [0, 1, 1, 2, 2, 3, 3, 3, 3]


def test_main_trunk_straight_at_thr_zero_and_first_pair_opposed():
    t = honda.develop({**honda.PRESETS["ginkgo"], "thr": 0.0, "leaves": 0})
    main = t.data["main"]
    d = t.end[main] - t.start[main]
    assert np.allclose(d[:, [0, 2]], 0.0)  # cedar-like: straight up
    # the first node's two branches are 180 + U[0, phi_max) degrees apart
    t = honda.develop({"phi_max": 0.0, "leaves": 0, "thr": 1.0, "theta_max": 0.0, "theta0": 30})
    a, b = (t.end[1] - t.start[1]), (t.end[2] - t.start[2])
    ang = math.degrees(math.atan2(b[2], b[0]) - math.atan2(a[2], a[0])) % 360
    assert ang == pytest.approx(180.0, abs=1e-6)


def test_droop_only_on_first_two_trunk_nodes_branches():
    t = honda.develop(
        {
            "f": 1.0,
            "generations": 4,
            "thq": 0.5,
            "theta_max": 0.0,
            "theta0": 10,
            "thr": 0.0,
            "leaves": 0,
        }
    )
    theta = np.degrees(np.arccos(np.clip((t.end[:, 1] - t.start[:, 1]) / t.lengths(), -1, 1)))
    # vertex 3 (segment 2) is the first lateral: 10 * (1 + 0.5); vertex 5 (segment 4) the
    # second; the trunk's third lateral (vertex 7 would be 2's... ) gets no droop.
    assert theta[2] == pytest.approx(15.0)
    assert theta[4] == pytest.approx(15.0)
    main = np.flatnonzero(t.data["main"])
    assert np.allclose(theta[main], 0.0)
    # the lateral of a drooping branch droops one thq more: 10 * (1 + 1.0)
    lateral_of_3 = [s for s in range(t.n_segments) if t.parent[s] == 2 and t.order[s] == 2]
    assert theta[lateral_of_3[0]] == pytest.approx(20.0)
    # a lateral of the main trunk after the second node: no droop (exactly theta0)
    late = [s for s in range(t.n_segments) if t.parent[s] in main[2:] and not t.data["main"][s]]
    assert np.allclose(theta[late], 10.0)


def test_presets_table2_and_reproducible():
    assert len(honda.PRESETS) == 8
    z = honda.PRESETS["zelkova"]
    assert (z["generations"], z["seed"], z["f"], z["theta_max"], z["bd"]) == (10, 3, 0.95, 40, 20)
    assert honda.PRESETS["ginkgo"]["generations"] == 13
    for name, p in honda.PRESETS.items():
        a, b = honda.develop(p), honda.develop(p)
        assert np.array_equal(a.end, b.end), name
        assert a.meta["seed"] == p["seed"]
    c = honda.develop(z, seed=99)
    assert not np.array_equal(c.end, honda.develop(z).end)


def test_spec_is_ga_codable_and_registered():
    model = get_model("honda")
    assert model is honda.MODEL and model.name == honda.NAME == "honda"
    assert model.params == honda.PARAMS and model.presets is honda.PRESETS
    names = [p.name for p in honda.PARAMS]
    for k in (
        "generations",
        "seed",
        "f",
        "theta0",
        "phi0",
        "theta_max",
        "phi_max",
        "thq",
        "thr",
        "bd",
        "b0",
        "b_max",
        "sag",
        "avoid",
    ):
        assert k in names
    kinds = {p.name: p.kind for p in honda.PARAMS}
    assert kinds["generations"] == kinds["seed"] == "int"
    defaults = {p.name: p.default for p in honda.PARAMS}
    assert defaults["sag"] == 0 and defaults["avoid"] == 0


def test_bad_input_and_memory_guard():
    with pytest.raises(UserInputError, match="f"):
        honda.develop({"f": 1.5})
    with pytest.raises(UserInputError, match="nope"):
        honda.develop({"nope": 1})
    with pytest.raises(ResourceError, match="67,108,863"):
        honda.develop({"f": 1.0, "generations": 25})


def test_leaves_carried_on_terminal_branches():
    t = honda.develop(honda.PRESETS["plane"])
    stems = t.kind == STEM
    leaf = t.kind == LEAF
    bearing = honda.leaf_bearing(t.parent[stems])
    assert t.n_leaves == 3 * bearing.sum()
    assert np.all(bearing[t.parent[leaf]])
    # leaves start on their branch
    s = t.parent[leaf]
    a, b, p = t.start[s], t.end[s], t.start[leaf]
    cross = np.linalg.norm(np.cross(b - a, p - a), axis=1) / np.linalg.norm(b - a, axis=1)
    assert cross.max() < 1e-9
    assert t.leaf_area() > 0


def test_sag_and_pipe_and_avoid_switches():
    p = honda.PRESETS["plane"]
    base = honda.develop(p)
    sag = honda.develop({**p, "sag": 1.0})
    assert sag.bbox()[1, 1] < base.bbox()[1, 1]  # weight lowers the crown
    stems = sag.kind == STEM
    # still connected: each stem starts where its parent ends
    ps = sag.parent[stems]
    has = ps >= 0
    assert np.allclose(sag.start[stems][has], sag.end[ps[has]])
    np.testing.assert_allclose(sag.lengths()[stems], base.lengths()[stems])
    pipe = honda.develop({**p, "pipe": 1})
    assert pipe.radius[0] == pytest.approx(p.get("radius", 1.0))
    r = pipe.radius[stems]
    par = pipe.parent[stems]
    kids = np.zeros(stems.sum())
    np.add.at(kids, par[par >= 0], r[par >= 0] ** 2)
    inner = kids > 0
    np.testing.assert_allclose(kids[inner], r[inner] ** 2)  # area preserved at each node
    avoid = honda.develop({**honda.PRESETS["f_dome"], "avoid": 1.0, "generations": 7})
    plain = honda.develop({**honda.PRESETS["f_dome"], "generations": 7})

    def crowding(t):
        e = t.end[t.kind == STEM]
        d = np.linalg.norm(e[:, None] - e[None], axis=2)
        d[np.diag_indices_from(d)] = np.inf
        return np.mean(d.min(1))

    assert crowding(avoid) > crowding(plain)


def test_subtree_tips_kernel():
    parent = np.array([-1, 0, 0, 1, 1, 2])
    assert subtree_tips_kernel(parent).tolist() == [3, 2, 1, 1, 1, 1]


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_sag_kernel_matches_oracle(seed):
    t = honda.develop({"generations": 7, "f": 0.8, "seed": seed, "leaves": 0})
    ns, ne = sag_kernel(t.start, t.end, t.radius, t.parent, 0.7, 1.0)
    os_, oe = sag_oracle(t.start, t.end, t.radius, t.parent, 0.7, 1.0)
    np.testing.assert_allclose(ns, os_, atol=1e-9)
    np.testing.assert_allclose(ne, oe, atol=1e-9)


@pytest.mark.parametrize("per_branch,e,cut", [(3, 1.2, 40.0), (1, 0.5, 0.0), (8, 2.0, 80.0)])
def test_leaves_kernel_matches_oracle(per_branch, e, cut):
    t = honda.develop({**honda.PRESETS["ginkgo"], "leaves": 0})
    ls, le, lr, lp = leaves_kernel(t.start, t.end, t.parent, per_branch, e, math.radians(cut))
    ids = np.flatnonzero(honda.leaf_bearing(t.parent))
    os_, oe, orad, op = leaves_oracle(t.start, t.end, ids, per_branch, e, cut)
    assert lp.tolist() == op.tolist()
    np.testing.assert_allclose(ls, os_, atol=1e-12)
    np.testing.assert_allclose(le, oe, atol=1e-12)
    np.testing.assert_allclose(lr, orad)
    # edge: a single vertical segment is a tip; zero leaves when e == 0
    one = leaves_kernel(np.zeros((1, 3)), np.array([[0.0, 1.0, 0.0]]), np.array([-1]), 2, 1.0, 0.0)
    assert one[0].shape == (2, 3)
    assert leaves_kernel(t.start, t.end, t.parent, 3, 0.0, 0.0)[0].shape == (0, 3)


@pytest.mark.parametrize("name", sorted(honda.PRESETS))
def test_develop_output_passes_plant_validation(name):
    from growsim.phenotypes.plant import Plant

    for extra in ({}, {"sag": 0.6, "pipe": 1, "avoid": 0.5, "leaves": 0}):
        t = honda.develop({**honda.PRESETS[name], **extra, "generations": 8})
        v = Plant(t.start, t.end, t.radius, t.parent, t.order, t.kind, data=t.data, meta=t.meta)
        for f in ("start", "end", "radius", "parent", "order", "kind"):
            a, b = getattr(t, f), getattr(v, f)
            assert a.dtype == b.dtype and a.shape == b.shape and a.flags.c_contiguous, f
            assert np.array_equal(a, b)
        for k, arr in t.data.items():
            assert arr.shape[0] == t.n_segments, k


def test_draws_override_the_arrangement_only_where_given():
    """``develop(draws=...)``: the given rows replace the seed's draws of the first
    branchings, the rest stay the seed's; without it the tree is the seed's, bit for bit."""
    p = {**honda.PRESETS["zelkova"], "leaves": 2}
    own = honda.develop(p)
    d = honda.draws(p)
    assert d.shape == ((own.n_stems - 1) // 2, N_DRAWS)
    assert np.array_equal(d, np.random.default_rng(3).random(d.shape))
    assert np.array_equal(honda.MODEL.draws(p, seed=9), honda.draws({**p, "seed": 9}))
    # the seed's own draws, or a longer array: the same tree
    for rows in (d, np.concatenate([d, np.full((5, N_DRAWS), 0.5)])):
        t = honda.develop(p, draws=rows)
        assert np.array_equal(t.start, own.start) and np.array_equal(t.end, own.end)
        assert np.array_equal(t.radius, own.radius)
    # the kernel with the override's uniforms: the first two rows changed, the rest the seed's
    new = d.copy()
    new[:2] = [[0.1, 0.9, 0.5, 0.5, 0.2, 0.8, 0.3, 1.0, 0.0]] * 2
    t = honda.MODEL.develop(p, draws=new[:2])
    n, _ = honda.count_topology(p["f"], int(p["generations"]))
    U = new.copy()
    U[1, 7] = np.nextafter(1.0, 0.0)  # a 1 read as the largest draw below 1
    U[0, 7] = np.nextafter(1.0, 0.0)
    pos = grow_kernel(p["f"], int(p["generations"]), honda._geo(p), U, n + 1)[0]
    np.testing.assert_array_equal(t.end[: own.n_stems], pos[1:])
    assert not np.array_equal(t.end[: own.n_stems], own.end[: own.n_stems])
    assert t.n_stems == own.n_stems and t.n_leaves == own.n_leaves
    with pytest.raises(UserInputError, match="draws must be an"):
        honda.develop(p, draws=np.zeros((3, 4)))
    with pytest.raises(UserInputError, match=r"\[0, 1\]"):
        honda.develop(p, draws=np.full((1, N_DRAWS), 1.5))
