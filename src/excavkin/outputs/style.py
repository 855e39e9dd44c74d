"""The look of every figure, in one place: colours of bodies, cylinders, ground and warnings, and
the check of matplotlib line-style keywords.

Every renderer (matplotlib in `drawing` and `plots`,
plotly in `report`, SVG in `sketch`) takes its
colours from here.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

#: body colours (matplotlib's "tab10" without its grey), cycled over the moving bodies
BODY_COLORS = (
    "#1f77b4",
    "#ff7f0e",
    "#2ca02c",
    "#d62728",
    "#9467bd",
    "#8c564b",
    "#e377c2",
    "#bcbd22",
    "#17becf",
)
CYLINDER_COLOR = "#4d4d4d"
ROD_COLOR = "#a8a8a8"
GROUND_COLOR = "#333333"
FAIL_COLOR = "#d62728"
DEAD_COLOR = "#9467bd"
#: the block of a slider
SLIDER_FILL = "#dddddd"


#: dotted paths of moving points
PATH_COLOR = "#8a94a6"


def rgba(hex_color: str, alpha: float) -> str:
    """A colour (``"#rrggbb"``) with an opacity, as Plotly writes it: ``"rgba(r,g,b,a)"``.

    Parameters
    ----------
    hex_color : str
        One of this module's colours.
    alpha : float
        Opacity, 0 to 1.

    Returns
    -------
    str
    """
    h = hex_color.lstrip("#")
    r, g, b = (int(h[k : k + 2], 16) for k in (0, 2, 4))
    return f"rgba({r},{g},{b},{alpha})"


def check_line_style(style: Mapping[str, Any]) -> dict[str, Any]:
    """Normalise matplotlib ``Line2D`` keywords (``lw`` → ``linewidth``) and reject others.

    Raises
    ------
    TypeError
        Naming the keywords that are not ``Line2D`` properties.
    """
    from matplotlib import cbook
    from matplotlib.artist import ArtistInspector
    from matplotlib.lines import Line2D

    norm = cbook.normalize_kwargs(dict(style), Line2D)
    valid = set(ArtistInspector(Line2D).get_setters())
    bad = sorted(
        k for k in norm if k not in valid or k in ("data", "xdata", "ydata", "figure", "transform")
    )
    if bad:
        raise TypeError(
            f"unexpected keyword argument{'s' if len(bad) > 1 else ''} "
            f"{', '.join(map(repr, bad))}: style keywords must be matplotlib Line2D "
            "properties such as color, linewidth, linestyle, marker, alpha"
        )
    return dict(norm)
