"""No module of excavkin reaches into another module's private names.

A leading underscore means "this module's own": a name another module needs is public within
its package (no underscore, documented), or it lives where both can import it. The walk reads
every module's syntax tree, so it also finds imports inside functions and attribute reaches
through an imported module (``kernels._cache``).
"""

from __future__ import annotations

import ast
from pathlib import Path

import excavkin

SRC = Path(excavkin.__file__).parent


def _module_name(path: Path, src: Path = SRC) -> str:
    parts = list(path.relative_to(src.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _is_private(name: str) -> bool:
    return name.startswith("_") and not name.startswith("__")


def private_reaches(path: Path, modules: set[str], src: Path = SRC) -> list[str]:
    """Every private name of another excavkin module that ``path`` imports or reaches."""
    me = _module_name(path, src)
    package = me.split(".") if path.name == "__init__.py" else me.split(".")[:-1]
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    bound: dict[str, str] = {}  # local name -> the excavkin module or name it stands for
    found: list[str] = []
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                up = package[: len(package) - node.level + 1]
                base = ".".join([*up, *([node.module] if node.module else [])])
            if base.split(".")[0] != "excavkin":
                continue
            for alias in node.names:
                if _is_private(alias.name) and base != me:
                    found.append(f"{path.name}:{node.lineno}: from {base} import {alias.name}")
                bound[alias.asname or alias.name] = f"{base}.{alias.name}"
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.split(".")[0] == "excavkin":
                    local = alias.asname or alias.name.split(".")[0]
                    bound[local] = alias.name if alias.asname else "excavkin"
    for node in ast.walk(tree):
        if not (isinstance(node, ast.Attribute) and _is_private(node.attr)):
            continue
        chain: list[str] = []
        value: ast.expr = node.value
        while isinstance(value, ast.Attribute):
            chain.append(value.attr)
            value = value.value
        if isinstance(value, ast.Name) and value.id in bound:
            target = ".".join([bound[value.id], *reversed(chain)])
            if target in modules and target != me:
                found.append(f"{path.name}:{node.lineno}: {target}.{node.attr}")
    return found


def test_no_module_imports_another_modules_private_names() -> None:
    files = sorted(SRC.rglob("*.py"))
    modules = {_module_name(p) for p in files}
    found = [hit for p in files for hit in private_reaches(p, modules)]
    assert found == []


def test_the_walk_finds_a_private_import_and_a_reach(tmp_path: Path) -> None:
    """The check can fail: a planted module with both kinds of reach is caught, its own
    private names and a dunder are not."""
    pkg = tmp_path / "excavkin" / "kinematics"
    pkg.mkdir(parents=True)
    bad = pkg / "planted.py"
    bad.write_text(
        "from excavkin.kinematics.compiled import _key\n"
        "from excavkin.kinematics import compiled as c\n"
        "from . import _helper\n"
        "from excavkin import __version__\n"
        "def f():\n"
        "    return c._kernels, _mine()\n"
        "def _mine():\n"
        "    return 1\n",
        encoding="utf-8",
    )
    modules = {"excavkin.kinematics.compiled", "excavkin.kinematics.planted"}
    found = private_reaches(bad, modules, tmp_path / "excavkin")
    assert found == [
        "planted.py:1: from excavkin.kinematics.compiled import _key",
        "planted.py:3: from excavkin.kinematics import _helper",
        "planted.py:6: excavkin.kinematics.compiled._kernels",
    ]
