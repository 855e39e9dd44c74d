"""A self-contained HTML report of a solved mechanism.

One file, no network needed to view it: the model summary and solve plan, an interactive view of
the mechanism with a slider over the samples and play/pause, the main curves (zoomable), the
warnings (dead positions, non-closure, shocks, low transmission angles) and the result table as
a download. The interactive parts are Plotly figures; plotly.js is embedded in the file.

The report draws what it is given and never solves: the caller solves (for instance over
[`excavkin.default_sweep.default_sweep`][]) and hands the result over.

>>> import excavkin
>>> from excavkin.default_sweep import default_sweep
>>> from excavkin.outputs.report import write_report
>>> mech = excavkin.load(excavkin.example_path("fourbar"))
>>> result = mech.solve(default_sweep(mech))
>>> # write_report(mech, result, "fourbar.html")

One module a concern:

* `document` — the template filled, the file written;
* `data` — what the sections read: the table, units, x axis;
* `mechanism` — the moving mechanism (Plotly);
* `curves` — the curves (Plotly);
* `warnings` — the events found in the result;
* `table` — the table download and the extremes.

Plotly is imported inside the functions only. ``default_sweep``, ``solve_default``,
``N_ROTARY``, ``N_LINEAR`` and ``STROKE`` live in `excavkin.default_sweep`; they are
named here too, as before.
"""

from excavkin.default_sweep import N_LINEAR, N_ROTARY, STROKE, default_sweep, solve_default
from excavkin.outputs.report.curves import MAX_CURVE_POINTS, curves_figure
from excavkin.outputs.report.document import HTML_SUFFIXES, build_report, write_report
from excavkin.outputs.report.mechanism import MAX_FRAMES, mechanism_figure

__all__ = [
    "HTML_SUFFIXES",
    "MAX_CURVE_POINTS",
    "MAX_FRAMES",
    "N_LINEAR",
    "N_ROTARY",
    "STROKE",
    "build_report",
    "curves_figure",
    "default_sweep",
    "mechanism_figure",
    "solve_default",
    "write_report",
]
