"""Independent closed-form reference implementations of the seed papers' equations.

Each module in this package re-implements one paper's own equations (with the printed
misprints corrected and documented) in pure NumPy, SI units, batch axis first. They do **not**
use the general solver engine: they exist so that the engine can be tested against them.

Modules
-------
mo100
    Eremyants & Raiymbekova, crank-rocker hammer MO-100 on the EO-2621 manipulator
    (inertia forces, Assur-group reactions, housing reactions, half-sine fit).
pasika
    Pasika & Koruniak, cylinder-rod-rocker module with an internal driving link
    (positions, angular velocities and accelerations for any rod motion law).
"""

__all__ = ["ReferenceAssemblyError", "ReferenceSingularityError"]


class ReferenceAssemblyError(ValueError):
    """A reference mechanism cannot be assembled (a triangle inequality fails)."""


class ReferenceSingularityError(ArithmeticError):
    """A reference formula is evaluated at a singular (dead-point) configuration."""
