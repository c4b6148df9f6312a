"""The README's two set-up commands are the ones CI and users run: keep them true."""

from __future__ import annotations

import re

from conftest import ROOT


def _readme_commands() -> list[str]:
    text = (ROOT / "README.md").read_text()
    blocks = re.findall(r"```bash\n(.*?)```", text, flags=re.S)
    return [b.strip() for b in blocks if "python3 -m venv" in b]


def test_readme_has_exactly_two_setup_commands():
    cmds = _readme_commands()
    assert len(cmds) == 2, cmds
    assert "growsim run experiments/quickstart.toml" in cmds[0]
    assert "pytest" in cmds[1]


def test_ci_runs_the_readme_test_command():
    test_cmd = _readme_commands()[1]
    tail = test_cmd.split("&&", 2)[-1].strip()  # after venv creation and activation
    ci = (ROOT / ".ci" / "run").read_text()
    assert tail in ci, f"{tail!r} not in .ci/run"


def test_quickstart_config_exists():
    assert (ROOT / "experiments" / "quickstart.toml").is_file()
