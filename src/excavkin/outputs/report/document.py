"""The report as one HTML document: the template filled with every section.

`build_report` takes a mechanism and a result solved already (the report never solves),
asks each section for its part — `mechanism`,
`curves`, `warnings`,
`table` — and fills ``template.html``;
[`write_report`][excavkin.outputs.report.document.write_report]
writes it atomically.
"""

from __future__ import annotations

import datetime as _dt
import html
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from string import Template
from typing import Any

from excavkin.outputs.events import ShockLike, find_events
from excavkin.outputs.protocols import MechanismLike, Solved
from excavkin.outputs.report.curves import curves_figure, curves_note
from excavkin.outputs.report.data import ReportData, sweep_text
from excavkin.outputs.report.mechanism import MAX_FRAMES, mechanism_figure
from excavkin.outputs.report.table import download, extremes_html
from excavkin.outputs.report.warnings import warnings_html

__all__ = ["HTML_SUFFIXES", "build_report", "write_report"]

HTML_SUFFIXES = (".html", ".htm")


def build_report(
    mech: MechanismLike,
    result: Solved,
    *,
    title: str | None = None,
    units: Mapping[str, str] | None = None,
    show: Iterable[str] | None = None,
    curves: Iterable[str] | None = None,
    ropes: Iterable[str] = (),
    length_unit: str = "mm",
    max_frames: int = MAX_FRAMES,
    command: str | None = None,
    shocks: Sequence[ShockLike] = (),
) -> str:
    """The HTML text of a report on ``result`` of ``mech``.

    Parameters
    ----------
    mech : Mechanism
    result : KinematicResult or a result with ``.kinematics`` and ``to_frame()``
    title : str, optional
        Default: the model's name.
    units : mapping of str to str, optional
        Display units by kind or column.
    show : iterable of str, optional
        Columns whose current value the mechanism view shows (see `mechanism_figure`).
    curves : iterable of str, optional
        Columns plotted (default `main_columns`).
    ropes : iterable of str
        Linear elements drawn as lines rather than cylinders.
    length_unit : str
    max_frames : int
    command : str, optional
        The command line that made the report, for the record.
    shocks : sequence of Shock, optional
        For a run in time, the exact shock report's shocks
        ([`excavkin.simulation.shocks.shock_report`][]), listed among the warnings.

    Returns
    -------
    str
        A complete HTML document; plotly.js is embedded, nothing is fetched when viewing.
    """
    from importlib.resources import files

    import plotly.offline

    from excavkin import __version__
    from excavkin.outputs.plots import main_columns

    data = ReportData(result, units)
    title = title or mech.name
    curve_cols = list(curves) if curves is not None else main_columns(data.table)
    mfig = mechanism_figure(
        result, units=units, show=show, ropes=ropes, length_unit=length_unit, max_frames=max_frames
    )
    cfig = curves_figure(result, curve_cols, units=units)
    config = {
        "displaylogo": False,
        "responsive": True,
        "toImageButtonOptions": {"format": "png", "scale": 2},
    }
    mech_html = mfig.to_html(
        full_html=False, include_plotlyjs=False, div_id="mechanism", config=config, auto_play=False
    )
    curves_html = cfig.to_html(
        full_html=False, include_plotlyjs=False, div_id="curves", config=config
    )
    events = find_events(data.table, describe_sample=data.name, shocks=shocks)
    frame = data.table.frame
    src = mech.model.source
    now = _dt.datetime.now().strftime("%Y-%m-%d %H:%M")
    subtitle = " · ".join(
        x
        for x in (
            html.escape(str(src)) if src else "model built in Python",
            f"{len(frame)} samples",
            f"{int(data.table.ok.sum())} solved",
            html.escape(command) if command else "",
        )
        if x
    )
    notes = ""
    if getattr(mech.plan, "notes", ()):
        notes = "<ul>" + "".join(f"<li>{html.escape(n)}</li>" for n in mech.plan.notes) + "</ul>"
    template = Template(
        files("excavkin.outputs.report").joinpath("template.html").read_text(encoding="utf-8")
    )
    return template.substitute(
        version=html.escape(__version__),
        title=html.escape(title),
        subtitle=subtitle,
        plotlyjs=plotly.offline.get_plotlyjs(),
        sweep=html.escape(sweep_text(data)),
        mechanism=mech_html,
        curves=curves_html,
        curves_note=html.escape(curves_note(result, "t" in frame)),
        warnings=warnings_html(events),
        describe=html.escape(mech.describe().split("\n  plan    :")[0]),
        plan=html.escape(mech.plan.describe()),
        notes=notes,
        **download(frame, title),
        extremes=extremes_html(data, curve_cols),
        date=now,
    )


def write_report(
    mech: MechanismLike,
    result: Solved,
    path: str | Path,
    *,
    force: bool = False,
    **options: Any,
) -> Path:
    """Write the HTML report of ``result`` to ``path``, atomically.

    Parameters
    ----------
    mech : Mechanism
    result : KinematicResult or a result with ``.kinematics`` and ``to_frame()``
    path : str or Path
        Ends in ``.html`` or ``.htm``.
    force : bool
        Replace an existing file.
    **options
        Passed to `build_report` (``title``, ``units``, ``show``, ``curves``, ``ropes``,
        ``length_unit``, ``max_frames``, ``command``, ``shocks``).

    Returns
    -------
    Path

    Raises
    ------
    excavkin.outputs.tables.OutputError
        If the file exists and ``force`` is false, or the folder does not exist.
    TypeError
        On an unknown option.
    """
    from excavkin.outputs.tables import check_target, write_atomic

    p = check_target(path, force=force, suffixes=HTML_SUFFIXES)
    text = build_report(mech, result, **options)

    def write(tmp: Path) -> None:
        tmp.write_text(text, encoding="utf-8")

    return write_atomic(p, write)
