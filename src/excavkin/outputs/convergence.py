"""An optimisation's convergence: the best objective after each iteration (drawn by
[`excavkin.studies.plots.plot_convergence`][], which an `Optimum`'s ``plot`` uses too)."""

from __future__ import annotations

from excavkin.studies.plots import plot_convergence

__all__ = ["plot_convergence"]
