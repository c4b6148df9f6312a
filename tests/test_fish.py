"""The fish in a tank (seed 001): kernel vs oracle, decoding, behaviour, collisions, the
trajectory phenotype, the objective, the CLI end to end, bad input."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from conftest import ROOT, growsim
from naive import fish as naive

from growsim.env import Environment, Tank
from growsim.errors import ConfigError
from growsim.experiment import load_plan
from growsim.kernels import fish as K
from growsim.models.fish import MODEL, PARAMS, default_tank, develop, fish_table
from growsim.phenotypes import load_phenotype
from growsim.phenotypes.trajectory import Trajectory

CONFIG = ROOT / "experiments" / "fish_tank.toml"
NAMES = [p.name for p in PARAMS]
EMPTY = np.zeros((0, 4))


def random_fish(rng, n, size=(300, 400, 300)):
    """Fish tables with every gene drawn uniformly from its range."""
    size = np.asarray(size, float)
    cols = [rng.uniform(40, s - 40, n) for s in size]
    cols += [rng.uniform(2, 17, n), rng.uniform(20, 100, n), np.radians(rng.uniform(45, 215, n))]
    cols += [rng.uniform(5, 45, n), rng.uniform(0, 2 * np.pi, n)]
    cols += [np.radians(rng.uniform(-30, 30, n)), rng.integers(0, 2, n).astype(float)]
    cols += [np.full(n, 2.0), np.full(n, 0.75), np.full(n, 1.0)]
    return np.column_stack(cols)


def tank_arrays(preset="small"):
    return Tank.model_validate({"preset": preset}).arrays()


# ---------------------------------------------------------------- kernel vs oracle
@pytest.mark.parametrize("preset", ["small", "large"])
def test_kernel_matches_the_oracle(preset):
    size, spheres, cubes = tank_arrays(preset)
    rng = np.random.default_rng(7)
    fish = random_fish(rng, 12, size)
    totals = []
    for i, g in enumerate(fish):
        pos, ang, hits, modes, total = K.swim_path(g, i, size, spheres, cubes, 300)
        npos, nang, nhits, nmodes, ntotal = naive.swim_path(g, i, size, spheres, cubes, 300)
        np.testing.assert_allclose(pos, npos, rtol=0, atol=1e-7)
        np.testing.assert_allclose(ang[:, :3], nang, rtol=0, atol=1e-9)
        assert (hits == nhits).all() and (modes == nmodes).all() and total == ntotal
        totals.append(total)
    assert any(t > 0 for t in totals) and any(t == 0 for t in totals)
    # the population kernel gives the same totals as one fish at a time
    pop = K.population_collisions(fish, np.arange(12), size, spheres, cubes, 300)
    assert pop.tolist() == totals


def test_random_stream_matches_the_oracle():
    r = naive.SplitMix(12345)
    assert K.uniform(12345, 5).tolist() == [r.uniform() for _ in range(5)]


def test_recount_equals_the_swim():
    size, spheres, cubes = tank_arrays()
    rng = np.random.default_rng(3)
    for i, g in enumerate(random_fish(rng, 10)):
        pos, ang, hits, _, total = K.swim_path(g, i, size, spheres, cubes, 3000)
        again, t2 = K.count_collisions(pos, ang, g, size, spheres, cubes)
        assert (again == hits).all() and t2 == total


# ---------------------------------------------------------------- genome and decoding
def test_genome_is_the_seeds_75_weighted_bits():
    plan = load_plan(CONFIG)
    genome = plan.genome
    assert genome.length == 75
    assert [p.name for p in plan.evolved] == NAMES[:11]
    raw = np.zeros((3, 75), np.uint8)
    raw[1] = 1
    raw[2, 3 * 8 : 4 * 8] = [1, 0, 1, 0, 0, 0, 0, 0]  # scale: weights 1 + 17 = 18 of 100
    dec = genome.decode(raw)
    col = {n: i for i, n in enumerate(genome.names)}
    assert dec[0, col["scale"]] == 2.0 and dec[1, col["scale"]] == 17.0
    assert dec[2, col["scale"]] == pytest.approx(2.0 + 0.18 * 15.0)
    assert dec[1, col["angle"]] == 215.0 and dec[1, col["color"]] == 3 and dec[1, col["turn"]] == 1
    # start positions stay at least the margin away from every wall, whatever the tank
    for preset in ("small", "large"):
        tank = Tank.model_validate({"preset": preset})
        f = load_plan(CONFIG, [f"environment.tank.preset={preset}"]).fitness()
        table = fish_table(f.full_params(dec), NAMES, tank)
        assert (table[:, :3] >= 40).all() and (table[:, :3] <= np.array(tank.size) - 40).all()


# ---------------------------------------------------------------- behaviour cases
def _one(**genes):
    g = dict(x=150, y=200, z=150, scale=2, view=60, angle=90, speed=20, heading=0, pitch=0)
    g.update(genes)
    row = [g["x"], g["y"], g["z"], g["scale"], g["view"], math.radians(g["angle"]), g["speed"]]
    row += [math.radians(g["heading"]), math.radians(g["pitch"]), g.get("turn", 1), 2, 0.75, 1]
    return np.array(row, float)


def test_straight_swim_moves_a_quarter_of_the_speed_and_wobbles_every_50_frames():
    g = _one(x=150, speed=20, heading=0)
    pos, ang, _, modes, _ = K.swim_path(g, 0, [1e4, 1e4, 1e4], EMPTY, EMPTY, 120)
    assert pos[1, 0] - pos[0, 0] == pytest.approx(5.0) and (modes == 0).all()
    pitch = np.degrees(ang[:, 1])
    assert pitch[49] == 0 and pitch[50] == pytest.approx(3.0)  # frame 49: 49 // 50 even, up
    assert pitch[100] == pytest.approx(0.0)  # frame 99: down again


def test_a_wall_ahead_starts_pattern_a_and_the_speed_recovers():
    g = _one(x=200, speed=20, heading=0, view=60, angle=175)  # wall x=300 at 100 px
    pos, ang, _, modes, _ = K.swim_path(g, 0, [300, 400, 300], EMPTY, EMPTY, 40)
    first = int(np.argmax(modes == 1))
    assert 300 - 60 < pos[first - 1, 0] <= 300 - 60 + 5  # seen once closer than the view
    turning = modes[first : first + 18]
    assert (turning == 1).all() and modes[first + 18] == 0  # 175 degrees: 17 x 10 + 5
    assert abs(abs(np.degrees(ang[first + 17, 0])) - 175) < 1e-9
    assert ang[first + 17, 2] == pytest.approx(20 - 18 * 0.01)
    assert ang[first + 18, 2] == pytest.approx(20 - 0.18 + 0.1)  # recovers 0.1 a frame
    assert ang[first + 19, 2] == pytest.approx(20.0)  # up to the max


def test_two_walls_turn_30_degrees_more_and_the_preferred_way_wins_3_to_1():
    g = _one(x=250, z=250, heading=45, view=80, angle=100)  # into the corner (300, 300)
    _, ang, _, modes, _ = K.swim_path(g, 0, [300, 400, 300], EMPTY, EMPTY, 30)
    first = int(np.argmax(modes == 1))
    turned = np.degrees(ang[first + 12, 0] - ang[first - 1, 0])
    assert abs(abs(turned) - 130) < 1e-9 and (modes[first : first + 13] == 1).all()
    signs = []
    for seed in range(400):
        _, ang, _, modes, _ = K.swim_path(g, seed, [300, 400, 300], EMPTY, EMPTY, 5)
        k = int(np.argmax(modes == 1))
        signs.append(np.sign(ang[k, 0] - ang[k - 1, 0]))
    assert 0.68 < np.mean(np.array(signs) > 0) < 0.82  # turn = 1 prefers +heading


def test_top_wall_alone_pitches_away_9_frames_of_5_degrees():
    g = _one(y=330, pitch=20, heading=0, view=60)
    _, ang, _, modes, _ = K.swim_path(g, 0, [1e4, 400, 1e4], EMPTY, EMPTY, 20)
    first = int(np.argmax(modes == 2))
    assert (modes[first : first + 9] == 2).all()
    assert np.degrees(ang[first + 8, 1]) == pytest.approx(20 - 45)
    assert ang[first + 8, 2] == ang[0, 2]  # speed unchanged


def test_an_obstacle_in_the_view_cone_is_avoided_one_beside_is_not():
    sphere = np.array([[250.0, 200.0, 150.0, 20.0]])
    ahead = _one(x=150, z=150, heading=0, view=90, speed=8)
    _, _, _, modes, _ = K.swim_path(ahead, 0, [1e4, 1e4, 1e4], sphere, EMPTY, 10)
    assert modes[1] == 1
    beside = np.array([[150.0, 200.0, 250.0, 20.0]])  # 90 degrees to the side
    _, _, _, modes, _ = K.swim_path(ahead, 0, [1e4, 1e4, 1e4], beside, EMPTY, 10)
    assert (modes == 0).all()


def test_collisions_count_body_points_in_obstacles_and_outside_walls():
    # parked inside a sphere (speed 5 for 1 frame): all 7 points inside it
    g = _one(x=100, z=100, scale=2, speed=5, view=20)
    sphere = np.array([[100.0, 200.0, 100.0, 30.0]])
    _, _, hits, _, total = K.swim_path(g, 0, [1e4, 1e4, 1e4], sphere, EMPTY, 1)
    assert total == 7
    cube = np.array([[100.0, 200.0, 100.0, 30.0]])
    assert K.swim_path(g, 0, [1e4, 1e4, 1e4], EMPTY, cube, 1)[4] == 7
    # nose out of the tank: the nose (and only it) is on the wrong side of the wall
    g = _one(x=296, scale=2, speed=5, view=20, heading=0)
    hits = K.count_collisions(
        np.array([[296.0, 200, 150]] * 2),
        np.tile([0, 0, 5, 1, 0, 1, 0], (2, 1)),
        g,
        [300, 400, 300],
        EMPTY,
        EMPTY,
    )[0]
    assert hits.tolist() == [0, 1]  # fmt: skip


# ---------------------------------------------------------------- the phenotype and objective
def test_trajectory_contract(tmp_path):
    t = develop({"frames": 2000}, seed=3)
    assert isinstance(t, Trajectory) and t.n_frames == 2000
    back = load_phenotype(t.save(tmp_path / "t.npz"))
    assert isinstance(back, Trajectory) and np.array_equal(back.positions, t.positions)
    assert back.params == t.params
    m = t.measures(Environment())
    assert m["collisions"] == t.collisions and {"coverage", "circling", "scale"} <= set(m)
    img = t.render_image(view="iso", size=(64, 48))
    assert img.shape == (48, 64, 3) and img.std() > 0
    gif = t.animation(tmp_path / "swim.gif", frames=3, size=(48, 48))
    assert gif.stat().st_size > 0


def test_objective_scores_recounts_and_batches_alike():
    from growsim.objectives import get_objective

    env = Environment.model_validate({"tank": {"preset": "medium"}})
    obj = get_objective("collisions")(env=env)
    rng = np.random.default_rng(0)
    rows = np.array([[p.default for p in PARAMS]] * 6)
    low = [0] * 3 + [2, 20, 45, 5, 0, -30]
    rows[:, :9] = rng.uniform(low, [1] * 3 + [17, 100, 215, 45, 360, 30], (6, 9))
    rows[:, NAMES.index("frames")] = 3000
    fast = obj.batch(MODEL, rows, NAMES, np.arange(6, dtype=np.uint64))
    slow = [obj(MODEL.develop(dict(zip(NAMES, r)), seed=i, env=env)) for i, r in enumerate(rows)]
    assert fast.tolist() == slow and not obj.maximize


# ---------------------------------------------------------------- the bar: every run solves
def test_random_reasonable_tanks_are_solved_within_200_generations():
    """Random tanks (each side 250..900 px) with 1-3 random obstacles (radius or half
    edge 10..30 px, centres at least 60 px inside): every GA run finds 0 collisions."""
    rng = np.random.default_rng(2024)
    for k in range(12):
        size = rng.uniform(250, 900, 3).round()
        obstacles = []
        for _ in range(rng.integers(1, 4)):
            obstacles.append(
                {
                    "shape": str(rng.choice(["sphere", "cube"])),
                    "center": [float(round(rng.uniform(60, s - 60))) for s in size],
                    "size": float(round(rng.uniform(10, 30))),
                }
            )
        tank = {"size": size.tolist(), "obstacles": obstacles}
        plan = load_plan(CONFIG, [f"environment.tank={json.dumps(tank).replace(':', '=')}"])
        plan = plan.with_seed(k)
        result = plan.build_ga(plan.fitness()).run(generations=200, target=0.0)
        assert result.best.fitness == 0.0, (k, tank)


# ---------------------------------------------------------------- CLI end to end, bad input
def test_cli_run_show_and_compare_end_to_end(tmp_path):
    out = tmp_path / "r"
    p = growsim("run", str(CONFIG), "--out", str(out), "--set", "ga.generations=30",
                 "--set", "model.params.frames=4000", "--set", "output.size=[64, 64]")  # fmt: skip
    assert p.returncode == 0, p.stderr
    best = json.loads((out / "best.json").read_text())
    assert best["phenotype"] == "trajectory" and (out / "best_trajectory.npz").exists()
    summary = json.loads((out / "summary.json").read_text())
    assert "collisions" in summary["measures"] and (out / "best_iso.png").exists()
    shot = tmp_path / "s.png"
    p = growsim("show", str(out), "--screenshot", str(shot), "--size", "48", "48")
    assert p.returncode == 0 and shot.exists(), p.stderr
    p = growsim("compare", str(out), "--out", str(tmp_path / "cmp"))
    assert p.returncode == 0, p.stderr


#: a bad override and the key its error names
BAD_INPUT = [
    ('environment.tank.obstacles=[{shape="sphere", center=[900, 10, 10], size=5}]',
     "obstacles[0]"),
    ("environment.tank.size=[70, 400, 300]", "margin"),
    ('environment.tank.preset="tiny"', "environment.tank.preset"),
    ("model.params.frames=0", "model.params.frames"),
    ("model.evolve.scale=[1, 5]", "model.evolve.scale"),
]  # fmt: skip


def test_bad_input_exits_2_naming_the_key_and_writes_nothing(tmp_path):
    """Each case of :data:`BAD_INPUT` in its own process (side by side: each is mostly an
    interpreter's start); every failing case is reported."""
    from concurrent.futures import ThreadPoolExecutor

    def case(i: int):
        out = tmp_path / f"r{i}"
        return out, growsim("run", str(CONFIG), "--out", str(out), "--set", BAD_INPUT[i][0])

    with ThreadPoolExecutor(max_workers=4) as pool:
        done = list(pool.map(case, range(len(BAD_INPUT))))
    failed = []
    for (override, key), (out, p) in zip(BAD_INPUT, done, strict=True):
        if p.returncode != 2 or key not in p.stderr or "growsim: error:" not in p.stderr:
            failed.append(f"{override}: exit {p.returncode}, not naming {key!r}: {p.stderr}")
        if out.exists():
            failed.append(f"{override}: wrote {out}")
    assert not failed, "\n".join(failed)


def test_default_tank_is_the_small_preset():
    assert default_tank().size == [300.0, 400.0, 300.0]
    with pytest.raises(ConfigError, match="too small"):
        Tank.parse({"size": [80, 100, 100]}, where="environment.tank.")


def test_a_tank_preset_can_be_varied_after_the_config_is_resolved():
    # a tank that is its preset's is saved as the preset alone, so a sweep's --vary of the
    # preset on a resolved config changes the size and the obstacles too
    from growsim.env.tank import TANKS, Tank
    from growsim.experiment import load_config

    assert Tank.model_validate({"preset": "small"}).model_dump() == {
        "preset": "small",
        "margin": 40.0,
    }
    own = Tank.model_validate({"preset": "small", "size": [500, 500, 500]}).model_dump()
    assert own["size"] == [500.0, 500.0, 500.0]  # a size of one's own is kept
    for name in TANKS:
        cfg = load_config(CONFIG, [f'environment.tank.preset="{name}"'])
        assert cfg.environment.tank.size == list(TANKS[name])


def test_grow_renders_and_saves_a_trajectory(tmp_path):
    from growsim.cli import main
    from growsim.phenotypes import load_phenotype

    png, npz = tmp_path / "fish.png", tmp_path / "fish.npz"
    assert main(["grow", "fish", "--preset", "calm", "--screenshot", str(png), "--size", "64",
                 "--save", str(npz)]) == 0  # fmt: skip
    assert png.stat().st_size > 0 and load_phenotype(npz).phenotype == "trajectory"
    assert main(["grow", "fish", "--preset", "calm", "--export", str(tmp_path / "x.vtp")]) == 2
    assert not (tmp_path / "x.vtp").exists()
