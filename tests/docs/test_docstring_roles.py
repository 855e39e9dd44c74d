"""No docstring in the source uses a Sphinx role (``:func:`x```): the API pages (mkdocstrings)
show them verbatim. Cross-references are written ``[`name`][excavkin.full.name]``
(scripts/docstring_roles.py rewrites roles so)."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[2] / "src" / "excavkin"
ROLE = re.compile(r":(?:py:)?(?:func|class|meth|mod|attr|data|exc|obj|ref):`")


def docstrings(path: Path) -> list[tuple[int, str]]:
    """The module's, classes' and functions' docstrings, and attribute comments (``#:``)."""
    text = path.read_text(encoding="utf-8")
    out = [
        (i + 1, line) for i, line in enumerate(text.splitlines()) if line.lstrip().startswith("#:")
    ]
    for node in ast.walk(ast.parse(text)):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            doc = ast.get_docstring(node, clean=False)
            if doc:
                out.append((getattr(node, "lineno", 1), doc))
    return out


FILES = sorted(SRC.rglob("*.py"))


def test_the_source_has_files() -> None:
    assert len(FILES) > 50


@pytest.mark.parametrize("path", FILES, ids=lambda p: str(p.relative_to(SRC)))
def test_no_sphinx_role_in_a_docstring(path: Path) -> None:
    found = [
        f"{path.name}:{line}: {ROLE.search(doc).group(0)}"  # type: ignore[union-attr]
        for line, doc in docstrings(path)
        if ROLE.search(doc)
    ]
    assert not found, found


def test_the_check_finds_a_role(tmp_path: Path) -> None:
    bad = tmp_path / "bad.py"
    bad.write_text('def f():\n    """See :func:`g`."""\n', encoding="utf-8")
    assert [ROLE.search(d) is not None for _, d in docstrings(bad)] == [True]


def test_the_rewrite_links_documented_names_and_quotes_others() -> None:
    import importlib.util

    spec = importlib.util.spec_from_file_location(
        "docstring_roles", SRC.parents[1] / "scripts" / "docstring_roles.py"
    )
    assert spec is not None and spec.loader is not None
    roles = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(roles)
    known = {"excavkin.mechanism.Mechanism.solve", "excavkin.load"}
    text = (
        '"""Use :meth:`Mechanism.solve`, :func:`~excavkin.load`, :func:`helper` and\n'
        ':meth:`the solve <excavkin.mechanism.Mechanism.solve>`."""\n'
    )
    # the first line, made longer than 100 characters, is broken at its last space within them
    assert roles.rewrite(text, "excavkin.x", known) == (
        '"""Use [`Mechanism.solve`][excavkin.mechanism.Mechanism.solve], [`load`][excavkin.load],'
        " `helper`\nand\n"
        '[`the solve`][excavkin.mechanism.Mechanism.solve]."""\n'
    )
