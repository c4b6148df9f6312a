"""Pictures of classic 2D IFS attractors, drawn by a program independent of growsim
(issue 27): its own chaos game in plain NumPy, black points on white, plotted with
matplotlib's ``scatter`` or set pixel by pixel with PIL, PNG, 300-800 px, with margins.
What a user with a picture of a fern from a textbook or a web page would hand to
``growsim fit-image PICTURE --model ifs2d``.

Coefficient tables (rows ``a b c d e f p``, ``x' = a x + b y + e``, ``y' = c x + d y + f``),
cited by title:

- discovery set (the fit's setup was tuned on these three):

  - ``fern``: Barnsley's fern, M. Barnsley, "Fractals Everywhere" (Table 3.8.3);
  - ``tree``: the branching fractal tree of six maps (a forked trunk, four branches) of
    Paul Bourke's pages "IFS - Iterated Function Systems" (the "tree" example);
  - ``maple``: the maple leaf of four maps, M. Barnsley, "Fractals Everywhere"
    (the leaf of the collage theorem's examples);

- held-out set (never tuned on; only measured):

  - ``sierpinski``: the Sierpinski triangle, three maps of scale 1/2;
  - ``spiral``: the spiral of three maps, Fractint's IFS library ("spiral");
  - ``tree4``: a four-map tree (a trunk, two branches at 45 degrees, a bud), Fractint's
    IFS library ("tree");
  - ``koch``: a Koch-like twig of five maps, Fractint's IFS library ("koch3");
  - ``crystal``: the two-map "crystal" of Fractint's IFS library.

Writes ``DIR/<name>.png`` and ``DIR/index.json`` (a list of ``{"name", "split",
"source", "size", "margin", "points", "plot", "file", "table"}``; ``table``: the code drawn,
for a benchmark's ceiling, never for a fit). Usage::

    python benchmarks/make_attractors.py --out runs/attractors
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

#: name -> (split, source, rows a b c d e f p)
TABLES: dict[str, tuple[str, str, list[list[float]]]] = {
    "fern": ("discovery", 'Barnsley, "Fractals Everywhere": the fern', [
        [0.0, 0.0, 0.0, 0.16, 0.0, 0.0, 0.01],
        [0.85, 0.04, -0.04, 0.85, 0.0, 1.6, 0.85],
        [0.2, -0.26, 0.23, 0.22, 0.0, 1.6, 0.07],
        [-0.15, 0.28, 0.26, 0.24, 0.0, 0.44, 0.07],
    ]),
    "tree": ("discovery", 'Paul Bourke, "IFS - Iterated Function Systems": the tree', [
        [0.05, 0.0, 0.0, 0.6, 0.0, 0.0, 0.17],
        [0.05, 0.0, 0.0, -0.5, 0.0, 1.0, 0.17],
        [0.46, -0.321, 0.386, 0.383, 0.0, 0.6, 0.17],
        [0.47, -0.154, 0.171, 0.423, 0.0, 1.0, 0.17],
        [0.433, 0.275, -0.25, 0.476, 0.0, 1.0, 0.16],
        [0.421, 0.257, -0.353, 0.306, 0.0, 0.7, 0.16],
    ]),
    "maple": ("discovery", 'Barnsley, "Fractals Everywhere": the maple leaf', [
        [0.14, 0.01, 0.0, 0.51, -0.08, -1.31, 0.10],
        [0.43, 0.52, -0.45, 0.5, 1.49, -0.75, 0.35],
        [0.45, -0.49, 0.47, 0.47, -1.62, -0.74, 0.35],
        [0.49, 0.0, 0.0, 0.51, 0.02, 1.62, 0.20],
    ]),
    "sierpinski": ("held-out", "the Sierpinski triangle", [
        [0.5, 0.0, 0.0, 0.5, 0.0, 0.0, 0.33],
        [0.5, 0.0, 0.0, 0.5, 1.0, 0.0, 0.33],
        [0.5, 0.0, 0.0, 0.5, 0.5, 0.866, 0.34],
    ]),
    "spiral": ("held-out", "Fractint's IFS library: spiral", [
        [0.787879, -0.424242, 0.242424, 0.859848, 1.758647, 1.408065, 0.895652],
        [-0.121212, 0.257576, 0.151515, 0.05303, -6.721654, 1.377236, 0.052174],
        [0.181818, -0.136364, 0.090909, 0.181818, 6.086107, 1.568035, 0.052174],
    ]),
    "tree4": ("held-out", "Fractint's IFS library: tree", [
        [0.0, 0.0, 0.0, 0.5, 0.0, 0.0, 0.05],
        [0.42, -0.42, 0.42, 0.42, 0.0, 0.2, 0.40],
        [0.42, 0.42, -0.42, 0.42, 0.0, 0.2, 0.40],
        [0.1, 0.0, 0.0, 0.1, 0.0, 0.2, 0.15],
    ]),
    "koch": ("held-out", "Fractint's IFS library: koch3", [
        [0.307692, 0.0, 0.0, 0.294118, 4.119164, 1.604278, 0.151515],
        [0.192308, -0.205882, 0.653846, 0.088235, -0.68884, 5.978916, 0.253788],
        [-0.192308, 0.205882, 0.653846, 0.088235, 0.66858, 5.962514, 0.253788],
        [0.307692, 0.0, 0.0, 0.294118, -4.13653, 1.604278, 0.151515],
        [0.384615, 0.0, 0.0, -0.294118, -0.007718, 2.941176, 0.189394],
    ]),
    "crystal": ("held-out", "Fractint's IFS library: crystal", [
        [0.69697, -0.481061, -0.393939, -0.662879, 2.147003, 10.310288, 0.747826],
        [0.090909, -0.443182, 0.515152, -0.094697, 4.286558, 2.925762, 0.252174],
    ]),
}  # fmt: skip

#: name -> (picture size px, margin px, points, plot: "scatter" (matplotlib) or "pixels"
#: (PIL))
DRAWN = {
    "fern": (600, 40, 200_000, "scatter"),
    "tree": (500, 30, 200_000, "pixels"),
    # 150,000 points at this size leave pinholes in the leaf that fit-image refuses as
    # noise (26.7 specks or pinholes per 1,000 pixels, at most 20): drawn denser
    "maple": (400, 20, 400_000, "scatter"),
    "sierpinski": (300, 15, 100_000, "pixels"),
    "spiral": (700, 50, 200_000, "scatter"),
    "tree4": (450, 25, 150_000, "pixels"),
    "koch": (800, 60, 200_000, "scatter"),
    "crystal": (350, 20, 120_000, "pixels"),
}


def chaos_game(table, n: int, seed: int = 0, burn: int = 50) -> np.ndarray:
    """``(n, 2)`` points of the attractor of ``table`` (rows ``a b c d e f p``): the random
    iteration algorithm, the map drawn with probability ``p`` at each step.

    >>> chaos_game([[0.5, 0, 0, 0.5, 0, 0, 1]], 3, burn=60).round(6).tolist()
    [[0.0, 0.0], [0.0, 0.0], [0.0, 0.0]]
    """
    t = np.asarray(table, dtype=np.float64)
    p = t[:, 6] / t[:, 6].sum()
    rng = np.random.default_rng(seed)
    picks = rng.choice(len(t), size=n + burn, p=p)
    out = np.empty((n + burn, 2))
    x = y = 0.0
    for i, k in enumerate(picks):
        a, b, c, d, e, f = t[k, :6]
        x, y = a * x + b * y + e, c * x + d * y + f
        out[i] = x, y
    return out[burn:]


def _fit_box(points, size: int, margin: int) -> np.ndarray:
    """Pixel coordinates (column, row; row 0 at the top) of ``points`` fitted into a
    ``size`` square less ``margin``, the aspect kept, centred."""
    lo, hi = points.min(axis=0), points.max(axis=0)
    scale = (size - 2 * margin - 1) / max(float((hi - lo).max()), 1e-12)
    xy = (points - lo) * scale
    off = (size - 1 - (hi - lo) * scale) / 2.0
    col = xy[:, 0] + off[0]
    row = size - 1 - (xy[:, 1] + off[1])
    return np.column_stack([col, row])


def draw_pixels(points, size: int, margin: int, path: Path) -> None:
    """Black pixels on white, set one by one with PIL."""
    from PIL import Image

    img = Image.new("L", (size, size), 255)
    px = img.load()
    for c, r in np.rint(_fit_box(points, size, margin)).astype(int):
        px[int(c), int(r)] = 0
    img.save(path)


def draw_scatter(points, size: int, margin: int, path: Path) -> None:
    """Black dots on white with matplotlib's ``scatter`` (round markers of 0.5 pt^2,
    antialiased: grey at their edges), saved as PNG."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    dpi = 100
    fig = plt.figure(figsize=(size / dpi, size / dpi), dpi=dpi)
    ax = fig.add_axes((0, 0, 1, 1))
    xy = _fit_box(points, size, margin)
    ax.scatter(xy[:, 0], xy[:, 1], s=0.5, c="black", marker="o", linewidths=0)
    ax.set_xlim(-0.5, size - 0.5)
    ax.set_ylim(size - 0.5, -0.5)
    ax.set_axis_off()
    fig.savefig(path, dpi=dpi, facecolor="white")
    plt.close(fig)


def make(out: Path, names=None) -> list[dict]:
    """Draw the pictures of ``names`` (all: None) into ``out``; returns the index rows."""
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    for i, name in enumerate(names or TABLES):
        split, source, table = TABLES[name]
        size, margin, n, plot = DRAWN[name]
        pts = chaos_game(table, n, seed=1000 + i)
        path = out / f"{name}.png"
        (draw_scatter if plot == "scatter" else draw_pixels)(pts, size, margin, path)
        rows.append(dict(name=name, split=split, source=source, size=size, margin=margin,
                         points=n, plot=plot, file=path.name, table=table))  # fmt: skip
    (out / "index.json").write_text(json.dumps(rows, indent=1))
    return rows


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default="runs/attractors")
    ap.add_argument("--only", nargs="*", help="names to draw (default: all)")
    args = ap.parse_args(argv)
    for row in make(Path(args.out), args.only):
        print(json.dumps(row))


if __name__ == "__main__":
    main()
