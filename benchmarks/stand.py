"""Speed of stands of hormone plants (JSON).

    NUMBA_NUM_THREADS=1 python benchmarks/stand.py [--repeats 3] [--split]

- ``periodic_vs_alone``: the 3D demo genome (40 steps, the configs' light: sun a little
  off the vertical, half the light from the sky) grown alone
  (:func:`growsim.models.hormone.develop`) and in a periodic stand
  (:func:`growsim.models.hormone.grow_periodic`, spacing 1 m, one and two rings of
  copies), timed in turn under one load; ``ratio`` is periodic over alone (issue 30's bar:
  at most 1.5). The plants differ (the periodic one is shaded), so the ratio per
  module-step is given too. Wall time (``s``, ``ratio``) and CPU time of the process
  (``cpu_s``, ``cpu_ratio``: less moved by other processes on a busy machine).
- ``split`` (with ``--split``): where a run's CPU time goes, alone and per ring: the
  walls' light (:func:`growsim.kernels.hormone.walls_light`: the shadow maps, their
  raster and queries) timed on each step's modules, and the rest of the step
  (``step_s`` less ``light_s``; best of ``--repeats`` per call).
- ``stand_9x200x40``: an explicit stand of 9 copies (3 x 3 at 1 m) of the 3D demo genome,
  200 modules each at most, 40 steps (:func:`growsim.models.hormone.grow_stand`), wall
  time.
- ``mixture_9x200x40``: a mixture of 9 plants of different genomes (the demo genome
  among 8 neighbours whose elongation gain is 0.3 to 1 times the demo's, 1 m apart),
  200 modules each at most, 40 steps (:func:`growsim.models.hormone.grow_mixture`):
  issue 30's bar, at most 1 s.

Best of ``--repeats`` after a warm-up call (numba compiled and cached first); ``load``
and ``load_after`` the 1-minute load average.
"""

from __future__ import annotations

import argparse
import json
import os
import time

import numpy as np


def _best(fn, repeats):
    """``(wall, out, cpu)``: the best wall and CPU times of ``repeats`` calls of ``fn``
    after a warm-up call, and its last result."""
    fn()  # warm-up (compile)
    best = cpu = np.inf
    for _ in range(repeats):
        t, c = time.perf_counter(), time.process_time()
        out = fn()
        cpu = min(cpu, time.process_time() - c)
        best = min(best, time.perf_counter() - t)
    return best, out, cpu


def _split(p, env, shifts, repeats):
    """``{light_s, step_s, rest_s}``: the CPU time of a run of the hormone plant ``p``
    (resolved) among ``shifts`` spent in :func:`growsim.kernels.hormone.walls_light`
    (each step's call timed alone, best of ``repeats``) and in whole steps."""
    from growsim.kernels import hormone as K
    from growsim.models import hormone as H

    def run(light):
        n, s = H.seedling(p, env)
        s["shifts"] = shifts
        for _ in range(int(p["steps"])):
            if light is not None:
                args = (n, int(p["dims"]), s["modules"], s["env"], shifts, s["scratch"])
                light.append(_best(lambda args=args: K.walls_light(*args), repeats)[2])
            n, _ = K.grow_step(n, *s.values())

    light = []
    run(light)
    step = _best(lambda: run(None), repeats)[2]
    return {"light_s": sum(light), "step_s": step, "rest_s": step - sum(light)}


def main(argv=None) -> dict:
    """Run the benchmarks and return their JSON-able results."""
    from growsim.env import Environment
    from growsim.models import hormone as H

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--split", action="store_true", help="time the light apart (slow)")
    args = ap.parse_args(argv)
    env = Environment.parse(H.PRESET_ENVIRONMENTS["demo_3d"])
    p = {**H.PRESETS["demo_3d"], "steps": 40}

    def steps_of(plants):
        return sum(x.n_segments for x in plants)

    out = {"load": os.getloadavg()[0]}
    t_alone, alone, c_alone = _best(lambda: list(H.grow(p, env=env)), args.repeats)
    res = {"alone_s": t_alone, "alone_cpu_s": c_alone, "alone_module_steps": steps_of(alone)}
    for rings in (1, 2):
        t, plants, c = _best(
            lambda rings=rings: list(H.grow_periodic(p, env=env, spacing=1.0, rings=rings)),
            args.repeats,
        )
        ms = steps_of(plants)
        res[f"rings{rings}"] = {
            "s": t,
            "cpu_s": c,
            "module_steps": ms,
            "ratio": t / t_alone,
            "cpu_ratio": c / c_alone,
            "ratio_per_module_step": (t / ms) / (t_alone / res["alone_module_steps"]),
        }
    out["periodic_vs_alone"] = res
    if args.split:
        from growsim.kernels.stand import periodic_shifts

        r = H.resolve_params(H.PARAMS, p)
        out["split"] = {
            f"rings{k}" if k else "alone": _split(
                r, env, periodic_shifts(1.0, k, 3) if k else np.zeros((0, 3)), args.repeats
            )
            for k in (0, 1, 2)
        }
    stand_env = Environment.parse(
        {**H.PRESET_ENVIRONMENTS["demo_3d"],
         "stand": {"mode": "explicit", "rows": 3, "cols": 3, "spacing": 1.0}}
    )  # fmt: skip
    q = {**p, "max_modules": 200}
    t, stand, _ = _best(lambda: list(H.grow_stand(q, env=stand_env))[-1], args.repeats)
    out["stand_9x200x40"] = {"s": t, "modules": stand.n_segments}
    mix_env = Environment.parse(
        {**H.PRESET_ENVIRONMENTS["demo_3d"],
         "stand": {"mode": "mixture", "neighbours": 8, "spacing": 1.0}}
    )  # fmt: skip
    others = [{**q, "h0_gain": q["h0_gain"] * f} for f in np.linspace(0.3, 1.0, 8)]
    t, focal, _ = _best(lambda: list(H.grow_mixture(q, others, env=mix_env))[-1], args.repeats)
    out["mixture_9x200x40"] = {"s": t, "focal_modules": focal.n_segments}
    out["load_after"] = os.getloadavg()[0]
    print(json.dumps(out, indent=2))
    return out


if __name__ == "__main__":
    main()
