r"""Pin loads and cylinder forces of an excavator front over its working range.

At each pose (a set of cylinder lengths) one **load case** acts on the front at rest, with its
weight (the model's bodies and the cylinders, as
[`Machine.weight_loads`][excavkin.excavator.machine.Machine.weight_loads] puts them) unless
``gravity=False``:

* ``"bucket"``, ``"arm"`` — the tool force of that working cylinder as
  [`tool_forces`][excavkin.excavator.forces.tool_forces] gives it at that pose: the working cylinder
  at
  its working pressure, the force capped where a holding cylinder reaches its port relief; the
  soil pushes back on the bucket at the tool point (the lip, ISO 6015; or the tooth tip).
* ``"lift"`` — a load hanging straight down from the lift point (``[lift] point`` of the machine
  file, default the bucket pin): by default the **hydraulic lift capacity** at that pose
  (ISO 10567's, before its 87 % factor: the boom cylinders at working pressure, the arm and
  bucket cylinders within their port relief), or a given load, where the cylinders hold it.
  The load hangs from the bucket where the lift point is the bucket's, else from the first of
  the H-link, the side link and the stick that holds it.

The general kinetostatics ([`Mechanism.forces`][excavkin.mechanism.Mechanism.forces]) then gives the
force of every pin on every member it joins and every cylinder's force, and the **load of a
pin** is the largest force it passes to any one of its members
([`pin_forces`][excavkin.machinery.pin_loads.pin_forces], shared by every machine family,
writes it out).

Everything is one batch over the poses: three transfer solves for the tool force (or the lift
capacity) and one static solve with the loads.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Literal

import numpy as np
from numpy.typing import ArrayLike

from excavkin.arrays import BoolArray as B
from excavkin.arrays import FloatArray as F
from excavkin.errors import InputError
from excavkin.excavator.forces import At, tool_forces
from excavkin.excavator.lift import hydraulic_lift
from excavkin.excavator.machine import ROLES, Machine, as_lengths, length_columns
from excavkin.kinematics.summary import batch_repr
from excavkin.kinetostatics import ForceResult, PointForce
from excavkin.machinery.pin_loads import first_largest, pin_forces

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.axes import Axes

    from excavkin.excavator.plots import ExcavatorPlot

Case = Literal["bucket", "arm", "lift"]
#: the load cases, in the order of every table
CASES: tuple[Case, Case, Case] = ("bucket", "arm", "lift")

_ROLE_TEXT = {
    "foot": "boom foot",
    "stick_pivot": "stick pivot",
    "bucket_pin": "bucket pin",
    "link_pivot": "side-link pivot",
    "junction": "link junction",
    "link_pin": "H-link pin",
}


@dataclass(frozen=True, slots=True)
class PinLoads:
    """Pin loads and cylinder forces of one load case at n poses (SI: N, m).

    Attributes
    ----------
    case : {"bucket", "arm", "lift"}
        The load case: the bucket- or arm-cylinder tool force, or a lift load.
    gravity : bool
        The front's weight is included.
    pins : tuple of str
        The pins' point names, in the engine's order.
    labels : tuple of str
        What each pin is (``"bucket pin"``, ``"link junction / bucket cylinder rod eye"``).
    members : tuple of tuple of str
        Per pin, its members: the bodies pinned there and ``"<role> cylinder"`` at a cylinder's
        end.
    member_force : tuple of ndarray, shape (n, k)
        Per pin, the magnitude of the force it passes to each of its k members (N).
    load : ndarray, shape (n, n_pins)
        The pin's load: its largest member force (N); NaN where the pose does not assemble.
    cylinder_force : ndarray, shape (n, 3)
        Boom, arm and bucket cylinder forces (N, > 0 pushing), from the kinetostatics.
    tool_force : ndarray, shape (n,)
        Magnitude of the tool force or of the lift load (N).
    tool_point : ndarray, shape (n, 2)
        Where it acts (lip, tooth tip or lift point; m).
    bucket_pin : ndarray, shape (n, 2)
        The bucket pin (m).
    lengths : ndarray, shape (n, 3)
        Boom, arm and bucket cylinder lengths of the poses (m).
    held : ndarray of bool, shape (n,)
        The pose assembles within the strokes and the cylinders hold the load: not where they
        cannot even hold the front (no tool force, no lift capacity), nor where a given lift
        load exceeds the capacity; the maxima are taken over these.
    forces : ForceResult
        The engine's kinetostatics (every pin force on every body, by name).
    """

    def __repr__(self) -> str:
        return batch_repr(self)

    case: str
    gravity: bool
    pins: tuple[str, ...]
    labels: tuple[str, ...]
    members: tuple[tuple[str, ...], ...]
    member_force: tuple[F, ...]
    load: F
    cylinder_force: F
    tool_force: F
    tool_point: F
    bucket_pin: F
    lengths: F
    held: B
    forces: ForceResult = field(repr=False)


def pin_labels(machine: Machine) -> dict[str, str]:
    """What each pin of the front is, by point name (several roles joined by ``" / "``)."""
    p = machine.pins
    roles: dict[str, list[str]] = {}
    for key, text in _ROLE_TEXT.items():
        roles.setdefault(getattr(p, key), []).append(text)
    for role, (base, rod) in zip(ROLES, p.cyl_ends, strict=True):
        roles.setdefault(base, []).append(f"{role} cylinder base")
        roles.setdefault(rod, []).append(f"{role} cylinder rod eye")
    return {name: " / ".join(texts) for name, texts in roles.items()}


def _lift_carrier(machine: Machine) -> str:
    """The body a lift load hangs from: the bucket, else a bucket link, else the stick."""
    f = machine.front
    bodies = {b.name: b.points for b in machine.mechanism.model.bodies}
    for body in (f.bucket, f.h_link, f.side_link, f.stick):
        if machine.lift_point in bodies[body]:
            return body
    raise AssertionError("Machine checks that the lift point is on one of these bodies")


def _lift_load(machine: Machine, L: F, load: float | None, gravity: bool) -> tuple[F, F, B]:
    """Lift load (N), its point, and whether the cylinders hold it (and the front: a pose
    where they cannot even hold the front has no capacity)."""
    hyd = hydraulic_lift(machine, L, gravity=gravity)
    held = hyd.ok & (hyd.load > 0.0)
    if load is None:
        return hyd.load, hyd.point, held
    W = np.where(hyd.ok, load, np.nan)
    return W, hyd.point, np.asarray(held & (load <= hyd.load * (1.0 + 1e-12)))


def pin_loads(
    machine: Machine,
    lengths: ArrayLike,
    case: Case = "bucket",
    *,
    load: float | None = None,
    at: At = "lip",
    gravity: bool = True,
    progress: Callable[[int, int], None] | None = None,
) -> PinLoads:
    """Every pin's load and every cylinder's force under one load case, at each pose.

    Parameters
    ----------
    machine : Machine
    lengths : array_like, shape (n, 3)
        Boom, arm and bucket cylinder lengths (m).
    case : {"bucket", "arm", "lift"}
        The bucket- or arm-cylinder tool force (capped by the holding cylinders), or a lift load.
    load : float, optional
        For ``"lift"``: the load (N) at the lift point; default the hydraulic lift capacity of
        each pose.
    at : {"lip", "tip"}
        For the tool forces: the lip (ISO 6015) or the tooth tip (SAE J1179).
    gravity : bool
        Include the front's weight (in the tool force or capacity too).
    progress : callable, optional
        ``progress(done, 3)`` after the load, the poses and their forces are found.

    Returns
    -------
    PinLoads
    """
    if case not in CASES:
        raise InputError(f"case must be 'bucket', 'arm' or 'lift', not {case!r}")
    if load is not None and (case != "lift" or not (np.isfinite(load) and load >= 0.0)):
        raise InputError(
            "a load is given for the lift case only, finite and not negative "
            f"(case {case!r}, load {load!r})"
        )
    L = as_lengths(lengths)
    n = len(L)
    f = machine.front
    if case == "lift":
        W, point, held = _lift_load(machine, L, load, gravity)
        body, where = _lift_carrier(machine), machine.lift_point
        P = np.zeros((n, 2))
        P[:, 1] = -W
        magnitude = W
    else:
        tf = tool_forces(machine, L, case, at=at, gravity=gravity)
        body, where = f.bucket, (f.lip if at == "lip" else f.tip)
        # the soil pushes back on the bucket against the tool's motion
        P = -tf.force[:, None] * tf.direction
        magnitude = tf.force
        # a pose where the holding cylinders cannot even hold the front has no tool force
        held = np.asarray(tf.pose.ok & (tf.force > 0.0))

    def tell(done: int) -> None:
        if progress is not None:
            progress(done, 3)

    tell(1)
    res = machine.solve(L)  # at rest: no inertia
    tell(2)
    loads = [*(machine.weight_loads() if gravity else []), PointForce("tool", body, where, P)]
    fr = machine.mechanism.forces(res, loads)
    tell(3)
    held = np.asarray(held & fr.ok & machine.within_stroke(L))
    labels = pin_labels(machine)
    pf = pin_forces(fr, machine.cylinders, machine.pins.cyl_ends)
    return PinLoads(
        case,
        gravity,
        pf.pins,
        tuple(labels.get(p, p) for p in pf.pins),
        pf.members,
        pf.member_force,
        pf.load,
        pf.cylinder_force,
        magnitude,
        res.point(where)[0],
        res.point(machine.pins.bucket_pin)[0],
        L,
        held,
        fr,
    )


@dataclass(frozen=True, slots=True)
class LoadMaximum:
    """The largest load of one pin or cylinder over the poses and cases, and where it occurs.

    Attributes
    ----------
    name : str
        The pin's point name, or the cylinder's role.
    label : str
        What it is (``"bucket pin"``, ``"boom cylinder"``).
    kind : {"pin", "cylinder"}
        A pin's load or a cylinder's force.
    value : float
        N; for a cylinder the force of largest magnitude, signed (> 0 pushing).
    case : str
        The load case where it occurs.
    index : int
        Its pose in that case's arrays.
    lengths : ndarray, shape (3,)
        Boom, arm and bucket cylinder lengths of that pose (m).
    tool_point, bucket_pin : ndarray, shape (2,)
        Where the tool force acts and the bucket pin, at that pose (m).
    tool_force : float
        The tool force or lift load there (N).
    by_case : dict of str to float
        The largest magnitude in each case given (N).
    """

    name: str
    label: str
    kind: str
    value: float
    case: str
    index: int
    lengths: F
    tool_point: F
    bucket_pin: F
    tool_force: float
    by_case: dict[str, float]


def _maximum(
    results: Sequence[PinLoads], name: str, label: str, kind: str, column: int
) -> LoadMaximum:
    best: tuple[float, int, int] = (-np.inf, -1, -1)
    by_case: dict[str, float] = {}
    for r_i, r in enumerate(results):
        values = r.load[:, column] if kind == "pin" else np.abs(r.cylinder_force[:, column])
        v = np.where(r.held & np.isfinite(values), values, -np.inf)
        k = first_largest(v, prefer=r.tool_force)
        by_case[r.case] = float(np.max(v))
        if by_case[r.case] > best[0]:
            best = (by_case[r.case], r_i, k)
    value, r_i, k = best
    r = results[r_i]
    if kind == "cylinder":  # signed (> 0 pushing), of the largest magnitude
        value = float(np.copysign(value, r.cylinder_force[k, column]))
    return LoadMaximum(
        name,
        label,
        kind,
        value,
        r.case,
        k,
        r.lengths[k],
        r.tool_point[k],
        r.bucket_pin[k],
        float(r.tool_force[k]),
        by_case,
    )


def load_maxima(results: Sequence[PinLoads]) -> tuple[LoadMaximum, ...]:
    """Per pin, then per cylinder, the largest load over the held poses of all cases given.

    Parameters
    ----------
    results : sequence of PinLoads
        One per case, of the same machine.

    Returns
    -------
    tuple of LoadMaximum
        The pins in the engine's order, then the boom, arm and bucket cylinders.

    Raises
    ------
    InputError
        No results, results of different pins, or no pose of any case where the front holds.
    """
    if not results:
        raise InputError("no load case to take the maxima of")
    first = results[0]
    if any(r.pins != first.pins for r in results):
        raise InputError("the load cases belong to different machines (their pins differ)")
    if not any(r.held.any() for r in results):
        raise InputError("no pose of any load case assembles with the load held")
    out = [
        _maximum(results, p, lab, "pin", j)
        for j, (p, lab) in enumerate(zip(first.pins, first.labels, strict=True))
    ]
    out += [
        _maximum(results, role, f"{role} cylinder", "cylinder", c) for c, role in enumerate(ROLES)
    ]
    return tuple(out)


def largest_pin_loads(
    machine: Machine,
    lengths: ArrayLike,
    cases: Sequence[Case] = CASES,
    *,
    load: float | None = None,
    at: At = "lip",
    gravity: bool = True,
) -> tuple[tuple[PinLoads, ...], tuple[LoadMaximum, ...]]:
    """[`pin_loads`][excavkin.excavator.pin_loads.pin_loads] of each case at the poses, and
    `load_maxima` over them.

    Parameters
    ----------
    machine : Machine
    lengths : array_like, shape (n, 3)
        E.g. `stroke_grid`.
    cases : sequence of {"bucket", "arm", "lift"}
        The load cases, each as [`pin_loads`][excavkin.excavator.pin_loads.pin_loads]'s ``case``.
    load, at, gravity
        As [`pin_loads`][excavkin.excavator.pin_loads.pin_loads] (``load`` for the lift case).

    Returns
    -------
    results : tuple of PinLoads
    maxima : tuple of LoadMaximum
    """
    results = tuple(
        pin_loads(machine, lengths, c, load=load if c == "lift" else None, at=at, gravity=gravity)
        for c in cases
    )
    return results, load_maxima(results)


def lift_grid(samples: int) -> tuple[int, int, int]:
    """The stroke grid of the lift case for ``samples`` points per stroke of the others: a lift
    load's point moves with the boom and the stick, so a finer grid of those two, at about the
    same count of poses, covers its map and its maxima better.

    Parameters
    ----------
    samples : int
        Grid points per stroke of the tool-force cases' sweep.

    Returns
    -------
    (int, int, int)
        Boom, arm and bucket points: ``2 samples - 1``, ``2 samples - 1``,
        ``max(3, round(samples / 4))``.
    """
    return (2 * samples - 1, 2 * samples - 1, max(3, round(samples / 4)))


#: the kinds of `WorkingRangePinLoads.to_frame`'s columns
FRAME_KINDS: dict[str, str] = {
    **dict.fromkeys(("x", "y", "boom", "arm", "bucket", "pin_x", "pin_y"), "length"),
    **dict.fromkeys(("load", "tool_force", *(f"max_{c}" for c in CASES)), "force"),
}


@dataclass(frozen=True)
class WorkingRangePinLoads:
    """The largest load on each pin and in each cylinder over the working range, over the load
    cases given (`working_range_pin_loads`).

    Attributes
    ----------
    machine : Machine
    cases : tuple of str
        The load cases, in the order of `CASES`.
    samples : int
        Grid points per stroke of the tool-force cases' sweep.
    at : {"lip", "tip"}
        The tool point.
    gravity : bool
        With the front's weight.
    mass : float or None
        The lift load (kg); None for the hydraulic lift capacity at each pose.
    results : tuple of PinLoads
        One per case.
    maxima : tuple of LoadMaximum
        Per pin, then per cylinder (`load_maxima`).
    """

    machine: Machine
    cases: tuple[Case, ...]
    samples: int
    at: At
    gravity: bool
    mass: float | None
    results: tuple[PinLoads, ...]
    maxima: tuple[LoadMaximum, ...]

    def to_frame(self) -> pd.DataFrame:
        """One row per pin and cylinder: its largest load, the case and the pose, SI.

        Returns
        -------
        pandas.DataFrame
            ``name``, ``label``, ``kind``, ``load`` (N), ``case``, ``max_<case>`` per case
            (N), ``tool_force`` (N), the tool point ``x``, ``y`` and bucket pin ``pin_x``,
            ``pin_y`` (m), and the cylinder lengths ``boom``, ``arm``, ``bucket`` (m); its
            ``attrs`` name the machine and each column's kind.
        """

        from excavkin.kinematics.columns import kinds_frame

        rows = [
            {
                "name": mx.name,
                "label": mx.label,
                "kind": mx.kind,
                "load": mx.value,
                "case": mx.case,
                **{f"max_{c}": mx.by_case[c] for c in self.cases},
                "tool_force": mx.tool_force,
                "x": mx.tool_point[0],
                "y": mx.tool_point[1],
                "pin_x": mx.bucket_pin[0],
                "pin_y": mx.bucket_pin[1],
                **length_columns(mx.lengths),
            }
            for mx in self.maxima
        ]
        return kinds_frame(rows, FRAME_KINDS, self.machine.name)

    def summary(self) -> str:
        """The table of largest loads as ``excavkin excavator pins`` prints it (kN; mm).

        Returns
        -------
        str
        """
        m, chosen = self.machine, list(self.cases)
        grids = f"{self.samples}³ stroke sweep" if chosen != ["lift"] else ""
        if "lift" in chosen:
            grids += (", " if grids else "") + "{} × {} × {} for the lift load".format(
                *lift_grid(self.samples)
            )
        std = "ISO 6015, lip" if self.at == "lip" else "SAE J1179, tooth tip"
        lifted = "the hydraulic lift capacity" if self.mass is None else f"{self.mass:.0f} kg"
        text = {
            "bucket": f"bucket: bucket-cylinder tool force ({std})",
            "arm": f"arm: arm-cylinder tool force ({std})",
            "lift": f"lift: {lifted} hanging at {m.lift_point}",
        }
        lines = [
            f"{m.name} — pin loads and cylinder forces over the working range (kN; mm)",
            f"{grids}; {'with' if self.gravity else 'without'} the front's weight; cases: "
            + "; ".join(text[c] for c in chosen),
        ]
        if self.mass is not None:
            lift = self.results[chosen.index("lift")]
            lines.append(
                f"the front holds the lift load at {100 * lift.held.mean():.0f} % of the poses"
            )
        per_case = "".join(f" {c:>7}" for c in chosen)
        lines.append(
            f"{'pin':<7} {'what':<40} {'max':>7} {'case':<7}{per_case}  {'load':>6} "
            f"{'x':>6} {'y':>6}  {'boom':>5} {'arm':>5} {'bucket':>6}"
        )
        for mx in self.maxima:
            name = mx.name if mx.kind == "pin" else ""
            cells = "".join(f" {mx.by_case[c] / 1e3:7.1f}" for c in chosen)
            lines.append(
                f"{name:<7} {mx.label:<40} {mx.value / 1e3:7.1f} {mx.case:<7}{cells}  "
                f"{mx.tool_force / 1e3:6.1f} {mx.tool_point[0] * 1e3:6.0f} "
                f"{mx.tool_point[1] * 1e3:6.0f}  {mx.lengths[0] * 1e3:5.0f} "
                f"{mx.lengths[1] * 1e3:5.0f} {mx.lengths[2] * 1e3:6.0f}"
            )
        lines.append(
            "max: largest force the pin passes to one of its members (a cylinder: its force, "
            "> 0 pushing); load: the tool force or lift load there, acting at (x, y)"
        )
        return "\n".join(lines)

    def plot(self, *, ax: Axes | None = None) -> ExcavatorPlot:
        """Bar chart of the largest loads
        ([`plot_load_maxima`][excavkin.excavator.pin_plots.plot_load_maxima]).

        Parameters
        ----------
        ax : matplotlib Axes, optional

        Returns
        -------
        ExcavatorPlot
        """
        from excavkin.excavator.pin_plots import plot_load_maxima

        return plot_load_maxima(self.machine, self.maxima, ax=ax)

    def plot_maps(self) -> dict[str, ExcavatorPlot]:
        """Heat maps of the pin loads over the working range, one figure per case
        ([`plot_pin_maps`][excavkin.excavator.pin_plots.plot_pin_maps]).

        Returns
        -------
        dict of str to ExcavatorPlot
            Case → its figure.
        """
        from excavkin.excavator.pin_plots import plot_pin_maps

        return {r.case: plot_pin_maps(self.machine, r) for r in self.results}


def working_range_pin_loads(
    machine: Machine,
    cases: Sequence[Case] = CASES,
    *,
    samples: int = 31,
    mass: float | None = None,
    at: At = "lip",
    gravity: bool = True,
    stages: Callable[[], Callable[[int, int], None] | None] | None = None,
) -> WorkingRangePinLoads:
    """[`pin_loads`][excavkin.excavator.pin_loads.pin_loads] of each case over the working
    range and the largest load on each pin and cylinder: the tool-force cases over a
    ``samples``³ stroke grid, the lift case over `lift_grid` (``excavkin excavator pins``).

    Parameters
    ----------
    machine : Machine
    cases : sequence of {"bucket", "arm", "lift"}
        The load cases (taken in the order of `CASES`).
    samples : int, default 31
        Grid points per stroke (at least 2).
    mass : float, optional
        The lift load (kg); default the hydraulic lift capacity at each pose. Only with the
        lift case.
    at : {"lip", "tip"}
        The tool point: the lip (ISO 6015) or the tooth tip (SAE J1179).
    gravity : bool, default True
        With the front's weight.
    stages : callable, optional
        ``stages()`` → the next case's ``progress(done, total)`` (a staged progress bar).

    Returns
    -------
    WorkingRangePinLoads

    Raises
    ------
    InputError
        No case or an unknown one, a mass without the lift case or not a finite mass of 0 kg
        or more, fewer than 2 samples.
    """
    from excavkin.excavator.ranges import stroke_grid

    for c in cases:
        if c not in CASES:
            from excavkin.errors import unknown_name

            raise unknown_name("load case", str(c), list(CASES))
    chosen = tuple(c for c in CASES if c in cases)
    if not chosen:
        raise InputError("no load case")
    if int(samples) < 2:
        raise InputError(f"samples must be at least 2, not {samples}")
    if mass is not None:
        if "lift" not in chosen:
            raise InputError("a lift mass applies to the lift case only")
        if not (np.isfinite(mass) and mass >= 0.0):
            raise InputError(f"the lift mass must be a finite mass of 0 kg or more, not {mass}")
    weight = None if mass is None else mass * machine.gravity
    results = tuple(
        pin_loads(
            machine,
            stroke_grid(machine, lift_grid(samples) if case == "lift" else samples),
            case,
            load=weight if case == "lift" else None,
            at=at,
            gravity=gravity,
            progress=None if stages is None else stages(),
        )
        for case in chosen
    )
    return WorkingRangePinLoads(
        machine, chosen, int(samples), at, gravity, mass, results, load_maxima(results)
    )
