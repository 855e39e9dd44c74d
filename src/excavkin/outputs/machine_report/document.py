"""The machine report as one HTML document: the template filled with every section.

`build_machine_report` lays out a computed `MachineReport` (it computes nothing): the identity
table, then each section's tables, named limits and charts. A matplotlib chart is embedded as a
PNG (a ``data:`` URI), a Plotly chart as an interactive figure with plotly.js in the page, so
the file needs no network. `write_machine_report` writes it atomically and never over an
existing file unless asked.
"""

from __future__ import annotations

import base64
import datetime as _dt
import html
import io
from pathlib import Path
from string import Template
from typing import Any

from excavkin.outputs.display_units import pretty_unit
from excavkin.outputs.machine_report.content import (
    Cell,
    Chart,
    MachineReport,
    Section,
    Table,
    Value,
)

__all__ = ["HTML_SUFFIXES", "build_machine_report", "write_machine_report"]

HTML_SUFFIXES = (".html", ".htm")

#: resolution of the embedded matplotlib charts (dots per inch)
DPI = 110


def _cell(c: Cell, tag: str = "td") -> str:
    if isinstance(c, Value):
        key = f' data-key="{html.escape(c.key)}"' if c.key else ""
        return (
            f'<{tag} class="num"{key} data-si="{c.si!r}" data-unit="{html.escape(c.unit)}">'
            f"{html.escape(c.text())}</{tag}>"
        )
    return f"<{tag}>{html.escape(c)}</{tag}>"


def table_html(t: Table) -> str:
    """A table as HTML: its caption, headers, rows and note.

    Parameters
    ----------
    t : Table

    Returns
    -------
    str
    """
    head = "".join(f"<th>{html.escape(c)}</th>" for c in t.columns)
    body = "".join("<tr>" + "".join(_cell(c) for c in r) + "</tr>" for r in t.rows)
    note = f'<p class="note">{html.escape(t.note)}</p>' if t.note else ""
    return (
        f"<div><table><caption>{html.escape(t.caption)}</caption><thead><tr>{head}</tr></thead>"
        f"<tbody>{body}</tbody></table>{note}</div>"
    )


def _is_plotly(fig: Any) -> bool:
    return hasattr(fig, "to_html") and hasattr(fig, "layout")


def chart_html(c: Chart) -> str:
    """A chart as HTML: a PNG of a matplotlib figure (which is closed) or a Plotly figure.

    Parameters
    ----------
    c : Chart

    Returns
    -------
    str
        A ``<figure>`` with its caption and standard.
    """
    caption = (
        f'<figcaption>{html.escape(c.caption)} — <span class="std">'
        f"{html.escape(c.standard)}</span></figcaption>"
    )
    key = html.escape(c.key)
    if _is_plotly(c.figure):
        config = {
            "displaylogo": False,
            "responsive": True,
            "toImageButtonOptions": {"format": "png", "scale": 2},
        }
        div = c.figure.to_html(
            full_html=False, include_plotlyjs=False, div_id=key, config=config, auto_play=False
        )
        return f'<figure class="wide" id="{key}-figure">{div}{caption}</figure>'
    import matplotlib.pyplot as plt

    buf = io.BytesIO()
    try:
        c.figure.savefig(buf, format="png", dpi=DPI)
    finally:
        plt.close(c.figure)
    data = base64.b64encode(buf.getvalue()).decode("ascii")
    alt = html.escape(c.caption)
    return (
        f'<figure id="{key}"><img alt="{alt}" src="data:image/png;base64,{data}">{caption}</figure>'
    )


def section_html(s: Section) -> str:
    """A section as HTML.

    Parameters
    ----------
    s : Section

    Returns
    -------
    str
    """
    std = f'<span class="std">{html.escape(s.standard)}</span>' if s.standard else ""
    intro = f'<p class="intro">{html.escape(s.intro)}</p>' if s.intro else ""
    tables = (
        '<div class="tables">' + "".join(table_html(t) for t in s.tables) + "</div>"
        if s.tables
        else ""
    )
    limits = (
        '<ul class="limits">' + "".join(f"<li>{html.escape(x)}</li>" for x in s.limits) + "</ul>"
        if s.limits
        else ""
    )
    charts = (
        '<div class="charts">' + "".join(chart_html(c) for c in s.charts) + "</div>"
        if s.charts
        else ""
    )
    key = html.escape(s.key)
    return (
        f'<section id="{key}-section"><h2>{html.escape(s.title)}{std}</h2>{intro}{tables}'
        f"{limits}{charts}</section>"
    )


def build_machine_report(report: MachineReport) -> str:
    """The HTML text of a machine report.

    Parameters
    ----------
    report : MachineReport

    Returns
    -------
    str
        A complete HTML document: charts embedded, plotly.js embedded where a chart is
        interactive, nothing fetched when viewing.
    """
    from importlib.resources import files

    from excavkin import __version__

    plotlyjs = ""
    if any(_is_plotly(c.figure) for s in report.sections for c in s.charts):
        from plotly.offline import get_plotlyjs

        plotlyjs = f"<script>{get_plotlyjs()}</script>"
    identity = (
        '<table class="identity"><tbody>'
        + "".join(
            f"<tr><td>{html.escape(k)}</td>"
            + (_cell(v) if isinstance(v, Value) else _cell(v))
            + (
                f"<td>{html.escape(pretty_unit(v.unit))}</td>"
                if isinstance(v, Value)
                else "<td></td>"
            )
            + "</tr>"
            for k, v in report.identity
        )
        + "</tbody></table>"
    )
    notes = "".join(f'<p class="note">{html.escape(n)}</p>' for n in report.notes)
    if report.tables:
        identity = (
            '<div class="tables"><div><table class="identity"><caption>Identity</caption>'
            + identity.removeprefix('<table class="identity">')
            + "</div>"
            + "".join(table_html(t) for t in report.tables)
            + "</div>"
        )
    nav = '<a href="#identity-section">Machine</a>' + "".join(
        f'<a href="#{html.escape(s.key)}-section">{html.escape(s.title)}</a>'
        for s in report.sections
    )
    subtitle = " · ".join(
        html.escape(x)
        for x in (report.family, report.source or "machine built in Python", report.command)
        if x
    )
    template = Template(
        files("excavkin.outputs.machine_report")
        .joinpath("template.html")
        .read_text(encoding="utf-8")
    )
    return template.substitute(
        version=html.escape(__version__),
        title=html.escape(report.title),
        subtitle=subtitle,
        plotlyjs=plotlyjs,
        nav=nav,
        identity=identity,
        notes=notes,
        sections="\n".join(section_html(s) for s in report.sections),
        date=_dt.datetime.now().strftime("%Y-%m-%d %H:%M"),
    )


def write_machine_report(report: MachineReport, path: str | Path, *, force: bool = False) -> Path:
    """Write the machine report to ``path``, atomically.

    Parameters
    ----------
    report : MachineReport
    path : str or Path
        Ends in ``.html`` or ``.htm``.
    force : bool
        Replace an existing file.

    Returns
    -------
    Path

    Raises
    ------
    excavkin.outputs.tables.OutputError
        If the file exists and ``force`` is false, the folder does not exist or the suffix is
        not ``.html``/``.htm``.
    """
    from excavkin.outputs.tables import check_target, write_atomic

    p = check_target(path, force=force, suffixes=HTML_SUFFIXES)
    text = build_machine_report(report)

    def write(tmp: Path) -> None:
        tmp.write_text(text, encoding="utf-8")

    return write_atomic(p, write)
