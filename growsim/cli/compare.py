"""``growsim compare DIR...``: groups, families, tests, curves, renders and an HTML report."""

from __future__ import annotations

import argparse
import math

__all__ = ["register"]

#: the measures printed beside the best fitness (all of them are in the report)
PRINTED_MEASURES = ("height", "crown_width", "n_segments", "light_captured")
#: at most this many best-fitness tests are printed per family (else the significant ones)
MAX_PRINTED_PAIRS = 15
#: group labels longer than this are printed as their number (#) in the tests
LONG_LABEL = 24


def register(subparsers) -> None:
    """Add the ``compare`` subcommand.

    Examples
    --------
    >>> from growsim.cli import build_parser
    >>> build_parser().parse_args(["compare", "runs/a", "runs/b", "--no-renders"]).dirs
    ['runs/a', 'runs/b']
    """
    p = subparsers.add_parser(
        "compare",
        help="compare results directories (runs or sweeps)",
        description="Group the runs in the DIRs (the same config up to the seed), test best "
        "fitness and every measure between the groups (Holm-adjusted) and write tables, "
        "plots and report.html to --out. Details: docs/compare.md.",
    )
    p.add_argument("dirs", nargs="+", metavar="DIR", help="run or sweep directories")
    p.add_argument(
        "--out",
        metavar="DIR",
        help="report directory (default: <the runs' directory>/compare-<time> when the runs "
        "are all under one directory, else runs/compare-<time>)",
    )
    p.add_argument("--no-renders", action="store_true", help="skip rendering the best plants")
    p.add_argument(
        "--garden",
        action="store_true",
        help="common garden: grow every run's best genome in the environment of every group "
        "of its family; test origins within a garden (genetic) and gardens within an origin "
        "(plastic); write garden.csv, garden_stats.csv, garden_variance.csv",
    )
    p.add_argument(
        "--confirm",
        nargs="+",
        metavar="DIR",
        help="the same sweep on a fresh block of seeds (growsim sweep CONFIG --block 2): "
        "make the primary tests again on these runs and write replication.csv (which "
        "findings replicated: same direction, Holm p below alpha)",
    )
    p.add_argument(
        "--primary",
        metavar="CONFIG",
        help="take the [compare] primary tests from this experiment TOML instead of the "
        "runs' configs (runs made before the section was added)",
    )
    p.add_argument("--quiet", "-q", action="store_true", help="print nothing")
    p.set_defaults(func=main)


def _group_lines(rows) -> str:
    """The groups of one family: n, duplicates, best fitness and a few measures."""
    import pandas as pd

    from growsim.report import format_mean_ci as _pm

    out = pd.DataFrame(
        {
            "#": range(1, len(rows) + 1),
            "group": rows["group"],
            "dirs": rows["dirs"],
            "n": rows["runs"],
            "dup": rows["duplicates"],
            "best": [f"{v:.4g}" for v in rows["best"]],
            "best fitness": [_pm(m, c) for m, c in zip(rows["mean"], rows["ci95"])],
        }
    )
    for m in PRINTED_MEASURES:
        if m in rows and rows[m].notna().any():
            out[m] = [_pm(v, c) for v, c in zip(rows[m], rows.get(f"{m}_ci95", rows[m] * math.nan))]
    return out.to_string(index=False)


def _test_lines(tests, groups: list[str], exploratory: bool = False) -> list[str]:
    """Best-fitness tests (all, or the significant ones when there are many) and the
    measures whose Holm-adjusted p is below 0.05; long group labels by their number.
    ``exploratory``: the tests besides the primary ones, Holm over those alone."""
    import pandas as pd

    if max(map(len, groups)) > LONG_LABEL:
        number = {g: f"#{i}" for i, g in enumerate(groups, 1)}
        tests = tests.assign(
            group_a=tests["group_a"].map(number), group_b=tests["group_b"].map(number)
        )

    sig = (tests["welch_t_p_holm"] < 0.05) | (tests["mann_whitney_p_holm"] < 0.05)
    best = tests["measure"] == "best_fitness"
    shown = best & (sig | (best.sum() <= MAX_PRINTED_PAIRS)) | (~best & sig)
    cols = [
        "measure",
        "group_a",
        "group_b",
        "difference",
        "cliffs_delta",
        "welch_t_p",
        "welch_t_p_holm",
        "mann_whitney_p",
        "mann_whitney_p_holm",
    ]
    if exploratory:
        head = f"  exploratory: {len(tests)} other tests, Holm-Bonferroni over these alone:"
    else:
        head = f"  {len(tests)} tests, Holm-Bonferroni over all of them (per test):"
    lines = [head]
    if shown.any():
        with pd.option_context(
            "display.width", 250, "display.max_columns", 20, "display.float_format", "{:.4g}".format
        ):
            lines += ["  " + s for s in tests.loc[shown, cols].to_string(index=False).splitlines()]
    rest = int((~shown).sum())
    if rest:
        n_sig = int((~shown & sig).sum())
        lines.append(
            f"  ... {rest} more in {'exploratory' if exploratory else 'stats'}.csv ({n_sig} of "
            "them with a Holm-adjusted p < 0.05)"
        )
    return lines


def _primary_lines(primary, replication) -> list[str]:
    """The primary tests (and, with a confirmation block, whether each replicated)."""
    import pandas as pd

    alpha = float(primary["alpha"].iloc[0]) if len(primary) else 0.05
    lines = [
        f"primary tests ([compare] primary): {len(primary)}, Holm over them alone; "
        f"finding = p_holm < {alpha:g} in the expected direction (primary.csv); every other "
        "test is exploratory (exploratory.csv)"
    ]
    cols = ["measure", "expect", "n_a", "n_b", "difference", "hedges_g", "p", "p_holm",
            "finding", "seeds_for_power"]  # fmt: skip
    with pd.option_context(
        "display.width", 250, "display.max_columns", 20, "display.float_format", "{:.4g}".format
    ):
        lines += ["  " + s for s in primary[cols].to_string(index=False).splitlines()]
        if replication is not None:
            n_rep, n_find = (
                int(replication["replicated"].sum()),
                int(replication["discovery_finding"].sum()),
            )
            lines.append(
                f"replication (replication.csv): {n_rep} of {n_find} discovery finding(s) "
                "replicated on the confirmation block"
            )
            cols = ["measure", "expect", "confirmation_difference", "confirmation_p_holm",
                    "verdict"]  # fmt: skip
            lines += ["  " + s for s in replication[cols].to_string(index=False).splitlines()]
    return lines


def main(args: argparse.Namespace) -> int:
    """Compare and print, per family, the groups and the tests; then where the report is."""
    from growsim.report import compare

    c = compare(
        args.dirs,
        args.out,
        renders=not args.no_renders,
        garden=args.garden,
        primary=args.primary,
        confirm=args.confirm,
    )
    if args.quiet:
        return 0
    if c.primary is not None:
        print("\n".join(_primary_lines(c.primary, c.replication)))
        print()
    for family, rows in c.table.groupby("family", sort=False):
        n = int(rows["runs"].sum())
        dup = int(rows["duplicates"].sum())
        head = f"{family}: {len(rows)} group(s), {n} run(s)"
        print(head + (f" ({dup} duplicated seed(s) not counted)" if dup else ""))
        print(_group_lines(rows.reset_index(drop=True)))
        every = c.stats if c.exploratory is None else c.exploratory
        tests = every[every["family"] == family]
        if len(tests):
            print("\n".join(_test_lines(tests, list(rows["group"]), c.exploratory is not None)))
        elif len(rows) > 1:
            print("  no tests: no two groups with at least 2 runs of distinct seeds")
        print()
    if "garden_variance" in c.files:
        import pandas as pd

        shares = pd.read_csv(c.files["garden_variance"])
        if len(shares):
            print("common garden: shares of each quantity's variation (garden_variance.csv)")
            print(shares.round(3).to_string(index=False))
            print()
    for note in c.notes:
        print(f"note: {note}")
    out = c.files["table"].parent
    print(f"report: {c.files.get('html', c.files['table'])}  (all files in {out}/)")
    return 0
