"""A fish in a tank whose path is tuned by a GA (Okusa's thesis, "GA-tuned path control
of a fish agent", graduation thesis, Tokyo University of Technology, 2003).

The fish swims straight and avoids what it sees by fixed patterns (turns of 10 degrees a
frame, pitching away from the top or bottom); its numbers (start, size, view distance,
avoidance angle, speed, initial heading and pitch, colour, preferred turn) are the genome
of the thesis's Table 1, so a GA can tune them until the fish never collides. The path is a
:class:`growsim.phenotypes.trajectory.Trajectory`. The frame loop is the numba kernel
:mod:`growsim.kernels.fish`; behaviour, genome and choices: ``docs/models/fish.md``.

Parameters, in the order of the thesis's Table 1 (the genome's order):

- ``x``, ``y``, ``z``: start as a share of the box ``[margin, size - margin]`` of the tank
  (0..1: at least ``tank.margin``, 40 px, from every wall whatever the tank);
- ``scale`` 2..17, ``view`` 20..100 px, ``angle`` 45..215 degrees, ``speed`` 5..45;
- ``heading`` 0..360 degrees (the thesis's 0..2 pi), ``pitch`` -30..30 degrees (-pi/6..pi/6);
- ``color`` 0..3 (one of 4), ``turn`` 0/1 (preferred turn: 1 = increasing heading);

then the fixed ones: ``frames`` (20,000 as the thesis) and the base body at scale 1
(``body_length`` 4, ``body_width`` 1.5, ``body_height`` 2 px).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from growsim.env.tank import Tank
from growsim.errors import ResourceError
from growsim.kernels.fish import population_collisions, swim_path
from growsim.models.base import Model, Param, resolve_params
from growsim.phenotypes.trajectory import Trajectory

__all__ = ["MODEL", "PARAMS", "PRESETS", "FishModel", "default_tank", "develop", "fish_table"]

#: the genes of the thesis's Table 1 (in its order), then the fixed parameters
PARAMS: tuple[Param, ...] = (
    Param("x", 0.0, 1.0, 0.5, doc="start x as a share of [margin, width - margin]"),
    Param("y", 0.0, 1.0, 0.5, doc="start y (up) as a share of [margin, height - margin]"),
    Param("z", 0.0, 1.0, 0.5, doc="start z as a share of [margin, depth - margin]"),
    Param("scale", 2.0, 17.0, 6.0, doc="body scale (times the base body)"),
    Param("view", 20.0, 100.0, 70.0, doc="view distance", unit="px"),
    Param("angle", 45.0, 215.0, 145.0, doc="avoidance turn angle", unit="deg"),
    Param("speed", 5.0, 45.0, 15.0, doc="maximum (cruising) speed; a frame moves 0.25 x speed"),
    Param("heading", 0.0, 360.0, 30.0, doc="initial heading in the x-z plane", unit="deg"),
    Param("pitch", -30.0, 30.0, 0.0, doc="initial pitch (up positive)", unit="deg"),
    Param("color", 0, 3, 0, kind="int", doc="colour, one of 4"),
    Param("turn", 0, 1, 1, kind="int", doc="preferred turn (1: heading increases), odds 3:1"),
    Param("frames", 1, 1_000_000, 20_000, kind="int", doc="frames simulated"),
    Param("body_length", 0.1, 100.0, 4.0, doc="body length at scale 1", unit="px"),
    Param("body_width", 0.1, 100.0, 1.5, doc="body width at scale 1", unit="px"),
    Param("body_height", 0.1, 100.0, 2.0, doc="body height at scale 1", unit="px"),
)

#: a named fish: the collision-free fish of ``growsim sweep`` (benchmarks/fish.py) in the
#: small preset tank, seed 0 (0 collisions in 20,000 frames with the run seed 0)
PRESETS: dict[str, dict[str, float]] = {
    "calm": {
        "x": 0.55,
        "y": 0.4,
        "z": 0.65,
        "scale": 6.8,
        "view": 76.8,
        "angle": 182.7,
        "speed": 5.0,
        "heading": 144.0,
        "pitch": -14.4,
        "color": 1.0,
        "turn": 1.0,
    },
}

#: frames x fish the population kernel accepts in one call (a bound on run time, not memory)
MAX_FRAMES = 1_000_000


def default_tank():
    """The tank used when the environment has none: the thesis's small tank with the
    documented obstacles (:data:`growsim.env.tank.TANKS`).

    Examples
    --------
    >>> default_tank().size
    [300.0, 400.0, 300.0]
    """

    return Tank.model_validate({"preset": "small"})


def _tank(env):
    tank = None if env is None else env.tank
    return default_tank() if tank is None else tank


def fish_table(params: np.ndarray, names: Sequence[str], tank) -> np.ndarray:
    """Rows of full model parameters (columns ``names``) -> the kernel's fish table
    (:data:`growsim.kernels.fish.FISH_FIELDS`: pixels and radians) in ``tank``.

    Examples
    --------
    >>> names = [p.name for p in PARAMS]
    >>> row = [[p.default for p in PARAMS]]
    >>> fish_table(np.array(row), names, default_tank())[0, :3].tolist()
    [150.0, 200.0, 150.0]
    """
    p = np.atleast_2d(np.asarray(params, dtype=np.float64))
    col = {n: p[:, i] for i, n in enumerate(names)}
    size = np.asarray(tank.size, dtype=np.float64)
    m = float(tank.margin)
    start = [m + col[k] * (size[i] - 2.0 * m) for i, k in enumerate("xyz")]
    return np.column_stack(
        [
            *start,
            col["scale"],
            col["view"],
            np.radians(col["angle"]),
            col["speed"],
            np.radians(col["heading"]),
            np.radians(col["pitch"]),
            np.round(col["turn"]),
            col["body_length"] / 2.0,
            col["body_width"] / 2.0,
            col["body_height"] / 2.0,
        ]
    )


def develop(params: Mapping[str, float] | None = None, *, seed: int | None = None, env=None):
    """Swim one fish: its :class:`growsim.phenotypes.trajectory.Trajectory` in ``env``'s tank
    (default: :func:`default_tank`). ``seed`` draws the 3:1 turn choices (None: 0).

    Examples
    --------
    >>> t = develop({"frames": 500})
    >>> t.n_frames, t.positions.shape
    (500, (501, 3))
    """

    p = resolve_params(PARAMS, params, where="fish.")
    tank = _tank(env)
    names = [q.name for q in PARAMS]
    g = fish_table(np.array([[p[n] for n in names]]), names, tank)[0]
    size, spheres, cubes = tank.arrays()
    seed = 0 if seed is None else int(seed)
    pos, ang, hits, modes, _ = swim_path(g, seed, size, spheres, cubes, int(p["frames"]))
    return Trajectory(
        positions=pos,
        angles=ang,
        hits=hits,
        modes=modes,
        body=g,
        size=size,
        spheres=spheres,
        cubes=cubes,
        params=p,
        meta={"model": "fish", "seed": seed},
    )


class FishModel(Model):
    """The fish of Okusa's thesis as a registered model (its path is the phenotype).

    Capability for objectives: :meth:`collisions` scores a whole population at once.

    Examples
    --------
    >>> MODEL.name, MODEL.phenotype, len([p for p in MODEL.params if p.name != "frames"])
    ('fish', 'trajectory', 14)
    """

    name = "fish"
    phenotype = "trajectory"
    capabilities = frozenset({"collisions"})
    params = PARAMS
    presets = PRESETS

    def develop(self, params=None, *, seed=None, env=None):
        """See :func:`develop`."""
        return develop(params, seed=seed, env=env)

    def collisions(self, params: np.ndarray, names: Sequence[str], seeds=None, env=None):
        """Total collisions of each row of full parameters ``(n, p)`` (columns ``names``)
        in ``env``'s tank: the population kernel, no path kept. ``seeds`` ``(n,)``:
        each fish's turn draws (None: 0).

        Examples
        --------
        >>> names = [p.name for p in PARAMS]
        >>> rows = np.array([[p.default for p in PARAMS]] * 2)
        >>> MODEL.collisions(rows, names).shape
        (2,)
        """

        tank = _tank(env)
        params = np.atleast_2d(np.asarray(params, dtype=np.float64))
        frames = params[:, list(names).index("frames")]
        if not (frames == frames[0]).all():
            return None
        n_frames = int(frames[0])
        if n_frames > MAX_FRAMES:
            raise ResourceError(f"fish: frames = {n_frames} exceeds {MAX_FRAMES}")
        seeds = np.zeros(len(params), np.uint64) if seeds is None else np.asarray(seeds)
        size, spheres, cubes = tank.arrays()
        table = fish_table(params, names, tank)
        return population_collisions(table, seeds, size, spheres, cubes, n_frames)


MODEL = FishModel()
