"""The findings table (``docs/models/findings.md``) is ``benchmarks/findings.py``'s
rendering of the result files, and lists every shipped hormone and stand experiment
under both physics."""

from __future__ import annotations

from conftest import ROOT, benchmark_module

FINDINGS = benchmark_module("findings")


def test_page_holds_the_current_table():
    text = FINDINGS.PAGE.read_text()
    a = text.index(FINDINGS.START) + len(FINDINGS.START)
    b = text.index(FINDINGS.END)
    assert text[a:b].strip() == FINDINGS.render().strip(), (
        "docs/models/findings.md is stale: run python benchmarks/findings.py --write"
    )


def test_every_hormone_and_stand_experiment_under_both_physics():
    import tomllib

    shipped = set()
    for path in sorted((ROOT / "experiments").glob("*.toml")):
        with path.open("rb") as f:
            config = tomllib.load(f)
        if config.get("model", {}).get("kind") == "hormone" and config.get("sweep"):
            shipped.add(path.stem)
    listed = {(c, p) for c, p, _ in FINDINGS.EXPERIMENTS}
    assert shipped, "no hormone sweep found in experiments/"
    for stem in shipped:
        assert {(stem, "growsim"), (stem, "paper")} <= listed, stem
    assert {c for c, _ in listed} <= shipped


def test_a_result_file_is_summarised_from_its_tests():
    import json

    data = json.loads((FINDINGS.RESULTS / "hormone_3d_replication.json").read_text())
    s = FINDINGS.summary(data)
    assert s["tests"] == len(data["replication"])
    assert len(s["replicated"]) == sum(r["replicated"] for r in data["replication"])
    assert s["largest"] < s["cap"] / 5
    assert 0 < s["cv"][0] <= s["cv"][1] < 1
