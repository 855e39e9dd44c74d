r"""The excavator arm's vector model (seed 001), by the engine.

The model ``arm_vector.toml`` is driven by its cylinder lengths; or, by
`arm_joint_mechanism`, by the link angles; or, by `arm_inverse_mechanism`, by the
tooth tip and the bucket angle. The closed-form reference
(`excavkin.papers.arm_vector.reference`) is used only for the agreement check.
"""

from __future__ import annotations

import dataclasses
import math
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from excavkin.arrays import FloatArray
from excavkin.mechanism import Mechanism
from excavkin.model.entities import Body, LinearDriver, Model, RotaryDriver, Slider

if TYPE_CHECKING:
    from excavkin.kinematics.result import KinematicResult

from excavkin.papers.common import PaperRun, load_paper_model, rel_error, wrap

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
    relative to their parents, `arm_joint_mechanism`) gives the tooth tip A and the
    three floating cylinders.

    Parameters
    ----------
    phi, omega, eps : tuple of 3 array_like, each shape (n,) or scalar
        φ1, φ2, φ3 [rad], ω1..ω3 [rad/s], ε1..ε3 [rad/s²], absolute.
    mech : Mechanism, optional
        A mechanism from `arm_joint_mechanism`; built from the example without one.

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
    inputs of `arm_inverse_mechanism`): ``r = |OA|``, ``θ = atan2(y, x)``,
    ``ṙ = (x vx + y vy)/r``, ``θ̇ = (x vy − y vx)/r²``,
    ``r̈ = (x ax + y ay + |v|²)/r − ṙ²/r``, ``θ̈ = (x ay − y ax)/r² − 2 ṙ θ̇ / r``.

    Parameters
    ----------
    tip : tuple of 2 array_like, shape (n,)
        x_A, y_A [m].
    phi3 : array_like, shape (n,)
        Absolute bucket angle [rad].
    branch : {1, -1}
        Elbow assembly, see `arm_inverse_mechanism`.
    tip_velocity, tip_acceleration : tuple of 2 array_like
        (v_xA, v_yA) [m/s] and (a_xA, a_yA) [m/s²].
    omega3, eps3 : array_like
        Bucket angular velocity and acceleration [rad/s, rad/s²].
    mech : Mechanism, optional
        From `arm_inverse_mechanism` with the same ``branch``.

    Returns
    -------
    PaperRun
        The columns of [`arm_forward`][excavkin.papers.arm_vector.study.arm_forward]; samples the
        arm cannot reach are NaN, with the
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
        The columns of [`arm_forward`][excavkin.papers.arm_vector.study.arm_forward].
    """
    mech = mech or load_paper_model("arm_vector")
    cyl = {lk: c for lk, c, _, _ in _ARM_LINKS}[link]
    z = np.linspace(*_ARM_STROKES[link], n)
    res = mech.solve({cyl: z})
    return PaperRun(_arm_columns(res), ARM_KINDS, res)


#: Pin-to-pin length ranges of the three cylinders [m] (EXCAVATOR_20T's z_min, z_max).
_ARM_STROKES = {"boom": (2.00, 3.40), "stick": (2.00, 3.25), "bucket": (2.00, 2.75)}


def arm_reference_agreement(n: int = 400, seed: int = 1) -> dict[str, float]:
    """Engine against `reference` over the whole working range.

    ``n`` poses drawn (seeded) uniformly from the three cylinders' link-angle ranges of
    ``EXCAVATOR_20T``, with random link rates and accelerations, are solved three ways:
    forward (link angles in, [`arm_forward`][excavkin.papers.arm_vector.study.arm_forward]), inverse
    (tooth tip and φ3 in, both
    branches, `arm_inverse`) and cylinder-driven (the model file itself, the reference's
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
    from excavkin.papers.arm_vector import reference as ref

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
        rel_error(fw[k], r, False)
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
        rel_error(fw[f"{link}_{f}"], np.asarray(getattr(ck, f)), f == "phi_z")
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
            rel_error(iv[k], r, k.startswith("phi"))
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
        rel_error(cd[f"{q}{i + 1}"], r[i], q == "phi")
        for q, r in (("phi", phi), ("omega", om), ("eps", ep))
        for i in range(3)
    )
    return out
