r"""A rope shovel along a dig: the drives' forces, the tooth's path and the digging margin.

The dig starts with the tooth tip on the ground at a crowd extension and runs with the hoist
motors at their rated speed, hauling in (rope speed v = ω·R/i), and the handle sliding out
along its rack at a fraction of the crowd's rated speed ω·r/i (> 0 crowds out), both constant,
until the hoist rope or the crowd reaches the end of its range; the crowd motor's speed follows
from the slide and the saddle's turn (the pinion is carried by the boom). At each of the
samples the general kinetostatics ([`Mechanism.forces`][excavkin.mechanism.Mechanism.forces])
holds the front — its weight and d'Alembert inertia, the payload's weight (the dipper filling
from empty to the rated payload over the dig, or a fixed fill) and the soil's digging
resistance at the tooth tip — with the crowd as a driver between the saddle and the handle and
the hoist as its winch. Its efforts are those of the drives by virtual work
([`pinion_efforts`][excavkin.shovel.dig.pinion_efforts]), the pinion on the shipper shaft
turning with the boom, not with the saddle:

* the **bail pull** (the hoist ropes' tension, all of them; per rope too) and the hoist motors'
  torque, speed and power;
* the **crowd force** (the rack's tooth force, > 0 crowds out) and the crowd motors' torque,
  speed and power;
* the tooth tip's path and speed.

The **digging resistance** is the machinery layer's soil model (`excavkin.machinery.soil`:
Zelenin, Balovnev or McKyes) for a cut of the given thickness and rake across the dipper's
width, acting at the tooth tip against its velocity (``along``) and across its path into the
bank (``normal``, the velocity turned clockwise: forward for an upward stroke). The **margin**
is the largest multiple of that resistance the motors overcome at their rated torque: the
drives' forces are affine in it (the weights and inertia, plus the resistance's part, solved
once each), so it is the least of (T_max − T₀)/T_R and the crowd's two bounds. A margin below 1
means the motors stall on that soil.

A rope never pushes: where the hoist would have to push, the row's status is
``slack rope 'hoist' (it would have to push)`` and ``ok`` is false; a row whose bail pull or
crowd force exceeds the motors' rated torque says so too.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.kinetostatics import ForceResult, PointForce
from excavkin.machinery.soil import MODELS, Tool, resistance, soil
from excavkin.shovel.envelope import floor_length
from excavkin.shovel.machine import Shovel, table_attrs

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.axes import Axes

    from excavkin.outputs.machine_plot import MachinePlot

#: the dig's defaults: cut thickness (m), rake (rad), crowd speed (fraction of rated)
DEPTH, RAKE, CROWD_SPEED, START = 0.8, np.radians(45.0), 0.1, 0.8


@dataclass(frozen=True, slots=True)
class Dig:
    """The rows of a dig, SI, shape (n,) each (module docstring).

    Attributes
    ----------
    machine : str
    soil : str
        The soil and its model, for titles (``"loam, McKyes"``).
    time, length, extension : ndarray
        s; the hoist rope's length and the crowd's extension (m).
    teeth : ndarray, shape (n, 2)
        The tooth tip (m).
    tooth_speed : ndarray
        m/s.
    fill : ndarray
        The payload's fraction.
    bail_pull, bail_pull_per_rope : ndarray
        The hoist ropes' tension, all and each (N).
    crowd_force : ndarray
        N, > 0 crowds out.
    hoist_torque, crowd_torque : ndarray
        Each motor's torque (N·m), in the sense of its angle (the crowd's > 0 crowds out).
    hoist_speed, crowd_speed : ndarray
        The motors' speeds (rad/s).
    hoist_power, crowd_power : ndarray
        The drives' power, all their motors (W; > 0 the motors drive).
    resistance_along, resistance_normal : ndarray
        The digging resistance (N).
    margin : ndarray
        The largest multiple of the resistance the rated motors overcome.
    status : ndarray of str
    forces : ForceResult
        The general kinetostatics of the rows (weights, inertia, payload, resistance).
    """

    machine: str
    soil: str
    time: F
    length: F
    extension: F
    teeth: F
    tooth_speed: F
    fill: F
    bail_pull: F
    bail_pull_per_rope: F
    crowd_force: F
    hoist_torque: F
    crowd_torque: F
    hoist_speed: F
    crowd_speed: F
    hoist_power: F
    crowd_power: F
    resistance_along: F
    resistance_normal: F
    margin: F
    status: np.ndarray
    forces: ForceResult

    @property
    def ok(self) -> np.ndarray:
        """Rows whose status is ``"ok"``, shape (n,)."""
        return np.asarray(self.status == "ok")

    def summary(self) -> str:
        """The dig's peaks and least margin, and the rows that are not ok.

        Returns
        -------
        str
        """
        ok = self.ok
        lines = [
            f"{self.machine}: along a dig ({self.soil}), {self.time.size} rows over "
            f"{self.time[-1]:.2f} s",
            f"  tooth tip from ({self.teeth[0, 0]:.2f}, {self.teeth[0, 1]:.2f}) m to "
            f"({self.teeth[-1, 0]:.2f}, {self.teeth[-1, 1]:.2f}) m, "
            f"speed {np.nanmin(self.tooth_speed):.2f}-{np.nanmax(self.tooth_speed):.2f} m/s",
        ]
        if ok.any():
            lines += [
                f"  bail pull       max {np.max(self.bail_pull[ok]) / 1e3:9.0f} kN "
                f"({np.max(self.bail_pull_per_rope[ok]) / 1e3:.0f} kN a rope)",
                f"  crowd force     {np.min(self.crowd_force[ok]) / 1e3:9.0f} .. "
                f"{np.max(self.crowd_force[ok]) / 1e3:.0f} kN",
                f"  hoist power     max {np.max(self.hoist_power[ok]) / 1e3:9.0f} kW",
                f"  crowd power     max {np.max(self.crowd_power[ok]) / 1e3:9.0f} kW",
                f"  resistance      max {np.max(self.resistance_along[ok]) / 1e3:9.0f} kN "
                "along the path",
                f"  margin          min {np.min(self.margin[ok]):9.2f} x the digging resistance",
            ]
        bad = np.flatnonzero(~ok)
        if bad.size:
            labels, counts = np.unique(self.status[bad], return_counts=True)
            for label, count in zip(labels, counts, strict=True):
                first = bad[self.status[bad] == label][0]
                lines.append(f"  not ok: {count} rows, {label} (first at {self.time[first]:.2f} s)")
        return "\n".join(lines)

    def to_frame(self) -> pd.DataFrame:
        """The rows as a table, SI; ``attrs`` record the machine and the columns' kinds and
        units.

        Returns
        -------
        pandas.DataFrame
        """
        import pandas as pd

        cols: dict[str, tuple[object, str]] = {
            "time": (self.time, "time"),
            "hoist_length": (self.length, "length"),
            "crowd_extension": (self.extension, "length"),
            "teeth_x": (self.teeth[:, 0], "length"),
            "teeth_y": (self.teeth[:, 1], "length"),
            "tooth_speed": (self.tooth_speed, "velocity"),
            "fill": (self.fill, "dimensionless"),
            "bail_pull": (self.bail_pull, "force"),
            "bail_pull_per_rope": (self.bail_pull_per_rope, "force"),
            "crowd_force": (self.crowd_force, "force"),
            "hoist_motor_torque": (self.hoist_torque, "torque"),
            "crowd_motor_torque": (self.crowd_torque, "torque"),
            "hoist_motor_speed": (self.hoist_speed, "angular_velocity"),
            "crowd_motor_speed": (self.crowd_speed, "angular_velocity"),
            "hoist_power": (self.hoist_power, "power"),
            "crowd_power": (self.crowd_power, "power"),
            "resistance_along": (self.resistance_along, "force"),
            "resistance_normal": (self.resistance_normal, "force"),
            "margin": (self.margin, "dimensionless"),
        }
        frame = pd.DataFrame({k: v for k, (v, _) in cols.items()})
        frame["status"] = self.status
        frame.attrs.update(table_attrs(self.machine, {k: kind for k, (_, kind) in cols.items()}))
        return frame

    def plot(self, machine: Shovel, *, ax: Axes | None = None) -> MachinePlot:
        """Bail pull and crowd force against the motors' limits, and the margin, over the
        tooth tip's height.

        Parameters
        ----------
        machine : Shovel
            The machine of this dig.
        ax : matplotlib Axes, optional

        Returns
        -------
        MachinePlot
        """
        from excavkin.shovel.plots import plot_dig

        return plot_dig(machine, self, ax=ax)


def dig(
    machine: Shovel,
    *,
    samples: int = 101,
    extension: float | None = None,
    crowd_speed: float = CROWD_SPEED,
    soil_name: str = "loam",
    model: str = "mckyes",
    depth: float = DEPTH,
    rake: float = RAKE,
    fill: float | None = None,
) -> Dig:
    """The forces along a dig (module docstring).

    Parameters
    ----------
    machine : Shovel
    samples : int, default 101
        Rows (≥ 3).
    extension : float, optional
        The crowd's extension at the start (m); default 80 % of the way out along its range.
    crowd_speed : float, default 0.1
        The handle's slide speed as a fraction of the crowd's rated speed ω·r/i, in [−1, 1]
        (> 0 crowds out).
    soil_name : str, default "loam"
        A soil of `excavkin.machinery.soil.SOILS`.
    model : {"zelenin", "balovnev", "mckyes"}, default "mckyes"
    depth : float, default 0.8
        The cut's thickness (m).
    rake : float, default 45°
        The teeth's rake to the path (rad).
    fill : float, optional
        A fixed payload fraction in [0, 1]; default filling from 0 to 1 over the dig.

    Returns
    -------
    Dig

    Raises
    ------
    InputError
        A value out of its range, an unknown soil or model, or a start the tooth does not
        reach (no rope length puts it on the ground there).
    """
    from excavkin.errors import InputError

    if not 3 <= samples <= 100_000:
        raise InputError(f"samples must be from 3 to 100000, not {samples}")
    if not -1.0 <= crowd_speed <= 1.0:
        raise InputError(f"crowd speed must be a fraction from -1 to 1, not {crowd_speed}")
    if model not in MODELS:
        raise InputError(f"unknown soil model {model!r}; known models: {', '.join(MODELS)}")
    ground = soil(soil_name)
    if not 0.0 < depth <= 10.0:
        raise InputError(f"depth must be in (0, 10] m, not {depth}")
    if not 0.0 < rake < np.pi:
        raise InputError(f"rake must be in (0, 180) deg, not {np.degrees(rake):.6g} deg")
    if fill is not None and not 0.0 <= fill <= 1.0:
        raise InputError(f"fill must be in [0, 1], not {fill}")
    lo_s, hi_s = machine.crowd.extension
    s0 = lo_s + START * (hi_s - lo_s) if extension is None else float(extension)
    if not lo_s <= s0 <= hi_s:
        raise InputError(f"extension {s0:.6g} m is outside the crowd's range {lo_s:g}-{hi_s:g} m")
    lo_l, hi_l = machine.hoist.length
    L0 = float(floor_length(machine, np.array([hi_l]), np.array([s0]))[0])
    if not np.isfinite(L0):
        raise InputError(
            f"at a crowd extension of {s0:.6g} m no hoist rope length in {lo_l:g}-{hi_l:g} m "
            "puts the tooth tip on the ground"
        )
    v_h = machine.hoist.speed
    v_c = crowd_speed * machine.crowd.speed
    t_end = (L0 - lo_l) / v_h
    if v_c > 0.0:
        t_end = min(t_end, (hi_s - s0) / v_c)
    elif v_c < 0.0:
        t_end = min(t_end, (lo_s - s0) / v_c)
    t = np.linspace(0.0, t_end, samples)
    L, s = L0 - v_h * t, s0 + v_c * t
    kin = machine.solve(L, s, np.full_like(t, -v_h), np.full_like(t, v_c))
    tip, vel, _ = kin.point(machine.front.teeth)
    speed = np.hypot(vel[:, 0], vel[:, 1])
    unit = vel / np.where(speed > 0.0, speed, 1.0)[:, None]
    into = np.stack([unit[:, 1], -unit[:, 0]], axis=1)  # the velocity turned clockwise

    tool = Tool(width=machine.dipper.width, normal_ratio=0.2)
    res = resistance(
        model, np.full_like(t, depth), np.full_like(t, rake), ground, tool,
        g=machine.gravity,
    )  # fmt: skip
    soil_force = -res.along[:, None] * unit + res.normal[:, None] * into
    f_soil = PointForce("digging resistance", machine.front.dipper, machine.front.teeth, soil_force)
    frac = t / t_end if fill is None else np.full_like(t, fill)
    forces = machine.mechanism.forces(kin, [*machine.weight_loads(frac), f_soil])
    # the resistance's part alone: the same poses at rest, no weight, no inertia
    static = machine.solve(L, s)
    part = machine.mechanism.forces(static, [f_soil])

    rope, crowd = machine.hoist.rope, machine.crowd.driver
    a, b = _saddle_transfer(machine, L, s)
    efforts = pinion_efforts(machine, forces.force(crowd), forces.winch_torque(rope), a, b)
    parts = pinion_efforts(machine, part.force(crowd), part.winch_torque(rope), a, b)
    pull, tooth = efforts.pull, efforts.tooth
    margin = _margin(pull - parts.pull, parts.pull, machine.hoist.pull,
                     tooth - parts.tooth, parts.tooth, machine.crowd.force)  # fmt: skip

    status = forces.kinematics.status.labels().astype(object)
    kin_ok = forces.kinematics.status.ok
    status[forces.singular & kin_ok] = "statically singular (redundant joint at this position)"
    good = status == "ok"
    status[good & (pull < 0.0)] = f"slack rope {rope!r} (it would have to push)"
    good = status == "ok"
    status[good & (pull > machine.hoist.pull)] = "bail pull over the hoist motors' rated torque"
    over = good & (np.abs(tooth) > machine.crowd.force)
    status[over] = "crowd force over the crowd motors' rated torque"

    theta_rate = kin.driver(rope)[1]
    omega_sad = kin.body(machine.front.saddle)[1]
    crowd_rate = machine.crowd.gear_ratio * (
        v_c / machine.crowd.pinion_radius - machine.crowd.sigma * omega_sad
    )
    return Dig(
        machine=machine.name,
        soil=f"{soil_name}, {model}",
        time=t,
        length=L,
        extension=s,
        teeth=tip,
        tooth_speed=speed,
        fill=frac,
        bail_pull=pull,
        bail_pull_per_rope=pull / machine.hoist.ropes,
        crowd_force=tooth,
        hoist_torque=efforts.hoist / machine.hoist.motor.count,
        crowd_torque=efforts.crowd / machine.crowd.motor.count,
        hoist_speed=theta_rate,
        crowd_speed=crowd_rate,
        hoist_power=efforts.hoist * theta_rate,
        crowd_power=efforts.crowd * crowd_rate,
        resistance_along=np.asarray(res.along, float),
        resistance_normal=np.asarray(res.normal, float),
        margin=margin,
        status=np.asarray(status, dtype=str),
        forces=forces,
    )


@dataclass(frozen=True, slots=True)
class Efforts:
    """The drives' efforts with the crowd pinion on the boom (`pinion_efforts`), shape (n,).

    Attributes
    ----------
    crowd : ndarray
        The crowd motors' torque, all of them, in the sense of the crowd-out motor angle (N·m).
    hoist : ndarray
        The hoist motors' torque, all of them, in the sense of their angle (N·m).
    tooth : ndarray
        The rack's tooth force, W = τ_crowd·i/r (N, > 0 crowds out).
    pull : ndarray
        The hoist ropes' tension, T = −τ_hoist·i/R (N).
    """

    crowd: F
    hoist: F
    tooth: F
    pull: F


def _saddle_transfer(machine: Shovel, length: F, extension: F) -> tuple[F, F]:
    """The saddle's turn per metre of crowd slide and per radian of the hoist motor, shape (n,)
    each: two solves of the engine's velocities with unit rates."""
    rope, crowd = machine.hoist.rope, machine.crowd.driver
    inputs = {rope: machine.hoist.angle(length), crowd: extension}
    one, zero = np.ones_like(length), np.zeros_like(length)
    per_s = machine.mechanism.solve(inputs, rates={rope: zero, crowd: one})
    per_h = machine.mechanism.solve(inputs, rates={rope: one, crowd: zero})
    return per_s.body(machine.front.saddle)[1], per_h.body(machine.front.saddle)[1]


def pinion_efforts(machine: Shovel, force: F, torque: F, a: F, b: F) -> Efforts:
    """The drives' efforts with the crowd pinion on the boom, from the general kinetostatics'
    crowd-driver force and hoist torque (the crowd as a driver between saddle and handle).

    The crowd motor's angle is θm = i·(s/r − σ·θsaddle) + const (`excavkin.shovel.machine`),
    so δθm = i·((1/r − σ·a)·δs − σ·b·δθh) with a and b the saddle's turn per metre of slide and
    per radian of the hoist motor. The configurations and the loads are the same in both
    coordinates, so their virtual work is: F·δs + τh·δθh = τm·δθm + τh'·δθh, whence

        τm = F / (i·(1/r − σ·a)),    τh' = τh + σ·i·b·τm.

    Parameters
    ----------
    machine : Shovel
    force : ndarray, shape (n,)
        The crowd driver's force (N, > 0 pushes the handle out).
    torque : ndarray, shape (n,)
        The hoist winch's torque (N·m).
    a, b : ndarray, shape (n,)
        The saddle's turn per metre of slide (rad/m) and per radian of the hoist motor.

    Returns
    -------
    Efforts
    """
    c, h = machine.crowd, machine.hoist
    crowd = force / (c.gear_ratio * (1.0 / c.pinion_radius - c.sigma * a))
    hoist = torque + c.sigma * c.gear_ratio * b * crowd
    return Efforts(
        crowd, hoist, crowd * c.gear_ratio / c.pinion_radius, -hoist * h.gear_ratio / h.drum_radius
    )


def _margin(t0: F, tr: F, t_max: float, f0: F, fr: F, f_max: float) -> F:
    """The largest k ≥ 0 with t0 + k·tr ≤ t_max and |f0 + k·fr| ≤ f_max (0 where even k = 0
    is beyond them, inf where nothing bounds it)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        k_t = np.where(tr > 0.0, (t_max - t0) / tr, np.inf)
        k_f = np.where(fr > 0.0, (f_max - f0) / fr, np.where(fr < 0.0, (-f_max - f0) / fr, np.inf))
    k = np.minimum(k_t, k_f)
    beyond = (t0 > t_max) | (np.abs(f0) > f_max)
    return np.where(beyond, 0.0, np.maximum(k, 0.0))
