"""Every parameter of the public API is documented in its numpydoc docstring.

The public API is what the API reference renders: each ``::: dotted.name`` directive of
``docs/api/*.md`` (a module expands to its ``__all__``, else its public names; a class to
itself and its public methods), together with the callables of the top-level
``excavkin.__all__``. Each callable's docstring is parsed with numpydoc:

* every parameter of its signature, bar ``self``, ``cls``, ``*args`` and ``**kwargs``, appears
  in its ``Parameters`` section (for a class, its ``Attributes`` section counts as well, so
  that a dataclass documents its fields once);
* a ``Parameters`` entry that names no parameter is stale, and fails;
* a function or method that returns something has a ``Returns`` (or ``Yields``) section;
* numpydoc parses the docstring without a warning (an unknown section, say).
"""

from __future__ import annotations

import importlib
import inspect
import re
import warnings
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType
from typing import Any

import pytest
from numpydoc.docscrape import NumpyDocString, Parameter

import excavkin

ROOT = Path(__file__).parents[2]
API_PAGES = sorted((ROOT / "docs" / "api").glob("*.md"))
DIRECTIVE = re.compile(r"^::: ([\w.]+)", re.M)
SKIPPED = {"self", "cls"}
NOTHING = (None, "None", inspect.Signature.empty)


def directives() -> list[str]:
    """The dotted names of the ``:::`` directives of the API pages, in page order."""
    return [name for page in API_PAGES for name in DIRECTIVE.findall(page.read_text())]


def resolve(dotted: str) -> Any:
    """The object a dotted name stands for: the longest importable module, then attributes."""
    parts = dotted.split(".")
    for k in range(len(parts), 0, -1):
        try:
            obj: Any = importlib.import_module(".".join(parts[:k]))
        except ImportError:
            continue
        for part in parts[k:]:
            obj = getattr(obj, part)
        return obj
    raise ImportError(dotted)


def _members(module: ModuleType) -> Iterator[tuple[str, Any]]:
    names = getattr(module, "__all__", None)
    if names is None:
        names = [n for n in dir(module) if not n.startswith("_")]
    for name in names:
        obj = getattr(module, name)
        if (inspect.isclass(obj) or inspect.isfunction(obj)) and getattr(
            obj, "__module__", ""
        ).startswith("excavkin"):
            yield name, obj


def walk(dotted: str, obj: Any, seen: set[int] | None = None) -> Iterator[tuple[str, Any]]:
    """``(name, callable)`` for ``obj`` and what the API reference renders under it."""
    seen = set() if seen is None else seen
    if id(obj) in seen:
        return
    seen.add(id(obj))
    if inspect.ismodule(obj):
        for name, member in _members(obj):
            yield from walk(f"{dotted}.{name}", member, seen)
    elif inspect.isclass(obj):
        yield dotted, obj
        for name, member in vars(obj).items():
            if name.startswith("_"):
                continue
            if isinstance(member, staticmethod | classmethod):
                member = member.__func__
            if inspect.isfunction(member):
                yield f"{dotted}.{name}", member
    elif callable(obj):
        yield dotted, obj


def public_callables() -> dict[str, Any]:
    """Every callable of the public API by its dotted name, each once."""
    seen: set[int] = set()
    found: dict[str, Any] = {}
    for dotted in directives():
        found.update(walk(dotted, resolve(dotted), seen))
    found.update(walk("excavkin", excavkin, seen))
    return found


def _names(entries: list[Parameter]) -> set[str]:
    """The names an entry list documents: ``a, b : float`` is two, ``*args`` is ``args``."""
    return {name.strip().lstrip("*") for e in entries for name in e.name.split(",")}


def problems(obj: Callable[..., Any]) -> list[str]:
    """What is wrong with the documentation of ``obj``'s parameters and return; empty when
    nothing is."""
    try:
        signature = inspect.signature(obj)
    except (TypeError, ValueError):
        return []
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            doc = NumpyDocString(inspect.getdoc(obj) or "")
        except Exception as exc:  # numpydoc raises plain ValueErrors on malformed sections
            return [f"unparsable docstring: {exc}"]
    out = [f"numpydoc: {w.message}" for w in caught]
    documented = _names(doc["Parameters"])
    if inspect.isclass(obj):
        documented |= _names(doc["Attributes"])
    for p in signature.parameters.values():
        if p.name in SKIPPED or p.kind in (p.VAR_POSITIONAL, p.VAR_KEYWORD):
            continue
        if p.name not in documented:
            out.append(f"parameter {p.name!r} undocumented")
    stale = _names(doc["Parameters"]) - set(signature.parameters)
    out += [f"documented {name!r} is no parameter" for name in sorted(stale)]
    returns = signature.return_annotation not in NOTHING and not inspect.isclass(obj)
    if returns and not doc["Returns"] and not doc["Yields"]:
        out.append("no Returns section")
    return out


def test_the_api_pages_list_what_exists() -> None:
    names = directives()
    assert len(names) > 50
    for dotted in names:
        resolve(dotted)
    assert len(public_callables()) > 150


def test_every_public_parameter_is_documented() -> None:
    report = [
        f"{name}: {problem}"
        for name, obj in public_callables().items()
        for problem in problems(obj)
    ]
    assert not report, "\n".join(report)


# The checker itself: it must fail on what it is meant to catch.


def _documented(length: float, width: float, *rest: float, scale: float = 1.0, **kw: Any) -> float:
    """Area.

    Parameters
    ----------
    length, width : float
        Sides, m.
    *rest : float
        Ignored.
    scale : float, default 1.0
        Factor.

    Returns
    -------
    float
        ``length * width * scale``, m².
    """
    return length * width * scale


def _one_missing(length: float, width: float) -> None:
    """Nothing.

    Parameters
    ----------
    length : float
        One side, m.
    height : float
        Stale.
    """


def _bare(length: float) -> float:
    """Area of a square."""
    return length**2


def _no_returns() -> float:
    """One.

    Notes
    -----
    A constant.
    """
    return 1.0


def _unknown_section(length: float) -> None:
    """Nothing.

    Parameters
    ----------
    length : float
        A side, m.

    Sources
    -------
    None.
    """


def _split_names(length: float, width: float) -> None:
    """Nothing.

    Parameters
    ----------
    length,
    width
        Sides, m: names broken over two lines are two entries, the first empty-handed.
    """


@dataclass
class _Record:
    """A record.

    Attributes
    ----------
    name : str
        Its name.
    """

    name: str
    size: float


@pytest.mark.parametrize(
    ("obj", "expected"),
    [
        (_documented, []),
        (_one_missing, ["parameter 'width' undocumented", "documented 'height' is no parameter"]),
        (_bare, ["parameter 'length' undocumented", "no Returns section"]),
        (_no_returns, ["no Returns section"]),
        (_unknown_section, ["numpydoc: Unknown section Sources"]),
        (_split_names, ["documented '' is no parameter"]),
        (_Record, ["parameter 'size' undocumented"]),
    ],
)
def test_the_checker_finds_what_is_undocumented(
    obj: Callable[..., Any], expected: list[str]
) -> None:
    assert problems(obj) == expected


def test_the_walk_expands_modules_and_classes() -> None:
    found = dict(walk("excavkin.errors", resolve("excavkin.errors")))
    assert "excavkin.errors.did_you_mean" in found
    assert "excavkin.errors.ModelError.with_source" in found
    assert not any(name.rsplit(".", 1)[1].startswith("_") for name in found)
    assert "excavkin.example_path" in public_callables()
