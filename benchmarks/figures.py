"""``docs/figures.md``: every measured figure the user pages quote, in one table, read
from the result files in ``benchmarks/results/``.

    python benchmarks/figures.py            # (re)writes docs/figures.md
    python benchmarks/figures.py --pages    # and the figures the pages quote from it
    python benchmarks/figures.py --check    # exit 1 if docs/figures.md is not up to date

Each row of :data:`ROWS` is one quantity: its id (the anchor pages link to), what it is,
its value and unit as the pages write them, the machine and load it was measured on, the
result file it is read from and the command that made that file. A page quotes a figure
as the table gives it and cites the row after it, e.g.
``8.6 s ([figures](figures.md#quickstart-run))``; ``tests/test_figures.py`` checks every
citation against the table and the table against this script (and so the result files).

Result files: the JSON a benchmark wrote (``ga_vs_peers.json``, ``command_times.json``,
``*.jsonl``, the reproduction pins), or, where the command's JSON was not kept,
``benchmarks/results/timings/*.json``: the figures copied from its printed output, each
entry with its command, date, machine and where it was copied from (``origin``). A new
measurement replaces its file; the old figure goes to ``benchmarks/log/``.
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results"
PAGE = ROOT / "docs" / "figures.md"
VM = "2-core VM"
#: units the pages name before the figure ("NCC 0.977-0.998"), not after it
UNWRITTEN = {"NCC"}


def load(source: str) -> Any:
    """A result file (``name.json``, ``name.jsonl``: a list) or, for
    ``file.json#key``, that file's ``measurements[key]``."""
    name, _, key = source.partition("#")
    path = RESULTS / name
    if path.suffix == ".jsonl":
        data = [json.loads(line) for line in path.read_text().splitlines() if line.strip()]
    else:
        data = json.loads(path.read_text())
    return data["measurements"][key] if key else data


def num(x: float, digits: int = 1) -> str:
    """``x`` with ``digits`` decimals, thousands separated (``12,600``, ``0.77``)."""
    return f"{x:,.{digits}f}"


def span(lo: float, hi: float, digits: int = 1) -> str:
    """``lo-hi`` (or one figure when they round the same)."""
    a, b = num(lo, digits), num(hi, digits)
    return a if a == b else f"{a}-{b}"


def loads(lo: float, hi: float) -> str:
    return f"load {span(lo, hi)}"


@dataclass(frozen=True)
class Row:
    """One quantity of the table."""

    id: str
    what: str
    unit: str
    source: str
    value: Callable[[Any], str]
    #: the machine and load; None: the measurement entry's ``machine`` and ``date``
    machine: Callable[[Any], str] | str | None = None
    #: the command that measured it (said here and in the result file, not in the table);
    #: None: the measurement entry's ``command``
    command: Callable[[Any], str] | str | None = None

    def cells(self) -> dict[str, str]:
        data = load(self.source)
        machine = self.machine
        if machine is None:
            machine = f"{data['machine']} ({data['date']})"
        elif callable(machine):
            machine = machine(data)
        command = self.command
        if command is None:
            command = data["command"]
        elif callable(command):
            command = command(data)
        return {"value": self.value(data), "machine": machine, "command": command}


def written(value: str, unit: str) -> str:
    """The figure as a page writes it: ``8.6 s``, ``10.7x``."""
    if unit in UNWRITTEN:
        return value
    return f"{value}{'' if unit in ('x', '%') else ' '}{unit}"


# -- command_times.json: the commands the pages print, re-measured together -------------


def _cmd(name: str, digits: int = 1) -> Row:
    def value(d):  # the fastest of the runs: the one least slowed by other work
        return num(d["commands"][name]["min_seconds"], digits)

    def machine(d):
        c = d["commands"][name]
        return f"{VM}, {loads(*c['load'])} ({c['date']})"

    return value, machine


def command_row(id: str, name: str, what: str, digits: int = 1) -> Row:
    value, machine = _cmd(name, digits)
    return Row(
        id,
        what,
        "s",
        "command_times.json",
        value,
        machine,
        lambda d: f"`{d['commands'][name]['command']}` (`{d['command']}`)",
    )


def _jsonl_summary(rows: list[dict], **match) -> dict:
    return next(r for r in rows if all(r.get(k) == v for k, v in match.items()))


def _photo(split: str, mean: bool = False):
    def value(rows):
        if mean:
            return num(_jsonl_summary(rows, kind="summary")["mean_seconds"], 0)
        fits = [r for r in rows if r["kind"] == "fit"]
        return span(min(r["seconds"] for r in fits), max(r["seconds"] for r in fits), 0)

    def machine(rows):
        ls = [r["load"] for r in rows if r["kind"] == "fit"]
        return f"{VM}, {loads(min(ls), max(ls))}, the benchmark alone (2026-11-28)"

    return value, machine


def _ga(problem: str, what: str):
    def value(d):
        p = d["problems"][problem]
        if what == "ms":
            return num(p["growsim"]["ms_per_generation"], 2)
        return num(p["speedup_vs_fastest_peer"], 1)

    return value


def _ga_machine(d) -> str:
    m = d["machine"]
    return f"{VM}, {loads(m['load_avg_1min'], m['load_avg_1min_end'])} (2026-11-24)"


def _cluster(key: str):
    def value(runs):
        xs = [r[key] for r in runs]
        return f"{min(xs):.2f}-{max(xs):.2f}"

    return value


def _cluster_machine(runs) -> str:
    ls = [r["load_average"][0] for r in runs]
    return f"{VM}, {loads(min(ls), max(ls))}, nothing else running (2026-11-24)"


def _drawing_value(rows) -> str:
    fits = [r for r in rows if r["kind"] == "drawing"]
    return span(min(r["seconds"] for r in fits), max(r["seconds"] for r in fits))


def _drawing_machine(rows) -> str:
    ls = [r["load"] for r in rows if r["kind"] == "drawing"]
    return f"{VM}, {loads(min(ls), max(ls))}, the benchmark alone (2026-11-28)"


def _ifs2d_machine(d) -> str:
    return f"{VM}, load {d['load_average_start']:.1f} (2026-11-28)"


def _pin_machine(d) -> str:
    return f"{d['machine']} ({d['date']})"


ROWS: list[Row] = [
    # the commands the README, the quickstart and the models' page print
    command_row("cli-help", "help", "`growsim --help`: the parser, no library import", 2),
    command_row(
        "quickstart-run",
        "quickstart",
        "the quickstart run (3,951 evaluations), warm numba cache, files and renders included",
    ),
    command_row(
        "quickstart-run-cold",
        "quickstart_cold",
        "the same, the first run after installing (an empty numba cache: the kernels compile)",
        0,
    ),
    command_row("grow-hormone", "grow_hormone", "grow one hormone plant (the 3D demo genome)"),
    command_row("grow-honda", "grow_honda", "grow one Honda tree (`zelkova`)"),
    command_row("grow-ifs3d", "grow_ifs3d", "grow the 3D IFS tree of Table 1"),
    command_row("grow-ifs2d", "grow_ifs2d", "grow the 2D IFS fern (100,000 points)"),
    command_row("grow-fish", "grow_fish", "swim the calm fish 20,000 frames"),
    command_row("run-hormone-2d", "run_hormone_2d", "one run of the 2D hormone experiment"),
    command_row(
        "run-hormone-3d", "run_hormone_3d", "one run of the 3D hormone experiment, 2 workers"
    ),
    command_row(
        "run-honda-silhouette",
        "run_honda_silhouette",
        "Honda parameters fitted to the cherry's silhouettes, one run",
    ),
    command_row(
        "run-ifs-tree-fit",
        "run_ifs_tree_fit",
        "the Table 1 fit with the paper's GA, 50,000 evaluations",
    ),
    command_row(
        "run-ifs-tree-best",
        "run_ifs_tree_best",
        "the Table 1 fit with the best setup (GA, then CMA-ES), 50,000 evaluations",
    ),
    command_row("run-ifs-species", "run_ifs_species", "one 2D IFS species run (10 x 8)"),
    command_row(
        "species-ifs",
        "species_ifs",
        "the same through `growsim species` (the best of every generation, its pictures)",
    ),
    command_row(
        "run-fish-tank", "run_fish_tank", "one fish run: the path tuned until no collision"
    ),
    # fitting pictures
    Row(
        "fit-drawing",
        "`growsim fit-image` on a Table 1 drawing, no flags (1.5-3.5x, margins 0-32 px, PNG "
        "or JPEG)",
        "s",
        "drawing_fit.jsonl",
        _drawing_value,
        _drawing_machine,
        "`python benchmarks/drawing_fit.py --rows 0 2 3 9 13`",
    ),
    Row(
        "fit-photo",
        "`growsim fit-image` on a photo, no flags (12 held-out modular-tree photos, 384-768 "
        "px): one fit",
        "s",
        "mtree_fit_held_out.jsonl",
        *_photo("held_out"),
        "`python benchmarks/mtree_fit.py --split held_out`",
    ),
    Row(
        "fit-photo-mean",
        "the same, the mean of the 12 fits",
        "s",
        "mtree_fit_held_out.jsonl",
        *_photo("held_out", mean=True),
        "`python benchmarks/mtree_fit.py --split held_out`",
    ),
    Row(
        "photo-learned-below",
        "a photo ending at the horizon: the learned step (29 photos)",
        "s",
        "learned_below_time.json",
        lambda d: span(d["added_min"], d["added_max"]),
    ),
    Row(
        "photo-trunk-trace",
        "a photo's trunk followed down (56 photos)",
        "s",
        "trunk_trace_time.json",
        lambda d: span(d["inside_min"], d["inside_max"]),
    ),
    Row(
        "fit-photo-discovery",
        "the same on the 12 discovery photos (tuned on)",
        "s",
        "mtree_fit_discovery.jsonl",
        *_photo("discovery"),
        "`python benchmarks/mtree_fit.py --split discovery`",
    ),
    Row(
        "fit-photo-discovery-mean",
        "the same, the mean of the 12 fits",
        "s",
        "mtree_fit_discovery.jsonl",
        *_photo("discovery", mean=True),
        "`python benchmarks/mtree_fit.py --split discovery`",
    ),
    Row(
        "ifs-fit-ncc",
        "best NCC of the Table 1 fit, best setup, 5 seeds (Kuwahara et al.'s GA: 0.661)",
        "NCC",
        "ifs_fit_table1.jsonl",
        lambda rows: span(
            _jsonl_summary(rows, kind="summary", config="experiments/ifs_tree_best.toml")[
                "ncc_min"
            ],
            _jsonl_summary(rows, kind="summary", config="experiments/ifs_tree_best.toml")[
                "ncc_max"
            ],
            3,
        ),
        lambda rows: f"{VM}, load 4.7-5.5 (2026-11-28)",
        "`python benchmarks/ifs_fit.py --config experiments/ifs_tree_best.toml --config "
        "experiments/ifs_tree_fit.toml --seeds 0 1 2 3 4`",
    ),
    # the GA
    Row(
        "ga-onemax",
        "GA, OneMax 1000 bits, population 1000, defaults: a generation",
        "ms",
        "ga_vs_peers.json",
        _ga("onemax", "ms"),
        _ga_machine,
        "`python benchmarks/ga_vs_peers.py --repeats 3`",
    ),
    Row(
        "ga-onemax-vs-peers",
        "the same, how many times faster than the faster peer (DEAP 31.8 ms, pymoo 799 ms)",
        "x",
        "ga_vs_peers.json",
        _ga("onemax", "x"),
        _ga_machine,
        "`python benchmarks/ga_vs_peers.py --repeats 3`",
    ),
    Row(
        "ga-rastrigin",
        "GA, Rastrigin-30D, population 1000, defaults: a generation",
        "ms",
        "ga_vs_peers.json",
        _ga("rastrigin", "ms"),
        _ga_machine,
        "`python benchmarks/ga_vs_peers.py --repeats 3`",
    ),
    Row(
        "ga-rastrigin-vs-peers",
        "the same, how many times faster than the faster peer (DEAP 40.0 ms, pymoo 102 ms)",
        "x",
        "ga_vs_peers.json",
        _ga("rastrigin", "x"),
        _ga_machine,
        "`python benchmarks/ga_vs_peers.py --repeats 3`",
    ),
    Row(
        "ga-small-populations",
        "GA, Sphere-10D (a microsecond fitness) at population 20 / 50 / 100: a generation",
        "ms",
        "ga_vs_peers.json",
        lambda d: " / ".join(
            num(d["overhead_sphere10d_ms_per_generation"][f"population {n}"]["growsim"], 2)
            for n in (20, 50, 100)
        ),
        lambda d: (
            f"{VM}, "
            f"{loads(*d['overhead_sphere10d_ms_per_generation']['load_avg_1min'])} (2026-11-24)"
        ),
        "`python benchmarks/ga_vs_peers.py --overhead --generations 200 --repeats 5`",
    ),
    # Honda
    Row(
        "honda-mesh",
        "Honda: grow one tree and mesh it, the eight presets and zelkova at 13 generations",
        "M vertices/s",
        "reproduction/endo_speed.json",
        lambda d: span(
            min(d["figures"]["vertices_per_ms"].values()) / 1000,
            max(d["figures"]["vertices_per_ms"].values()) / 1000,
        ),
        _pin_machine,
    ),
    Row(
        "honda-arrays",
        "the same as raw arrays (`mesh_arrays`)",
        "M vertices/s",
        "timings/honda.json#arrays",
        lambda d: span(
            min(d["figures"]["M_vertices_per_s_arrays"].values()),
            max(d["figures"]["M_vertices_per_s_arrays"].values()),
        ),
    ),
    # the experiment layer
    Row(
        "quickstart-evaluation",
        "one quickstart evaluation (grow a Honda tree, its 64 px shadow map, the wood)",
        "ms",
        "timings/experiment.json#evaluation",
        lambda d: num(d["figures"]["quickstart_eval_ms"], 2),
    ),
    Row(
        "load-config",
        "reading a config (`load_config`, the quickstart's)",
        "ms",
        "timings/experiment.json#glue",
        lambda d: num(d["figures"]["load_config_ms"], 2),
    ),
    Row(
        "fitness-glue",
        "the fitness glue over a population fast path, an individual",
        "µs",
        "timings/experiment.json#glue",
        lambda d: num(d["figures"]["glue_overhead_us_per_individual"], 1),
    ),
    Row(
        "startup",
        "from `run()` to the first generation (validate, plan, objectives, GA), quickstart "
        "to `ifs_tree_fit`",
        "ms",
        "timings/experiment.json#startup",
        lambda d: span(*d["figures"]["to_first_generation_ms"].values(), 0),
    ),
    Row(
        "startup-process",
        "the same with the interpreter and the imports",
        "s",
        "timings/experiment.json#startup",
        lambda d: span(*d["figures"]["with_interpreter_s"], 2),
    ),
    # the environment's passes
    Row(
        "gravity-pass",
        "gravity pass, 1,000 plants x 300 segments, one core, the kernel",
        "M segments/s",
        "timings/environment.json#gravity",
        lambda d: num(d["figures"]["kernel_M_segments_per_s"], 0),
    ),
    Row(
        "gravity-public",
        "the same through the public functions",
        "M segments/s",
        "timings/environment.json#gravity",
        lambda d: num(d["figures"]["public_M_segments_per_s"], 1),
    ),
    Row(
        "water-pass",
        "water pass, the same forest, one core, the kernel",
        "M segments/s",
        "timings/environment.json#water",
        lambda d: num(d["figures"]["kernel_M_segments_per_s"], 0),
    ),
    Row(
        "water-public",
        "the same through the public functions",
        "M segments/s",
        "timings/environment.json#water",
        lambda d: num(d["figures"]["public_M_segments_per_s"], 0),
    ),
    Row(
        "light-hard",
        "shadow-map light, the same forest, 64 px, one core, the whole public pass, hard shadows",
        "M segments/s",
        "timings/environment.json#light",
        lambda d: span(*d["figures"]["hard_M_segments_per_s"], 2),
    ),
    Row(
        "light-soft",
        "the same, soft shadows",
        "M segments/s",
        "timings/environment.json#light",
        lambda d: span(*d["figures"]["soft_M_segments_per_s"], 2),
    ),
    Row(
        "light-resolutions",
        "the same, numba, hard shadows, at 128 / 256 px",
        "M segments/s",
        "timings/environment.json#light_resolutions",
        lambda d: " / ".join(
            num(v, 1) for v in d["figures"]["numba_hard_M_segments_per_s"].values()
        ),
    ),
    Row(
        "light-moderngl",
        "the moderngl backend (llvmpipe) at 64 / 128 / 256 px",
        "M segments/s",
        "timings/environment.json#light_resolutions",
        lambda d: " / ".join(f"{v:g}" for v in d["figures"]["moderngl_M_segments_per_s"].values()),
    ),
    Row(
        "light-moderngl-vs-numba",
        "moderngl's time over numba's, 1 to 100 plants a call at 256-1024 px",
        "x",
        "timings/environment.json#crossover",
        lambda d: span(*d["figures"]["moderngl_over_numba_time"]),
    ),
    # the hormone model
    Row(
        "hormone-steps-2d",
        "hormone model, one core, module-steps a second: the 2D demo genome",
        "M/s",
        "timings/hormone.json#module_steps",
        lambda d: num(d["figures"]["module_steps_per_s"]["demo_2d"] / 1e6, 2),
    ),
    Row(
        "hormone-steps-3d",
        "the same, the 3D demo genome (127 modules)",
        "M/s",
        "timings/hormone.json#module_steps",
        lambda d: num(d["figures"]["module_steps_per_s"]["demo_3d"] / 1e6, 2),
    ),
    Row(
        "hormone-steps-3d-module-walls",
        'the same with `environment.light.walls = "module"`',
        "M/s",
        "timings/hormone.json#module_steps",
        lambda d: num(d["figures"]["module_steps_per_s"]["demo_3d_module_walls"] / 1e6, 2),
    ),
    Row(
        "hormone-step-3d",
        "hormone model, one 3D module-step of a 188-module plant (the grown demo), CPU time",
        "µs",
        "timings/hormone.json#breakdown",
        lambda d: num(d["figures"]["us_per_module_step"], 2),
    ),
    Row(
        "hormone-step-3d-light",
        "of which the light (exact: every wall point)",
        "µs",
        "timings/hormone.json#breakdown",
        lambda d: num(d["figures"]["light_us"], 2),
    ),
    Row(
        "hormone-step-3d-light-module-walls",
        'the light with `environment.light.walls = "module"` (one query per module)',
        "µs",
        "timings/hormone.json#breakdown",
        lambda d: num(d["figures"]["light_module_walls_us"], 2),
    ),
    Row(
        "hormone-generation",
        "a generation of 10,000 grown 3D hormone plants (40 steps, 111 modules on average), "
        "a pool of 2",
        "s",
        "timings/hormone.json#generation",
        lambda d: num(d["figures"]["grown_pool_2_s"], 1),
    ),
    Row(
        "hormone-generation-serial",
        "the same, serially",
        "s",
        "timings/hormone.json#generation",
        lambda d: num(d["figures"]["grown_serial_s"], 1),
    ),
    Row(
        "hormone-generation-random",
        "the same, 10,000 random genomes (small plants), a process pool of 2",
        "s",
        "timings/hormone.json#generation",
        lambda d: num(d["figures"]["random_pool_2_s"], 1),
    ),
    Row(
        "hormone-3d-sweep",
        "`hormone_3d.toml`'s sweep: 3 environments x 8 seeds, `--workers 2`",
        "min",
        "timings/sweeps.json#hormone_3d",
        lambda d: span(*d["figures"]["sweep_min"], 0),
    ),
    Row(
        "hormone-3d-sweep-run",
        "one run of that sweep",
        "s",
        "timings/sweeps.json#hormone_3d",
        lambda d: span(*d["figures"]["run_s"], 0),
    ),
    Row(
        "hormone-2d-sweep",
        "`hormone_2d.toml`'s sweep: 3 environments x 8 seeds, `--workers 2`",
        "min",
        "timings/sweeps.json#hormone_2d",
        lambda d: span(*d["figures"]["sweep_min"], 0),
    ),
    Row(
        "hormone-3d-4x",
        "one `hormone_3d.toml` run at 4x the budget (240 x 80), a process pool of 2",
        "s",
        "timings/sweeps.json#hormone_3d_4x",
        lambda d: num(d["figures"]["pool_2_s"], 0),
    ),
    Row(
        "hormone-3d-4x-dask",
        "the same on a Dask `LocalCluster` of 2 workers",
        "s",
        "timings/sweeps.json#hormone_3d_4x",
        lambda d: num(d["figures"]["dask_local_2_s"], 0),
    ),
    Row(
        "paper-ga-3d-sweep",
        "the paper's own GA (10,000 x 10), a 3D sweep of 24 runs, `--workers 2`",
        "min",
        "timings/sweeps.json#paper_ga",
        lambda d: span(*d["figures"]["sweep_3d_min"], 0),
    ),
    Row(
        "paper-ga-2d-sweep",
        "the same in 2D",
        "min",
        "timings/sweeps.json#paper_ga",
        lambda d: span(*d["figures"]["sweep_2d_min"], 1),
    ),
    Row(
        "paper-ga-run",
        "one 3D run of it (95,500 evaluations)",
        "s",
        "timings/sweeps.json#paper_ga",
        lambda d: span(*d["figures"]["run_3d_s"], 0),
    ),
    Row(
        "paper-ga-generation",
        "one generation of its 10,000 (the plants of the first generations stay small)",
        "s",
        "timings/sweeps.json#paper_ga",
        lambda d: span(*d["figures"]["generation_of_10000_s"]),
    ),
    Row(
        "paper-ga-2d-run",
        "one 2D run of it",
        "s",
        "timings/sweeps.json#paper_ga",
        lambda d: span(*d["figures"]["run_2d_s"], 0),
    ),
    Row(
        "stand-density-2d-run",
        "one run of `stand_density_2d.toml`, 2 workers",
        "s",
        "timings/sweeps.json#stand_density_2d",
        lambda d: span(*d["figures"]["run_s"], 0),
    ),
    Row(
        "stand-density-3d-run",
        "one run of `stand_density_3d.toml`, 2 workers",
        "s",
        "timings/sweeps.json#stand_density_3d",
        lambda d: span(*d["figures"]["run_s"], 0),
    ),
    Row(
        "stand-mixture-2d-run",
        "one run of `stand_mixture_2d.toml`, 2 workers: mixture / monoculture",
        "s",
        "timings/sweeps.json#stand_mixture_2d",
        lambda d: (
            f"{num(d['figures']['mixture_run_s'], 0)} / {num(d['figures']['monoculture_run_s'], 0)}"
        ),
    ),
    Row(
        "stand-mixture-3d-run",
        "one run of `stand_mixture_3d.toml`, 2 workers: mixture",
        "s",
        "timings/sweeps.json#stand_mixture_3d",
        lambda d: span(*d["figures"]["mixture_run_s"], 0),
    ),
    Row(
        "stand-mixture-3d-run-monoculture",
        "the same, monoculture",
        "s",
        "timings/sweeps.json#stand_mixture_3d",
        lambda d: span(*d["figures"]["monoculture_run_s"], 0),
    ),
    Row(
        "water-supply-2d-run",
        "one run of `water_supply_2d.toml`, 2 workers",
        "s",
        "timings/sweeps.json#water_supply_2d",
        lambda d: span(*d["figures"]["run_s"], 0),
    ),
    Row(
        "water-supply-2d-sweep",
        "`water_supply_2d.toml`'s sweep (32 runs), `--workers 2`",
        "min",
        "timings/sweeps.json#water_supply_2d",
        lambda d: span(*d["figures"]["sweep_min"], 0),
    ),
    Row(
        "stand-density-2d-sweep",
        "`stand_density_2d.toml`'s sweep (24 runs), `--workers 2`",
        "min",
        "timings/sweeps.json#stand_density_2d",
        lambda d: span(*d["figures"]["sweep_min"], 0),
    ),
    Row(
        "stand-density-3d-sweep",
        "`stand_density_3d.toml`'s sweep (24 runs), `--workers 2`",
        "min",
        "timings/sweeps.json#stand_density_3d",
        lambda d: span(*d["figures"]["sweep_min"], 0),
    ),
    Row(
        "stand-mixture-2d-sweep",
        "`stand_mixture_2d.toml`'s sweep (16 runs), `--workers 2`",
        "min",
        "timings/sweeps.json#stand_mixture_2d",
        lambda d: num(d["figures"]["sweep_min"], 1),
    ),
    Row(
        "stand-mixture-3d-sweep",
        "`stand_mixture_3d.toml`'s sweep (16 runs), `--workers 2`",
        "min",
        "timings/sweeps.json#stand_mixture_3d",
        lambda d: span(*d["figures"]["sweep_min"], 0),
    ),
    Row(
        "stand-periodic",
        "hormone model in a periodic stand, 1 / 2 rings of copies, over alone (CPU time)",
        "x",
        "timings/stand.json#periodic",
        lambda d: f"{num(d['figures']['one_ring_x'], 2)} / {num(d['figures']['two_rings_x'], 2)}",
    ),
    Row(
        "stand-mixture",
        "a mixture of 9 plants of 200 modules at most, 40 steps, 3D",
        "s",
        "timings/stand.json#mixture",
        lambda d: num(d["figures"]["mixture_9_s"], 2),
    ),
    # Dask and the process pool
    Row(
        "pool-speedup",
        "a process pool of 2 over serial, the hormone 3D workload (6,000 evaluations)",
        "x",
        "cluster_speedup_hormone_quiet.json",
        _cluster("speedup_pool_2_vs_serial"),
        _cluster_machine,
        lambda runs: (
            "`python benchmarks/cluster_speedup.py --config experiments/hormone_3d.toml "
            "--population 2000 --generations 3 --set model.params.upkeep=100 --repeat 3 --ceiling`"
        ),
    ),
    Row(
        "dask-speedup",
        "2 Dask workers over 1, the same workload",
        "x",
        "cluster_speedup_hormone_quiet.json",
        _cluster("speedup_dask_1_to_2"),
        _cluster_machine,
        lambda runs: "the same",
    ),
    Row(
        "dask-vs-serial",
        "2 Dask workers over serial evaluation, the same workload",
        "x",
        "cluster_speedup_hormone_quiet.json",
        _cluster("speedup_dask_2_vs_serial"),
        _cluster_machine,
        lambda runs: "the same",
    ),
    # IFS
    Row(
        "ifs-fit-kernel",
        "the 3D IFS fit's kernel (3,906 segments composed, 2 views at 64 px, NCC), 2 threads",
        "evaluations/s",
        "timings/ifs.json#kernel",
        lambda d: num(d["figures"]["evaluations_per_s"], 0),
    ),
    Row(
        "ifs-fit-kernel-blur",
        "the same with `blur = 1` / `2`",
        "evaluations/s",
        "timings/ifs.json#kernel_blur",
        lambda d: " / ".join(num(v, 0) for v in d["figures"]["evaluations_per_s"].values()),
    ),
    Row(
        "chaos-game",
        "the 2D IFS chaos game, 10 M fern points, one core (allocation included)",
        "M points/s",
        "ifs2d_claim.json",
        lambda d: num(d["chaos_game_points_per_s"] / 1e6, 0),
        _ifs2d_machine,
        "`NUMBA_NUM_THREADS=1 python benchmarks/ifs2d.py --repeats 20 --json "
        "benchmarks/results/ifs2d_claim.json`",
    ),
    Row(
        "chaos-kernel",
        "the same, the kernel alone",
        "M points/s",
        "ifs2d_claim.json",
        lambda d: num(d["chaos_kernel_points_per_s"] / 1e6, 0),
        _ifs2d_machine,
        "the same",
    ),
    Row(
        "fern-fit-run",
        "a 2D IFS code fitted to the fern (40,000 evaluations), one run",
        "s",
        "timings/ifs.json#fern_fit",
        lambda d: span(*d["figures"]["run_s"], 0),
    ),
    Row(
        "attractor-fit",
        "`growsim fit-image --model ifs2d` on an attractor's picture (8 pictures, 20,000 "
        "evaluations)",
        "s",
        "timings/ifs.json#attractor_fit",
        lambda d: span(
            min(d["figures"]["seconds"].values()), max(d["figures"]["seconds"].values()), 0
        ),
    ),
    # the fish
    Row(
        "fish-kernel",
        "the fish's population kernel, 200 genomes x 20,000 frames, one core",
        "M fish-frames/s",
        "timings/fish.json#kernel",
        lambda d: num(d["figures"]["M_fish_frames_per_s"], 1),
    ),
    Row(
        "fish-sweep",
        "3 tanks x 20 repeats of `fish_tank.toml` through `growsim sweep` (60 runs)",
        "s",
        "timings/fish.json#sweep",
        lambda d: num(d["figures"]["sweep_3_tanks_x_20_s"], 1),
    ),
]


HEADER = """\
# Measured figures

Every figure the user pages quote, one row each: a page writes it as given here and
links its row (`8.6 s ([figures](figures.md#quickstart-run))`). Made by
`python benchmarks/figures.py` (each row's id and command) from `benchmarks/results/`
(dates); `tests/test_figures.py` fails when it or a citing page is stale. Measured on the
2-core development VM, shared with other work: under load a time is an upper bound; a
command's time is its fastest run. "The same": as above. History: `benchmarks/log/`.

| quantity | value | unit | load | result file |
|---|---|---|---|---|
"""


def table() -> str:
    """The text of ``docs/figures.md``."""
    ids = [r.id for r in ROWS]
    dup = {i for i in ids if ids.count(i) > 1}
    if dup:
        raise SystemExit(f"duplicate row ids: {sorted(dup)}")
    lines = []
    before = ("", "")
    for r in ROWS:
        c = r.cells()
        machine = c["machine"].removeprefix(f"{VM}, ").removeprefix("load ")
        machine = re.sub(r" \(\d{4}-\d{2}-\d{2}\)$", "", machine)  # the file has the date
        machine = machine.replace(", other jobs beside them: upper bounds", ", other jobs beside")
        # the result file (it holds the command), and the load, as the row above: said once
        source = f"`{r.source.partition('#')[0]}`"
        shared = (machine, source)
        told = [b if b != a else "the same" for a, b in zip(before, shared)]
        before = shared
        cells = [f'<a id="{r.id}"></a>{r.what}', c["value"], r.unit, *told]
        lines.append("| " + " | ".join(cell.replace("|", "\\|") for cell in cells) + " |")
    return HEADER + "\n".join(lines) + "\n"


def values() -> dict[str, str]:
    """Each row's figure as the pages write it (value and unit), by id."""
    return {r.id: written(r.value(load(r.source)), r.unit) for r in ROWS}


def tabulated() -> dict[str, str]:
    """Each row's figure as the pages write it, read from ``docs/figures.md`` as it is."""
    if not PAGE.is_file():
        return {}
    rows = re.findall(
        r'^\| <a id="([^"]+)"></a>.*? \| ([^|]+) \| ([^|]+) \| ',
        PAGE.read_text(),
        flags=re.M,
    )
    return {i: written(value, unit) for i, value, unit in rows}


def update_pages(old: dict[str, str], new: dict[str, str]) -> list[Path]:
    """Rewrite the figure written just before each citation of a row whose figure
    changed (``OLD ([figures](figures.md#id))`` -> ``NEW ...``) in README.md and docs/;
    a citation whose page does not show the old figure there is left for a person (and
    ``tests/test_figures.py`` names it)."""
    changed = {i: (old[i], new[i]) for i in new if i in old and old[i] != new[i]}
    pages = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]
    written_to = []
    for page in (p for p in pages if p != PAGE):
        text = original = page.read_text()
        for i, (was, now) in changed.items():
            cite = r"(\s*\(\[figures\]\((?:\.\./)*(?:docs/)?figures\.md#" + re.escape(i) + r"\)\))"
            text = re.sub(re.escape(was) + cite, lambda m, now=now: now + m.group(1), text)
        if text != original:
            page.write_text(text)
            written_to.append(page)
    return written_to


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--check", action="store_true", help="exit 1 if docs/figures.md is stale")
    ap.add_argument(
        "--pages",
        action="store_true",
        help="also rewrite the pages' figures of the rows that changed",
    )
    args = ap.parse_args(argv)
    text = table()
    if args.check:
        if PAGE.read_text() != text:
            print("docs/figures.md is stale: python benchmarks/figures.py", file=sys.stderr)
            return 1
        return 0
    old = tabulated()
    PAGE.write_text(text)
    print(f"wrote {PAGE.relative_to(ROOT)}: {len(ROWS)} rows")
    if args.pages:
        for page in update_pages(old, values()):
            print(f"rewrote figures in {page.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
