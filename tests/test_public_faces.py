"""Everything a user is shown imports from a package's face: ``growsim`` or a package's
``__init__`` (``growsim.models``, ``growsim.phenotypes.plant``, ``growsim.env``,
``growsim.ga``, ...), never from a module inside it (``growsim.phenotypes.plant.views``),
so modules can move without breaking what users copied.

Imports are read from every code block of ``README.md``, ``docs/**/*.md`` and
``examples/*.md`` (fenced blocks of any language: ``python``, ``pycon`` with its ``>>>``
and ``...`` prompts, a ``python -c`` in a ``bash`` block; parenthesised imports over
several lines too) and from ``examples/*.py`` and ``examples/*.ipynb`` (with :mod:`ast`,
function-local imports included). Each ``from growsim... import name`` must name a package
whose face really has ``name`` (it is imported and looked up, lazy exports included).
Two exceptions, each with its reason: :data:`PLACEHOLDERS` (a module the page has the
reader write) and a model's own module (``from growsim.models import honda``: a model in
:data:`growsim.models.MODELS` is documented by its module, its presets and functions:
``docs/models/<name>.md``).
"""

from __future__ import annotations

import ast
import importlib
import json
import re
from pathlib import Path

import pytest
from conftest import ROOT

#: modules shown that do not exist: the page has the reader write them. module -> why
PLACEHOLDERS = {
    "growsim.kernels.mymodel": (
        "docs/extending.md has the reader write this kernel module; the model module it "
        "writes next imports its kernel from there, as every model does"
    ),
}

_FENCE = re.compile(r"^\s*(```|~~~)")
_PROMPT = re.compile(r"^\s*(?:>>>|\.\.\.)(?: |$)")
_IMPORT = re.compile(r"^\s*(?:from\s+[\w.]+\s+import\b|import\s+[\w.])")


def sources(root: Path = ROOT) -> list[Path]:
    """Every file whose code a user is shown, under ``root``."""
    return [
        root / "README.md",
        *sorted((root / "docs").rglob("*.md")),
        *sorted((root / "examples").glob("*.md")),
        *sorted((root / "examples").glob("*.py")),
        *sorted((root / "examples").glob("*.ipynb")),
    ]


def code_blocks(text: str) -> list[tuple[int, list[str]]]:
    """``(line number of the first line, lines)`` of each fenced code block of a page.

    Examples
    --------
    >>> code_blocks("a\\n```python\\nimport x\\n```\\nb\\n  ```\\n  y\\n  ```\\n")
    [(3, ['import x']), (7, ['  y'])]
    """
    lines = text.splitlines()
    blocks, i = [], 0
    while i < len(lines):
        m = _FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        j = i + 1
        while j < len(lines) and not lines[j].strip().startswith(m.group(1)):
            j += 1
        blocks.append((i + 2, lines[i + 1 : j]))
        i = j + 1
    return blocks


def block_imports(lines: list[str], first: int) -> list[tuple[int, ast.stmt | str]]:
    """``(line number, import node)`` of every import line of a code block (prompts
    stripped, a parenthesised import joined over its lines); a line that looks like an
    import but does not parse: ``(line number, its text)``.

    Examples
    --------
    >>> [(n, ast.unparse(s)) for n, s in block_imports(
    ...     [">>> from growsim.ga import (", "...     GA,", "...     Real)", "x = 1"], 10)]
    [(10, 'from growsim.ga import GA, Real')]
    """
    found, k = [], 0
    while k < len(lines):
        line = _PROMPT.sub("", lines[k], count=1)
        if _IMPORT.match(line):
            start, stmt = first + k, line.split("#")[0].strip()
            while stmt.count("(") > stmt.count(")") and k + 1 < len(lines):
                k += 1
                stmt += " " + _PROMPT.sub("", lines[k], count=1).split("#")[0].strip()
            try:
                body = ast.parse(stmt.rstrip(";\"'")).body
            except SyntaxError:
                found.append((start, stmt))
            else:
                found.extend((start, node) for node in body)
        k += 1
    return found


def shown_imports(root: Path = ROOT) -> list[tuple[str, ast.stmt | str]]:
    """``("file:line", import node)`` of every import shown under ``root``."""
    found = []
    for path in sources(root):
        rel = path.relative_to(root).as_posix()
        if path.suffix == ".md":
            for first, lines in code_blocks(path.read_text()):
                found.extend((f"{rel}:{n}", node) for n, node in block_imports(lines, first))
            continue
        if path.suffix == ".ipynb":
            cells = json.loads(path.read_text())["cells"]
            codes = ["".join(c["source"]) for c in cells if c["cell_type"] == "code"]
        else:
            codes = [path.read_text()]
        for code in codes:
            for node in ast.walk(ast.parse(code)):
                if isinstance(node, (ast.Import, ast.ImportFrom)):
                    found.append((f"{rel}:{node.lineno}", node))
    return found


def _kind(root: Path, module: str) -> str:
    """``"package"``, ``"module"`` or ``"missing"``: what ``module`` is under ``root``."""
    path = root.joinpath(*module.split("."))
    if (path / "__init__.py").is_file():
        return "package"
    return "module" if path.with_suffix(".py").is_file() else "missing"


def _model_module(module: str, name: str) -> bool:
    from growsim.models import MODELS

    return module == "growsim.models" and name in MODELS


def face_problems(root: Path = ROOT) -> list[str]:
    """What is wrong with the imports shown under ``root``: an import of a growsim module
    that is not a package, a package's name that is a module (but a model's) or that
    its face lacks, an import line that does not parse."""
    problems = []
    for where, node in shown_imports(root):
        if isinstance(node, str):
            problems.append(f"{where}: cannot parse {node!r}")
            continue
        if isinstance(node, ast.Import):
            pairs = [(a.name, None) for a in node.names]
        else:
            pairs = [(node.module or "", a.name) for a in node.names]
        for module, name in pairs:
            if module != "growsim" and not module.startswith("growsim."):
                continue
            kind = _kind(root, module)
            shown = module if name is None else f"from {module} import {name}"
            if kind == "missing" and module in PLACEHOLDERS:
                continue
            if kind != "package":
                why = "no such module" if kind == "missing" else "a module, not a package's face"
                problems.append(f"{where}: {shown}: {module} is {why}")
                continue
            if name is None or name == "*":
                continue
            if _kind(root, f"{module}.{name}") != "missing":
                if not _model_module(module, name):
                    problems.append(f"{where}: {shown}: {module}.{name} is a module, not a name")
                continue
            face = importlib.import_module(module)
            try:
                getattr(face, name)
            except AttributeError:
                problems.append(f"{where}: {shown}: {module} has no {name!r}")
    return problems


def test_what_users_are_shown_imports_from_faces_only():
    problems = face_problems()
    assert not problems, "\n".join(problems)


def test_the_imports_are_found():
    """The reader finds the imports of every kind of source (a guard against a reader
    that finds nothing and so passes)."""
    shown = {where.split(":")[0] for where, _ in shown_imports()}
    assert {"docs/ga.md", "docs/extending.md", "examples/notebook_viewer.py"} <= shown
    code = "```pycon\n>>> from growsim.ga.problems import rastrigin\n```\n"
    (node,) = [node for _, node in block_imports(code_blocks(code)[0][1], 2)]
    assert ast.unparse(node) == "from growsim.ga.problems import rastrigin"


@pytest.mark.parametrize(
    ("line", "problem"),
    [
        ("from growsim.phenotypes.plant.views import render_grid", "is a module, not"),
        ("import growsim.ga.engine", "is a module, not"),
        ("from growsim.phenotypes.plant import views", "is a module"),
        ("from growsim.ga import nosuch", "has no 'nosuch'"),
        ("from growsim.nosuch import x", "is no such module"),
    ],
)
def test_a_deep_import_is_refused(tmp_path, line, problem):
    (tmp_path / "docs").mkdir()
    (tmp_path / "docs" / "page.md").write_text(f"Text.\n\n```python\n{line}\n```\n")
    (tmp_path / "README.md").write_text("```python\nfrom growsim.models import honda\n```\n")
    (tmp_path / "growsim").symlink_to(ROOT / "growsim")
    problems = face_problems(tmp_path)
    assert len(problems) == 1 and problems[0].startswith("docs/page.md:4: "), problems
    assert problem in problems[0]
