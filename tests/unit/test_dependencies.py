"""Every package the code, the tests, the benchmarks and the scripts import is declared in
pyproject.toml, so that a fresh machine's install has it (a package installed by hand on a
developer's machine hides a missing declaration until a new user runs the tests)."""

from __future__ import annotations

import ast
import re
import sys
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

#: import names whose distribution is called otherwise
DISTRIBUTION = {
    "PIL": "pillow",
    "distributed": "dask",
    "importlinter": "import-linter",
    "llvmlite": "numba",
    "yaml": "pyyaml",
}

#: the extras each tree may rely on
TREES = {
    "src": ("dependencies", "parquet", "fast", "cluster"),
    "tests": ("dependencies", "test", "docs"),
    "benchmarks": ("dependencies", "test", "bench"),
    "scripts": ("dependencies", "test", "docs"),
}


def _normal(name: str) -> str:
    return re.sub(r"[-_.]+", "-", name).lower()


def _declared(extras: tuple[str, ...]) -> set[str]:
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    names = []
    for extra in extras:
        names += (
            project["dependencies"]
            if extra == "dependencies"
            else (project["optional-dependencies"][extra])
        )
    return {_normal(re.split(r"[\s\[<>=!~;]", n, maxsplit=1)[0]) for n in names}


def _imports(tree: Path) -> dict[str, str]:
    """Top-level modules imported under ``tree`` (absolute imports), each with one file."""
    local = {p.stem for p in ROOT.rglob("*.py")} | {"excavkin", "tests"}
    found: dict[str, str] = {}
    for f in sorted(tree.rglob("*.py")):
        for node in ast.walk(ast.parse(f.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                mods = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
                mods = [node.module]
            else:
                continue
            for m in mods:
                top = m.split(".")[0]
                if top not in sys.stdlib_module_names and top not in local:
                    found.setdefault(top, str(f.relative_to(ROOT)))
    return found


def test_every_import_is_declared() -> None:
    missing = []
    for tree, extras in TREES.items():
        declared = _declared(extras)
        for module, where in _imports(ROOT / tree).items():
            if _normal(DISTRIBUTION.get(module, module)) not in declared:
                missing.append(f"{module} (imported in {where}; extras {', '.join(extras)})")
    assert not missing, "imported but not declared in pyproject.toml: " + "; ".join(missing)
