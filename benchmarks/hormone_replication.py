"""Discovery and confirmation of the hormone and stand sweeps, as one JSON file.

Reads the directories ``growsim compare`` wrote for a discovery block (with
``--confirm`` and ``--garden``) and for the confirmation block alone (with ``--garden``),
or for one block alone (its ``--garden`` compare), and writes what
``docs/reproduction.md`` reports of them:

- ``primary``: each block's primary tests (``primary.csv``: means, Hedges' g, p, Holm p
  over the primary tests, finding, seeds a replication needs for 80 % power);
- ``replication``: ``replication.csv`` (same direction, replicated, verdict);
- ``garden``: each block's genetic contrasts (origins within a garden) that pass Holm,
  by garden and measure, light per area apart;
- ``spread``: each block's coefficient of variation of the best fitness (and of each
  primary measure) within each environment, from ``runs.csv``;
- ``fitness_by_garden``: each block's genetic contrasts of fitness in every garden
  (passing Holm or not: does a genome evolved in one environment do better or worse in
  another garden);
- ``sizes``: each block's best plants: the most modules (against the config's module
  cap, ``max_modules``), the leaf area index's range, and why the plants of each garden
  cell stopped growing (``garden_stops.csv``);
- ``variance``: each block's shares of each quantity's variation in the common garden
  (``garden_variance.csv``: origin = genetic, garden = plastic, their interaction).

    growsim compare runs/h3d --confirm runs/h3d-b2 --garden --out runs/h3d-cmp
    growsim compare runs/h3d-b2 --garden --out runs/h3d-b2-cmp
    python benchmarks/hormone_replication.py runs/h3d-cmp runs/h3d-b2-cmp \\
        --json benchmarks/results/hormone_3d_replication.json
    python benchmarks/hormone_replication.py runs/d3d-cmp \\
        --json benchmarks/results/stand_density_3d.json             # one block
"""

from __future__ import annotations

import argparse
import json
import re
from pathlib import Path

import numpy as np
import pandas as pd


def _records(df: pd.DataFrame) -> list[dict]:
    return json.loads(df.to_json(orient="records"))


def _cv(v) -> float:
    v = np.asarray(v, dtype=float)
    return float(v.std(ddof=1) / abs(v.mean())) if len(v) > 1 and v.mean() != 0 else float("nan")


def spread(compare_dir: Path, measures: list[str]) -> dict:
    """CV of the best fitness and of ``measures`` within each group of ``runs.csv``."""
    runs = pd.read_csv(compare_dir / "runs.csv")
    out = {}
    for group, rows in runs.groupby("group", sort=False):
        cols = ["best_fitness", *[m for m in measures if m in rows.columns]]
        out[str(group)] = {c: round(_cv(rows[c]), 3) for c in cols}
        out[str(group)]["best_mean"] = round(float(rows["best_fitness"].mean()), 1)
    return out


def garden(compare_dir: Path, alpha: float = 0.05) -> list[dict]:
    """The genetic contrasts of the common garden that pass Holm (light per area apart)."""
    g = pd.read_csv(compare_dir / "garden_stats.csv")
    keep = (g.contrast == "genetic") & (g.welch_t_p_holm < alpha)
    hit = g[keep & (g.measure != "light_per_area")]
    cols = ["within", "measure", "group_a", "group_b", "mean_a", "mean_b", "welch_t_p_holm"]
    return _records(hit[cols])


def sizes(compare_dir: Path) -> dict:
    """The best plants' largest module count, the module cap of their configs, the leaf
    area index's range and (from the common garden) why each cell's plants stopped."""
    runs = pd.read_csv(compare_dir / "runs.csv")
    caps = set()
    for path in runs["path"]:
        text = (Path(path) / "config.toml").read_text()
        caps |= {int(m) for m in re.findall(r"max_modules\s*=\s*(\d+)", text)}
    out = {"max_modules": int(runs["n_segments"].max()), "cap": sorted(caps)}
    if "leaf_area_index" in runs:
        out["leaf_area_index"] = [float(runs["leaf_area_index"].min()),
                                  float(runs["leaf_area_index"].max())]  # fmt: skip
    stops = compare_dir / "garden_stops.csv"
    if stops.is_file():
        out["stops"] = _records(pd.read_csv(stops))
    return out


def fitness_by_garden(compare_dir: Path) -> list[dict]:
    """Every genetic contrast of fitness in the common garden (``garden_stats.csv``)."""
    g = pd.read_csv(compare_dir / "garden_stats.csv")
    hit = g[(g.contrast == "genetic") & (g.measure == "fitness")]
    cols = ["within", "group_a", "group_b", "mean_a", "mean_b", "welch_t_p", "welch_t_p_holm",
            "mann_whitney_p"]  # fmt: skip
    return _records(hit[cols])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("discovery", help="compare's directory of the discovery block (--confirm)")
    ap.add_argument(
        "confirmation",
        nargs="?",
        default=None,
        help="compare's directory of the confirmation block (none: one block)",
    )
    ap.add_argument("--json", default=None, help="write the figures here")
    a = ap.parse_args(argv)
    blocks = {"discovery": Path(a.discovery)}
    if a.confirmation is not None:
        blocks["confirmation"] = Path(a.confirmation)
    prim = {k: pd.read_csv(p / "primary.csv") for k, p in blocks.items()}
    measures = sorted(set(prim["discovery"].measure))
    out = {
        "primary": {k: _records(v) for k, v in prim.items()},
        "garden": {k: garden(p) for k, p in blocks.items()},
        "spread": {k: spread(p, measures) for k, p in blocks.items()},
        "fitness_by_garden": {k: fitness_by_garden(p) for k, p in blocks.items()},
        "sizes": {k: sizes(p) for k, p in blocks.items()},
        "variance": {
            k: _records(pd.read_csv(p / "garden_variance.csv")) for k, p in blocks.items()
        },
    }
    if a.confirmation is not None:
        out["replication"] = _records(pd.read_csv(blocks["discovery"] / "replication.csv"))
    text = json.dumps(out, indent=1)
    if a.json:
        Path(a.json).write_text(text + "\n")
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
