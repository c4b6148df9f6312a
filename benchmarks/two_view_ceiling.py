"""How far a reconstruction from two pictures can go when it keeps the front picture's
skeleton (issue 42's two-picture bar: both views >= 0.85 NCC at 256 px).

Honda trees, whose 3D shape is known, are drawn from the front and from the right
(:func:`growsim.objectives.silhouette.plant_views`, 384 px, with their widths) and
reconstructed from both pictures three ways:

- ``carved``: :func:`growsim.reconstruction.reconstruct` as users get it;
- ``true_depth``: the same front skeleton, each point given the true depth (of the
  tree's stem segments passing by it in the front picture, the one that keeps the
  branch's depth most even: :func:`true_depth`), no branch grafted from the side picture;
- ``true_depth_grafted``: the same, then the side picture's branches that the tree does
  not cover grafted on as the reconstruction grafts them.

Each judged by :func:`growsim.reconstruction.judge` (front and side NCC at 256 px); the
depth each branch travels over its run across, over the tree's own (``travel``: 1 is the
tree's; horizontal hatching travels several times that). One JSON line per tree, then a
``summary`` line.

    python benchmarks/two_view_ceiling.py
"""

from __future__ import annotations

import argparse
import json
import sys

import numpy as np


def _travel(plant) -> float:
    d = plant.end - plant.start
    return float(np.abs(d[:, 2]).sum() / max(np.linalg.norm(d[:, :2], axis=1).sum(), 1e-12))


def true_depth(tree, world: list[np.ndarray], reach_px: float = 2.0) -> list[np.ndarray]:
    """``world``'s branches (the reconstruction's front skeleton, metres from the base)
    with each point's depth read off ``tree`` (scaled as the reconstruction scales the
    tree's height): among the tree's stem segments passing within ``reach_px`` pixels of
    the point in the front picture (else the nearest one), the depths at the nearest
    points on them; along each branch the sequence of least total change of depth
    (dynamic programming), so that where branches cross in the picture a branch keeps to
    its own. A child's first point is set to its parent's end by the caller."""
    stem = tree.kind == 0
    base = tree.start[np.flatnonzero(tree.parent < 0)[0]]
    a, b = tree.start[stem] - base, tree.end[stem] - base
    f = max(float(p[:, 1].max()) for p in world) / float(max(b[:, 1].max(), a[:, 1].max()))
    a, b = a * f, b * f
    d = b - a
    ab = d[:, :2]
    den = np.maximum((ab * ab).sum(-1), 1e-12)
    steps = np.concatenate([np.linalg.norm(np.diff(p[:, :2], axis=0), axis=1) for p in world])
    pix = float(np.median(steps[steps > 0]))
    out = []
    for q in world:
        xy = q[:, :2]
        t = np.clip(((xy[:, None, :] - a[None, :, :2]) * ab[None]).sum(-1) / den[None], 0, 1)
        dist = np.linalg.norm(xy[:, None, :] - (a[None, :, :2] + t[..., None] * ab[None]), axis=-1)
        z_all = a[None, :, 2] + t * d[None, :, 2]
        cands = []
        for i in range(len(q)):
            near = np.flatnonzero(dist[i] <= max(reach_px * pix, float(dist[i].min())))
            cands.append(np.unique(z_all[i, near]))
        cost = np.zeros(cands[0].size)
        back = []
        for i in range(1, len(q)):
            tot = cost[:, None] + np.abs(cands[i][None, :] - cands[i - 1][:, None])
            arg = np.argmin(tot, axis=0)
            back.append(arg)
            cost = tot[arg, np.arange(cands[i].size)]
        k = int(np.argmin(cost))
        p = q.copy()
        for i in range(len(q) - 1, 0, -1):
            p[i, 2] = cands[i][k]
            k = int(back[i - 1][k])
        p[0, 2] = cands[0][k]
        out.append(p)
    return out


def main(argv=None) -> int:
    import growsim.reconstruction.build as build
    import growsim.reconstruction.lift as lift
    from growsim.models import honda
    from growsim.objectives.silhouette import plant_views
    from growsim.reconstruction import judge, reconstruct

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seeds", type=int, nargs="*", default=[1, 2])
    ap.add_argument("--size", type=int, default=384)
    a = ap.parse_args(argv)
    state: dict = {}

    def oracle(sk, world, side, side_world, seed=0, *, same_picture=False):
        _out, why, _sk = lift.lift_two_views(sk, world, side, side_world, seed,
                                             same_picture=same_picture)  # fmt: skip
        new = true_depth(state["tree"], world)
        for b in range(len(new)):
            if sk.parent[b] >= 0:
                new[b][0, 2] = new[sk.parent[b]][-1, 2]
        if not state["graft"]:
            return new, why, sk
        pix = lift._pixel(world)
        _, grid = lift._carve_all(sk, world, new, side, side_world)  # the side's grid
        cover, c_off, nrows = grid[0], grid[1], grid[2]
        cover[:] = 0
        for b, p in enumerate(new):
            rows = np.clip(np.round(p[:, 1] / pix).astype(np.int64), 0, nrows - 1)
            lift._cover(cover, rows, p[:, 2] / pix + c_off, np.asarray(sk.radii[b], float), 1)
        sk2, out2, _n = lift._graft_hidden(sk, new, side, side_world, grid, pix)
        return out2, why, sk2

    rows = []
    for preset in sorted(honda.PRESETS):
        for seed in a.seeds:
            tree = honda.develop(honda.PRESETS[preset], seed=seed)
            front, side = (v > 0 for v in plant_views(tree, a.size, "radius", views=2))
            row = {"preset": preset, "seed": seed}
            for name, graft in (("carved", None), ("true_depth", False),
                                ("true_depth_grafted", True)):  # fmt: skip
                build.lift_two_views = lift.lift_two_views if graft is None else oracle
                state.update(tree=tree, graft=graft)
                try:
                    rec = reconstruct(front, side, height_m=10.0)
                finally:
                    build.lift_two_views = lift.lift_two_views
                s = judge(rec, front, side)
                row[name] = {"front": round(s["ncc"], 4), "side": round(s["ncc_side"], 4),
                             "travel": round(_travel(rec.plant) / _travel(tree), 3)}  # fmt: skip
            print(json.dumps(row), flush=True)
            rows.append(row)
    summary = {"summary": "honda trees from front and side", "n": len(rows)}
    for name in ("carved", "true_depth", "true_depth_grafted"):
        for key in ("front", "side", "travel"):
            vals = [r[name][key] for r in rows]
            summary[f"{name}_{key}"] = round(float(np.mean(vals)), 4)
        summary[f"{name}_both_085"] = sum(
            min(r[name]["front"], r[name]["side"]) >= 0.85 for r in rows
        )
    print(json.dumps(summary))
    return 0


if __name__ == "__main__":
    sys.exit(main())
