"""Every picture of ``docs/images/``, re-made from the current code by one command.

    python benchmarks/gallery.py                      # every picture it can re-make (about an hour)
    python benchmarks/gallery.py --only fish_calm.png honda_presets.png
    python benchmarks/gallery.py --list               # each picture: how it is made, its page
    python benchmarks/gallery.py --save runs/h2d runs/h3d runs/h2dp runs/h3dp   # see below

Each picture comes from the code that makes it: a ``growsim`` command (as the page that
shows it prints it), a model's ``develop``/``grow`` and the plant views, or a benchmark's
own figure function (``benchmarks/env_figures.py``, ``hormone_figures.py``, ``ifs2d.py``).
Pictures of long runs (a sweep of 24 runs, a fit of minutes) are drawn from the runs'
results saved in ``benchmarks/results/gallery/`` (the best genome of each environment and
the run's resolved config): ``--save SWEEP ...`` writes them from ``growsim sweep``
directories (``hormone_2d.toml``, ``hormone_3d.toml``, their ``*_paper_ga`` twins,
``stand_density_3d.toml``). A picture whose inputs are not saved, or that another
command makes, is listed with what re-makes it and left as it is. The fitting pictures
(``fit_image``, ``fit_mtree``, ``ifs2d_fern_fit``) take 15, 2 and 3-14 minutes of fits,
``ifs3d_identifiability`` a search of 3-26 minutes (by the machine's load).
``docs/gallery.md`` shows every picture (``tests/test_gallery.py``: every file of
``docs/images/`` is listed here and shown on a page).
"""

from __future__ import annotations

import argparse
import json
import shlex
import shutil
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
IMAGES = ROOT / "docs" / "images"
SAVED = ROOT / "benchmarks" / "results" / "gallery"
EXP = ROOT / "experiments"
sys.path.insert(0, str(ROOT / "benchmarks"))  # the benchmarks' own figure functions


def growsim(line: str, **paths) -> None:
    """The command line ``growsim LINE`` (``{name}`` fields filled from ``paths``) in this
    process, as a user types it; raise if it fails."""
    from growsim.cli import main

    argv = [a.format(**paths) for a in shlex.split(line)]
    if main(argv) != 0:
        raise SystemExit(f"failed: growsim {' '.join(argv)}")


def tile(paths, dest: Path, columns: int, labels=None, cell=None) -> Path:
    """Pictures side by side (``columns`` a row), each with its label under it."""
    from PIL import Image, ImageDraw, ImageFont

    ims = [Image.open(p).convert("RGB") for p in paths]
    w, h = cell or ims[0].size
    label_h = 30 if labels else 0
    rows = -(-len(ims) // columns)
    sheet = Image.new("RGB", (columns * w, rows * (h + label_h)), "white")
    font = ImageFont.load_default(size=18)
    draw = ImageDraw.Draw(sheet)
    for i, im in enumerate(ims):
        x, y = (i % columns) * w, (i // columns) * (h + label_h)
        sheet.paste(im.resize((w, h)), (x, y))
        if labels:
            draw.text((x + w // 2, y + h + 4), labels[i], fill="black", font=font, anchor="ma")
    sheet.save(dest, optimize=True)
    return dest


# -- the makers: each writes its pictures into ``out`` ------------------------------------


def make_env(out: Path) -> None:
    import env_figures

    for argv in env_figures.commands(out, 600).values():
        growsim(shlex.join(argv))


def make_fish(out: Path) -> None:
    growsim("grow fish --preset calm --screenshot {p} --size 600 600", p=out / "fish_calm.png")


def make_honda_presets(out: Path) -> None:
    from growsim.models import honda
    from growsim.phenotypes.plant import render_grid

    trees = [honda.develop(p) for p in honda.PRESETS.values()]
    render_grid(
        trees, out / "honda_presets.png", titles=list(honda.PRESETS), cell=(240, 240), columns=4
    )


def make_honda_silhouette(out: Path) -> None:
    """The cherry preset beside the Honda tree fitted to its silhouettes (seed 1 of
    ``experiments/honda_silhouette.toml``, a run of seconds)."""
    from growsim.experiment import run
    from growsim.models import honda
    from growsim.phenotypes.plant import render_grid

    with tempfile.TemporaryDirectory() as tmp:
        r = run(
            EXP / "honda_silhouette.toml",
            Path(tmp) / "run",
            progress=False,
            overrides=["output.mesh=[]", "output.screenshots=[]", "output.plot=false"],
        )
        render_grid(
            [honda.develop(honda.PRESETS["cherry"]), r.best_plant],
            out / "honda_silhouette_fit.png",
            titles=[
                "target: the cherry preset",
                f"fitted, seed {r.summary['seed']} (NCC {r.best_fitness:.3f})",
            ],
            cell=(300, 300),
        )


def make_hormone_demo(out: Path) -> None:
    import hormone_figures

    hormone_figures.DOCS = out
    hormone_figures.demo()


def _saved_best(name: str, out: Path, gifs: bool, picture: str | None = None) -> None:
    """The best plant of each environment of a saved sweep, side by side (and each one's
    growth as a GIF): ``benchmarks/results/gallery/<name>.json``."""

    from growsim.phenotypes.plant.views import growth_animation, render_grid

    saved = json.loads((SAVED / f"{name}.json").read_text())
    plants, titles = [], []
    for variant, best in saved["variants"].items():
        steps = _grown(best)
        plants.append(steps[-1])
        titles.append(f"{variant.replace('_', ' ')}: {steps[-1].n_segments} modules")
        view = "front" if int(best["params"]["dims"]) == 2 else "iso"
        if gifs:
            growth_animation(
                steps, out / f"{name}_{variant}.gif", view=view, size=(260, 260), fps=6
            )
    render_grid(
        plants,
        out / (picture or f"{name}_best.png"),
        titles=titles,
        view=view,
        cell=(320, 320),
        columns=len(plants),
        same_scale=True,
    )


def make_hormone_2d(out: Path) -> None:
    _saved_best("hormone_2d", out, gifs=True)


def make_hormone_3d(out: Path) -> None:
    _saved_best("hormone_3d", out, gifs=True)
    _largest_growth("hormone_3d", out / "hormone_3d_growth.gif")


def _grown(best: dict) -> list:
    """A saved run's best genome (``params``, ``config``: :func:`save_sweep`) grown again
    in its run's environment: the plant after each step."""
    import numpy as np

    from growsim.experiment import load_plan

    plan = load_plan(best["config"])
    f = plan.fitness()
    params = f.param_dict(np.array([float(best["params"][n]) for n in f.names]))
    return list(plan.model.grow(params, env=f.env))


def _largest_growth(name: str, path: Path) -> None:
    """The growth, a frame a week, of the largest best plant of a saved sweep (its
    ``largest`` run: the one whose best plant has the most modules)."""
    from growsim.phenotypes.plant.views import growth_animation

    best = json.loads((SAVED / f"{name}.json").read_text())["largest"]
    growth_animation(_grown(best), path, view="iso", size=(300, 300), fps=6)


def make_hormone_2d_paper_ga(out: Path) -> None:
    _saved_best("hormone_2d_paper_ga", out, gifs=False)


def make_hormone_3d_paper_ga(out: Path) -> None:
    _saved_best("hormone_3d_paper_ga", out, gifs=False)


def make_stand_density_3d(out: Path) -> None:
    _saved_best("stand_density_3d", out, gifs=False, picture="stand_density_3d.png")


def make_ifs2d(out: Path) -> None:
    """``benchmarks/ifs2d.py``'s figures; each tree's terms by generation labelled with how
    its seed 0 stands among the 20 seeds of ``benchmarks/results/ifs2d_claim.json``."""
    import ifs2d

    with tempfile.TemporaryDirectory() as tmp:
        tables = {
            name: ifs2d.run_tree(overrides, 0, Path(tmp) / "seed_experiment" / name)
            for name, overrides in ifs2d.TREES.items()
        }
        ifs2d.figures(out, Path(tmp))
    claim = json.loads((ROOT / "benchmarks" / "results" / "ifs2d_claim.json").read_text())
    for name, table in tables.items():
        path = out / f"ifs2d_{name}_terms.png"
        first, last = table["stability"].iloc[0], table["stability"].iloc[-1]
        s = claim["claim"][name]["terms"]["stability"]
        n = s["better"] + s["equal"] + s["worse"]
        way = "rises" if last > first else "falls" if last < first else "stays"
        label = (
            f"{name.replace('_', ' ')}, seed 0: stability {way} ({first:.2f} -> {last:.2f}); "
            f"over {n} seeds it rises in {s['better']}, falls in {s['worse']}"
        )
        _title(path, label)


def _title(path: Path, text: str) -> None:
    """Write ``text`` in a white band above the picture at ``path``."""
    from PIL import Image, ImageDraw, ImageFont

    im = Image.open(path).convert("RGB")
    font = ImageFont.load_default(size=15)
    band = Image.new("RGB", (im.width, im.height + 28), "white")
    band.paste(im, (0, 28))
    ImageDraw.Draw(band).text((im.width // 2, 6), text, fill="black", font=font, anchor="ma")
    band.save(path)


def make_ifs3d(out: Path) -> None:
    growsim(
        "grow ifs3d --preset table1 --screenshot {p} --size 400 400", p=out / "ifs3d_table1.png"
    )


def make_ifs3d_fit(out: Path) -> None:
    """Target and fitted silhouettes of the Table 1 fit, best setup, seed 0 (as
    ``growsim fit-image`` writes its ``silhouettes.png``)."""
    from growsim.experiment import load_plan, run
    from growsim.objectives.silhouette import plant_views
    from growsim.pictures.images import silhouette_image

    with tempfile.TemporaryDirectory() as tmp:
        r = run(
            EXP / "ifs_tree_best.toml",
            Path(tmp) / "run",
            seed=0,
            progress=False,
            overrides=["output.mesh=[]", "output.screenshots=[]", "output.plot=false"],
        )
        target = load_plan(EXP / "ifs_tree_best.toml").objectives[0].target
        views = plant_views(r.best_plant, 64, "thin")
        silhouette_image(
            [target[0], target[1], views[0], views[1]],
            out / "ifs3d_table1_fit.png",
            titles=[
                "target: front",
                "target: side",
                f"fit (NCC {r.best_fitness:.3f}): front",
                "fit: side",
            ],
        )


def make_ifs2d_fern_fit(out: Path) -> None:
    """Two runs of ``experiments/ifs_fern_fit.toml``, seed 0 (2-7 min each): its
    ``collage`` objective left out (row 1), then as it is (row 2). Each row: the fern, its
    64 px view (the target), the fitted code's view (as the run drew it) with its binary
    NCC, and the fitted code's attractor drawn with the fern's 100,000 points."""
    import tomllib

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from growsim.experiment import load_plan, run
    from growsim.models import ifs2d

    config = EXP / "ifs_fern_fit.toml"
    alone = tomllib.loads(config.read_text())
    alone["objective"] = [o for o in alone["objective"] if o["kind"] != "collage"]
    fern = ifs2d.develop(ifs2d.PRESETS["fern"])
    fig, axes = plt.subplots(2, 4, figsize=(12, 6.6))
    with tempfile.TemporaryDirectory() as tmp:
        for row, (label, cfg) in zip(
            axes, (("silhouette only", alone), ("silhouette + collage", config))
        ):
            r = run(cfg, Path(tmp) / label.replace(" ", "_"), seed=0, progress=False,
                    overrides=["output.mesh=[]", "output.screenshots=[]",
                               "output.plot=false"])  # fmt: skip
            silhouette = load_plan(r.config).objectives[0]  # the binary NCC, not the blurred
            fit, dense = r.best_plant, {**r.best_params, "iterations": fern.n_points}
            panels = (
                (fern.render_image(view="front", size=(300, 300)), "the fern (Table 1)"),
                (silhouette.target[0], "target view, 64 px"),
                (silhouette.views(fit)[0], f"{label}: NCC {silhouette.exact(fit):.3f}"),
                (
                    ifs2d.develop(dense).render_image(view="front", size=(300, 300)),
                    "the fitted code's attractor",
                ),
            )
            for ax, (img, title) in zip(row, panels):
                ax.imshow(img, cmap="gray_r", interpolation="nearest")
                ax.set_title(title)
                ax.set_axis_off()
    fig.tight_layout()
    fig.savefig(out / "ifs2d_fern_fit.png", dpi=75)
    plt.close(fig)


def make_quickstart(out: Path) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        run = Path(tmp) / "quickstart-doc"
        growsim("run {config} --out {run} --quiet", config=EXP / "quickstart.toml", run=run)
        growsim(
            "show {run} --screenshot {p} --view front --size 480 480",
            run=run,
            p=out / "quickstart_tree.png",
        )


def make_stand(out: Path) -> None:
    """``docs/models/stand.md``'s commands: a stand of hormone plants beside one of Honda
    trees coloured by light, and nine plants growing."""
    with tempfile.TemporaryDirectory() as tmp:
        a, b = Path(tmp) / "hormone.png", Path(tmp) / "trees.png"
        growsim(
            "grow hormone --preset demo_3d --stand 5x5 --spacing 1.5 --view iso "
            "--screenshot {a} --size 400 400",
            a=a,
        )
        growsim(
            "grow honda --preset zelkova --stand 5x5 --spacing 35 --color light --view iso "
            "--screenshot {b} --size 400 400",
            b=b,
        )
        tile([a, b], out / "stand.png", columns=2)
    growsim(
        "grow hormone --preset demo_3d --stand 3x3 --spacing 1 --gif {p} --size 280 280",
        p=out / "stand_growth.gif",
    )


def _example(name: str):
    """The ``main`` of ``examples/NAME.py`` (run as the script runs)."""
    import runpy

    return runpy.run_path(str(ROOT / "examples" / f"{name}.py"))["main"]


def make_examples(out: Path) -> None:
    """What each ``examples/`` script draws, run as its docstring shows (full budgets):
    ``grow_each_model.py``'s six pictures side by side, ``run_experiment.py``'s
    ``fitness.png``, ``compare_environments.py``'s ``curves.png`` and
    ``notebook_viewer.py``'s off-screen picture."""
    import os

    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        written = _example("grow_each_model")(["--out", str(tmp / "models"), "--size", "320"])
        tile(
            written,
            out / "examples_grow_each_model.png",
            columns=3,
            labels=[p.stem.replace("_", " ", 1) for p in written],
        )
        result = _example("run_experiment")(["--out", str(tmp / "run")])
        shutil.copyfile(result.out / "fitness.png", out / "examples_run_experiment.png")
        _example("compare_environments")(["--out", str(tmp / "lights"), "--no-renders"])
        shutil.copyfile(
            tmp / "lights" / "compare" / "curves.png", out / "examples_compare_environments.png"
        )
        cwd = os.getcwd()
        try:
            os.chdir(tmp)
            _example("notebook_viewer")(["--out", str(out / "examples_notebook_viewer.png")])
        finally:
            os.chdir(cwd)


@dataclass(frozen=True)
class Maker:
    make: Callable[[Path], None] | None
    pictures: tuple[str, ...]
    how: str
    #: why it is not re-made by default (None: it is)
    kept: str | None = None


def _saved(name: str) -> str | None:
    if (SAVED / f"{name}.json").is_file():
        return None
    return (
        f"needs benchmarks/results/gallery/{name}.json: --save a sweep of experiments/{name}.toml"
    )


#: ``benchmarks/make_mtree.py``'s pictures of another generator's trees (not in the
#: repository: made in about a minute)
MTREE = ROOT / "runs" / "mtree"


def make_fit_mtree(out: Path) -> None:
    """The modular-tree fit sheets: every picture's target beside its no-flags
    ``fit-image`` fit, both splits (``benchmarks/mtree_fit.py --sheet``)."""
    with tempfile.TemporaryDirectory() as tmp:
        for split in ("discovery", "held_out"):
            cmd = [sys.executable, str(ROOT / "benchmarks" / "mtree_fit.py"), "--pictures",
                   str(MTREE), "--split", split, "--out", f"{tmp}/{split}", "--sheet",
                   str(out / f"fitting_mtree_{split}.png")]  # fmt: skip
            subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)


def make_ifs3d_identifiability(out: Path) -> None:
    """Table 1 beside the farthest tree found at NCC >= 0.95 and the worst tree within
    tolerance (``benchmarks/ifs_identifiability.py``'s search: 200 s at load 2 in its log,
    26 min at load 5 here)."""
    cmd = [sys.executable, str(ROOT / "benchmarks" / "ifs_identifiability.py"), "--restarts",
           "4", "--iters", "1000", "--png", str(out / "ifs3d_identifiability.png")]  # fmt: skip
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)


def make_fit_side(out: Path) -> None:
    """The reconstruction's worst and best held-out fit of each kind, front and side, from
    the front picture alone and from front and side pictures (``benchmarks/reconstruct_fit.py
    --sheet --sheet2``, the true masks, about 1 min)."""
    cmd = [sys.executable, str(ROOT / "benchmarks" / "reconstruct_fit.py"), "--pictures",
           str(MTREE), "--split", "held_out", "--sheet", str(out / "fitting_side.png"),
           "--sheet2", str(out / "fitting_two_views.png")]  # fmt: skip
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


#: the pictures of ``fitting_arrangement.png``: fits whose start is not the picture's own
#: arrangement (``benchmarks/log/fitting.md``)
ARRANGED = ("ginkgo_bare", "columnar_bare_overcast", "zelkova_leafy_evening")


def make_fit_image(out: Path) -> None:
    """The photo benchmark's pictures (``benchmarks/photo_fit.py``): the worked example
    (``cherry_leafy``'s photo, silhouette and fit), the fits of ``ARRANGED`` before
    (``--arrange 0 --blur 0``) and with the arrangement search, and the segmentation's
    errors on the two pictures of the set it reads worst. Seven fits, about 15 min."""
    import photo_fit
    from make_photos import EXTRA_PICTURES, PICTURES, SUPERSAMPLE, write_set

    bench = str(ROOT / "benchmarks" / "photo_fit.py")
    with tempfile.TemporaryDirectory() as tmp:
        for sub, extra in (("fits", ()), ("before", ("--arrange", "0", "--blur", "0"))):
            names = ARRANGED + (("cherry_leafy",) if sub == "fits" else ())
            cmd = [sys.executable, bench, "--extra", "--only", *names, "--out",
                   f"{tmp}/{sub}", *extra]  # fmt: skip
            subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        photo_fit.figures(Path(tmp, "fits", "fits", "cherry_leafy"), out)
        photo_fit.comparison_figure(f"{tmp}/fits", f"{tmp}/before", out, ARRANGED)
        pics = PICTURES + EXTRA_PICTURES
        camera = {"supersample": SUPERSAMPLE, "blur": 0.0, "linear": True}
        table = photo_fit.segmentation_table(pics, camera, limit=False)
        worst = [r["picture"] for r in sorted(table["pictures"], key=lambda r: r["iou"])[:2]]
        write_set(Path(tmp, "photos"), [p for p in pics if p.name in worst], **camera)
        photo_fit.error_figure(Path(tmp, "photos"), out, worst, 830)


#: real photographs whose licence allows them here (``benchmarks/data/real_photos/``)
REAL = ROOT / "benchmarks" / "data" / "real_photos"


def make_fit_real(out: Path) -> None:
    """Each real photograph of ``REAL`` as a user gives it, no flags: the photo with the
    tree's outline beside the fitted silhouette and the fit's NCC, or the photo with the
    refusal's line; four a row. About 70 s (35 photographs, 8 fitted)."""
    import textwrap

    from PIL import Image, ImageDraw, ImageFont

    from growsim.errors import UserInputError
    from growsim.pictures.photo import segment_photo

    font = ImageFont.load_default(size=12)
    half, tall, caption, per_row = 150, 150, 56, 4

    def fitted(im):  # letterboxed into half x tall
        im = im.convert("RGB")
        k = min(half / im.width, tall / im.height)
        box = Image.new("RGB", (half, tall), "white")
        small = im.resize((max(1, round(im.width * k)), max(1, round(im.height * k))))
        box.paste(small, ((half - small.width) // 2, (tall - small.height) // 2))
        return box

    tiles = []
    with tempfile.TemporaryDirectory() as tmp:
        for photo in sorted(REAL.glob("*.jpg")):
            tile = Image.new("RGB", (2 * half, tall + caption), "white")
            try:
                segment_photo(photo)
            except UserInputError as e:
                tile.paste(fitted(Image.open(photo)), (0, 0))
                text = f"{photo.stem}: refused: {str(e).replace(str(photo) + ': ', '')}"
            else:
                fit = Path(tmp) / photo.stem
                growsim("fit-image {photo} --out {fit}", photo=photo, fit=fit)
                seg = Image.open(fit / "segmentation_front.png")
                sil = Image.open(fit / "silhouettes.png")
                tile.paste(fitted(seg.crop((0, 0, seg.width // 2, seg.height))), (0, 0))
                tile.paste(fitted(sil.crop((sil.width // 2, 0, sil.width, sil.height))), (half, 0))
                ncc = json.loads((fit / "fit.json").read_text())["ncc"]
                text = f"{photo.stem}: fitted, NCC {ncc:.2f}"
            lines = textwrap.wrap(text, 48)[:4]
            ImageDraw.Draw(tile).multiline_text((4, tall + 2), "\n".join(lines), fill="black",
                                                font=font, spacing=1)  # fmt: skip
            tiles.append(tile)
    rows = -(-len(tiles) // per_row)
    sheet = Image.new("RGB", (per_row * (2 * half + 10), rows * (tall + caption)), "white")
    for i, tile in enumerate(tiles):
        sheet.paste(tile, ((i % per_row) * (2 * half + 10), (i // per_row) * (tall + caption)))
    sheet.quantize(256).save(out / "fitting_real_photos.png", optimize=True)  # photos: small


MAKERS: dict[str, Maker] = {
    "env": Maker(
        make_env,
        ("env_light.png", "env_stress.png", "env_water.png"),
        "growsim grow honda --preset zelkova --color light|stress|water "
        "(benchmarks/env_figures.py)",
    ),
    "fish": Maker(make_fish, ("fish_calm.png",), "growsim grow fish --preset calm --screenshot"),
    "honda_presets": Maker(
        make_honda_presets, ("honda_presets.png",), "render_grid of the eight honda.PRESETS"
    ),
    "honda_silhouette": Maker(
        make_honda_silhouette,
        ("honda_silhouette_fit.png",),
        "a run of experiments/honda_silhouette.toml beside the cherry",
    ),
    "hormone_demo": Maker(
        make_hormone_demo,
        ("hormone_demo.png",),
        "benchmarks/hormone_figures.py: the demo genomes, 2D and 3D",
    ),
    "hormone_2d": Maker(
        make_hormone_2d,
        (
            "hormone_2d_best.png",
            "hormone_2d_ample.gif",
            "hormone_2d_half_water.gif",
            "hormone_2d_half_light.gif",
        ),
        "the best genome of each environment of a hormone_2d.toml sweep, grown again",
        _saved("hormone_2d"),
    ),
    "hormone_3d": Maker(
        make_hormone_3d,
        (
            "hormone_3d_best.png",
            "hormone_3d_ample.gif",
            "hormone_3d_half_water.gif",
            "hormone_3d_half_light.gif",
            "hormone_3d_growth.gif",
        ),
        "the same for hormone_3d.toml, and the growth of its largest best plant",
        _saved("hormone_3d"),
    ),
    "hormone_2d_paper_ga": Maker(
        make_hormone_2d_paper_ga,
        ("hormone_2d_paper_ga_best.png",),
        "the same for hormone_2d_paper_ga.toml",
        _saved("hormone_2d_paper_ga"),
    ),
    "hormone_3d_paper_ga": Maker(
        make_hormone_3d_paper_ga,
        ("hormone_3d_paper_ga_best.png",),
        "the same for hormone_3d_paper_ga.toml",
        _saved("hormone_3d_paper_ga"),
    ),
    "stand_density_3d": Maker(
        make_stand_density_3d,
        ("stand_density_3d.png",),
        "the best genome of each density of a stand_density_3d.toml sweep",
        _saved("stand_density_3d"),
    ),
    "ifs2d": Maker(
        make_ifs2d,
        (
            "ifs2d_presets.png",
            "ifs2d_terms.png",
            "ifs2d_tree_one.png",
            "ifs2d_tree_one_terms.png",
            "ifs2d_tree_two.png",
            "ifs2d_tree_two_terms.png",
        ),
        "benchmarks/ifs2d.py's figures: the presets, the terms, seed 0 of each tree",
    ),
    "ifs3d": Maker(make_ifs3d, ("ifs3d_table1.png",), "growsim grow ifs3d --preset table1"),
    "ifs3d_fit": Maker(
        make_ifs3d_fit,
        ("ifs3d_table1_fit.png",),
        "a run of experiments/ifs_tree_best.toml, seed 0: target and fit",
    ),
    "quickstart": Maker(
        make_quickstart,
        ("quickstart_tree.png",),
        "growsim run experiments/quickstart.toml, then growsim show",
    ),
    "stand": Maker(
        make_stand,
        ("stand.png", "stand_growth.gif"),
        "growsim grow hormone|honda --stand (docs/models/stand.md's commands)",
    ),
    "examples": Maker(
        make_examples,
        (
            "examples_grow_each_model.png",
            "examples_run_experiment.png",
            "examples_compare_environments.png",
            "examples_notebook_viewer.png",
        ),
        "the examples/ scripts, run as their docstrings show",
    ),
    "ifs2d_fern_fit": Maker(
        make_ifs2d_fern_fit,
        ("ifs2d_fern_fit.png",),
        "two runs of experiments/ifs_fern_fit.toml, seed 0 (silhouette only; with the collage "
        "term; 2-7 min each): the fern, its 64 px view, the fit's view and NCC, its attractor",
    ),
    "ifs3d_identifiability": Maker(
        make_ifs3d_identifiability,
        ("ifs3d_identifiability.png",),
        "python benchmarks/ifs_identifiability.py --restarts 4 "
        "--iters 1000 --png docs/images/ifs3d_identifiability.png (a search of 3-26 min)",
    ),
    "fit_mtree": Maker(
        make_fit_mtree,
        ("fitting_mtree_discovery.png", "fitting_mtree_held_out.png"),
        "python benchmarks/mtree_fit.py --split discovery|held_out --sheet ... (24 fits)",
        None
        if (MTREE / "index.json").is_file()
        else ("needs runs/mtree: python benchmarks/make_mtree.py --out runs/mtree"),
    ),
    "fit_side": Maker(
        make_fit_side,
        ("fitting_side.png", "fitting_two_views.png"),
        "python benchmarks/reconstruct_fit.py --split held_out --sheet ... --sheet2 ... "
        "(12 reconstructions, each from one and from two pictures)",
        None
        if (MTREE / "index.json").is_file()
        else ("needs runs/mtree: python benchmarks/make_mtree.py --out runs/mtree --side"),
    ),
    "fit_real": Maker(
        make_fit_real,
        ("fitting_real_photos.png",),
        "growsim fit-image on each photograph of benchmarks/data/real_photos/, no flags "
        "(the refused ones with their one line; about 70 s)",
    ),
    "fit_image": Maker(
        make_fit_image,
        (
            "fitting_arrangement.png",
            "fitting_photo.png",
            "fitting_silhouettes.png",
            "photo_segmentation.png",
        ),
        "benchmarks/photo_fit.py's figures: cherry_leafy's fit, three fits before and with "
        "the arrangement search, the two worst segmentations (seven fits, ~15 min)",
    ),
}


def pictures() -> dict[str, str]:
    """Every picture the gallery knows -> its maker's name."""
    return {p: name for name, m in MAKERS.items() for p in m.pictures}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--only", nargs="*", default=None, help="picture or maker names")
    ap.add_argument("--out", type=Path, default=IMAGES, help="picture directory")
    ap.add_argument("--list", action="store_true", help="list the pictures and stop")
    ap.add_argument(
        "--save",
        nargs="*",
        default=None,
        metavar="SWEEP",
        help="save each sweep's best genomes to benchmarks/results/gallery/",
    )
    args = ap.parse_args(argv)
    if args.list:
        for name, m in MAKERS.items():
            state = f"kept: {m.kept}" if m.kept or m.make is None else "re-made"
            print(f"{name}: {', '.join(m.pictures)}\n    {m.how}\n    {state}")
        return 0
    if args.save is not None:
        for sweep in args.save:
            print(save_sweep(Path(sweep)))
        return 0
    owner = pictures()
    names = list(MAKERS)
    if args.only:
        names = [owner.get(n, n) for n in args.only]
    args.out.mkdir(parents=True, exist_ok=True)
    for name in dict.fromkeys(names):
        m = MAKERS[name]
        if m.make is None or m.kept:
            print(f"{name}: kept ({m.kept})", flush=True)
            continue
        t = time.perf_counter()
        if len(names) == 1:
            m.make(args.out)
        else:  # each maker in a process of its own (numba's threads, the benchmarks' state)
            cmd = [sys.executable, __file__, "--only", name, "--out", str(args.out)]
            subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        print(f"{name}: {', '.join(m.pictures)} ({time.perf_counter() - t:.1f} s)", flush=True)
    return 0


def save_sweep(sweep: Path) -> Path:
    """The best run of each variant of a ``growsim sweep`` directory: its seed, fitness,
    parameters and resolved config, to ``benchmarks/results/gallery/<experiment>.json``."""
    from growsim.experiment.results import find_runs

    best = {}
    for r in find_runs([sweep]):
        variant = r.path.parent.name
        if variant not in best or r.best_fitness > best[variant].best_fitness:
            best[variant] = r
    first = next(iter(best.values()))
    name = first.config["experiment"]["name"]
    order = [
        v for v in ("ample", "half_water", "half_light", "alone", "sparse", "dense") if v in best
    ] + sorted(
        v
        for v in best
        if v not in ("ample", "half_water", "half_light", "alone", "sparse", "dense")
    )

    def entry(r):
        return {
            "seed": r.summary["seed"],
            "fitness": r.best_fitness,
            "params": r.best["params"],
            "config": r.config,
        }

    runs = find_runs([sweep])
    largest = max(runs, key=lambda r: r.summary["measures"].get("n_segments", 0))
    saved = {
        "experiment": name,
        "made": f"growsim sweep experiments/{name}.toml ({time.strftime('%Y-%m-%d')}): the "
        f"best run of each variant ({len(runs)} runs in all), and the run whose best plant "
        "has the most modules",
        "variants": {v: entry(best[v]) for v in order},
        "largest": {"variant": largest.path.parent.name, **entry(largest)},
    }
    SAVED.mkdir(parents=True, exist_ok=True)
    path = SAVED / f"{name}.json"
    path.write_text(json.dumps(saved, indent=1) + "\n")
    return path


if __name__ == "__main__":
    raise SystemExit(main())
