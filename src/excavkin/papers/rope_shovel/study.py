r"""Maksimov's bucket-turning mechanism of the EO-4112 rope backhoe, by the engine.

The model ``rope_shovel.toml`` is driven by the drag-rope length FE and its rate ``-v_rope``
(`RopeWinch`); this module turns the engine's result into the paper's
angles and rates and compares them with the closed-form reference
(`excavkin.papers.rope_shovel.reference`).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from excavkin.arrays import FloatArray
from excavkin.mechanism import Mechanism
from excavkin.motion.drives import RopeWinch

if TYPE_CHECKING:
    from excavkin.kinematics.result import KinematicResult

from excavkin.papers.common import PaperRun, load_paper_model, rel_error, wrap

#: The EO-4112 drag winch assumed for the rope shovel (the paper gives no numbers; same values
#: as `excavkin.papers.rope_shovel.reference.EO4112_DRIVE`): motor 750 rpm, drum radius
#: 0.25 m, gear ratio 20, two-fall pulley block → rope speed 0.491 m/s, hauling in.
EO4112_WINCH = RopeWinch(750.0 * 2.0 * math.pi / 60.0, 0.25, 20.0, 2.0)

#: Quantity kind of every rope-shovel column.
ROPE_SHOVEL_KINDS: dict[str, str] = {
    "t": "time",
    "fe": "length",
    "v_rope": "velocity",
    "alpha_tk": "angle",
    "phi1": "angle",
    "omega1": "angular_velocity",
    "eps": "angle",
    "v": "angle",
    "delta": "angle",
    "phi2": "angle",
    "phi3": "angle",
    "phi5": "angle",
    "omega2": "angular_velocity",
    "omega3": "angular_velocity",
    "theta": "angle",
    "eps2": "angle",
    "v2": "angle",
    "delta2": "angle",
    "phi6": "angle",
    "phi7": "angle",
    "phi7p": "angle",
    "omega6": "angular_velocity",
    "omega7p": "angular_velocity",
    "omega7_abs": "angular_velocity",
    "bucket_to_horizon": "angle",
    "hk": "length",
    "gamma": "angle",
    "v_c1": "velocity",
    "omega10": "angular_velocity",
    "epsilon1": "angular_acceleration",
    "epsilon7_abs": "angular_acceleration",
    "a_c1": "acceleration",
}


def rope_length_at(mech: Mechanism, phi1: npt.ArrayLike) -> FloatArray:
    """Drag-rope length FE at stick angles φ1 (triangle O1FE of the model's dimensions).

    Parameters
    ----------
    mech : Mechanism
        The ``rope_shovel`` model.
    phi1 : array_like, shape (n,)
        Stick angles [rad].

    Returns
    -------
    ndarray, shape (n,)
        FE [m].
    """
    p = np.asarray(phi1, dtype=np.float64)
    o1e = mech.plan.shapes["stick"].distance("O1", "E")
    o1f = mech.plan.shapes["boom"].distance("O1", "F")
    return np.asarray(np.sqrt(o1f**2 + o1e**2 - 2.0 * o1f * o1e * np.cos(p)), dtype=np.float64)


def _angle(v: FloatArray) -> FloatArray:
    return np.asarray(np.arctan2(v[:, 1], v[:, 0]), dtype=np.float64)


def _interior(res: KinematicResult, at: str, p: str, q: str) -> FloatArray:
    """Angle at point ``at`` between the rays to ``p`` and ``q``, in [0, π]."""
    x0 = res.point(at)[0]
    u, w = res.point(p)[0] - x0, res.point(q)[0] - x0
    cr = u[:, 0] * w[:, 1] - u[:, 1] * w[:, 0]
    dot = u[:, 0] * w[:, 0] + u[:, 1] * w[:, 1]
    return np.asarray(np.arctan2(np.abs(cr), dot), dtype=np.float64)


def rope_shovel_run(
    rope_length: npt.ArrayLike,
    rope_speed: npt.ArrayLike,
    rope_accel: npt.ArrayLike = 0.0,
    mech: Mechanism | None = None,
    *,
    time: npt.ArrayLike | None = None,
) -> PaperRun:
    """Solve the bucket-turning mechanism for a drag-rope motion (paper §3.1-3.5).

    The input is the rope length FE (linear driver ``drag``, F–E) with rate
    ``-v_rope`` (the paper's ``v_тк = −dFE/dt``, > 0 hauling in) and acceleration
    ``-dv_rope/dt``. Cylinder Ц2 (``c2``) is locked, Ц1 (``c1``) free.

    Parameters
    ----------
    rope_length : array_like, shape (n,)
        FE [m].
    rope_speed : array_like, shape (n,) or scalar
        v_тк [m/s], positive hauling in.
    rope_accel : array_like, shape (n,) or scalar
        dv_тк/dt [m/s²].
    mech : Mechanism, optional
        Default ``examples/rope_shovel.toml``.
    time : array_like, shape (n,), optional
        Sample times, added as column ``t``.

    Returns
    -------
    PaperRun
        Columns (paper's names, spec §2.4): ``fe, v_rope, alpha_tk, phi1, omega1, epsilon1,
        eps, v, delta, phi2, phi3, phi5, omega2, omega3, theta, eps2, v2, delta2, phi6, phi7,
        phi7p, omega6, omega7p, omega7_abs, epsilon7_abs, bucket_to_horizon, hk, gamma, v_c1,
        a_c1, omega10`` (and ``t``). Angles relative to the stick (θ, φ6, φ7', γ) are in
        ``(-π, π]``; ω6, ω7', ω10 are relative to the stick.
    """
    mech = mech or load_paper_model("rope_shovel")
    fe = np.atleast_1d(np.asarray(rope_length, dtype=np.float64))
    vr = np.broadcast_to(np.asarray(rope_speed, dtype=np.float64), fe.shape)
    ar = np.broadcast_to(np.asarray(rope_accel, dtype=np.float64), fe.shape)
    res = mech.solve({"drag": fe}, {"drag": -vr}, {"drag": -ar}, time=time)
    phi1, w1, e1 = res.body("stick")
    phi2, w2, _ = res.body("lever")
    c2 = [res.column(f"c2.{q}") for q in ("angle", "omega")]
    cpl, w_cpl, _ = res.body("coupler")
    bkt, w_bkt, e_bkt = res.body("bucket")
    hk, v_c1, a_c1 = res.driver("c1")
    c1_angle, c1_omega = res.column("c1.angle"), res.column("c1.omega")
    o2, a_pt, c_pt = (res.point(n)[0] for n in ("O2", "A", "C"))
    v = _angle(o2 - a_pt)
    phi7p = wrap(bkt - phi1)
    cols = {
        "fe": res.driver("drag")[0],
        "v_rope": -res.driver("drag")[1],
        "alpha_tk": _interior(res, "F", "E", "O1"),
        "phi1": phi1,
        "omega1": w1,
        "epsilon1": e1,
        "eps": _interior(res, "B", "O2", "A"),
        "v": v,
        "delta": wrap(c2[0] - v),
        "phi2": phi2,
        "phi3": c2[0],
        "phi5": _angle(c_pt - o2),
        "omega2": w2,
        "omega3": c2[1],
        "theta": wrap(_angle(c_pt - o2) - phi1),
        "eps2": _interior(res, "D", "C", "E"),
        "v2": _interior(res, "E", "O2", "C"),
        "delta2": _interior(res, "E", "C", "D"),
        "phi6": wrap(cpl - phi1),
        "phi7": wrap(np.pi - phi7p),
        "phi7p": phi7p,
        "omega6": w_cpl - w1,
        "omega7p": w_bkt - w1,
        "omega7_abs": w_bkt,
        "epsilon7_abs": e_bkt,
        "bucket_to_horizon": bkt,
        "hk": hk,
        "gamma": wrap(c1_angle - phi1),
        "v_c1": v_c1,
        "a_c1": a_c1,
        "omega10": c1_omega - w1,
    }
    if time is not None:
        cols = {"t": np.asarray(time, dtype=np.float64), **cols}
    return PaperRun(
        {k: np.asarray(x, dtype=np.float64) for k, x in cols.items()}, ROPE_SHOVEL_KINDS, res
    )


def rope_shovel_sweep(
    phi1: npt.ArrayLike,
    winch: RopeWinch = EO4112_WINCH,
    mech: Mechanism | None = None,
) -> PaperRun:
    """The mechanism at given stick angles, hauled in by a winch at constant speed.

    The rope length at each φ1 comes from triangle O1FE (`rope_length_at`); the engine
    then solves from the rope alone. Time runs from the largest φ1 (rope longest) while the
    winch hauls in at ``winch.rope_speed``.

    Parameters
    ----------
    phi1 : array_like, shape (n,)
        Stick angles [rad].
    winch : RopeWinch
        Constant-speed winch; default `EO4112_WINCH`.
    mech : Mechanism, optional
        Default ``examples/rope_shovel.toml``.

    Returns
    -------
    PaperRun
        As [`rope_shovel_run`][excavkin.papers.rope_shovel.study.rope_shovel_run], with ``t`` [s].
    """
    mech = mech or load_paper_model("rope_shovel")
    fe = rope_length_at(mech, phi1)
    v = winch.rope_speed
    t = (np.max(fe) - fe) / v
    return rope_shovel_run(fe, v, 0.0, mech, time=t)


def rope_shovel_reference_agreement(run: PaperRun) -> dict[str, float]:
    """Engine against `bucket_mechanism` at φ1, ω1.

    Parameters
    ----------
    run : PaperRun
        From [`rope_shovel_run`][excavkin.papers.rope_shovel.study.rope_shovel_run] or
        `rope_shovel_sweep` on ``rope_shovel.toml``.

    Returns
    -------
    dict of str to float
        Per quantity of `BucketMechanismState`
        that the run has: the largest difference relative to the reference's largest
        magnitude. ω1 itself is compared with eq. (2) corrected, from the rope speed.
    """
    from excavkin.papers.rope_shovel import reference as ref

    geom = ref.EO4112_GEOMETRY
    st = ref.bucket_mechanism(geom, run["phi1"], run["omega1"])
    out = {
        f: rel_error(run[f], np.asarray(getattr(st, f)), ROPE_SHOVEL_KINDS[f] == "angle")
        for f in st._fields
        if f in run.columns and f != "omega1"
    }
    w1 = ref.stick_rate_from_rope(geom.o1e_length, geom.l13, run["phi1"], run["v_rope"])
    out["omega1"] = rel_error(run["omega1"], w1, False)
    return out
