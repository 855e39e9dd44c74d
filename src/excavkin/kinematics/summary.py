"""Short text and HTML summaries of results, for the REPL and notebooks.

A result of a million samples must not print a million numbers: ``repr()`` gives the sample
count, the status counts and the columns grouped by owner; ``_repr_html_`` the same as a small
table. Nothing here imports pandas, matplotlib or pint.
"""

from __future__ import annotations

import html
from collections.abc import Iterable, Sequence

import numpy as np

from excavkin.kinematics.columns import Column

_PLURAL = {"body": "bodies", "time": "time"}


def status_counts(labels: np.ndarray) -> list[tuple[str, int]]:
    """``[(label, count), ...]``, ``ok`` first, then by count."""
    values, counts = np.unique(labels.astype(str), return_counts=True)
    pairs = sorted(zip(values.tolist(), counts.tolist(), strict=True), key=lambda p: -p[1])
    return sorted(pairs, key=lambda p: p[0] != "ok")


def failures(total: int, groups: Sequence[tuple[str, int, Sequence[str]]], limit: int) -> str:
    """The failing samples as one paragraph: per reason (in order of its first sample) its
    count and its first ``limit`` samples, each already named."""
    bad = sum(count for _, count, _ in groups)
    if not bad:
        return "all samples solved"
    parts = []
    for label, count, shown in groups:
        more = f" and {count - limit} more" if count > limit else ""
        parts.append(f"{label}: sample{'s' if count > 1 else ''} {', '.join(shown)}{more}")
    return f"{bad} of {total} samples failed — " + "; ".join(parts)


def grouped(columns: Iterable[Column]) -> list[tuple[str, str, list[str]]]:
    """Columns grouped by owner: ``[(owner kind, owner, [quantities]), ...]`` in table order."""
    groups: dict[tuple[str, str], list[str]] = {}
    for c in columns:
        groups.setdefault((c.owner_kind, c.owner or c.name), []).append(c.quantity)
    return [(kind, owner, qty) for (kind, owner), qty in groups.items()]


def text(title: str, n: int, labels: np.ndarray, columns: Sequence[Column]) -> str:
    """``Title(n samples: ok 359, dead position … 2; 38 columns: points A, B; bodies …)``."""
    counts = ", ".join(f"{lab} {k}" for lab, k in status_counts(labels)) if n else "none"
    owners: dict[str, list[str]] = {}
    for kind, owner, _ in grouped(columns):
        owners.setdefault(kind, []).append(owner)
    shown = "; ".join(
        f"{_PLURAL.get(kind, kind + 's')} {', '.join(names[:8])}{' …' if len(names) > 8 else ''}"
        for kind, names in owners.items()
    )
    return f"{title}({n} samples: {counts}; {len(columns)} columns: {shown})"


def html_table(rows: Sequence[Sequence[str]], header: Sequence[str]) -> str:
    """A small HTML table of already-escaped cells."""
    head = "".join(f"<th style='text-align:left'>{h}</th>" for h in header)
    body = "".join(
        "<tr>" + "".join(f"<td style='text-align:left'>{c}</td>" for c in row) + "</tr>"
        for row in rows
    )
    return f"<table><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>"


def result_html(title: str, n: int, labels: np.ndarray, columns: Sequence[Column]) -> str:
    """A notebook summary: samples, status counts and the columns grouped by owner."""
    e = html.escape
    status = html_table(
        [[e(lab), str(k)] for lab, k in status_counts(labels)], ["status", "samples"]
    )
    cols = html_table(
        [[e(kind), e(owner), e(" ".join(qty))] for kind, owner, qty in grouped(columns)],
        ["owner", "name", "columns (.quantity)"],
    )
    return (
        f"<div><b>{e(title)}</b> — {n} samples, {len(columns)} columns (SI)"
        f"<details open><summary>status</summary>{status}</details>"
        f"<details><summary>columns</summary>{cols}</details></div>"
    )


def batch_repr(obj: object) -> str:
    """``Name(n samples; field shape, …)`` for a dataclass of batch arrays: short at any n."""
    import dataclasses

    parts, n = [], None
    for f in dataclasses.fields(obj):  # type: ignore[arg-type]
        value = getattr(obj, f.name)
        if isinstance(value, np.ndarray):
            n = value.shape[0] if value.ndim and n is None else n
            parts.append(f"{f.name} {value.shape}")
        elif isinstance(value, str | bool | int | float):
            parts.append(f"{f.name}={value!r}")
    head = f"{n} samples; " if n is not None else ""
    return f"{type(obj).__name__}({head}{', '.join(parts)})"
