"""Honda growth + mesh speed, against the report's Table 3 (about 50-70 vertices per ms).

Prints JSON: for each of the eight presets, the 13-generation zelkova (the report's a') and
the f = 1 tree (2,047 segments), the mesh vertex counts and vertices per second of
growth + mesh (``develop`` then ``plant_mesh``: a ready pyvista PolyData; and the same
with ``mesh_arrays``, raw arrays without the pyvista object), best of
``--repeat`` runs after a warm-up (numba compile excluded), one thread.

    .venv/bin/python benchmarks/honda.py [--repeat 20] [--sides 6] [--segments 1]
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import time

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

from growsim.models import honda
from growsim.phenotypes.plant.mesh import mesh_arrays, plant_mesh

# the report's Table 3: tree / leaf / total vertices and ms per image (1991)
TABLE3 = {
    "zelkova": (3906, 2940, 6846, 109.96),
    "zelkova_13": (10626, 7980, 18606, 275.0),
    "cherry": (3906, 2940, 6846, 110.06),
    "ginkgo": (2982, 2352, 5334, 83.01),
    "plane": (2730, 2142, 4872, 91.99),
    "e_wandering_bush": (3906, 2940, 6846, 110.06),
    "f_dome": (42966, 32214, 75180, 609918.46),
    "g_tall_trunk": (3486, 2688, 6174, 110.06),
    "h_columnar": (1134, 924, 2058, 34.08),
}


def _best(fn, repeat):
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--repeat", type=int, default=20)
    ap.add_argument("--sides", type=int, default=6)
    ap.add_argument("--segments", type=int, default=1)
    args = ap.parse_args()
    cases = dict(honda.PRESETS)
    cases["zelkova_13"] = {**honda.PRESETS["zelkova"], "generations": 13}
    cases["f1_gen10"] = {**honda.PRESETS["zelkova"], "f": 1.0, "generations": 10}
    cases["f1_gen14"] = {**honda.PRESETS["zelkova"], "f": 1.0, "generations": 14}
    # warm up the kernels (compile or load the cache)
    plant_mesh(honda.develop(cases["h_columnar"]))
    rows = []
    for name, p in cases.items():
        t_grow, plant = _best(lambda p=p: honda.develop(p), args.repeat)
        t_mesh, mesh = _best(
            lambda plant=plant: plant_mesh(plant, sides=args.sides, segments=args.segments),
            args.repeat,
        )
        t_kernel, _ = _best(
            lambda plant=plant: mesh_arrays(plant, sides=args.sides, segments=args.segments),
            args.repeat,
        )
        t_all, _ = _best(
            lambda p=p: plant_mesh(honda.develop(p), sides=args.sides, segments=args.segments),
            args.repeat,
        )
        t_raw, _ = _best(
            lambda p=p: mesh_arrays(honda.develop(p), sides=args.sides, segments=args.segments),
            args.repeat,
        )
        kind = mesh.point_data["kind"]
        nv = int(mesh.n_points)
        row = {
            "case": name,
            "stems": plant.n_stems,
            "leaves": plant.n_leaves,
            "tree_vertices": int((kind == 0).sum()),
            "leaf_vertices": int((kind == 1).sum()),
            "vertices": nv,
            "grow_ms": round(t_grow * 1e3, 3),
            "mesh_ms": round(t_mesh * 1e3, 3),
            "mesh_kernel_ms": round(t_kernel * 1e3, 3),
            "grow_mesh_ms": round(t_all * 1e3, 3),
            "vertices_per_s": round(nv / t_all),
            "vertices_per_ms": round(nv / t_all / 1e3, 1),
            # the same without building the pyvista object (raw vertex/triangle arrays)
            "grow_mesh_arrays_ms": round(t_raw * 1e3, 3),
            "arrays_vertices_per_s": round(nv / t_raw),
        }
        if name in TABLE3:
            _tv, _lv, tot, ms = TABLE3[name]
            row["seed_1991"] = {"vertices": tot, "ms": ms, "vertices_per_ms": round(tot / ms, 1)}
        rows.append(row)
    out = {
        "benchmark": "honda growth + mesh",
        "sides": args.sides,
        "segments": args.segments,
        "repeat": args.repeat,
        "python": platform.python_version(),
        "machine": platform.machine(),
        "load_avg_1min": os.getloadavg()[0],
        "floor_vertices_per_s": 10_000_000,
        "cases": rows,
    }
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
