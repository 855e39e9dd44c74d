"""Every code block of the README and the docs runs.

Python blocks run in order, one namespace per page, in a scratch folder that holds the
repository's ``examples/``. Command lines (``$ excavkin …`` in console blocks, ``excavkin …`` in
bash blocks) run through the CLI there and must succeed; where a console block shows output, its
first line must be what the command prints. The set-up commands of the README (``pip install``,
``bash scripts/test.sh``) are what CI itself runs, so they are not run again here.
"""

from __future__ import annotations

import os
import re
import shlex
from pathlib import Path

import matplotlib
import pytest
from click.testing import CliRunner

from excavkin.cli import main

ROOT = Path(__file__).parents[2]
PAGES = sorted([ROOT / "README.md", *(ROOT / "docs").rglob("*.md")])
FENCE = re.compile(r"^```(\w+)[^\n]*\n(.*?)^```", re.S | re.M)
SETUP = ("pip ", "bash scripts/test.sh", "mkdocs ")


def blocks(page: Path, lang: str) -> list[str]:
    return [body for kind, body in FENCE.findall(page.read_text()) if kind == lang]


def bash_lines(body: str) -> list[str]:
    """The excavkin command lines of a bash block, continuations joined, comments dropped."""
    out = []
    for line in re.sub(r"\\\n\s*", " ", body).splitlines():
        line = line.split(" #", 1)[0].strip()
        if line.startswith("excavkin") and not line.startswith(SETUP):
            out.append(line)
    return out


def commands_before_python(page: Path) -> list[str]:
    """Command lines of the bash blocks that come before a page's first Python block: the
    tables its Python reads."""
    out: list[str] = []
    for kind, body in FENCE.findall(page.read_text()):
        if kind == "python":
            break
        if kind == "bash":
            out += bash_lines(body)
    return out


def commands(page: Path) -> list[tuple[str, str]]:
    """(command line, first line of its shown output) of every CLI call on a page."""
    out = []
    for body in blocks(page, "console"):
        lines = body.splitlines()
        for k, line in enumerate(lines):
            if line.startswith("$ excavkin"):
                shown = lines[k + 1].strip() if k + 1 < len(lines) else ""
                out.append((line[2:], "" if shown.startswith(("$", "...")) else shown))
    for body in blocks(page, "bash"):
        out += [(line, "") for line in bash_lines(body)]
    return out


@pytest.fixture
def scratch(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    (tmp_path / "examples").symlink_to(ROOT / "examples")
    (tmp_path / "docs" / "img").mkdir(parents=True)
    monkeypatch.chdir(tmp_path)
    # the printed outputs are the NumPy path's: "auto" would take a compiled kernel wherever
    # one is cached (by an earlier test, or not), equal to round-off, and round-off can change
    # an optimiser's path (the count of designs it solves); a block naming a backend gets it
    monkeypatch.setenv("EXCAVKIN_COMPILED", "0")
    matplotlib.use("Agg")
    return tmp_path


def page_id(page: Path) -> str:
    return str(page.relative_to(ROOT))


@pytest.mark.parametrize("page", [p for p in PAGES if blocks(p, "python")], ids=page_id)
def test_python_blocks_run(page: Path, scratch: Path) -> None:
    for line in commands_before_python(page):
        result = CliRunner().invoke(main, shlex.split(line, comments=True)[1:])
        assert result.exit_code == 0, f"{page_id(page)}: {line}\n{result.output}"
    namespace: dict[str, object] = {"__name__": "__docs__"}
    for k, code in enumerate(blocks(page, "python")):
        try:
            exec(compile(code, f"{page.name} block {k + 1}", "exec"), namespace)
        except Exception as exc:  # name the block, not this harness
            pytest.fail(f"{page_id(page)}, python block {k + 1}: {type(exc).__name__}: {exc}")
    import matplotlib.pyplot as plt

    plt.close("all")


CALLS = [(p, c, s) for p in PAGES for c, s in commands(p)]


@pytest.mark.parametrize(
    ("page", "line", "shown"), CALLS, ids=[f"{page_id(p)}: {c[:60]}" for p, c, _ in CALLS]
)
def test_command_lines_run(page: Path, line: str, shown: str, scratch: Path) -> None:
    args = shlex.split(line, comments=True)[1:]
    result = CliRunner().invoke(main, args, env={**os.environ, "COLUMNS": "200"})
    assert result.exit_code == 0, f"{page_id(page)}: {line}\n{result.output}"
    if shown:
        assert shown in result.output, f"{page_id(page)}: {line} no longer prints {shown!r}"


def test_every_page_with_code_is_checked() -> None:
    assert any(page.name == "README.md" for page in PAGES) and len(CALLS) >= 10
