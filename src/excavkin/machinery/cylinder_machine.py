"""What every family's machine with hydraulic cylinders has in common: a general mechanism
driven by cylinders in the order of the roles its family declares, each on a circuit.

A family's machine (the excavator's [`Machine`][excavkin.excavator.machine.Machine], the wheel
loader's [`Loader`][excavkin.loader.machine.Loader]) derives from
[`CylinderMachine`][excavkin.machinery.cylinder_machine.CylinderMachine], sets its ``ROLES``
and fills ``mechanism``, ``cylinders`` (in role order), ``circuits``, ``gravity``, ``source``
and ``pins`` (whose ``cyl_ends`` names each cylinder's two end pins); the strokes, the checks
of a cylinder, the solve at cylinder lengths and the weight as loads are then the same for
every family.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike

from excavkin.arrays import BoolArray as B
from excavkin.arrays import FloatArray as F
from excavkin.errors import ModelError
from excavkin.machinery.cylinders import Circuit, Cylinder, cylinder_lengths

if TYPE_CHECKING:
    from excavkin.kinematics import KinematicResult
    from excavkin.mechanism import Mechanism
    from excavkin.model.entities import Load

__all__ = ["CylinderMachine"]


class CylinderMachine:
    """A mechanism driven by cylinders, one per role of its family, each on a circuit.

    Attributes
    ----------
    ROLES : tuple of str (class attribute)
        The family's cylinder roles: the order of ``cylinders`` and of every ``(n, k)`` array
        of lengths.
    mechanism : Mechanism
    cylinders : tuple of Cylinder
        In the order of ``ROLES``.
    circuits : dict of str to Circuit
    gravity : float
        m/s².
    source : str or None
        The machine file, for messages.
    """

    ROLES: ClassVar[tuple[str, ...]] = ()
    mechanism: Mechanism
    cylinders: tuple[Cylinder, ...]
    circuits: dict[str, Circuit]
    gravity: float
    source: str | None
    pins: Any

    def _err(self, problem: str, table: str | None = None, entry: str | None = None) -> ModelError:
        return ModelError(problem, table=table, entry=entry, source=self.source)

    def _check_cylinder(self, c: Cylinder) -> None:
        """Refuse a cylinder that no driven linear driver of the model carries, or whose
        dimensions, count or circuit cannot be, naming its table and entry."""
        table = f"cylinders.{c.role}"
        model = self.mechanism.model
        drivers = {d.name: d for d in model.linear}
        if c.driver not in drivers or drivers[c.driver].mode != "driven":
            known = ", ".join(d.name for d in model.linear if d.mode == "driven") or "none"
            raise self._err(
                f"driver {c.driver!r} is not a driven linear driver of the model "
                f"(driven ones: {known})",
                table,
                "driver",
            )
        for key, val in (("retracted", c.retracted), ("stroke", c.stroke), ("bore", c.bore)):
            if not val > 0.0:
                raise self._err(f"{key} must be positive", table, key)
        if not 0.0 <= c.rod < c.bore:
            raise self._err("the rod diameter must be smaller than the bore", table, "rod")
        if c.count < 1:
            raise self._err("count must be at least 1", table, "count")
        if c.circuit not in self.circuits:
            raise self._err(
                f"unknown circuit {c.circuit!r} (known: {', '.join(self.circuits) or 'none'})",
                table,
                "circuit",
            )
        circ = self.circuits[c.circuit]
        if not 0.0 < circ.working <= circ.relief:
            raise self._err(
                "needs 0 < working pressure ≤ relief pressure", f"circuits.{c.circuit}", "working"
            )

    def index(self, point: str) -> int:
        """The engine's index of a point of the model (its column in a result's arrays).

        Parameters
        ----------
        point : str

        Returns
        -------
        int
        """
        return self.mechanism.plan.points.index(point)

    @property
    def roles(self) -> tuple[str, ...]:
        """The family's cylinder roles: the order of every ``(n, k)`` array of lengths."""
        return type(self).ROLES

    @property
    def drivers(self) -> tuple[str, ...]:
        """The model's drivers of the cylinders, in role order."""
        return tuple(c.driver for c in self.cylinders)

    @property
    def lengths_min(self) -> F:
        """Fully retracted lengths, shape (k,) (m)."""
        return np.array([c.retracted for c in self.cylinders])

    @property
    def lengths_max(self) -> F:
        """Fully extended lengths, shape (k,) (m)."""
        return np.array([c.extended for c in self.cylinders])

    def circuit(self, role: str) -> Circuit:
        """The circuit of the cylinder ``role``.

        Parameters
        ----------
        role : str
            One of `roles`.

        Returns
        -------
        Circuit
            The pressures of the circuit that cylinder is on.

        Raises
        ------
        UnknownNameError
            Another role, with the nearest ones.
        """
        if role not in self.roles:
            from excavkin.errors import unknown_name

            raise unknown_name("cylinder role", role, list(self.roles))
        return self.circuits[self.cylinders[self.roles.index(role)].circuit]

    def within_stroke(self, lengths: ArrayLike, tol: float = 1e-9) -> B:
        """Whether each row of ``lengths`` lies within every cylinder's stroke.

        Parameters
        ----------
        lengths : array_like, shape (..., k)
            Cylinder lengths (m), in role order.
        tol : float
            Allowance beyond either end (m).

        Returns
        -------
        ndarray of bool, shape (...)
        """
        L = np.asarray(lengths, dtype=np.float64)
        lo, hi = self.lengths_min - tol, self.lengths_max + tol
        return np.asarray(np.all((lo <= L) & (hi >= L), axis=-1))

    def weight_loads(self) -> list[Load]:
        """The machine's moving weight as loads of the general kinetostatics: the model's
        bodies ([`Gravity`][excavkin.kinetostatics.Gravity]) and half of each cylinder's mass at
        each end pin on a moving body (a [`PointForce`][excavkin.kinetostatics.PointForce]).

        Returns
        -------
        list of Gravity or PointForce
            The gravity load first, then ``DRIVER@PIN``: half of a cylinder's weight (N) at
            each of its end pins on a moving body, for the cylinders that have a mass.
        """
        from excavkin.kinetostatics import Gravity, PointForce

        loads: list[Load] = [Gravity(self.gravity)]
        moving = [b for b in self.mechanism.model.bodies if not b.ground]
        ends: Sequence[tuple[str, str]] = self.pins.cyl_ends
        for cyl, pair in zip(self.cylinders, ends, strict=True):
            for pin in pair:
                body = next((b.name for b in moving if pin in b.points), None)
                if cyl.mass > 0.0 and body is not None:
                    w = (0.0, -0.5 * cyl.mass * self.gravity)
                    loads.append(PointForce(f"{cyl.driver}@{pin}", body, pin, w))
        return loads

    def solve(self, lengths: ArrayLike, rates: ArrayLike | None = None) -> KinematicResult:
        """Run the general engine at cylinder lengths (at rest unless rates are given).

        Parameters
        ----------
        lengths : array_like, shape (n, k)
            Cylinder lengths (m), in role order.
        rates : array_like, shape (n, k) or (k,), optional
            Their rates (m/s); default zero, so that velocities are zero. A one-hot row makes
            the velocities the transfer functions ∂(·)/∂L of that cylinder.

        Returns
        -------
        KinematicResult
        """
        L = cylinder_lengths(lengths, self.roles)
        R = (
            np.zeros_like(L)
            if rates is None
            else np.broadcast_to(np.asarray(rates, dtype=np.float64), L.shape)
        )
        return self.mechanism.solve(
            {d: L[:, i] for i, d in enumerate(self.drivers)},
            {d: R[:, i] for i, d in enumerate(self.drivers)},
        )
