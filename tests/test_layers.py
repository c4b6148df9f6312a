"""The house's rules, read from the code: few modules at the top, no private names taken
across modules, capabilities asked for (never probed with ``getattr``), import-linter's
layers kept.

The checks parse ``growsim/`` with :mod:`ast` (nothing is imported but the two
``CAPABILITIES`` tuples). ``tests/`` is exempt from the private-name rule on purpose: a
test may reach a module's private helpers (an oracle test calls a private kernel, a
runner test its census) without making them part of anyone's interface.
"""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

from conftest import ROOT

from growsim.models.base import CAPABILITIES as MODEL_CAPABILITIES
from growsim.phenotypes.base import CAPABILITIES as PHENOTYPE_CAPABILITIES

PACKAGE = ROOT / "growsim"
#: the most modules directly in ``growsim/`` (``__init__`` and ``__main__`` included)
MAX_TOP_MODULES = 8


def _module_name(path: Path) -> str:
    parts = path.relative_to(ROOT).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


#: every module of growsim: dotted name -> path
MODULES = {_module_name(p): p for p in sorted(PACKAGE.rglob("*.py"))}


def _private(name: str) -> bool:
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def _dotted(node: ast.AST) -> str | None:
    """``a.b.c`` of a Name/Attribute chain, else None."""
    parts = []
    while isinstance(node, ast.Attribute):
        parts.append(node.attr)
        node = node.value
    if not isinstance(node, ast.Name):
        return None
    parts.append(node.id)
    return ".".join(reversed(parts))


def private_uses(path: Path, text: str | None = None) -> list[str]:
    """Where the module at ``path`` (its source: ``text``, default the file's) takes
    another growsim module's private name: ``from growsim.x import _name``, or ``_name``
    read as an attribute of another growsim module (``import growsim.x as x; x._name``,
    ``from growsim import x; x._name``, ``growsim.x._name``)."""
    me = _module_name(path)
    tree = ast.parse(path.read_text() if text is None else text, filename=str(path))
    aliases: dict[str, str] = {}  # local name -> growsim module it stands for
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            if not (node.module == "growsim" or node.module.startswith("growsim.")):
                continue
            for a in node.names:
                full = f"{node.module}.{a.name}"
                if full in MODULES:  # a module imported from its package
                    aliases[a.asname or a.name] = full
                if _private(a.name) and node.module != me:
                    found.append(f"{path.relative_to(ROOT)}:{node.lineno}: from {full}")
        elif isinstance(node, ast.Import):
            for a in node.names:
                if a.name == "growsim" or a.name.startswith("growsim."):
                    if a.asname:
                        aliases[a.asname] = a.name
                    else:
                        aliases["growsim"] = "growsim"
    for node in ast.walk(tree):
        if isinstance(node, ast.Attribute) and _private(node.attr):
            base = _dotted(node.value)
            if base is None:
                continue
            head, _, rest = base.partition(".")
            module = aliases.get(head)
            if module is None:
                continue
            module = f"{module}.{rest}" if rest else module
            if module in MODULES and module != me:
                found.append(f"{path.relative_to(ROOT)}:{node.lineno}: {module}.{node.attr}")
    return found


def capability_probes(path: Path, text: str | None = None) -> list[str]:
    """Where the module at ``path`` (its source: ``text``, default the file's) probes a
    declared capability by name: ``getattr(x, "population", ...)`` or
    ``hasattr(x, "front_view")``."""
    names = set(MODEL_CAPABILITIES) | set(PHENOTYPE_CAPABILITIES)
    tree = ast.parse(path.read_text() if text is None else text, filename=str(path))
    found = []
    for node in ast.walk(tree):
        if (
            isinstance(node, ast.Call)
            and isinstance(node.func, ast.Name)
            and node.func.id in ("getattr", "hasattr")
            and len(node.args) >= 2
            and isinstance(node.args[1], ast.Constant)
            and node.args[1].value in names
        ):
            name = node.args[1].value
            found.append(f"{path.relative_to(ROOT)}:{node.lineno}: {node.func.id}(..., {name!r})")
    return found


def test_at_most_eight_modules_directly_in_growsim():
    top = sorted(p.name for p in PACKAGE.glob("*.py"))
    assert len(top) <= MAX_TOP_MODULES, top


def test_no_module_takes_another_modules_private_names():
    found = [hit for path in MODULES.values() for hit in private_uses(path)]
    assert not found, "\n".join(found)


def test_the_private_name_check_sees_every_form():
    # the checker itself, on a made-up source read as if it were growsim/ga/engine.py:
    # imports and attribute reads are caught; one's own private names and others' public
    # ones are not
    code = (
        "import growsim.ga.state as st\n"
        "import growsim.ga.options\n"
        "from growsim.kernels import ga\n"
        "from growsim.ga.operator import _x, public\n"
        "from growsim.ga.engine import _mine\n"
        "st._hidden(); ga._sbx(); st.public(); growsim.ga.options._spec\n"
    )
    hits = private_uses(PACKAGE / "ga" / "engine.py", code)
    assert sorted(h.split(": ", 1)[1] for h in hits) == [
        "from growsim.ga.operator._x",
        "growsim.ga.options._spec",
        "growsim.ga.state._hidden",
        "growsim.kernels.ga._sbx",
    ]


def test_no_capability_is_probed_with_getattr():
    """``"population" in model.capabilities``, never ``getattr(model, "population", None)``
    (the names of ``growsim.models.base.CAPABILITIES`` and
    ``growsim.phenotypes.base.CAPABILITIES``)."""
    found = [hit for path in MODULES.values() for hit in capability_probes(path)]
    assert not found, "\n".join(found)
    # the checker itself
    code = 'getattr(m, "population", None); hasattr(p, "front_view"); getattr(a, "kind")\n'
    hits = capability_probes(PACKAGE / "models" / "base.py", code)
    assert [h.split(": ", 1)[1] for h in hits] == [
        "getattr(..., 'population')",
        "hasattr(..., 'front_view')",
    ]


def test_import_linter_contracts_are_kept():
    """``lint-imports`` (the layers of ``[tool.importlinter]`` in pyproject.toml), as
    ``.ci/run`` runs it; about a quarter of a second."""
    exe = Path(sys.executable).with_name("lint-imports")  # import-linter is in [test]
    assert exe.exists(), "lint-imports is not installed next to this Python: pip install .[test]"
    p = subprocess.run([str(exe), "--no-cache"], cwd=ROOT, capture_output=True, text=True,
                       timeout=120)  # fmt: skip
    assert p.returncode == 0, p.stdout + p.stderr
    assert "0 broken" in p.stdout
