"""The report's warnings section: the events of the result (dead positions, non-closure,
shocks, low transmission angles) as a list, or one line saying there are none.

The events are found by [`excavkin.outputs.events.find_events`][].
"""

from __future__ import annotations

import html

from excavkin.outputs.events import Event

__all__ = ["warnings_html"]


def warnings_html(events: list[Event]) -> str:
    """The warnings list's items, one per event, or an OK line when there are none.

    Parameters
    ----------
    events : list of Event
        From [`excavkin.outputs.events.find_events`][].

    Returns
    -------
    str
        ``<li>`` elements.
    """
    if not events:
        return (
            '<li class="ok"><span class="tag">OK</span>No dead positions, non-closure, shocks '
            "or low transmission angles found.</li>"
        )
    return "".join(
        f'<li class="{e.severity}"><span class="tag">{html.escape(e.kind)}</span>'
        f"{html.escape(e.message)}</li>"
        for e in events
    )
