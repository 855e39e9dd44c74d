"""Runs in time: drives a mechanism's inputs by motion laws (`timeline`)
and reports their exact shocks (`shocks`).

Import the modules directly, e.g. ``from excavkin.simulation.timeline import simulate``.
"""
