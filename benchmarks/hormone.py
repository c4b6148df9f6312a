"""Speed of the hormone-module model (JSON).

    NUMBA_NUM_THREADS=1 python benchmarks/hormone.py [--repeats 3]

Grows the demo genomes (``demo_2d``, ``demo_3d``) in the configs' environment (sun a little
off the vertical, half the light from the sky) and reports module-steps per second (the
sum over steps of the modules alive, over the wall time of the whole growth: light,
water, hormones, growth, gravity), best of ``--repeats``; and the share of the time in
the step kernel.
"""

from __future__ import annotations

import argparse
import json
import os
import time


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    from growsim.env import Environment
    from growsim.kernels import hormone as K
    from growsim.models import hormone

    env = Environment.model_validate({"light": {"diffuse": 0.5, "direction": [0.3, -1, 0.2]}})
    out = {"numba_threads": os.environ.get("NUMBA_NUM_THREADS", "default")}
    for name in ("demo_2d", "demo_3d"):
        params = hormone.PRESETS[name]
        list(hormone.grow(params, env=env))  # compile
        best = None
        for _ in range(args.repeats):
            kernel = [0.0]
            step = K.step_kernel

            def timed(*a, step=step, kernel=kernel):
                t0 = time.perf_counter()
                r = step(*a)
                kernel[0] += time.perf_counter() - t0
                return r

            K.step_kernel = timed
            t0 = time.perf_counter()
            module_steps = sum(p.n_segments for p in hormone.grow(params, env=env))
            wall = time.perf_counter() - t0
            K.step_kernel = step
            if best is None or wall < best[0]:
                best = (wall, module_steps, kernel[0])
        wall, module_steps, kernel = best
        out[name] = {
            "module_steps": module_steps,
            "seconds": round(wall, 3),
            "module_steps_per_s": round(module_steps / wall),
            "kernel_share": round(kernel / wall, 3),
        }
    out["load_1min"] = round(os.getloadavg()[0], 2)
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
