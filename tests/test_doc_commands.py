"""Every ``growsim`` command shown to a user runs (issue 28): the README's, every page's of
``docs/`` and those in the comments of every shipped config, so none can go stale.

Commands are taken from fenced and indented code blocks (``$ `` prompts and ``\\``
continuations too), from inline code spans and, in ``experiments/*.toml``, from comment
lines (a continuation line starting with ``--`` belongs to the command above it). Each
source's commands run in order, in the command line's own process (:func:`growsim.cli.main`),
in a fresh working directory holding ``experiments/`` and the inputs the commands name
(pictures, a finished and an interrupted quickstart run), so a ``compare`` finds the
``sweep`` written above it. Budgets are small: a run, a species or a sweep gets
``ga.generations=2``, ``ga.population=8`` (and a polish of 16 evaluations where the
config has one) and no end-of-run meshes, renders or plot; a sweep ``--repeats 1``;
``fit-image`` ``--budget 0.01 --restarts 1``; screenshots and animations 160 px.

A command that cannot run as written is listed below with the reason: :data:`INSTEAD`
(what runs in its place: placeholders, interactive windows), :data:`PARSE_ONLY` (needs
what a test has not: a Dask scheduler) and :data:`EXIT_CODES` (shown failing on
purpose). A mention of a command with options only (``growsim compare --garden``) is
checked to name options the command has. A new command with a placeholder fails here
until it is listed.
"""

from __future__ import annotations

import argparse
import contextlib
import glob
import re
import shlex
import shutil
import tomllib
from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT
from PIL import Image

from growsim.cli import build_parser, main

#: where commands are shown to users
SOURCES = [
    ROOT / "README.md",
    # docs/figures.md: the command that measured each figure (its benchmark runs it)
    *sorted(p for p in (ROOT / "docs").rglob("*.md") if p.name != "figures.md"),
    *sorted((ROOT / "experiments").glob("*.toml")),
]

#: commands that cannot run as written: reason and the command that runs instead
INSTEAD = {
    "growsim grow MODEL --help": ("MODEL is a placeholder", "growsim grow fish --help"),
    "growsim show runs/quickstart-...": (
        "an interactive window: rendered off-screen instead",
        "growsim show runs/quickstart-20261122-054552 --screenshot show.png",
    ),
    "growsim show runs/quickstart-... --screenshot tree.png --view side": (
        "runs/quickstart-... is a placeholder for a run's directory",
        "growsim show runs/quickstart-20261122-054552 --screenshot tree.png --view side",
    ),
    "growsim show runs/quickstart-... --color light": (
        "an interactive window: rendered off-screen instead",
        "growsim show runs/quickstart-20261122-054552 --color light --screenshot lit.png",
    ),
    "growsim run --resume runs/quickstart-20261122-054552": (
        "resumes an interrupted run: one is made for it",
        "growsim run --resume runs/interrupted",
    ),
    "growsim show DIR": (
        "an interactive window on DIR, a placeholder: a fish run rendered off-screen instead",
        "growsim show runs/fish --screenshot show.png",
    ),
    "growsim run experiments/ifs_fern_fit.toml --seed N": (
        "N is a placeholder",
        "growsim run experiments/ifs_fern_fit.toml --seed 1",
    ),
    "growsim fit-image front.png [side.png] --out DIR": (
        "[side.png] is optional, DIR a placeholder",
        "growsim fit-image front.png side.png --out runs/fit",
    ),
    "growsim fit-image picture.png --model ifs2d --out DIR": (
        "DIR is a placeholder",
        "growsim fit-image picture.png --model ifs2d --out runs/fit-ifs2d",
    ),
}

#: commands checked by the parser only, and why they cannot run in a test
PARSE_ONLY = {
    "growsim run experiments/quickstart.toml --scheduler tcp://SCHEDULER_HOST:8786": (
        "needs a Dask scheduler you started"
    ),
    "growsim sweep experiments/quickstart.toml --vary env.light=1.0,0.5 --repeats 5 "
    "--scheduler tcp://SCHEDULER_HOST:8786": "needs a Dask scheduler you started",
}

#: commands shown failing on purpose, and their exit code
EXIT_CODES = {
    "growsim run experiments/quickstart.toml --set ga.populaton=50": 2,
    # shown for an interrupted fit; the page's fit before it finished
    "growsim fit-image --resume runs/mytree": 2,
}

#: sources whose commands take long (fits, Dask, process pools): marked slow
SLOW = {
    "README.md",
    "docs/cluster.md",
    "docs/models/fitting.md",
    "docs/models/ifs3d.md",
    "docs/performance.md",
    "docs/reproduction.md",
    "experiments/hormone_2d_paper_ga.toml",
    "experiments/hormone_3d_paper_ga.toml",
}

#: the small budget every run, sweep and species command gets (a mixture: a population of
#: its neighbours + 1)
POPULATION = 8
BUDGET = ["--set", "ga.generations=2", "--set", f"ga.population={POPULATION}"]
#: a run's end-of-run pictures and meshes (tested elsewhere) left out, for time
NO_ARTEFACTS = [
    "--set",
    "output.mesh=[]",
    "--set",
    "output.screenshots=[]",
    "--set",
    "output.plot=false",
]
PLACEHOLDER = re.compile(r"\.\.\.|\[[A-Za-z][^\]]*\]|(?<![\w.])[A-Z][A-Z_]{1,}(?![\w])")


def _strip_comment(cmd: str) -> str:
    """The command without its trailing ``# comment`` (a ``#`` outside quotes)."""
    quote = None
    for i, ch in enumerate(cmd):
        if quote:
            quote = None if ch == quote else quote
        elif ch in "'\"":
            quote = ch
        elif ch == "#" and (i == 0 or cmd[i - 1].isspace()):
            return cmd[:i].rstrip()
    return cmd.strip()


def _markdown_commands(text: str) -> list[str]:
    """The ``growsim`` commands of a Markdown page, in order."""
    out, lines, fence = [], text.splitlines(), False
    i = 0
    while i < len(lines):
        line, stripped = lines[i], lines[i].strip().removeprefix("$ ")
        if line.lstrip().startswith("```"):
            fence = not fence
        elif (fence or line.startswith("    ")) and "growsim " in stripped:
            # the growsim part of a chain: python3 -m venv ... && growsim run ...
            cmd = next(
                (p.strip() for p in stripped.split("&&") if p.strip().startswith("growsim ")), ""
            )
            if not cmd:
                i += 1
                continue
            while cmd.endswith("\\") and i + 1 < len(lines):
                i += 1
                cmd = cmd[:-1].rstrip() + " " + lines[i].strip()
            out.append(cmd)
        elif not fence:
            out += re.findall(r"`(growsim [^`]*)`", line)
        i += 1
    return out


def _toml_commands(text: str) -> list[str]:
    """The ``growsim`` commands in a config's comments, in order."""
    comments = [line.split("#", 1)[1] for line in text.splitlines() if line.startswith("#")]
    out, i = [], 0
    while i < len(comments):
        c = comments[i].strip()
        if c.startswith("growsim "):
            cmd = c
            while i + 1 < len(comments):
                nxt = comments[i + 1].strip()
                if cmd.endswith("\\"):
                    cmd = cmd[:-1].rstrip() + " " + nxt
                elif nxt.startswith("--"):
                    cmd += " " + nxt
                else:
                    break
                i += 1
            out.append(cmd)
        else:
            out += re.findall(r"`(growsim [^`]*)`", c)
        i += 1
    return out


def commands_of(path: Path) -> list[str]:
    """The commands shown in one source, comments stripped, duplicates dropped."""
    text = path.read_text()
    found = _toml_commands(text) if path.suffix == ".toml" else _markdown_commands(text)
    seen: dict[str, None] = {}
    for cmd in found:
        seen.setdefault(_strip_comment(cmd), None)
    return list(seen)


def _subparser(name: str) -> argparse.ArgumentParser:
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    sub.choices[name].fill_now()  # options a subcommand adds when first used
    return sub.choices[name]


def _is_mention(argv: list[str]) -> bool:
    """A command named with options only (no positional argument), e.g. ``growsim compare
    --garden``; its options must exist (asserted here)."""
    if not argv or argv[0].startswith("-"):
        return False
    sub, rest = _subparser(argv[0]), [t for t in argv[1:] if t != "..."]
    i, positional = 0, False
    while i < len(rest):
        tok = rest[i]
        if tok.startswith("-") and not tok[1:2].isdigit():
            opt = tok.split("=", 1)[0]
            action = sub._option_string_actions.get(opt)
            assert action is not None, f"growsim {argv[0]} has no option {opt}"
            n = 0 if action.nargs == 0 else 1 if action.nargs is None else action.nargs
            if n in ("+", "*"):
                while i + 1 < len(rest) and not rest[i + 1].startswith("-"):
                    i += 1
            elif "=" not in tok:
                i += n
        else:
            positional = True
        i += 1
    return not positional or "..." in argv


def _with_budget(argv: list[str], cwd: Path) -> list[str]:
    """The command at a small budget (options later on the line win)."""
    sub = argv[0]
    if "--help" in argv or "-h" in argv:
        return argv
    if sub in ("run", "species", "sweep") and "--resume" not in argv:
        extra = [*BUDGET, *NO_ARTEFACTS]
        config = next((a for a in argv[1:] if a.endswith(".toml")), None)
        cfg = tomllib.loads((cwd / config).read_text()) if config else {}
        if "polish" in cfg.get("ga", {}):
            extra += ["--set", "ga.polish.evaluations=16"]
        neighbours = cfg.get("environment", {}).get("stand", {}).get("neighbours", 0)
        if neighbours >= POPULATION:  # a mixture draws its neighbours from the population
            extra += ["--set", f"ga.population={neighbours + 1}"]
        if sub == "sweep":
            extra += ["--repeats", "1"]
        return argv + extra
    if sub == "fit-image":
        return [*argv, "--budget", "0.01", "--restarts", "1"]
    if sub in ("grow", "show") and ("--screenshot" in argv or "--gif" in argv):
        return [*argv, "--size", "160", "160"]
    return argv


def _expand(argv: list[str], cwd: Path) -> list[str]:
    """Shell globs, as a shell expands them in ``cwd``."""
    out = []
    for tok in argv:
        if "*" in tok:
            hits = sorted(str(Path(p)) for p in glob.glob(tok, root_dir=cwd))
            assert hits, f"{tok}: matches nothing"
            out += hits
        else:
            out.append(tok)
    return out


def _main(argv: list[str]) -> int:
    try:
        return main(argv)
    except SystemExit as exc:  # --help, --version and argparse errors
        return int(exc.code or 0)


#: commands that only write (not compare or show, which read what the source made before):
#: one shown in several sources runs once; later sources get a copy of what it wrote
PRODUCERS = {"run", "sweep", "species", "grow", "fit-image"}
_DONE: dict[tuple[str, ...], tuple[int, Path, list[str]]] = {}


def _files(root: Path) -> dict[str, tuple[int, int]]:
    out = {}
    for path in root.rglob("*"):
        rel = path.relative_to(root)
        if rel.parts[0] != "experiments" and path.is_file():
            st = path.stat()
            out[rel.as_posix()] = (st.st_mtime_ns, st.st_size)
    return out


def _run_once(argv: list[str], cwd: Path) -> int:
    """``growsim ARGV`` in ``cwd``; a producer run before (in another source's fresh
    working directory: the same inputs) is not run again, its files are copied."""
    key = tuple(argv)
    if argv[0] in PRODUCERS and key in _DONE:
        rc, where, written = _DONE[key]
        for rel in written:
            (cwd / rel).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(where / rel, cwd / rel)
        return rc
    before = _files(cwd)
    rc = _main(argv)
    if argv[0] in PRODUCERS:
        after = _files(cwd)
        _DONE[key] = (rc, cwd, [f for f, stat in after.items() if before.get(f) != stat])
    return rc


# -- the inputs the commands name -------------------------------------------------------


def _pictures(d: Path) -> None:
    """The Table 1 tree drawn (front.png, side.png), as photos (front.jpg, side.jpg,
    tree.jpg, photo.png), two trees side by side (two_trees.jpg) and the fern's attractor
    (picture.png)."""
    from growsim.models import ifs3d
    from growsim.objectives.silhouette import plant_views

    views = plant_views(ifs3d.develop(ifs3d.PRESETS["table1"]), 64)
    for v, label in zip(views, ("front", "side")):
        grey = np.pad(np.where(np.kron(v, np.ones((4, 4))) > 0, 20, 240), 30, constant_values=240)
        Image.fromarray(grey.astype(np.uint8)).save(d / f"{label}.png")
        tree = grey < 128
        photo = np.empty((*grey.shape, 3))
        photo[...] = np.linspace(0, 1, grey.shape[0])[:, None, None] * [60, 50, 0] + [120, 170, 235]
        photo[tree] = (70, 50, 30)
        photo[np.nonzero(tree.any(axis=1))[0].max() + 1 :] = (90, 110, 50)
        Image.fromarray(photo.astype(np.uint8)).save(d / f"{label}.jpg", quality=92)
    shutil.copy(d / "front.jpg", d / "tree.jpg")
    # two trees side by side (a composite of tests/data/composites): the hints' commands
    shutil.copy(ROOT / "tests" / "data" / "composites" / "c21_gradient_slope_second_tree_bare.jpg",
                d / "two_trees.jpg")  # fmt: skip
    Image.open(d / "front.jpg").save(d / "photo.png")
    fern = f"grow ifs2d --preset fern --screenshot {d / 'picture.png'} --size 256 256"
    assert _main(fern.split()) == 0


@pytest.fixture(scope="module")
def inputs(tmp_path_factory):
    """Pictures, two quickstart runs (finished; interrupted after one generation) and a
    fish run."""
    from growsim.experiment import run

    d = tmp_path_factory.mktemp("doc-inputs")
    _pictures(d)
    quick = ROOT / "experiments" / "quickstart.toml"
    run(quick, d / "runs" / "quickstart-20261122-054552", overrides=BUDGET[1::2], progress=False)

    def stop(ga, row):
        if row["generation"] >= 1:
            raise KeyboardInterrupt

    with contextlib.suppress(KeyboardInterrupt):
        run(
            quick, d / "runs" / "interrupted", overrides=BUDGET[1::2], progress=False, callback=stop
        )
    assert not (d / "runs" / "interrupted" / "summary.json").exists()
    run(
        ROOT / "experiments" / "fish_tank.toml",
        d / "runs" / "fish",
        overrides=BUDGET[1::2],
        progress=False,
    )
    return d


@pytest.fixture
def workspace(inputs, tmp_path, monkeypatch):
    """A working directory as a user's checkout: experiments/, docs/images/, the inputs."""
    shutil.copytree(inputs, tmp_path, dirs_exist_ok=True)
    (tmp_path / "experiments").symlink_to(ROOT / "experiments")
    (tmp_path / "docs" / "images").mkdir(parents=True)
    (tmp_path / "runs" / "photos").mkdir()
    shutil.copy(tmp_path / "tree.jpg", tmp_path / "runs" / "photos" / "columnar_bare_overcast.jpg")
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("MPLBACKEND", "Agg")
    return tmp_path


def _name(path: Path) -> str:
    return path.relative_to(ROOT).as_posix()


@pytest.mark.parametrize(
    "source",
    [
        pytest.param(p, id=_name(p), marks=[pytest.mark.slow] if _name(p) in SLOW else [])
        for p in SOURCES
    ],
)
def test_every_shown_command_runs(source, workspace):
    for cmd in commands_of(source):
        where = f"{_name(source)}: {cmd}"
        if cmd in PARSE_ONLY:
            try:
                build_parser().parse_args(shlex.split(cmd)[1:])
            except SystemExit as exc:  # pragma: no cover - the failure's message
                pytest.fail(f"{where}: does not parse ({exc})")
            continue
        run_cmd = INSTEAD[cmd][1] if cmd in INSTEAD else cmd
        argv = shlex.split(run_cmd)[1:]
        helps = "--help" in argv or "-h" in argv
        if cmd not in INSTEAD and not helps and _is_mention(argv):
            continue  # a command named with its options: checked by _is_mention
        assert cmd in INSTEAD or not PLACEHOLDER.search(cmd.replace("tcp://", "")), (
            f"{where}: has a placeholder; list it in INSTEAD or PARSE_ONLY"
        )
        rc = _run_once(_with_budget(_expand(argv, workspace), workspace), workspace)
        assert rc == EXIT_CODES.get(cmd, 0), f"{where}: exit code {rc}"


def test_commands_are_found():
    """The extraction sees the commands (a broken pattern would make the test above vacuous)."""
    readme = commands_of(ROOT / "README.md")
    assert "growsim run experiments/quickstart.toml" in readme
    assert "growsim compare runs/h2d --garden" in readme
    fish = commands_of(ROOT / "experiments" / "fish_tank.toml")
    assert any(c.endswith("--repeats 20") for c in fish), fish
    assert sum(len(commands_of(p)) for p in SOURCES) > 60


def test_listed_commands_are_still_shown():
    """Every exception listed here is still a command of some source (no stale entries)."""
    shown = {c for p in SOURCES for c in commands_of(p)}
    for cmd in (*INSTEAD, *PARSE_ONLY, *EXIT_CODES):
        assert cmd in shown, f"{cmd!r} is listed in the test but shown nowhere"


def test_placeholders_are_caught():
    assert PLACEHOLDER.search("growsim compare DIR --garden")
    assert PLACEHOLDER.search("growsim show runs/quickstart-...")
    assert PLACEHOLDER.search("growsim fit-image front.png [side.png] --out DIR")
    assert not PLACEHOLDER.search("growsim sweep x.toml --vary 'env.light.direction=[[0, -1, 0]]'")
    assert _is_mention(["compare", "--garden"]) and not _is_mention(["compare", "runs/x"])


def test_docs_cite_nothing_outside_the_repository():
    """Links, images and the repository paths a page names exist in the repository; the
    source papers are named by title, not by a file or a "seed NNN" users do not have
    ("seed" means a random seed), in the pages and in the shipped configs' comments."""
    for config in sorted((ROOT / "experiments").glob("*.toml")):
        bad = re.search(r"seed 00\d|[Tt]he seed's", config.read_text())
        assert not bad, f"{_name(config)}: {bad.group(0)!r}: name the paper by title"
    pages = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]
    for page in pages:
        text, name = page.read_text(), _name(page)
        for target in re.findall(r"\]\(([^)#\s]+)", text):
            if not target.startswith(("http://", "https://")):
                path = (page.parent / target).resolve()
                assert path.exists() and path.is_relative_to(ROOT), f"{name}: link {target}"
        paths = r"`((?:docs|benchmarks|experiments|examples|growsim|tests)/[\w./-]*\.\w+)`"
        for path in re.findall(paths, text):
            if "/my" not in path and "_my" not in path:  # docs/extending.md: a new model
                assert (ROOT / path).exists(), f"{name}: {path} is not in the repository"
        assert not re.search(r"shared/|seeds/|research/", text), f"{name}: a file outside"
        bad = re.search(r"seed 00\d|[Tt]he seed's|seed document", text)
        assert not bad, f"{name}: {bad.group(0)!r}: name the paper by title"


def test_every_config_is_on_the_models_page():
    """docs/models/index.md lists every shipped config (with its run time) and every model."""
    page = (ROOT / "docs" / "models" / "index.md").read_text()
    for config in sorted((ROOT / "experiments").glob("*.toml")):
        row = next((r for r in page.splitlines() if f"`{config.name}`" in r), None)
        assert row and re.search(r"\d+(\.\d+)? (s|min)\b", row), f"{config.name}: no row or time"
    from growsim.models import MODELS

    for name in MODELS:
        assert f"## {name}:" in page, f"model {name} is not on docs/models/index.md"
