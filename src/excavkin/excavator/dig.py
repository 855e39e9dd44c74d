r"""Digging resistance along a dig, against the force the machine can exert there.

A dig is a path in cylinder space, lengths shape (n, 3) (given, or from one pose to another,
spaced by a motion law). At each point:

- the tool point (the lip, ISO 6015) and its direction of motion t = J·L′/|J·L′|, L′ the
  path's tangent in cylinder space (central differences over the samples; the direction of
  J·L̇ for any timing of the same path);
- the depth below the ground line, d = y_ground − y (the thickness of the cut for a single
  pass under a level surface); out of the soil (d ≤ 0) there is no resistance;
- the cutting (rake) angle α between the cutting face — from the edge back along the teeth
  (tip → lip), or along the floor of a bucket without teeth — and the path behind the edge,
  on the side of the free surface (the cut frame's normal n: the unit normal to t pointing
  up);
- the soil resistance of the chosen model (`excavkin.excavator.soil`): ``along`` against
  t, ``normal`` along −n, so the tool must exert R = along·t + normal·n on the soil;
- the available force along R's direction
([`directed_force`][excavkin.excavator.forces.directed_force]:
  the cylinders doing the work at working pressure, the others at their port relief, the
  front's weight counted), capped by tipping and slipping where the machine has a base;
- the margin, available − |R|: the dig stalls at the first point where it is negative.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from excavkin.arrays import FloatArray as F
from excavkin.errors import InputError
from excavkin.excavator.forces import At, directed_force
from excavkin.excavator.machine import (
    FrontPose,
    Machine,
    as_lengths,
    mm_field,
    pose_of,
    transfer,
)
from excavkin.excavator.stability import SWING, Over
from excavkin.kinematics.summary import batch_repr
from excavkin.machinery.equilibrium import equilibrium
from excavkin.machinery.soil import Resistance, Soil, Tool, resistance
from excavkin.motion import get_law

if TYPE_CHECKING:
    import pandas as pd


@dataclass(frozen=True, slots=True)
class Dig:
    """Resistance and available force along a dig of n points.

    Attributes
    ----------
    model : str
    soil : Soil
    tool : Tool
    lengths : ndarray, shape (n, 3)
    point : ndarray, shape (n, 2)
        The tool point (m).
    depth : ndarray, shape (n,)
        Below the ground line (m; ≤ 0 out of the soil).
    direction : ndarray, shape (n, 2)
        Unit direction of motion t.
    rake : ndarray, shape (n,)
        Cutting angle α (rad).
    resistance : Resistance
        The model's force (cut frame).
    required : ndarray, shape (n,)
        |R|, the force the tool must exert on the soil (N).
    load : ndarray, shape (n, 2)
        Unit direction of R (t where there is no resistance).
    available : ndarray, shape (n,)
        The largest force along ``load`` (N), every cap applied.
    limiting : ndarray of str, shape (n,)
        The cylinder, ``"tipping (<line>)"`` or ``"slipping"`` that caps ``available``.
    margin : ndarray, shape (n,)
        available − required (N).
    stall : int
        First point in the soil with a negative margin; −1 where the dig goes through.
    pose : FrontPose
    machine : str
        The machine's name (for the table and the summary).
    """

    def __repr__(self) -> str:
        return batch_repr(self)

    model: str
    soil: Soil
    tool: Tool
    lengths: F
    point: F
    depth: F
    direction: F
    rake: F
    resistance: Resistance
    required: F
    load: F
    available: F
    limiting: NDArray[np.str_]
    margin: F
    stall: int
    pose: FrontPose
    machine: str = ""

    def to_frame(self) -> pd.DataFrame:
        """One row per point of the dig, SI.

        Returns
        -------
        pandas.DataFrame
            ``point``, the cylinder lengths ``boom``, ``arm``, ``bucket``, the tool point
            ``x``, ``y`` and ``depth`` (m), ``cutting_angle`` (rad), ``resistance_along``,
            ``resistance_normal``, ``required``, ``available`` and ``margin`` (N),
            ``limited_by``; its ``attrs`` name the machine and each column's kind.
        """
        import pandas as pd

        from excavkin.kinematics.columns import kinds_attrs

        L = self.lengths
        frame = pd.DataFrame(
            [
                {
                    "point": i,
                    "boom": L[i, 0],
                    "arm": L[i, 1],
                    "bucket": L[i, 2],
                    "x": self.point[i, 0],
                    "y": self.point[i, 1],
                    "depth": self.depth[i],
                    "cutting_angle": self.rake[i],
                    "resistance_along": self.resistance.along[i],
                    "resistance_normal": self.resistance.normal[i],
                    "required": self.required[i],
                    "available": self.available[i],
                    "margin": self.margin[i],
                    "limited_by": str(self.limiting[i]),
                }
                for i in range(len(L))
            ]
        )
        kinds = {
            **dict.fromkeys(("x", "y", "boom", "arm", "bucket", "depth"), "length"),
            "cutting_angle": "angle",
            **dict.fromkeys(
                ("resistance_along", "resistance_normal", "required", "available", "margin"),
                "force",
            ),
        }
        frame.attrs.update(kinds_attrs(self.machine, kinds))
        return frame

    def summary(self) -> str:
        """The dig as ``excavkin excavator dig`` prints it (kN; positions mm).

        Returns
        -------
        str
        """

        s, d = self.soil, self
        lines = [
            f"{self.machine} — {self.model} resistance along a dig in {s.name}, "
            f"{self.tool.width * 1e3:.0f} mm wide (kN; positions mm)",
            f"{'pt':>3} {'x':>7} {'y':>7} {'depth':>6} {'angle':>5} {'along':>7} {'normal':>7} "
            f"{'needed':>7} {'avail':>7} {'margin':>7}  limited by",
        ]
        for i in range(len(self.lengths)):
            flag = "  ← stalls" if i == d.stall else ""
            lines.append(
                f"{i:3d} {mm_field(d.point[i, 0]):>7} {mm_field(d.point[i, 1]):>7} "
                f"{mm_field(max(d.depth[i], 0.0)).strip():>6} {np.degrees(d.rake[i]):5.1f} "
                f"{d.resistance.along[i] / 1e3:7.1f} {d.resistance.normal[i] / 1e3:7.1f} "
                f"{d.required[i] / 1e3:7.1f} {d.available[i] / 1e3:7.1f} "
                f"{d.margin[i] / 1e3:7.1f}  {d.limiting[i]}{flag}"
            )
        lines.append(
            f"soil {s.name}: ρ {s.density:.0f} kg/m³, φ {np.degrees(s.friction_angle):.0f}°, "
            f"c {s.cohesion / 1e3:.0f} kPa, δ {np.degrees(s.metal_friction):.0f}°, "
            f"c_a {s.adhesion / 1e3:.0f} kPa, C {s.blows:g} blows, q {s.surcharge / 1e3:.0f} kPa"
        )
        inside = d.depth > 0.0
        k = int(np.nanargmax(np.where(inside, d.required, -np.inf)))
        lines.append(
            f"largest resistance {d.required[k] / 1e3:.1f} kN at point {k} "
            f"(depth {d.depth[k] * 1e3:.0f} mm); least margin "
            f"{np.nanmin(np.where(inside, d.margin, np.inf)) / 1e3:.1f} kN"
        )
        if d.stall >= 0:
            i = d.stall
            lines.append(
                f"the dig stalls at point {i} (x {d.point[i, 0] * 1e3:.0f}, y "
                f"{d.point[i, 1] * 1e3:.0f} mm): {d.required[i] / 1e3:.1f} kN needed, "
                f"{d.available[i] / 1e3:.1f} kN available, limited by {d.limiting[i]}"
            )
        else:
            lines.append(
                "the dig goes through: the available force exceeds the resistance throughout"
            )
        return "\n".join(lines)


def dig_path(
    machine: Machine,
    start: ArrayLike,
    end: ArrayLike,
    samples: int = 41,
    *,
    law: str | None = None,
) -> F:
    """Cylinder lengths from ``start`` to ``end`` (each shape (3,), m): shape (samples, 3).

    The path is the straight line between the poses in cylinder space. Without a ``law`` the
    samples are evenly spaced along it; with one (a name of [`excavkin.motion.get_law`][])
    every cylinder follows that rest-to-rest law and the samples are at equal time steps.

    Parameters
    ----------
    machine : Machine
        The excavator whose strokes the path must keep to.
    start, end : array_like, shape (3,)
        Boom, arm and bucket cylinder lengths at the ends of the path (m).
    samples : int, default 41
        Samples along the path, ends included (at least 3).
    law : str, optional
        A motion law's name, e.g. ``"cycloidal"``; default: even spacing.

    Returns
    -------
    ndarray, shape (samples, 3)
        Boom, arm and bucket cylinder lengths (m).

    Raises
    ------
    InputError
        Fewer than 3 samples, an unknown law, or a sample outside a cylinder's stroke.
    """
    a = as_lengths(np.asarray(start, dtype=np.float64).reshape(1, 3))[0]
    b = as_lengths(np.asarray(end, dtype=np.float64).reshape(1, 3))[0]
    if samples < 3:
        raise InputError(f"a dig needs at least 3 samples, not {samples}")
    s = np.linspace(0.0, 1.0, samples)
    if law is not None:
        try:
            s = get_law(law, 1.0, 1.0).evaluate(s).s
        except (ValueError, TypeError) as exc:
            raise InputError(str(exc)) from None
    L = a[None, :] + s[:, None] * (b - a)[None, :]
    out = ~machine.within_stroke(L)
    if np.any(out):
        k = int(np.argmax(out))
        raise InputError(
            f"the dig leaves the cylinders' strokes at sample {k}: lengths "
            f"{np.array2string(L[k] * 1e3, precision=0)} mm"
        )
    return np.asarray(L, dtype=np.float64)


def _lip_height(machine: Machine, L: F) -> F:
    return np.asarray(pose_of(machine, L, machine.solve(L)).lip[:, 1] - machine.ground_line)


def _crossing(x: F, y: F, level: float) -> float | None:
    """The first x (in order) where y crosses ``level``, linearly interpolated."""
    z = y - level
    ok = np.isfinite(z)
    k = np.flatnonzero(ok[:-1] & ok[1:] & (np.sign(z[:-1]) != np.sign(z[1:])))
    if len(k) == 0:
        return None
    i = int(k[0])
    return float(x[i] - z[i] * (x[i + 1] - x[i]) / (z[i + 1] - z[i]))


def default_dig(
    machine: Machine, samples: int = 41, *, depth: float = 0.5, law: str | None = None
) -> F:
    """An arm-in curl from the ground, shape (samples, 3).

    It starts with the stick out (the arm cylinder at its dig start), the bucket half curled
    and the boom where the lip touches the ground line; the arm crowds in and the bucket curls
    towards the ends of their strokes while the boom moves linearly to the length that makes
    the deepest point of the cut ``depth`` (m) below the ground line; the dig ends where the
    lip comes back up through the ground line (or at the ends of the strokes).

    Parameters
    ----------
    machine : Machine
        The excavator.
    samples : int, default 41
        Samples along the path, ends included (at least 3).
    depth : float, default 0.5
        Depth of the cut's deepest point below the ground line (m, > 0).
    law : str, optional
        A motion law's name, as for `dig_path`; default: even spacing.

    Returns
    -------
    ndarray, shape (samples, 3)
        Boom, arm and bucket cylinder lengths (m).

    Raises
    ------
    InputError
        A non-positive depth, or no boom motion that puts the lip on the ground and cuts that
        deep.
    """
    if not (np.isfinite(depth) and depth > 0.0):
        raise InputError(f"the dig's depth must be > 0, not {depth!r} m")
    lo, hi = machine.lengths_min, machine.lengths_max
    arm0, arm1 = (lo[1], hi[1]) if machine.cylinders[1].dig == "extend" else (hi[1], lo[1])
    bkt0 = 0.5 * (lo[2] + hi[2])
    bkt1 = hi[2] if machine.cylinders[2].dig == "extend" else lo[2]
    boom = np.linspace(lo[0], hi[0], 401)
    L = np.column_stack([boom, np.full_like(boom, arm0), np.full_like(boom, bkt0)])
    b0 = _crossing(boom, _lip_height(machine, L), 0.0)
    if b0 is None:
        raise InputError("no boom length puts the lip on the ground line with the stick out")
    # the boom's end length: the deepest point of the cut as it goes, from the boom's longest
    # (shallowest) end towards its shortest
    ends = np.linspace(hi[0], lo[0], 81)
    # the deepest point of each candidate path on a fine grid of its own, whatever the
    # samples asked for, so that the path reaches the depth asked for
    fine = 401
    u = np.linspace(0.0, 1.0, fine)
    paths = np.stack(
        [
            b0 + u[None, :] * (ends[:, None] - b0),
            np.broadcast_to(arm0 + u * (arm1 - arm0), (len(ends), fine)),
            np.broadcast_to(bkt0 + u * (bkt1 - bkt0), (len(ends), fine)),
        ],
        axis=2,
    )
    y = _lip_height(machine, paths.reshape(-1, 3)).reshape(len(ends), fine)
    deepest = np.where(np.all(np.isfinite(y), axis=1), -np.min(y, axis=1), np.nan)
    b1 = _crossing(ends, deepest, depth)
    if b1 is None:
        raise InputError(f"no boom motion makes an arm-in curl {depth * 1e3:.0f} mm deep")
    start, end = np.array([b0, arm0, bkt0]), np.array([b1, arm1, bkt1])
    # the dig ends where the lip comes back up through the ground line
    u = np.linspace(0.0, 1.0, 401)
    y = _lip_height(machine, start + u[:, None] * (end - start))
    below = np.flatnonzero(y < 0.0)
    if len(below):
        out = _crossing(u[below[0] :], y[below[0] :], 0.0)
        if out is not None:
            end = start + out * (end - start)
    return dig_path(machine, start, end, samples, law=law)


def _cut_frame(machine: Machine, lengths: F, at: At) -> tuple[F, F, F, F, FrontPose]:
    """Tool point, unit motion t, unit normal n (up) and rake α along the path."""
    tr = transfer(machine, lengths)
    pose = pose_of(machine, lengths, tr.result)
    point = pose.lip if at == "lip" else pose.tip
    _, J = tr.point(machine, machine.front.lip if at == "lip" else machine.front.tip)
    dL = np.gradient(lengths, axis=0)
    v = np.einsum("nic,nc->ni", J, dL)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = v / np.hypot(v[:, 0], v[:, 1])[:, None]
    n = np.column_stack([-t[:, 1], t[:, 0]])
    n = np.where((n[:, 1] < 0.0)[:, None], -n, n)
    # the cutting face, from the edge back: the teeth tip → lip (or floor → lip reversed)
    face = pose.bucket_angle - (machine.wall_bucket_angle + 0.5 * np.pi) + np.pi
    f = np.column_stack([np.cos(face), np.sin(face)])
    rake = np.arctan2(np.einsum("ni,ni->n", f, n), -np.einsum("ni,ni->n", f, t))
    return point, t, n, rake, pose


def dig(
    machine: Machine,
    lengths: ArrayLike,
    soil: Soil,
    tool: Tool,
    model: str = "balovnev",
    *,
    at: At = "lip",
    gravity: bool = True,
    swing: float | Over = "front",
) -> Dig:
    """Resistance, available force, margin and stall point along a dig.

    Parameters
    ----------
    machine : Machine
    lengths : array_like, shape (n, 3)
        The dig in cylinder space (m), n ≥ 3, in the order it is dug.
    soil : Soil
    tool : Tool
    model : {"zelenin", "balovnev", "mckyes"}
        The soil resistance model (`excavkin.excavator.soil.resistance`).
    at : {"lip", "tip"}
        The tool point: the lip (ISO 6015) or the tooth tip.
    gravity : bool
        Count the front's weight in the cylinders' balance.
    swing : float or {"front", "side"}
        Where the front points, for tipping and slipping (machines with a base).

    Returns
    -------
    Dig
    """
    L = as_lengths(lengths)
    if isinstance(swing, str) and swing not in SWING:
        raise InputError(f"swing must be 'front', 'side' or an angle, not {swing!r}")
    if len(L) < 3:
        raise InputError(f"a dig needs at least 3 points, not {len(L)}")
    point, t, n, rake, pose = _cut_frame(machine, L, at)
    depth = machine.ground_line - point[:, 1]
    inside = depth > 0.0
    bad = inside & ~((rake > 0.0) & (rake < np.pi))
    if np.any(bad):
        k = int(np.argmax(bad))
        raise InputError(
            f"at dig point {k} the bucket's back leads (cutting angle "
            f"{np.degrees(rake[k]):.1f}°, outside 0°–180°): not a cut the models describe"
        )
    res = resistance(model, depth, np.clip(rake, 1e-9, np.pi - 1e-9), soil, tool)
    R = res.along[:, None] * t + res.normal[:, None] * n
    required = np.hypot(R[:, 0], R[:, 1])
    with np.errstate(divide="ignore", invalid="ignore"):
        load = np.where((required > 0.0)[:, None], R / required[:, None], t)
    df = directed_force(machine, L, load, np.gradient(L, axis=0), at=at, gravity=gravity)
    available, limiting = df.force, df.limiting.astype("<U40")
    if machine.base is not None:
        ok = pose.ok & np.all(np.isfinite(load), axis=1)
        st = equilibrium(
            machine,
            pose.result.positions,
            point,
            np.where(ok[:, None], -load, (0.0, -1.0)),
            SWING[swing] if isinstance(swing, str) else float(swing),
            pose.ok,
        )
        tip_name = np.char.add(np.char.add("tipping (", st.tipping_line.astype(str)), ")")
        for names, cap in ((tip_name, st.tipping_load), ("slipping", st.slipping_load)):
            lower = cap < available
            available = np.where(lower, cap, available)
            limiting = np.where(lower, names, limiting)
    margin = available - required
    stalled = np.flatnonzero(inside & ~(margin >= 0.0))
    stall = int(stalled[0]) if len(stalled) else -1
    return Dig(
        model,
        soil,
        tool,
        L,
        point,
        depth,
        t,
        rake,
        res,
        required,
        load,
        available,
        limiting,
        margin,
        stall,
        pose,
        machine.name,
    )
