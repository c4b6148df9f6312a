"""Benchmark of the 2D IFS plants (Liu & Zhang, "IFS and genetic algorithm
studying in simulation of plant", 2011): chaos-game speed, the paper's whole experiment,
and the paper's claim measured over repeats.

    NUMBA_NUM_THREADS=1 python benchmarks/ifs2d.py [--repeats 20] [--points 10000000]
        [--larger 0] [--out DIR] [--json PATH]

Prints one JSON object (``--json PATH`` also writes it to ``PATH``, e.g. the results file
``benchmarks/results/ifs2d_claim.json`` that ``tests/test_reproduction_claims.py`` checks
``docs/reproduction.md`` against):

- ``chaos_game_points_per_s``: points per second of :func:`growsim.kernels.ifs2d.chaos_game`
  (the public function: allocation included) on the fern, ``--points`` points, best of 3,
  one core (the kernel is serial; ``NUMBA_NUM_THREADS=1`` is set here before numba loads);
  ``chaos_kernel_points_per_s`` the kernel alone into a reused buffer;
- ``seed_experiment_seconds``: wall time of the paper's whole experiment (population 10, 8
  generations, both fractal trees: ``experiments/ifs_species.toml`` and its tree-two
  variant), in this process, results and pictures written;
- ``claim``: per tree, over ``--repeats`` seeds, the four terms of the first and the last
  generation's best plant, and for the paper's claim (the last is more stable and captures
  more light) the one-sided Wilcoxon signed-rank test of last > first (paired by seed),
  Holm-adjusted over the claims, with the mean difference, its 95 % CI and the counts of
  seeds where the last is better / equal / worse;
- with ``--larger R``: the same over ``R`` seeds for the larger setup (40 plants, 30
  generations).

``--figures DIR`` also writes the pictures of ``docs/models/ifs2d.md`` into ``DIR``
(``ifs2d_presets.png``, ``ifs2d_terms.png``, ``ifs2d_tree_one.png``, ``ifs2d_tree_two.png``
and their ``*_terms.png``: the seed-0 runs of the paper's experiment).
"""

from __future__ import annotations

import os

os.environ.setdefault("NUMBA_NUM_THREADS", "1")

import argparse
import json
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
CONFIG = ROOT / "experiments" / "ifs_species.toml"
#: the paper's two fractal trees: overrides of the config
TREES = {
    "tree_one": [],
    "tree_two": ['model.preset="tree3"', 'objective[0].species="tree_two"'],
}
LARGER = ["ga.population=40", "ga.generations=30"]
TERMS = ("phototropism", "light", "stability", "symmetry")
CLAIMS = ("stability", "light")


def chaos_speed(points: int) -> tuple[float, float]:
    """Points per second of the public chaos game and of the kernel alone (best of 3)."""
    from growsim.kernels.ifs2d import chaos_game, chaos_game_kernel, cumulative
    from growsim.models.ifs2d import TABLE1

    maps, p = TABLE1[:, :6].copy(), TABLE1[:, 6].copy()
    chaos_game(maps, p, 1000)  # compile / load the cache
    best = best_kernel = np.inf
    out = np.empty((points, 2))
    cum = cumulative(p)
    for seed in range(3):
        t = time.perf_counter()
        chaos_game(maps, p, points, seed=seed)
        best = min(best, time.perf_counter() - t)
        t = time.perf_counter()
        chaos_game_kernel(maps, cum, 0.0, 0.0, 100, np.uint64(seed), out)
        best_kernel = min(best_kernel, time.perf_counter() - t)
    return points / best, points / best_kernel


def run_tree(overrides, seed: int, out: Path):
    """One species run; returns its generations table."""
    from growsim.experiment.species import evolve_species

    _, table = evolve_species(CONFIG, out=out, seed=seed, overrides=overrides)
    return table


def paired(first: np.ndarray, last: np.ndarray) -> dict:
    """Last against first, paired by seed: one-sided Wilcoxon signed-rank (last > first),
    mean difference with its 95 % CI, and the better / equal / worse counts."""
    from scipy import stats

    from growsim.report.statistics import ci95

    d = last - first
    p = float("nan")
    if np.any(d != 0):
        p = float(stats.wilcoxon(last, first, alternative="greater", zero_method="wilcox").pvalue)
    return {
        "mean_first": float(first.mean()),
        "mean_last": float(last.mean()),
        "mean_difference": float(d.mean()),
        "difference_ci95": float(ci95(d)),
        "better": int((d > 0).sum()),
        "equal": int((d == 0).sum()),
        "worse": int((d < 0).sum()),
        "wilcoxon_p": p,
    }


def claim(overrides, repeats: int, root: Path) -> dict:
    """The paper's claim for one tree over ``repeats`` seeds."""
    from growsim.report.statistics import holm

    first, last, gens, fit = [], [], [], []
    for seed in range(repeats):
        table = run_tree(overrides, seed, root / f"seed{seed}")
        first.append([table.iloc[0][t] for t in TERMS])
        last.append([table.iloc[-1][t] for t in TERMS])
        gens.append(int(table["generation"].iloc[-1]) + 1)
        fit.append((float(table["fitness"].iloc[0]), float(table["fitness"].iloc[-1])))
    first, last = np.array(first), np.array(last)
    tests = {t: paired(first[:, i], last[:, i]) for i, t in enumerate(TERMS)}
    adjusted = holm([tests[t]["wilcoxon_p"] for t in CLAIMS])
    for t, p in zip(CLAIMS, adjusted):
        tests[t]["wilcoxon_p_holm"] = float(p)
    fit = np.array(fit)
    return {
        "repeats": repeats,
        "mean_generations": float(np.mean(gens)),
        "fitness_first": float(fit[:, 0].mean()),
        "fitness_last": float(fit[:, 1].mean()),
        "terms": tests,
    }


def figure_presets(path: Path) -> None:
    """The presets side by side, each named."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from growsim.models.ifs2d import PRESETS, develop

    names = ["fern", "tree", "tree3", "tree6", "bush", "sierpinski"]
    fig, axes = plt.subplots(1, len(names), figsize=(2.6 * len(names), 3.0))
    for ax, name in zip(axes, names):
        ax.imshow(develop(PRESETS[name]).render_image(view="front", size=(300, 300)))
        ax.set_title(name)
        ax.set_axis_off()
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def figure_terms(path: Path, size: int = 128) -> None:
    """What the four terms read, on the fern and the tree: the 2D view (grey), its pruned
    skeleton (black), branching points with many branches (red) or 3 (blue), the columns
    lit from above (yellow bar on top), the main stem (green line) and the reach left and
    right of it."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from scipy import ndimage
    from skimage.morphology import skeletonize

    from growsim.kernels.ochoa import prune
    from growsim.models.ifs2d import PRESETS, develop
    from growsim.objectives.ochoa import ochoa_terms, plane_view

    fig, axes = plt.subplots(1, 2, figsize=(9, 4.8))
    for ax, name in zip(axes, ["fern", "tree"]):
        plant = develop(PRESETS[name])
        img, height = plane_view(plant, size)
        t = ochoa_terms(img, height, height_ref=10.0 if name == "fern" else 2.0)
        skel = prune(skeletonize(img.astype(bool)).astype(np.uint8), 2)
        deg = ndimage.convolve(skel.astype(int), np.ones((3, 3), int), mode="constant") - skel
        rgb = np.ones((size, size, 3))
        rgb[img > 0] = 0.8
        rgb[skel > 0] = 0.0
        # branching points as the kernel defines them (growsim.kernels.ochoa), to colour
        eight = np.ones((3, 3), int)
        junction = (skel > 0) & (deg >= 3)
        labels, n = ndimage.label(junction, structure=eight)
        for k in range(1, n + 1):
            cluster = labels == k
            ring = ndimage.binary_dilation(cluster, structure=eight) & (skel > 0) & ~junction
            branches = ndimage.label(ring, structure=eight)[1]
            if branches >= 3:
                grown = ndimage.binary_dilation(cluster, structure=eight)
                rgb[grown] = (1.0, 0.1, 0.1) if branches >= 4 else (0.1, 0.3, 1.0)
        lit = img.any(axis=0)
        rgb[:2, lit] = (1.0, 0.8, 0.0)
        ax.imshow(rgb, interpolation="nearest")
        c = size // 2 + 0.5 - 0.5
        ax.axvline(c, color="green", lw=1)
        cols = np.flatnonzero(lit)
        ax.annotate("", xy=(cols[0], size * 0.95), xytext=(c, size * 0.95),
                    arrowprops={"arrowstyle": "->", "color": "green"})  # fmt: skip
        ax.annotate("", xy=(cols[-1], size * 0.95), xytext=(c, size * 0.95),
                    arrowprops={"arrowstyle": "->", "color": "green"})  # fmt: skip
        ax.set_title(
            f"{name}: a {t['phototropism']:.2f}  b {t['light']:.2f}  c {t['stability']:.2f}"
            f"  d {t['symmetry']:.2f}\n{int(t['branch_points'])} branching points, "
            f"{int(t['many_branch_points'])} with >= 4 branches",
            fontsize=9,
        )
        ax.set_axis_off()
    fig.tight_layout()
    fig.savefig(path, dpi=90, bbox_inches="tight", pad_inches=0.15)  # the titles whole
    plt.close(fig)


def figures(out: Path, root: Path) -> None:
    """The pictures of docs/models/ifs2d.md (see the module docstring)."""
    import shutil

    out.mkdir(parents=True, exist_ok=True)
    figure_presets(out / "ifs2d_presets.png")
    figure_terms(out / "ifs2d_terms.png")
    for name in TREES:
        run = root / "seed_experiment" / name
        shutil.copyfile(run / "generations.png", out / f"ifs2d_{name}.png")
        shutil.copyfile(run / "terms.png", out / f"ifs2d_{name}_terms.png")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeats", type=int, default=20)
    ap.add_argument("--points", type=int, default=10_000_000)
    ap.add_argument("--larger", type=int, default=0, metavar="R")
    ap.add_argument("--out", default=None)
    ap.add_argument("--figures", default=None, metavar="DIR")
    ap.add_argument("--json", default=None, metavar="PATH", help="also write the JSON here")
    args = ap.parse_args()
    out = {"load_average_start": os.getloadavg()[0]}
    speed, kernel = chaos_speed(args.points)
    out["chaos_game_points_per_s"] = speed
    out["chaos_kernel_points_per_s"] = kernel
    root = Path(args.out or tempfile.mkdtemp(prefix="ifs2d-bench-"))
    t = time.perf_counter()
    for name, overrides in TREES.items():
        run_tree(overrides, 0, root / "seed_experiment" / name)
    out["seed_experiment_seconds"] = time.perf_counter() - t
    if args.figures:
        figures(Path(args.figures), root)
    out["claim"] = {
        name: claim(overrides, args.repeats, root / "claim" / name)
        for name, overrides in TREES.items()
    }
    if args.larger:
        out["claim_larger"] = {
            name: claim(overrides + LARGER, args.larger, root / "larger" / name)
            for name, overrides in TREES.items()
        }
    out["load_average_end"] = os.getloadavg()[0]
    out["results"] = str(root)
    print(json.dumps(out, indent=1))
    if args.json:
        Path(args.json).write_text(json.dumps(out, indent=1) + "\n")


if __name__ == "__main__":
    main()
