"""Wall-clock time of the commands the user pages print (README, ``docs/models/index.md``,
``docs/quickstart.md``): each run in a fresh temporary directory, as a user types it.

    python benchmarks/command_times.py [--repeats 3] [--only NAME ...] [--json PATH]

For every command: each run's wall seconds (interpreter start, imports, a warm numba
cache, renders and files included), the 1-minute load average before and after each run,
and the command line. ``quickstart_cold`` runs the quickstart once with an empty
``NUMBA_CACHE_DIR`` (what the first run after installing costs). With ``--json PATH`` the
JSON also goes to ``PATH`` (``benchmarks/results/command_times.json``, which
``benchmarks/figures.py`` reads into ``docs/figures.md``); with ``--only`` the commands
it measures replace theirs in that file, the others keep their figures and dates. Run it
alone on the machine: a figure measured under load is an upper bound.
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import subprocess
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EXP = ROOT / "experiments"

#: name -> (the command as the pages print it, argv after ``growsim``, repeats cap)
COMMANDS: dict[str, tuple[str, list[str], int]] = {
    "help": ("growsim --help", ["--help"], 5),
    "quickstart": (
        "growsim run experiments/quickstart.toml",
        ["run", str(EXP / "quickstart.toml"), "--out", "run"],
        3,
    ),
    "grow_hormone": (
        "growsim grow hormone --preset demo_3d --screenshot hormone.png --json",
        ["grow", "hormone", "--preset", "demo_3d", "--screenshot", "hormone.png", "--json"],
        3,
    ),
    "grow_honda": (
        "growsim grow honda --preset zelkova --screenshot tree.png --json",
        ["grow", "honda", "--preset", "zelkova", "--screenshot", "tree.png", "--json"],
        3,
    ),
    "grow_ifs3d": (
        "growsim grow ifs3d --preset table1 --screenshot tree.png",
        ["grow", "ifs3d", "--preset", "table1", "--screenshot", "tree.png"],
        3,
    ),
    "grow_ifs2d": (
        "growsim grow ifs2d --preset fern --screenshot fern.png",
        ["grow", "ifs2d", "--preset", "fern", "--screenshot", "fern.png"],
        3,
    ),
    "grow_fish": (
        "growsim grow fish --preset calm --screenshot fish.png --json",
        ["grow", "fish", "--preset", "calm", "--screenshot", "fish.png", "--json"],
        3,
    ),
    "run_honda_silhouette": (
        "growsim run experiments/honda_silhouette.toml",
        ["run", str(EXP / "honda_silhouette.toml"), "--out", "run"],
        3,
    ),
    "run_ifs_tree_fit": (
        "growsim run experiments/ifs_tree_fit.toml",
        ["run", str(EXP / "ifs_tree_fit.toml"), "--out", "run"],
        3,
    ),
    "run_ifs_tree_best": (
        "growsim run experiments/ifs_tree_best.toml",
        ["run", str(EXP / "ifs_tree_best.toml"), "--out", "run"],
        3,
    ),
    "run_ifs_species": (
        "growsim run experiments/ifs_species.toml",
        ["run", str(EXP / "ifs_species.toml"), "--out", "run"],
        3,
    ),
    "species_ifs": (
        "growsim species experiments/ifs_species.toml --out runs/tree_one",
        ["species", str(EXP / "ifs_species.toml"), "--out", "run"],
        3,
    ),
    "run_fish_tank": (
        "growsim run experiments/fish_tank.toml",
        ["run", str(EXP / "fish_tank.toml"), "--out", "run"],
        3,
    ),
    "run_hormone_2d": (
        "growsim run experiments/hormone_2d.toml",
        ["run", str(EXP / "hormone_2d.toml"), "--out", "run"],
        1,
    ),
    "run_hormone_3d": (
        "growsim run experiments/hormone_3d.toml --workers 2",
        ["run", str(EXP / "hormone_3d.toml"), "--out", "run", "--workers", "2"],
        1,
    ),
}


def _load() -> float:
    return round(os.getloadavg()[0], 2)


def time_command(argv: list[str], env: dict | None = None) -> dict:
    """One run of ``growsim ARGV`` in a fresh directory: wall seconds and the load."""
    growsim = str(Path(os.environ.get("VIRTUAL_ENV", ROOT / ".venv")) / "bin" / "growsim")
    with tempfile.TemporaryDirectory() as tmp:
        before = _load()
        t0 = time.perf_counter()
        subprocess.run(
            [growsim, *argv], cwd=tmp, env=env, check=True, capture_output=True, text=True
        )
        seconds = time.perf_counter() - t0
    return {"seconds": round(seconds, 3), "load_before": before, "load_after": _load()}


def summarise(runs: list[dict]) -> dict:
    secs = [r["seconds"] for r in runs]
    loads = [r["load_before"] for r in runs] + [r["load_after"] for r in runs]
    return {
        "runs": runs,
        "min_seconds": min(secs),
        "max_seconds": max(secs),
        "load": [min(loads), max(loads)],
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeats", type=int, default=3, help="runs of each command (at most)")
    ap.add_argument("--only", nargs="*", default=None, help="command names (and quickstart_cold)")
    ap.add_argument("--json", default=None, metavar="PATH", help="also write the JSON here")
    args = ap.parse_args()
    names = args.only or [*COMMANDS, "quickstart_cold"]
    out: dict = {
        "date": datetime.date.today().isoformat(),
        "machine": {"cpus": os.cpu_count(), "python": platform.python_version()},
        "command": "python benchmarks/command_times.py "
        + " ".join([f"--repeats {args.repeats}"] + (["--only", *args.only] if args.only else [])),
        "commands": {},
    }
    for name in names:
        if name == "quickstart_cold":
            with tempfile.TemporaryDirectory() as cache:
                env = {**os.environ, "NUMBA_CACHE_DIR": cache}
                runs = [time_command(COMMANDS["quickstart"][1], env=env)]
            line = "growsim run experiments/quickstart.toml (empty NUMBA_CACHE_DIR)"
        else:
            line, argv, cap = COMMANDS[name]
            if cap > 1:
                time_command(argv)  # warm the numba cache and the file cache first
            runs = [time_command(argv) for _ in range(min(args.repeats, cap))]
        entry = {"command": line, "date": out["date"], **summarise(runs)}
        out["commands"][name] = entry
        print(name, entry["min_seconds"], entry["max_seconds"], entry["load"], flush=True)
    if args.json and args.only and Path(args.json).is_file():
        # --only re-measures some commands: the others keep their figures (and dates)
        kept = json.loads(Path(args.json).read_text())
        kept["commands"].update(out["commands"])
        out = {**kept, "date": out["date"]}
    text = json.dumps(out, indent=1)
    print(text)
    if args.json:
        Path(args.json).write_text(text + "\n")


if __name__ == "__main__":
    main()
