"""The report's table section: the result table as a CSV download embedded in the page, and
each curve's extremes with the samples where they occur.
"""

from __future__ import annotations

import base64
import html
from typing import Any

import numpy as np

from excavkin.outputs.display_units import pretty_unit
from excavkin.outputs.report.data import ReportData

__all__ = ["download", "extremes_html"]


def download(frame: Any, title: str) -> dict[str, Any]:
    """The template's fields of the table download: its file name, its CSV (base64) and size.

    Parameters
    ----------
    frame : pandas.DataFrame
        The result table.
    title : str
        The report's title, of which the file is named.

    Returns
    -------
    dict
        ``csv_name``, ``csv``, ``n_rows``, ``n_cols``.
    """
    csv = frame.to_csv(index=False, float_format="%.10g")
    stem = "".join(ch if ch.isalnum() or ch in "-_" else "-" for ch in title).strip("-") or "result"
    return {
        "csv_name": html.escape(f"{stem}.csv"),
        "csv": base64.b64encode(csv.encode("utf-8")).decode("ascii"),
        "n_rows": len(frame),
        "n_cols": len(frame.columns),
    }


def extremes_html(data: ReportData, cols: list[str]) -> str:
    """Each column's minimum and maximum with the sample where it occurs, as a table.

    Parameters
    ----------
    data : ReportData
    cols : list of str
        The columns shown (the curves' columns).

    Returns
    -------
    str
        A ``<table>``, or a line saying no sample solved.
    """
    rows = []
    for c in cols:
        d = data.units(c)
        v = d.values(data.table.frame[c].to_numpy(dtype=np.float64))
        if not np.isfinite(v).any():
            continue
        i, j = int(np.nanargmin(v)), int(np.nanargmax(v))
        rows.append(
            f"<tr><td>{html.escape(c)}</td><td>{html.escape(pretty_unit(d.unit))}</td>"
            f'<td class="num">{v[i]:.5g}</td><td>{html.escape(data.name(i))}</td>'
            f'<td class="num">{v[j]:.5g}</td><td>{html.escape(data.name(j))}</td></tr>'
        )
    if not rows:
        return '<p class="muted">No solved samples.</p>'
    return (
        "<table><thead><tr><th>column</th><th>unit</th><th>min</th><th>at</th><th>max</th>"
        f"<th>at</th></tr></thead><tbody>{''.join(rows)}</tbody></table>"
    )
