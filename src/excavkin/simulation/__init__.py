"""Runs in time: drives a mechanism's inputs by motion laws (:mod:`~excavkin.simulation.timeline`)
and reports their exact shocks (:mod:`~excavkin.simulation.shocks`).

Import the modules directly, e.g. ``from excavkin.simulation.timeline import simulate``.
"""
