"""Rewrite Sphinx roles (``:func:`x```, ``:class:`~a.b.C```, ``:meth:`title <a.b.c>```) in the
source's docstrings as what the API pages (mkdocstrings) render: a cross-reference
``[`name`][excavkin.full.name]`` (``[`excavkin.full.name`][]`` where the name is the
target's full name) where the target is an object the API pages document, plain
``name`` in backticks otherwise.

Run it after building the site (``mkdocs build -d SITE``), whose ``objects.inv`` lists the
documented objects::

    python scripts/docstring_roles.py SITE/objects.inv src

It is idempotent: a second run finds no role. A short name links where it is a name of the
file's own module, of the package or imported by the file, and a dotted one
(``Mechanism.solve``) also where exactly one documented object ends with it
(``excavkin.mechanism.Mechanism.solve``).
"""

from __future__ import annotations

import ast
import re
import sys
import zlib
from pathlib import Path

#: the longest line (ruff's line-length)
WIDTH = 100
#: a role: its kind, an optional ``~`` and its text (a target, or ``title <target>``), which
#: may run over a line break
ROLE = re.compile(r":(?:py:)?(func|class|meth|mod|attr|data|exc|obj):`(~?)([^`]+)`")


def inventory(path: Path) -> set[str]:
    """The documented objects' full names of a Sphinx inventory (version 2)."""
    head, _, _, _, body = path.read_bytes().split(b"\n", 4)
    if not head.startswith(b"# Sphinx inventory version 2"):
        raise SystemExit(f"{path}: not a Sphinx inventory version 2")
    return {line.split(" ", 1)[0] for line in zlib.decompress(body).decode().splitlines() if line}


def imports(text: str) -> dict[str, str]:
    """The names a file imports from modules (anywhere in it), each to its full name."""
    out = {}
    for node in ast.walk(ast.parse(text)):
        if isinstance(node, ast.ImportFrom) and node.module and not node.level:
            for alias in node.names:
                out[alias.asname or alias.name] = f"{node.module}.{alias.name}"
    return out


def resolve(target: str, module: str, imported: dict[str, str], known: set[str]) -> str | None:
    """The documented object a role's target names, or None: the name itself, a name of the
    file's module, of the package or imported by the file; a dotted name (``Class.method``)
    also where exactly one documented object ends with it."""
    target = target.removesuffix("()")
    head, _, rest = target.partition(".")
    candidates = [target, f"{module}.{target}", f"excavkin.{target}"]
    if head in imported:
        candidates.append(imported[head] + ("." + rest if rest else ""))
    for candidate in candidates:
        if candidate in known:
            return candidate
    if not rest:
        return None
    ends = [k for k in known if k.endswith("." + target)]
    return ends[0] if len(ends) == 1 else None


def rewrite(text: str, module: str, known: set[str]) -> str:
    """``text`` with every role replaced."""
    imported = imports(text)

    def one(match: re.Match[str]) -> str:
        tilde, body = match.group(2), match.group(3)
        titled = re.fullmatch(r"(.*?)\s*<([^<>]+)>", body, flags=re.DOTALL)
        if titled:
            title, target = titled.group(1), titled.group(2).strip()
        else:
            target = body.strip()
            title = target.rsplit(".", 1)[-1] if tilde else target
        title = " ".join(title.split())  # a title broken over lines, on one
        full = resolve(target, module, imported, known)
        if full is None:
            return f"`{title}`"
        return f"[`{title}`][]" if title == full else f"[`{title}`][{full}]"

    new = ROLE.sub(one, text)
    if new == text:
        return text
    before = set(text.splitlines())
    lines = []
    for line in new.splitlines(keepends=True):
        lines.extend(line if line.rstrip("\n") in before else wrap(line))
    return "".join(lines)


def wrap(line: str, width: int = WIDTH) -> list[str]:
    """A line made longer than ``width`` by the rewrite, broken at spaces outside inline code
    into lines of the same indentation (and comment mark)."""
    end = "\n" if line.endswith("\n") else ""
    line = line.rstrip("\n")
    prefix = re.match(r"\s*(?:#:? )?", line).group(0)  # type: ignore[union-attr]
    out = []
    while len(line) > width:
        spaces = [
            i for i in range(len(prefix) + 1, width + 1)
            if line[i] == " " and line[:i].count("`") % 2 == 0 and line[:i].strip("# :")
        ]  # fmt: skip
        later = [i for i in range(width + 1, len(line)) if line[i] == " "]
        if not spaces and not later:
            break
        cut = spaces[-1] if spaces else later[0]
        out.append(line[:cut].rstrip() + "\n")
        line = prefix + line[cut + 1 :].lstrip()
    out.append(line + end)
    return out


def main(argv: list[str]) -> int:
    if len(argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    known = inventory(Path(argv[0]))
    root = Path(argv[1])
    changed = 0
    for path in sorted(root.rglob("*.py")):
        text = path.read_text(encoding="utf-8")
        parts = path.relative_to(root).with_suffix("").parts
        module = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        new = rewrite(text, module, known)
        if new != text:
            path.write_text(new, encoding="utf-8")
            changed += 1
    print(f"rewrote the roles of {changed} files", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
