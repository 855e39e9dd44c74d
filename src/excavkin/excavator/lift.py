r"""Lift capacity of a hydraulic excavator (ISO 10567): a table over load-point radius × height.

**Load point** — the bucket pin, or the machine file's ``[lift] point`` (a lifting hook on the
stick, the bucket or a link). Its radius is measured from the swing axis, its height from the
ground line, and the load hangs straight down from it.

**Posture** — a load point at (radius, height) fixes the boom and the stick (the boom foot, the
stick pivot and the load point form a triangle of known sides); the bucket is **fully curled**
(its cylinder at the end of its digging stroke), the reading of the usual lift-chart
conditions. Of the triangle's two sides the stick pivot is taken above the line boom foot →
load point (the backhoe's posture), or below it where only that one lies within the strokes.
The cylinder lengths come from the closed-form [`inverse`][excavkin.excavator.machine.inverse].

**Hydraulic lift capacity** — the largest load at the load point that the front holds with the
**lifting cylinder (the boom's) at the working pressure** of its circuit (the main relief: what
the pump can put behind it) and the **arm and bucket cylinders within their port relief
pressure** (what they hold before their overload valves open), the front's own weight
included. By virtual work, a load W straight down at P needs of cylinder c the force::

    f_c = W·∂y_P/∂L_c + g·Σ_k m_k·∂y_k/∂L_c                (> 0 pushes)

and the capacity is the least W at which one of them reaches its limit, which is named.
``pressure="relief"`` puts the lifting cylinder at its relief pressure instead.

**Tipping load** — the load at the load point that tips the whole machine
(`stability`), over the front (upper structure along the tracks, the
idler axis the tipping line) or over the side (swung 90°, the track's outer edge).

**Rated lift capacity** (ISO 10567) — the lesser of 75 % of the tipping load and 87 % of the
hydraulic lift capacity; a cell where the hydraulic part is the lesser is marked ``*`` (as spec
sheets mark it). Loads are reported as masses (kg = N / g). The bucket (and any link) stays on
the machine: its weight is the machine's, not the load's.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from excavkin.arrays import BoolArray as B
from excavkin.arrays import FloatArray as F
from excavkin.errors import InputError, ModelError
from excavkin.excavator.machine import (
    ROLES,
    Machine,
    as_lengths,
    circle_point,
    direction_angle,
    forward,
    inverse,
    transfer,
)
from excavkin.excavator.stability import SWING
from excavkin.kinematics.summary import batch_repr
from excavkin.machinery.capped_force import gravity_terms
from excavkin.machinery.equilibrium import equilibrium, need_base

if TYPE_CHECKING:
    import pandas as pd

#: ISO 10567 rating factors
TIPPING_FACTOR = 0.75
HYDRAULIC_FACTOR = 0.87
OVER: tuple[str, str] = ("front", "side")
Pressure = Literal["working", "relief"]


def curl_length(machine: Machine) -> float:
    """Bucket cylinder length with the bucket fully curled (end of its digging stroke) (m)."""
    c = machine.cylinders[2]
    return c.extended if c.dig == "extend" else c.retracted


def _frame_coords(p0: F, p1: F, x: F) -> F:
    """(s, t) of x in the frame p0 + s·w + t·perp(w), w = p1 − p0; shapes (..., 2)."""
    w = p1 - p0
    r = x - p0
    w2 = np.sum(w * w, axis=-1)
    s = np.sum(r * w, axis=-1) / w2
    t = (w[..., 0] * r[..., 1] - w[..., 1] * r[..., 0]) / w2
    return np.stack([s, t], axis=-1)


def _from_frame(p0: F, p1: F, st: F) -> F:
    w = p1 - p0
    perp = np.stack([-w[..., 1], w[..., 0]], axis=-1)
    return p0 + st[..., 0, None] * w + st[..., 1, None] * perp


def lift_poses(machine: Machine, points: ArrayLike) -> tuple[F, B]:
    """Cylinder lengths putting the load point at ``points`` with the bucket curled.

    Parameters
    ----------
    machine : Machine
    points : array_like, shape (n, 2)
        Load-point positions in the model's coordinates (m).

    Returns
    -------
    lengths : ndarray, shape (n, 3)
        NaN where no posture within the strokes reaches the point.
    reachable : ndarray of bool, shape (n,)
    """
    P = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    n = len(P)
    p = machine.pins
    curl = curl_length(machine)
    lo, hi = machine.lengths_min, machine.lengths_max
    # the stick, the curled bucket and its links move as one body: read the load point, the
    # bucket pin and the tip in the frame stick pivot → load point from one solve
    ref = forward(machine, np.array([[0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), curl]]))
    if not ref.ok[0]:
        raise ModelError(
            "the front does not assemble with the bucket curled and the boom and arm at "
            "mid-stroke, so the lift posture is unknown",
            table="cylinders.bucket",
            source=machine.source,
        )
    res = ref.result
    f0 = res.point(p.stick_pivot)[0][0]
    p0 = res.point(machine.lift_point)[0][0]
    q_st = _frame_coords(f0, p0, res.point(p.bucket_pin)[0][0])
    t_st = _frame_coords(f0, p0, ref.tip[0])
    r_fp = float(np.hypot(*(p0 - f0)))
    if r_fp < 1e-9:
        raise ModelError(
            "the lift point is the stick pivot; it cannot be placed by the front",
            table="lift",
            entry="point",
            source=machine.source,
        )
    a = np.broadcast_to(machine._ground_xy[p.foot], (n, 2))
    l_boom = machine.mechanism.plan.shapes[machine.front.boom].distance(p.foot, p.stick_pivot)
    out = np.full((n, 3), np.nan)
    found = np.zeros(n, dtype=bool)
    for side in (1.0, -1.0):  # the stick pivot above the line foot → load point first
        fp, ok = circle_point(a, l_boom, P, r_fp, side)
        q = _from_frame(fp, P, np.broadcast_to(q_st, (n, 2)))
        t = _from_frame(fp, P, np.broadcast_to(t_st, (n, 2)))
        beta = direction_angle(t - q)
        sol = inverse(machine, np.where(ok[:, None], t, 0.0), np.where(ok, beta, 0.0))
        curled = np.abs(sol.lengths[:, :, 2] - curl) <= 1e-6
        v = sol.valid & curled & ok[:, None]
        k = np.argmax(v, axis=1)
        take = v.any(axis=1) & ~found
        out[take] = sol.lengths[np.arange(n), k][take]
        found |= take
    return out, found


@dataclass(frozen=True, slots=True)
class HydraulicLift:
    """Hydraulic lift capacity at n poses.

    Attributes
    ----------
    load : ndarray, shape (n,)
        The largest load straight down at the load point that the cylinders hold (N); 0 where
        the front cannot hold itself, NaN where the pose does not assemble.
    limiting : ndarray of str, shape (n,)
        The cylinder that reaches its limit (``"boom"``, ``"arm"``, ``"bucket"``).
    cylinder_force : ndarray, shape (n, 3)
        The cylinders' forces with that load (N, > 0 pushing).
    point : ndarray, shape (n, 2)
        The load point (m).
    positions : ndarray, shape (n, n_points, 2)
        Every point of the model.
    ok : ndarray of bool, shape (n,)
    """

    def __repr__(self) -> str:
        return batch_repr(self)

    load: F
    limiting: NDArray[np.str_]
    cylinder_force: F
    point: F
    positions: F
    ok: B


def cylinder_limits(
    machine: Machine, lifting: str = "boom", pressure: Pressure = "working"
) -> tuple[F, F]:
    """Pull (≤ 0) and push (≥ 0) limits of the three cylinders while lifting, shape (3,) each:
    the lifting cylinder at ``pressure`` of its circuit, the others at their port relief."""
    lo, hi = np.zeros(3), np.zeros(3)
    for c, cyl in enumerate(machine.cylinders):
        circ = machine.circuits[cyl.circuit]
        p = circ.relief if (ROLES[c] != lifting or pressure == "relief") else circ.working
        lo[c], hi[c] = cyl.force_limits(p)
    return lo, hi


def hydraulic_lift(
    machine: Machine,
    lengths: ArrayLike,
    *,
    lifting: Literal["boom", "arm"] = "boom",
    pressure: Pressure = "working",
    gravity: bool = True,
) -> HydraulicLift:
    """The hydraulic lift capacity at each pose (see the module's text).

    Parameters
    ----------
    machine : Machine
    lengths : array_like, shape (n, 3)
        Boom, arm and bucket cylinder lengths (m).
    lifting : {"boom", "arm"}
        The lifting cylinder.
    pressure : {"working", "relief"}
        Its pressure: the circuit's working (main relief) pressure, or its port relief.
    gravity : bool
        Include the front's own weight (the cylinders carry it besides the load).

    Returns
    -------
    HydraulicLift
    """
    if lifting not in ("boom", "arm"):
        raise InputError(f"lifting must be 'boom' or 'arm', not {lifting!r}")
    if pressure not in ("working", "relief"):
        raise InputError(f"pressure must be 'working' or 'relief', not {pressure!r}")
    L = as_lengths(lengths)
    tr = transfer(machine, L)
    point, J = tr.point(machine, machine.lift_point)
    a = J[:, 1, :]  # ∂y_P/∂L_c: the load's share of each cylinder, per newton
    G = gravity_terms(machine, tr.d) if gravity else np.zeros_like(a)
    lo, hi = cylinder_limits(machine, lifting, pressure)
    with np.errstate(divide="ignore", invalid="ignore"):
        cap = np.where(a > 0.0, (hi - G) / a, np.where(a < 0.0, (lo - G) / a, np.inf))
    k = np.argmin(np.where(np.isnan(cap), np.inf, cap), axis=1)
    load = np.maximum(cap[np.arange(len(L)), k], 0.0)
    ok = tr.ok & np.all(np.isfinite(J), axis=(1, 2))
    load = np.where(ok, load, np.nan)
    limiting = np.where(ok, np.array(ROLES)[k], "")
    force = load[:, None] * a + G
    return HydraulicLift(load, limiting, force, point, tr.positions, ok)


@dataclass(frozen=True, slots=True)
class LiftCapacity:
    """Rated lift capacity (ISO 10567) at n poses, over the front and over the side.

    Attributes
    ----------
    rated : dict of str to ndarray, shape (n,)
        Keys ``"front"``, ``"side"``: min(0.75·tipping, 0.87·hydraulic) (N).
    hydraulic_limited : dict of str to ndarray of bool, shape (n,)
        The hydraulic part is the lesser (``*`` on a spec sheet).
    tipping : dict of str to ndarray, shape (n,)
        Tipping loads (N).
    tipping_line : dict of str to ndarray of str, shape (n,)
    hydraulic : HydraulicLift
    """

    def __repr__(self) -> str:
        return batch_repr(self)

    rated: dict[str, F]
    hydraulic_limited: dict[str, B]
    tipping: dict[str, F]
    tipping_line: dict[str, NDArray[np.str_]]
    hydraulic: HydraulicLift


def lift_capacity(
    machine: Machine,
    lengths: ArrayLike,
    *,
    lifting: Literal["boom", "arm"] = "boom",
    pressure: Pressure = "working",
) -> LiftCapacity:
    """Rated lift capacity at each pose (any posture), over the front and the side.

    Parameters
    ----------
    machine : Machine
        With a base.
    lengths : array_like, shape (n, 3)
    lifting, pressure
        As [`hydraulic_lift`][excavkin.excavator.lift.hydraulic_lift].

    Returns
    -------
    LiftCapacity
    """
    need_base(machine)
    hyd = hydraulic_lift(machine, lengths, lifting=lifting, pressure=pressure)
    rated, star, tip, line = {}, {}, {}, {}
    for over in OVER:
        st = equilibrium(
            machine, hyd.positions, hyd.point, np.array([0.0, -1.0]), SWING[over], hyd.ok
        )
        t_part = TIPPING_FACTOR * st.tipping_load
        h_part = HYDRAULIC_FACTOR * hyd.load
        rated[over] = np.minimum(t_part, h_part)
        star[over] = np.asarray(h_part < t_part)
        tip[over] = st.tipping_load
        line[over] = st.tipping_line
    return LiftCapacity(rated, star, tip, line, hyd)


@dataclass(frozen=True, slots=True)
class LiftTable:
    """A lift-capacity table over load-point radius × height (ISO 10567).

    Attributes
    ----------
    radii : ndarray, shape (R,)
        Load radius from the swing axis (m).
    heights : ndarray, shape (H,)
        Load-point height above the ground line (m).
    reachable : ndarray of bool, shape (H, R)
    lengths : ndarray, shape (H, R, 3)
        Cylinder lengths of each cell's posture (NaN where not reachable).
    capacity : LiftCapacity
        Of the H·R cells, flattened (height major); NaN where not reachable.
    max_reach : ndarray, shape (H,)
        Largest load radius reachable at each height (m; NaN where none).
    at_max_reach : LiftCapacity
        At those radii.
    max_reach_lengths : ndarray, shape (H, 3)
    point : str
        The load point.
    machine : str
        The machine's name (for the table and the summary).
    gravity : float
        g (m/s²): loads in kg are the capacities over it.
    lifting : {"boom", "arm"}
        The lifting cylinder.
    pressure : {"working", "relief"}
        The lifting cylinder's pressure.
    bucket_pin : bool
        Whether the load point is the bucket pin.
    """

    def __repr__(self) -> str:
        return f"LiftTable({len(self.heights)} heights × {len(self.radii)} radii at {self.point!r})"

    radii: F
    heights: F
    reachable: B
    lengths: F
    capacity: LiftCapacity
    max_reach: F
    at_max_reach: LiftCapacity
    max_reach_lengths: F
    point: str
    machine: str = ""
    gravity: float = 9.80665
    lifting: str = "boom"
    pressure: str = "working"
    bucket_pin: bool = False

    def rated(self, over: str) -> F:
        """Rated capacity (N), shape (H, R), over ``"front"`` or ``"side"``."""
        return self.capacity.rated[over].reshape(self.reachable.shape)

    def hydraulic_limited(self, over: str) -> B:
        """Cells where the hydraulic part governs, shape (H, R)."""
        return self.capacity.hydraulic_limited[over].reshape(self.reachable.shape)

    def _cells(self) -> list[tuple[int, float, float, int, LiftCapacity, int, F]]:
        """(height index, height, radius, radius index or -1 at max reach, capacity, its
        index, lengths) of every reachable cell, height by height, max reach last."""
        out = []
        R = len(self.radii)
        for i, h in enumerate(self.heights):
            for j, r in enumerate(self.radii):
                if self.reachable[i, j]:
                    out.append((i, float(h), float(r), j, self.capacity, i * R + j,
                                self.lengths[i, j]))  # fmt: skip
            if np.isfinite(self.max_reach[i]):
                out.append((i, float(h), float(self.max_reach[i]), -1, self.at_max_reach, i,
                            self.max_reach_lengths[i]))  # fmt: skip
        return out

    def to_frame(self) -> pd.DataFrame:
        """One row per reachable height, radius and side (over the front, over the side), the
        radius at max reach of each height included, SI.

        Returns
        -------
        pandas.DataFrame
            ``height``, ``radius`` (m), ``at_max_reach``, ``over``, ``rated_load`` (kg),
            ``limit`` (``"hydraulic"`` or ``"tipping"``), ``tipping_load`` (kg),
            ``tipping_line``, ``hydraulic_load`` (kg), ``hydraulic_limit`` and the cylinder
            lengths ``boom``, ``arm``, ``bucket`` (m); its ``attrs`` name the machine and each
            column's kind.
        """
        import pandas as pd

        from excavkin.kinematics.columns import kinds_attrs

        g = self.gravity
        rows = [
            {
                "height": h,
                "radius": r,
                "at_max_reach": j < 0,
                "over": over,
                "rated_load": cap.rated[over][k] / g,
                "limit": "hydraulic" if cap.hydraulic_limited[over][k] else "tipping",
                "tipping_load": cap.tipping[over][k] / g,
                "tipping_line": cap.tipping_line[over][k],
                "hydraulic_load": cap.hydraulic.load[k] / g,
                "hydraulic_limit": cap.hydraulic.limiting[k],
                "boom": L[0],
                "arm": L[1],
                "bucket": L[2],
            }
            for _, h, r, j, cap, k, L in self._cells()
            for over in ("front", "side")
        ]
        frame = pd.DataFrame(rows)
        kinds = {
            **dict.fromkeys(("boom", "arm", "bucket", "radius", "height"), "length"),
            **dict.fromkeys(("rated_load", "tipping_load", "hydraulic_load"), "mass"),
        }
        frame.attrs.update(
            kinds_attrs(self.machine, {c: k for c, k in kinds.items() if c in frame})
        )
        return frame

    def summary(self) -> str:
        """The lift chart as ``excavkin excavator lift`` prints it (kg; ``*``: the hydraulic
        capacity governs).

        Returns
        -------
        str
        """
        import math

        def kg(value: float, star: bool) -> str:
            if not math.isfinite(value):
                return ""
            return f"{value:,.0f}".replace(",", " ") + ("*" if star else " ")

        g = self.gravity
        others = "arm and bucket" if self.lifting == "boom" else "boom and bucket"
        lines = [
            f"{self.machine} — rated lift capacity (ISO 10567), kg; load point {self.point}"
            f"{' (bucket pin)' if self.bucket_pin else ''}, bucket curled",
            "the lesser of 75 % of the tipping load and 87 % of the hydraulic capacity "
            f"({self.lifting} cylinders at {self.pressure} pressure, {others} within their "
            "relief); * hydraulic",
            f"{'':>7}"
            + "".join(f" | {f'radius {r:.1f} m':^17}" for r in self.radii)
            + f" | {'at max reach':^26}",
            f"{'height':>7}"
            + f" | {'front':>8} {'side':>8}" * len(self.radii)
            + f" | {'radius':>8} {'front':>8} {'side':>8}",
        ]
        front, side = self.rated("front") / g, self.rated("side") / g
        sf, ss = self.hydraulic_limited("front"), self.hydraulic_limited("side")
        a = self.at_max_reach
        for i, h in enumerate(self.heights):
            cells = ""
            for j in range(len(self.radii)):
                if self.reachable[i, j]:
                    cells += f" | {kg(front[i, j], sf[i, j]):>8} {kg(side[i, j], ss[i, j]):>8}"
                else:
                    cells += f" | {'':>17}"
            if np.isfinite(self.max_reach[i]):
                cells += (
                    f" | {self.max_reach[i]:>6.2f} m"
                    f" {kg(a.rated['front'][i] / g, a.hydraulic_limited['front'][i]):>8}"
                    f" {kg(a.rated['side'][i] / g, a.hydraulic_limited['side'][i]):>8}"
                )
            lines.append(f"{h:6.1f}m{cells}")
        return "\n".join(lines)


def load_point_extent(machine: Machine, n: int = 41) -> tuple[F, F]:
    """Radius and height ranges of the load point over the boom and arm strokes with the
    bucket curled, ``(r_min, r_max)`` and ``(h_min, h_max)`` (m), from an n × n grid."""
    lo, hi = machine.lengths_min, machine.lengths_max
    b, a = np.meshgrid(np.linspace(lo[0], hi[0], n), np.linspace(lo[1], hi[1], n))
    L = np.column_stack([b.ravel(), a.ravel(), np.full(b.size, curl_length(machine))])
    res = forward(machine, L).result
    P = res.point(machine.lift_point)[0][res.status.ok]
    if not len(P):
        raise ModelError(
            "no pose with the bucket curled assembles", table="lift", source=machine.source
        )
    r = P[:, 0] - machine.swing_axis
    h = P[:, 1] - machine.ground_line
    return np.array([r.min(), r.max()]), np.array([h.min(), h.max()])


def default_grid(machine: Machine, step: float = 1.5) -> tuple[F, F]:
    """Radii (from 2·step to the largest reach) and heights (every step within reach), m."""
    if not step > 0.0:
        raise InputError("the grid step must be positive")
    (r0, r1), (h0, h1) = load_point_extent(machine)
    radii = step * np.arange(2, int(np.floor(r1 / step)) + 1)
    heights = step * np.arange(int(np.floor(h1 / step)), int(np.ceil(h0 / step)) - 1, -1)
    return radii.astype(np.float64), heights.astype(np.float64)


def _max_reach(machine: Machine, heights: F) -> tuple[F, F]:
    """Largest reachable load radius at each height and its lengths: the last reachable of a
    5 cm scan, then bisection to 1e-6 m (vectorised over heights)."""
    (r0, r1), _ = load_point_extent(machine)
    H = len(heights)
    scan = np.arange(max(r0 - 0.1, 0.0), r1 + 0.1, 0.05)
    pts = np.stack(
        [
            np.broadcast_to(machine.swing_axis + scan, (H, len(scan))),
            np.broadcast_to((machine.ground_line + heights)[:, None], (H, len(scan))),
        ],
        axis=-1,
    )
    _, ok = lift_poses(machine, pts.reshape(-1, 2))
    ok = ok.reshape(H, len(scan))
    has = ok.any(axis=1)
    last = len(scan) - 1 - np.argmax(ok[:, ::-1], axis=1)
    good = scan[last]
    bad = np.where(last + 1 < len(scan), scan[np.minimum(last + 1, len(scan) - 1)], good + 0.05)
    y = machine.ground_line + heights
    for _ in range(16):  # 5 cm / 2^16 < 1e-6 m
        mid = 0.5 * (good + bad)
        _, m_ok = lift_poses(machine, np.column_stack([machine.swing_axis + mid, y]))
        good = np.where(m_ok, mid, good)
        bad = np.where(m_ok, bad, mid)
    L, ok_final = lift_poses(machine, np.column_stack([machine.swing_axis + good, y]))
    reach = np.where(has & ok_final, good, np.nan)
    return reach, np.where((has & ok_final)[:, None], L, np.nan)


def lift_table(
    machine: Machine,
    radii: ArrayLike | None = None,
    heights: ArrayLike | None = None,
    *,
    step: float = 1.5,
    lifting: Literal["boom", "arm"] = "boom",
    pressure: Pressure = "working",
) -> LiftTable:
    """The rated lift capacity (ISO 10567) over a grid of load-point radius × height.

    Parameters
    ----------
    machine : Machine
        With a base.
    radii, heights : array_like, optional
        Load radius from the swing axis and height above the ground line (m); default every
        ``step`` within reach (`default_grid`).
    step : float
        Grid step of the default (m).
    lifting, pressure
        As [`hydraulic_lift`][excavkin.excavator.lift.hydraulic_lift].

    Returns
    -------
    LiftTable
    """
    need_base(machine)
    r_def, h_def = default_grid(machine, step) if radii is None or heights is None else (None, None)
    R = np.atleast_1d(np.asarray(radii if radii is not None else r_def, dtype=np.float64))
    H = np.atleast_1d(np.asarray(heights if heights is not None else h_def, dtype=np.float64))
    if R.ndim != 1 or H.ndim != 1 or not (np.all(np.isfinite(R)) and np.all(np.isfinite(H))):
        raise InputError("radii and heights must be finite 1-D lists")
    if not (len(R) and len(H)):
        raise InputError("the lift table needs at least one radius and one height")
    rr, hh = np.meshgrid(R, H)
    pts = np.column_stack([machine.swing_axis + rr.ravel(), machine.ground_line + hh.ravel()])
    L, ok = lift_poses(machine, pts)
    cap = lift_capacity(
        machine, np.where(ok[:, None], L, np.nan), lifting=lifting, pressure=pressure
    )
    reach, L_reach = _max_reach(machine, H)
    at_reach = lift_capacity(machine, L_reach, lifting=lifting, pressure=pressure)
    return LiftTable(
        R,
        H,
        ok.reshape(rr.shape),
        L.reshape(*rr.shape, 3),
        cap,
        reach,
        at_reach,
        L_reach,
        machine.lift_point,
        machine.name,
        machine.gravity,
        lifting,
        pressure,
        machine.lift_point == machine.pins.bucket_pin,
    )
