r"""The seed papers' mechanisms solved by the general engine: what ``excavkin reproduce`` computes.

Each paper's mechanism is a model file in ``examples/`` run by :class:`~excavkin.Mechanism`;
this module turns the engine's result into the quantities the paper defines, under the
paper's names, and puts the published values beside them. Pure NumPy (no plotting); the
closed-form reference modules (:mod:`excavkin.reference`) are used only for the columns that
show the agreement, never to compute the engine's values.

======================  ======================  ============================================
paper                   model                   engine inputs
======================  ======================  ============================================
Pasika & Koruniak       ``pasika_module.toml``  cylinder length ``l_OA0 + s(t)`` from the
                                                cubic law (:class:`~excavkin.motion.CubicLaw`)
Maksimov (EO-4112)      ``rope_shovel.toml``    drag-rope length FE and its rate ``-v_rope``
                                                (:class:`~excavkin.motion.RopeWinch`)
arm vector model (001)  ``arm_vector.toml``     cylinder lengths; or, by
                                                :func:`arm_joint_mechanism`, the link angles;
                                                or, by :func:`arm_inverse_mechanism`, the
                                                tooth tip and the bucket angle
======================  ======================  ============================================

Every quantity is SI (m, rad, s) with the batch axis first: arrays of shape ``(n,)``.

>>> import numpy as np
>>> run = pasika_run(np.array([0.0, 2.5, 5.0]))
>>> np.round(np.degrees(run["phi1"]), 4).tolist()
[34.1497, 45.194, 55.4185]
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from excavkin.mechanism import Mechanism
from excavkin.model.entities import Body, LinearDriver, Model, RotaryDriver, Slider
from excavkin.motion.drives import RopeWinch
from excavkin.motion.laws import CubicLaw

if TYPE_CHECKING:
    from excavkin.kinematics.result import KinematicResult

__all__ = [
    "ARM_KINDS",
    "EO4112_WINCH",
    "PASIKA_KINDS",
    "PASIKA_SPEC_TABLE",
    "PASIKA_TIMES",
    "ROPE_SHOVEL_KINDS",
    "PaperRun",
    "Published",
    "arm_cylinder_sweep",
    "arm_forward",
    "arm_inverse",
    "arm_inverse_mechanism",
    "arm_joint_mechanism",
    "arm_reference_agreement",
    "central_differences",
    "load_paper_model",
    "pasika_derivative_agreement",
    "pasika_published",
    "pasika_reference_agreement",
    "pasika_run",
    "rope_length_at",
    "rope_shovel_reference_agreement",
    "rope_shovel_run",
    "rope_shovel_sweep",
    "text_table",
    "wrap",
]

FloatArray = npt.NDArray[np.float64]

#: The EO-4112 drag winch assumed for the rope shovel (the paper gives no numbers; same values
#: as :data:`excavkin.reference.maksimov.EO4112_DRIVE`): motor 750 rpm, drum radius 0.25 m,
#: gear ratio 20, two-fall pulley block → rope speed 0.491 m/s, hauling in.
EO4112_WINCH = RopeWinch(750.0 * 2.0 * math.pi / 60.0, 0.25, 20.0, 2.0)

#: Pasika's stroke H [m] and stroke time T [s].
PASIKA_STROKE = 0.5
PASIKA_DURATION = 5.0

#: Times of the spec's §4.3 table [s].
PASIKA_TIMES = (0.0, 1.0, 2.0, 2.5, 3.0, 4.0, 5.0)

#: ``seeds/pasika-internal-driving-link.md`` §4.3: the paper's equations evaluated with its
#: data (its figures, where these curves were published, are missing from the seed). Columns:
#: s [m], v21 [m/s], a21 [m/s²], φ1 [deg], ω1 [1/s], ε1 [1/s²], φ3 [deg], ω3 [1/s], ε3 [1/s²].
PASIKA_SPEC_TABLE: dict[str, tuple[float, ...]] = {
    "s": (0.0, 0.0520, 0.1760, 0.2500, 0.3240, 0.4480, 0.5000),
    "v21": (0.0, 0.0960, 0.1440, 0.1500, 0.1440, 0.0960, 0.0),
    "a21": (0.1200, 0.0720, 0.0240, 0.0, -0.0240, -0.0720, -0.1200),
    "phi1": (34.1497, 36.5876, 42.0704, 45.1940, 48.2516, 53.3038, 55.4185),
    "omega1": (0.0, 0.07697, 0.10758, 0.10916, 0.10306, 0.06808, 0.0),
    "eps1": (0.10034, 0.05235, 0.01131, -0.00470, -0.01963, -0.05098, -0.08530),
    "phi3": (-22.0714, -19.0749, -11.8313, -7.4228, -2.9334, 4.8121, 8.1595),
    "omega3": (0.0, 0.09688, 0.14851, 0.15731, 0.15401, 0.10683, 0.0),
    "eps3": (0.12031, 0.07398, 0.02918, 0.00579, -0.01936, -0.07646, -0.13616),
}

#: Quantity kind of every Pasika column (for display units).
PASIKA_KINDS: dict[str, str] = {
    "t": "time",
    "s": "length",
    "v21": "velocity",
    "a21": "acceleration",
    "l_oa": "length",
    "phi1": "angle",
    "omega1": "angular_velocity",
    "eps1": "angular_acceleration",
    "phi3": "angle",
    "omega3": "angular_velocity",
    "eps3": "angular_acceleration",
    "coriolis": "acceleration",
}

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

#: Quantity kind of every arm column (``<cyl>_`` prefixed for the cylinders).
ARM_KINDS: dict[str, str] = {
    **{f"phi{i}": "angle" for i in (1, 2, 3)},
    **{f"omega{i}": "angular_velocity" for i in (1, 2, 3)},
    **{f"eps{i}": "angular_acceleration" for i in (1, 2, 3)},
    "x_a": "length",
    "y_a": "length",
    "v_xa": "velocity",
    "v_ya": "velocity",
    "a_xa": "acceleration",
    "a_ya": "acceleration",
    **{
        f"{c}_{q}": k
        for c in ("boom", "stick", "bucket")
        for q, k in (
            ("z", "length"),
            ("phi_z", "angle"),
            ("v_r", "velocity"),
            ("omega_z", "angular_velocity"),
            ("a_r", "acceleration"),
            ("eps_z", "angular_acceleration"),
            ("a_k", "acceleration"),
            ("psi", "angle"),
        )
    },
}

#: Cylinder driver, parent body and link body of each arm link, in the model ``arm_vector``.
_ARM_LINKS = (
    ("boom", "boom_cyl", "turntable", "O"),
    ("stick", "stick_cyl", "boom", "J"),
    ("bucket", "bucket_cyl", "stick", "Q"),
)


@dataclass(frozen=True, slots=True)
class PaperRun:
    """A paper's quantities computed by the engine.

    Attributes
    ----------
    columns : dict of str to ndarray, shape (n,)
        The paper's quantities by name, SI.
    kinds : dict of str to str
        Quantity kind of each column (``"angle"``, ``"velocity"``, ...), for display units.
    result : KinematicResult
        The engine's result they were read from.
    """

    columns: dict[str, FloatArray]
    kinds: dict[str, str]
    result: KinematicResult

    def __getitem__(self, name: str) -> FloatArray:
        return self.columns[name]

    def __len__(self) -> int:
        return len(self.result)


@dataclass(frozen=True, slots=True)
class Published:
    """One published (or reconstructed) value beside ours.

    Attributes
    ----------
    quantity : str
        What it is, in words, with the paper's symbol.
    published : str
        The value as the paper (or the spec) states it, or ``"not published"``.
    ours : str
        The engine's value, formatted.
    source : str
        Where the published value comes from.
    """

    quantity: str
    published: str
    ours: str
    source: str


def wrap(a: npt.ArrayLike) -> FloatArray:
    """Angles wrapped to ``(-π, π]``, shape preserved."""
    x = np.asarray(a, dtype=np.float64)
    return np.asarray(np.arctan2(np.sin(x), np.cos(x)), dtype=np.float64)


def load_paper_model(name: str) -> Mechanism:
    """Load a seed paper's example model by its file stem (``"rope_shovel"``, ...).

    Parameters
    ----------
    name : str
        ``"pasika_module"``, ``"rope_shovel"`` or ``"arm_vector"``.

    Returns
    -------
    Mechanism
    """
    import excavkin

    return excavkin.load(excavkin.example_path(name))


def central_differences(values: FloatArray, h: float) -> tuple[FloatArray, FloatArray]:
    """First and second derivatives by 8th-order central differences (Fornberg 1988).

    Parameters
    ----------
    values : ndarray, shape (9, n)
        ``f(x + k h)`` for ``k = -4 … 4`` (rows), at n points.
    h : float
        Step.

    Returns
    -------
    d1, d2 : ndarray, shape (n,)
    """
    d1 = np.array([1 / 280, -4 / 105, 1 / 5, -4 / 5, 0.0, 4 / 5, -1 / 5, 4 / 105, -1 / 280])
    d2 = np.array([-1 / 560, 8 / 315, -1 / 5, 8 / 5, -205 / 72, 8 / 5, -1 / 5, 8 / 315, -1 / 560])
    return d1 @ values / h, d2 @ values / (h * h)


# ------------------------------------------------------------------------------------------
# 1. Pasika & Koruniak: cylinder-rocker module with an internal driving link
# ------------------------------------------------------------------------------------------


def pasika_run(
    t: npt.ArrayLike,
    mech: Mechanism | None = None,
    *,
    stroke: float = PASIKA_STROKE,
    duration: float = PASIKA_DURATION,
) -> PaperRun:
    """Solve the module over time with the paper's cubic law, eqs. (4)-(6).

    The rod's relative displacement ``s(t)`` enters the engine as the length of the linear
    driver ``cyl`` (O–A), ``l_OA = l_OA0 + s``, with rate ``v21`` and acceleration ``a21``:
    the input is the internal driving link itself. The cylinder's φ1, ω1, ε1 are the
    driver's line O→A (``cyl.angle .omega .epsilon``); the rocker's φ3, ω3, ε3 its body angle
    B→A.

    Parameters
    ----------
    t : array_like, shape (n,)
        Times [s]; the law holds on ``0 <= t <= T`` and the rod rests outside.
    mech : Mechanism, optional
        Default ``examples/pasika_module.toml``.
    stroke, duration : float
        H [m] and T [s].

    Returns
    -------
    PaperRun
        Columns ``t, s, v21, a21, l_oa, phi1, omega1, eps1, phi3, omega3, eps3, coriolis``
        (``coriolis = 2 ω1 v21``, the corrected Coriolis term).
    """
    mech = mech or load_paper_model("pasika_module")
    tt = np.atleast_1d(np.asarray(t, dtype=np.float64))
    law = CubicLaw(stroke, duration).evaluate(tt)
    l0 = mech.sketch_values()["cyl"]
    res = mech.solve({"cyl": l0 + law.s}, {"cyl": law.v}, {"cyl": law.a}, time=tt)
    phi1, omega1, eps1 = (res.column(f"cyl.{q}") for q in ("angle", "omega", "epsilon"))
    phi3, omega3, eps3 = res.body("rocker")
    cols = {
        "t": tt,
        "s": law.s,
        "v21": law.v,
        "a21": law.a,
        "l_oa": res.driver("cyl")[0],
        "phi1": phi1,
        "omega1": omega1,
        "eps1": eps1,
        "phi3": phi3,
        "omega3": omega3,
        "eps3": eps3,
        "coriolis": 2.0 * omega1 * law.v,
    }
    return PaperRun(
        {k: np.asarray(v, dtype=np.float64) for k, v in cols.items()}, PASIKA_KINDS, res
    )


def pasika_derivative_agreement(
    mech: Mechanism | None = None, n: int = 201, h: float = 1e-2
) -> dict[str, float]:
    """The paper's check, redone: analytic ω, ε against numerical differentiation of φ(t).

    The paper differentiated its displacement expressions (2)-(3) numerically twice and found
    the analytic ω and ε within 0.2 %. Here the engine's angles φ1(t), φ3(t) are
    differentiated by 8th-order central differences (step ``h``) at ``n`` times inside
    ``[4h, T − 4h]`` (the stencil must not cross the soft shocks at 0 and T).

    Parameters
    ----------
    mech : Mechanism, optional
        Default ``examples/pasika_module.toml``.
    n : int
        Number of times.
    h : float
        Difference step [s].

    Returns
    -------
    dict of str to float
        ``"omega1", "omega3", "eps1", "eps3"``: the largest difference, relative to the
        largest magnitude of the quantity over the stroke.
    """
    mech = mech or load_paper_model("pasika_module")
    t = np.linspace(4 * h, PASIKA_DURATION - 4 * h, n)
    stencil = t[None, :] + h * np.arange(-4, 5)[:, None]
    shifted = pasika_run(stencil.ravel(), mech)
    exact = pasika_run(t, mech)
    out: dict[str, float] = {}
    for k in ("1", "3"):
        phi = np.unwrap(shifted[f"phi{k}"].reshape(9, n), axis=0)
        d1, d2 = central_differences(phi, h)
        for name, num in ((f"omega{k}", d1), (f"eps{k}", d2)):
            ref = exact[name]
            out[name] = float(np.max(np.abs(num - ref)) / np.max(np.abs(ref)))
    return out


def _fmt(x: float, digits: int = 5) -> str:
    return f"{x:+.{digits}f}" if x != 0.0 else f"{0.0:.{digits}f}"


def pasika_published(mech: Mechanism | None = None) -> list[Published]:
    """What the paper publishes about its results, beside the engine's values.

    The paper's Fig. 3 and Fig. 5 are lost from the seed; its text states the values below.

    Parameters
    ----------
    mech : Mechanism, optional
        Default ``examples/pasika_module.toml``.

    Returns
    -------
    list of Published
    """
    mech = mech or load_paper_model("pasika_module")
    t = np.linspace(0.0, PASIKA_DURATION, 5001)
    run = pasika_run(t, mech)
    i_v = int(np.argmax(run["v21"]))
    fd = pasika_derivative_agreement(mech)
    worst = max(fd.values())
    mono = bool(np.all(np.diff(run["phi1"]) > 0) and np.all(np.diff(run["phi3"]) > 0))
    rows = [
        Published("rod stroke s(T) (Fig. 3)", "0.5 m", f"{run['s'][-1]:.4f} m", "text, Fig. 3"),
        Published(
            "max v21 and its time (Fig. 3)",
            "0.15 m/s at 2.5 s",
            f"{run['v21'][i_v]:.4f} m/s at {t[i_v]:.3f} s",
            "text, Fig. 3",
        ),
        Published(
            "a21 at t = 0 and t = T (Fig. 3)",
            "+0.12 / -0.12 m/s²",
            f"{run['a21'][0]:+.4f} / {run['a21'][-1]:+.4f} m/s²",
            "text, Fig. 3",
        ),
        Published(
            "φ1, φ3 increase monotonically (Fig. 5)",
            "yes",
            "yes" if mono else "no",
            "text, Fig. 5",
        ),
        Published(
            "ε1, ε3 jump at t = 0 and T: soft shocks (Fig. 5)",
            "yes",
            f"Δε1 = {run['eps1'][0]:+.4f} / {-run['eps1'][-1]:+.4f}, "
            f"Δε3 = {run['eps3'][0]:+.4f} / {-run['eps3'][-1]:+.4f} rad/s²",
            "text, Fig. 5",
        ),
        Published(
            "analytic vs numerical ω, ε",
            "≤ 0.2 %",
            f"≤ {100 * worst:.1e} % (8th-order differences of the engine's φ(t))",
            "text",
        ),
    ]
    return rows


# ------------------------------------------------------------------------------------------
# 2. Maksimov: bucket-turning mechanism of the EO-4112 rope backhoe
# ------------------------------------------------------------------------------------------


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

    The rope length at each φ1 comes from triangle O1FE (:func:`rope_length_at`); the engine
    then solves from the rope alone. Time runs from the largest φ1 (rope longest) while the
    winch hauls in at ``winch.rope_speed``.

    Parameters
    ----------
    phi1 : array_like, shape (n,)
        Stick angles [rad].
    winch : RopeWinch
        Constant-speed winch; default :data:`EO4112_WINCH`.
    mech : Mechanism, optional
        Default ``examples/rope_shovel.toml``.

    Returns
    -------
    PaperRun
        As :func:`rope_shovel_run`, with ``t`` [s].
    """
    mech = mech or load_paper_model("rope_shovel")
    fe = rope_length_at(mech, phi1)
    v = winch.rope_speed
    t = (np.max(fe) - fe) / v
    return rope_shovel_run(fe, v, 0.0, mech, time=t)


# ------------------------------------------------------------------------------------------
# 3. Excavator arm vector model (seed 001)
# ------------------------------------------------------------------------------------------


def arm_joint_mechanism(mech: Mechanism | None = None) -> Mechanism:
    """The arm driven by its link angles instead of its cylinders; the cylinders float.

    Rotary drivers ``phi1`` (boom about O from the turntable: the absolute φ1), ``psi2``
    (stick about J from the boom: φ2 − φ1) and ``psi3`` (bucket about Q from the stick:
    φ3 − φ2); the three cylinders become ``free`` and report z, φz, v_r, ωz, a_r, εz — the
    paper's direction of the cylinder–link relation (φ1 → z, φz; ω1 → v_r, ωz; ε1 → a_r, εz).

    Parameters
    ----------
    mech : Mechanism, optional
        The ``arm_vector`` model; default the example file.

    Returns
    -------
    Mechanism
    """
    model = (mech or load_paper_model("arm_vector")).model
    rotary = (
        RotaryDriver("phi1", "boom", "O", "turntable"),
        RotaryDriver("psi2", "stick", "J", "boom"),
        RotaryDriver("psi3", "bucket", "Q", "stick"),
    )
    linear = tuple(dataclasses.replace(d, mode="free") for d in model.linear)
    return Mechanism(
        dataclasses.replace(model, name=model.name + " (link angles)", rotary=rotary, linear=linear)
    )


def _rigid(
    points: dict[str, tuple[float, float]],
    names: tuple[str, ...],
    a0: FloatArray,
    b0: FloatArray,
    a1: FloatArray,
    b1: FloatArray,
) -> None:
    """Move ``names`` by the rigid motion taking segment a0→b0 onto a1→b1 (same length)."""
    r0, r1 = b0 - a0, b1 - a1
    ang = math.atan2(r1[1], r1[0]) - math.atan2(r0[1], r0[0])
    c, s = math.cos(ang), math.sin(ang)
    for n in names:
        x, y = np.asarray(points[n]) - a0
        points[n] = (float(a1[0] + c * x - s * y), float(a1[1] + s * x + c * y))


def arm_inverse_mechanism(mech: Mechanism | None = None, branch: int = 1) -> Mechanism:
    """The arm positioned by its tooth tip A and its bucket angle: the inverse problem.

    A ray body about the boom foot O (rotary driver ``tip_direction``: the polar angle of A),
    a slider keeping A on it and a linear driver ``tip_distance`` = |OA| place the tooth tip;
    a rotary driver ``bucket_abs`` turns the bucket about A (value: the polar angle of A→Q,
    i.e. φ3 + π); the engine then finds J as the dyad from O (boom) and Q (stick) — the
    elbow, on the sketch's side of O→Q. The cylinders float.

    Parameters
    ----------
    mech : Mechanism, optional
        The ``arm_vector`` model; default the example file.
    branch : {1, -1}
        +1: the model's own assembly ("elbow up", ``sin(φ1 − φ2) > 0``); −1: the other one,
        the boom and stick reflected about the line O–Q.

    Returns
    -------
    Mechanism
    """
    if branch not in (1, -1):
        raise ValueError(f"branch must be +1 or -1, got {branch!r}")
    base = mech or load_paper_model("arm_vector")
    model = base.model
    pts = {n: (float(x), float(y)) for n, (x, y) in model.points.items()}
    o, j, q = (np.asarray(pts[n]) for n in ("O", "J", "Q"))
    elbow_up = (j - o)[0] * (q - o)[1] - (j - o)[1] * (q - o)[0] < 0.0
    if (1 if elbow_up else -1) != branch:
        u = (q - o) / np.hypot(*(q - o))
        jm = o + 2.0 * np.dot(j - o, u) * u - (j - o)
        boom = tuple(n for n in model.body("boom").points if n != "O")
        stick = tuple(n for n in model.body("stick").points if n != "J")
        _rigid(pts, stick, j, q, jm, q)
        _rigid(pts, boom, o, j, o, jm)
    ray = np.asarray(pts["A"]) - o
    pts["R"] = (float(o[0] + ray[0] / np.hypot(*ray)), float(o[1] + ray[1] / np.hypot(*ray)))
    bodies = (*model.bodies, Body("ray", ("O", "R")))
    rotary = (
        RotaryDriver("tip_direction", "ray", "O", "turntable"),
        RotaryDriver("bucket_abs", "bucket", "A", "turntable"),
    )
    linear = (
        LinearDriver("tip_distance", ("O", "A"), "driven"),
        *(dataclasses.replace(d, mode="free") for d in model.linear),
    )
    inv = Model(
        model.name + f" (tooth tip, branch {branch:+d})",
        pts,
        bodies,
        rotary=rotary,
        linear=linear,
        sliders=(Slider("tip_on_ray", "A", ("O", "R")),),
        lengths={k: v for k, v in model.lengths.items()},
        source=model.source,
    )
    return Mechanism(inv)


def _arm_columns(res: KinematicResult) -> dict[str, FloatArray]:
    cols: dict[str, FloatArray] = {}
    for i, link in enumerate(("boom", "stick", "bucket"), start=1):
        ang, om, ep = res.body(link)
        cols[f"phi{i}"], cols[f"omega{i}"], cols[f"eps{i}"] = ang, om, ep
    x, v, a = res.point("A")
    cols.update(x_a=x[:, 0], y_a=x[:, 1], v_xa=v[:, 0], v_ya=v[:, 1], a_xa=a[:, 0], a_ya=a[:, 1])
    for link, cyl, parent, _ in _ARM_LINKS:
        z, vr, ar = res.driver(cyl)
        cols[f"{link}_z"], cols[f"{link}_v_r"], cols[f"{link}_a_r"] = z, vr, ar
        pz, wz, ez = (res.column(f"{cyl}.{q}") for q in ("angle", "omega", "epsilon"))
        cols[f"{link}_phi_z"], cols[f"{link}_omega_z"], cols[f"{link}_eps_z"] = pz, wz, ez
        cols[f"{link}_a_k"] = 2.0 * wz * vr
        ang = res.body(link)[0]
        par = res.body(parent)[0] if parent != "turntable" else np.zeros_like(ang)
        cols[f"{link}_psi"] = wrap(ang - par)
    return {k: np.asarray(v, dtype=np.float64) for k, v in cols.items()}


def arm_forward(
    phi: tuple[npt.ArrayLike, npt.ArrayLike, npt.ArrayLike],
    omega: tuple[npt.ArrayLike, npt.ArrayLike, npt.ArrayLike] = (0.0, 0.0, 0.0),
    eps: tuple[npt.ArrayLike, npt.ArrayLike, npt.ArrayLike] = (0.0, 0.0, 0.0),
    mech: Mechanism | None = None,
) -> PaperRun:
    """Forward problem, eqs. (2), (3), (5), and the cylinders, eqs. (8)-(12).

    Absolute link angles, rates and accelerations in; the engine (driven by the link angles
    relative to their parents, :func:`arm_joint_mechanism`) gives the tooth tip A and the
    three floating cylinders.

    Parameters
    ----------
    phi, omega, eps : tuple of 3 array_like, each shape (n,) or scalar
        φ1, φ2, φ3 [rad], ω1..ω3 [rad/s], ε1..ε3 [rad/s²], absolute.
    mech : Mechanism, optional
        A mechanism from :func:`arm_joint_mechanism`; built from the example without one.

    Returns
    -------
    PaperRun
        Columns ``phi1..3, omega1..3, eps1..3, x_a, y_a, v_xa, v_ya, a_xa, a_ya`` and, for
        ``<link>`` in boom, stick, bucket: ``<link>_z, _phi_z, _v_r, _omega_z, _a_r, _eps_z,
        _a_k, _psi`` (φz, ωz, εz absolute; ``_psi`` = link angle in its parent's frame).
    """
    mech = mech or arm_joint_mechanism()
    p = np.broadcast_arrays(*(np.atleast_1d(np.asarray(x, dtype=np.float64)) for x in phi))
    w = [np.broadcast_to(np.asarray(x, dtype=np.float64), p[0].shape) for x in omega]
    e = [np.broadcast_to(np.asarray(x, dtype=np.float64), p[0].shape) for x in eps]
    res = mech.solve(
        {"phi1": p[0], "psi2": wrap(p[1] - p[0]), "psi3": wrap(p[2] - p[1])},
        {"phi1": w[0], "psi2": w[1] - w[0], "psi3": w[2] - w[1]},
        {"phi1": e[0], "psi2": e[1] - e[0], "psi3": e[2] - e[1]},
    )
    return PaperRun(_arm_columns(res), ARM_KINDS, res)


def arm_inverse(
    tip: tuple[npt.ArrayLike, npt.ArrayLike],
    phi3: npt.ArrayLike,
    branch: int = 1,
    *,
    tip_velocity: tuple[npt.ArrayLike, npt.ArrayLike] = (0.0, 0.0),
    omega3: npt.ArrayLike = 0.0,
    tip_acceleration: tuple[npt.ArrayLike, npt.ArrayLike] = (0.0, 0.0),
    eps3: npt.ArrayLike = 0.0,
    mech: Mechanism | None = None,
) -> PaperRun:
    """Inverse problem: tooth tip (x_A, y_A) and bucket angle φ3 → φ1, φ2, and the paper's
    mixed rate problems (ω3, v_xA, v_yA → ω1, ω2; ε3, a_xA, a_yA → ε1, ε2).

    The tip's Cartesian motion is handed to the engine as polar coordinates about O (the
    inputs of :func:`arm_inverse_mechanism`): ``r = |OA|``, ``θ = atan2(y, x)``,
    ``ṙ = (x vx + y vy)/r``, ``θ̇ = (x vy − y vx)/r²``,
    ``r̈ = (x ax + y ay + |v|²)/r − ṙ²/r``, ``θ̈ = (x ay − y ax)/r² − 2 ṙ θ̇ / r``.

    Parameters
    ----------
    tip : tuple of 2 array_like, shape (n,)
        x_A, y_A [m].
    phi3 : array_like, shape (n,)
        Absolute bucket angle [rad].
    branch : {1, -1}
        Elbow assembly, see :func:`arm_inverse_mechanism`.
    tip_velocity, tip_acceleration : tuple of 2 array_like
        (v_xA, v_yA) [m/s] and (a_xA, a_yA) [m/s²].
    omega3, eps3 : array_like
        Bucket angular velocity and acceleration [rad/s, rad/s²].
    mech : Mechanism, optional
        From :func:`arm_inverse_mechanism` with the same ``branch``.

    Returns
    -------
    PaperRun
        The columns of :func:`arm_forward`; samples the arm cannot reach are NaN, with the
        reason in ``result.status``.
    """
    mech = mech or arm_inverse_mechanism(branch=branch)
    x, y, p3 = np.broadcast_arrays(
        *(np.atleast_1d(np.asarray(a, dtype=np.float64)) for a in (*tip, phi3))
    )
    vx, vy, w3, ax, ay, e3 = (
        np.broadcast_to(np.asarray(a, dtype=np.float64), x.shape)
        for a in (*tip_velocity, omega3, *tip_acceleration, eps3)
    )
    r = np.hypot(x, y)
    rd = (x * vx + y * vy) / r
    td = (x * vy - y * vx) / r**2
    rdd = (x * ax + y * ay + vx**2 + vy**2) / r - rd**2 / r
    tdd = (x * ay - y * ax) / r**2 - 2.0 * rd * td / r
    res = mech.solve(
        {"tip_direction": np.arctan2(y, x), "tip_distance": r, "bucket_abs": wrap(p3 + np.pi)},
        {"tip_direction": td, "tip_distance": rd, "bucket_abs": w3},
        {"tip_direction": tdd, "tip_distance": rdd, "bucket_abs": e3},
    )
    return PaperRun(_arm_columns(res), ARM_KINDS, res)


def arm_cylinder_sweep(link: str, n: int = 181, mech: Mechanism | None = None) -> PaperRun:
    """One cylinder over its whole stroke, the cylinder driving its link (eqs. 7-12, inverse).

    The model file's own drivers: the cylinder's length sweeps its stroke range at unit rate
    (so the link's ω, ε are the transfer functions dψ/dz, d²ψ/dz²), the other two cylinders
    held at their sketch lengths.

    Parameters
    ----------
    link : {"boom", "stick", "bucket"}
        Which cylinder.
    n : int
        Number of samples.
    mech : Mechanism, optional
        The ``arm_vector`` model; default the example file.

    Returns
    -------
    PaperRun
        The columns of :func:`arm_forward`.
    """
    mech = mech or load_paper_model("arm_vector")
    cyl = {lk: c for lk, c, _, _ in _ARM_LINKS}[link]
    z = np.linspace(*_ARM_STROKES[link], n)
    res = mech.solve({cyl: z})
    return PaperRun(_arm_columns(res), ARM_KINDS, res)


#: Pin-to-pin length ranges of the three cylinders [m] (EXCAVATOR_20T's z_min, z_max).
_ARM_STROKES = {"boom": (2.00, 3.40), "stick": (2.00, 3.25), "bucket": (2.00, 2.75)}


# ------------------------------------------------------------------------------------------
# Agreement with the closed-form reference modules, and a plain-text table
# ------------------------------------------------------------------------------------------


def _rel(engine: FloatArray, ref: FloatArray, angle: bool) -> float:
    d = np.abs(wrap(engine - ref)) if angle else np.abs(engine - ref)
    scale = float(np.nanmax(np.abs(ref)))
    return float(np.nanmax(d) / scale) if scale > 0.0 else float(np.nanmax(d))


def pasika_reference_agreement(run: PaperRun) -> dict[str, float]:
    """Engine against :mod:`excavkin.reference.pasika` (eqs. 1-12) on the same samples.

    Parameters
    ----------
    run : PaperRun
        From :func:`pasika_run`.

    Returns
    -------
    dict of str to float
        Per quantity (φ1, φ3, ω1, ω3, ε1, ε3): the largest difference relative to the
        largest magnitude of the reference over the run.
    """
    from excavkin.reference import pasika as ref

    k = ref.kinematics(run["s"], run["v21"], run["a21"])
    refs = {
        "phi1": k.positions.phi1,
        "phi3": k.positions.phi3,
        "omega1": k.velocities.omega1,
        "omega3": k.velocities.omega3,
        "eps1": k.accelerations.eps1,
        "eps3": k.accelerations.eps3,
    }
    return {n: _rel(run[n], r, n.startswith("phi")) for n, r in refs.items()}


def rope_shovel_reference_agreement(run: PaperRun) -> dict[str, float]:
    """Engine against :func:`excavkin.reference.maksimov.bucket_mechanism` at the run's φ1, ω1.

    Parameters
    ----------
    run : PaperRun
        From :func:`rope_shovel_run` or :func:`rope_shovel_sweep` on ``rope_shovel.toml``.

    Returns
    -------
    dict of str to float
        Per quantity of :class:`~excavkin.reference.maksimov.BucketMechanismState` that the run
        has: the largest difference relative to the reference's largest magnitude. ω1 itself is
        compared with eq. (2) corrected, from the rope speed.
    """
    from excavkin.reference import maksimov as ref

    geom = ref.EO4112_GEOMETRY
    st = ref.bucket_mechanism(geom, run["phi1"], run["omega1"])
    out = {
        f: _rel(run[f], np.asarray(getattr(st, f)), ROPE_SHOVEL_KINDS[f] == "angle")
        for f in st._fields
        if f in run.columns and f != "omega1"
    }
    w1 = ref.stick_rate_from_rope(geom.o1e_length, geom.l13, run["phi1"], run["v_rope"])
    out["omega1"] = _rel(run["omega1"], w1, False)
    return out


def text_table(headers: Sequence[str], rows: Sequence[Sequence[str]]) -> str:
    """Rows of strings as a plain-text table with aligned columns.

    Parameters
    ----------
    headers : sequence of str
    rows : sequence of sequence of str

    Returns
    -------
    str
    """
    widths = [max(len(h), *(len(r[i]) for r in rows)) for i, h in enumerate(headers)]
    fmt = "  ".join(f"{{:<{w}}}" for w in widths)
    lines = [fmt.format(*headers), "  ".join("-" * w for w in widths)]
    lines += [fmt.format(*r) for r in rows]
    return "\n".join(line.rstrip() for line in lines)


def arm_reference_agreement(n: int = 400, seed: int = 1) -> dict[str, float]:
    """Engine against :mod:`excavkin.reference.arm_vector` over the arm's whole working range.

    ``n`` poses drawn (seeded) uniformly from the three cylinders' link-angle ranges of
    ``EXCAVATOR_20T``, with random link rates and accelerations, are solved three ways:
    forward (link angles in, :func:`arm_forward`), inverse (tooth tip and φ3 in, both
    branches, :func:`arm_inverse`) and cylinder-driven (the model file itself, the reference's
    lengths in).

    Parameters
    ----------
    n : int
        Number of poses.
    seed : int
        Seed of the random poses.

    Returns
    -------
    dict of str to float
        Largest difference relative to the reference's largest magnitude, per group:
        ``"forward A"`` (x_A … a_yA), ``"cylinders"`` (z, φz, v_r, ωz, a_r, εz, a_k of all
        three), ``"inverse +1"``, ``"inverse -1"`` (φ1, φ2, ω1, ω2, ε1, ε2) and
        ``"cylinder-driven"`` (φ1, φ2, φ3 from the lengths; ω, ε from v_r, a_r).
    """
    from excavkin.reference import arm_vector as ref

    dims = ref.EXCAVATOR_20T
    rng = np.random.default_rng(seed)
    mounts = (dims.boom, dims.stick, dims.bucket)
    psi = [rng.uniform(min(m.psi_limits), max(m.psi_limits), n) for m in mounts]
    phi = np.cumsum(psi, axis=0)
    om = rng.normal(0.0, 0.3, (3, n))
    ep = rng.normal(0.0, 0.5, (3, n))
    out: dict[str, float] = {}
    fw = arm_forward((phi[0], phi[1], phi[2]), (om[0], om[1], om[2]), (ep[0], ep[1], ep[2]))
    xa, ya = ref.arm_position(dims, *phi)
    vx, vy = ref.arm_velocity(dims, *phi, *om)
    ax, ay = ref.arm_acceleration(dims, *phi, *om, *ep)
    out["forward A"] = max(
        _rel(fw[k], r, False)
        for k, r in (
            ("x_a", xa),
            ("y_a", ya),
            ("v_xa", vx),
            ("v_ya", vy),
            ("a_xa", ax),
            ("a_ya", ay),
        )
    )
    cyl = ref.arm_cylinder_kinematics(dims, *phi, *om, *ep)
    out["cylinders"] = max(
        _rel(fw[f"{link}_{f}"], np.asarray(getattr(ck, f)), f == "phi_z")
        for link, ck in cyl.items()
        for f in ck._fields
    )
    for branch in (1, -1):
        q1, q2 = ref.arm_inverse_position(dims, xa, ya, phi[2], branch)
        w1, w2 = ref.arm_rates_from_tool(dims, q1, q2, phi[2], om[2], vx, vy)
        e1, e2 = ref.arm_accelerations_from_tool(dims, q1, q2, phi[2], w1, w2, om[2], ep[2], ax, ay)
        iv = arm_inverse(
            (xa, ya),
            phi[2],
            branch,
            tip_velocity=(vx, vy),
            omega3=om[2],
            tip_acceleration=(ax, ay),
            eps3=ep[2],
        )
        out[f"inverse {branch:+d}"] = max(
            _rel(iv[k], r, k.startswith("phi"))
            for k, r in (
                ("phi1", q1),
                ("phi2", q2),
                ("omega1", w1),
                ("omega2", w2),
                ("eps1", e1),
                ("eps2", e2),
            )
        )
    mech = load_paper_model("arm_vector")
    res = mech.solve(
        {f"{link}_cyl": cyl[link].z for link in ("boom", "stick", "bucket")},
        {f"{link}_cyl": cyl[link].v_r for link in ("boom", "stick", "bucket")},
        {f"{link}_cyl": cyl[link].a_r for link in ("boom", "stick", "bucket")},
    )
    cd = _arm_columns(res)
    out["cylinder-driven"] = max(
        _rel(cd[f"{q}{i + 1}"], r[i], q == "phi")
        for q, r in (("phi", phi), ("omega", om), ("eps", ep))
        for i in range(3)
    )
    return out
