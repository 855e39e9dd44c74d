r"""The MO-100 crank-rocker hammer by the general engine: what ``excavkin reproduce mo100`` does.

Paper: V.E. Eremyants, G.M. Raiymbekova, *Determination of reactive forces acting on the
manipulator of excavator EO-2621 with mounted hammer MO-100* (seed 002;
``docs/papers/mo100.md``). The hammer is the model file ``examples/mo100_hammer.toml`` solved by
[`Mechanism`][excavkin.Mechanism] (kinematics, then d'Alembert kinetostatics with ``loads=[]``:
inertia only, crank and coupler massless as in the paper), with the crank at constant speed
ω1 (`ConstantSpeedCrank`). The paper's own closed forms
(`excavkin.papers.mo100.reference`) are used only for the columns that show the agreement,
never to compute the engine's values. Pure NumPy, SI units, batch axis first.

Axes
----
The engine works in the model's frame axes x', y' (origin A, x' along A->D). The paper's
housing axes x, y have x along D->S *at the impact position* and y its counter-clockwise
normal ("up", against the blow). At impact D->C lies along A->D, and S is a fixed point of the
rocker at the angle ∠CDS from D->C, so the housing x axis is at the angle
``theta_h = angle(A->D) + angle(D->C -> D->S)`` in frame axes; the model file puts S on the
clockwise side of D->C (``theta_h = -50 deg``). A vector's housing components are its frame
components rotated by ``-theta_h`` (+50 deg):
``[Rx, Ry] = [[cos a, -sin a], [sin a, cos a]] @ [Rx', Ry']`` with ``a = -theta_h``
(`housing_axes_angle`, `to_housing_axes`)::

         y (up, against the blow)
         ^        C (phi ~ 300 deg)
         |       /
         |      / 3
         |     /
    A ---------D--------------- x'  (frame, along A->D)
                \  alpha = 50 deg
                 \
                  S ........> x (housing: along D->S at impact)

Change point
------------
The linkage is a change-point linkage (``l1 + l2 = l0 + l3``): at ``phi = 0 (mod 2 pi)`` the
joints A, B, D, C are collinear, the Assur group (2, 3) is singular and the rocker's angular
velocity has two one-sided limits (``u31 = -3.8804`` before the blow, ``+0.6804`` after). The
engine reports such a sample as a *dead position at dyad C* and returns NaN rates and forces
there; it is never solved silently. This module handles it explicitly:

* sample grids are *open*: ``phi_k = 2 pi k / n``, ``k = 1 ... n - 1`` (`cycle_grid`),
  they exclude ``phi = 0 (mod 2 pi)``;
* the values at the change point are the engine's **one-sided limits**, extrapolated from
  its own samples at 1, 2, 3, 4 mrad on each side by the cubic through them
  (`one_sided_limits`; the Cartesian engine loses about ``1e-16 / phi^2`` of relative
  precision as ``phi -> 0``, so closer samples would not help);
* impulses integrate the smooth lobes of one cycle ``0+ ... 2 pi -`` with the trapezoid rule
  on a fine grid closed by those one-sided limits; each lobe of Rx is split at its zero
  crossings;
* the blow itself — the rocker's rebound from the tool, where its velocity jumps from
  ``u31(2 pi -)`` to ``u31(0 +)`` — is the paper's physics, outside the rigid constant-speed
  kinematics: it is not modelled. The housing takes the momentum ``m3 (v_S(0+) - v_S(2 pi-))``
  as the integral of its force over the open cycle (534.6 N s along y for the paper's data,
  `excavkin.papers.mo100.reference.cycle_impulse`).

>>> import numpy as np
>>> run = mo100_run(np.radians([90.0, 350.0]))
>>> np.round(run.ry).tolist()
[1351.0, 39900.0]
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from excavkin.arrays import FloatArray
from excavkin.kinetostatics import inertia_loads as dalembert_loads
from excavkin.motion import ConstantSpeedCrank
from excavkin.papers.mo100 import reference as ref

if TYPE_CHECKING:
    from excavkin.kinetostatics import ForceResult
    from excavkin.mechanism import Mechanism

__all__ = [
    "MO100_OMEGA1",
    "FitRow",
    "Lobe",
    "MO100Run",
    "OneSided",
    "ReproductionRow",
    "RxImpulses",
    "cycle_grid",
    "engine_fits",
    "housing_axes_angle",
    "load_mo100",
    "lobes",
    "main_ry_lobe",
    "mirror_center_of_mass",
    "mo100_run",
    "one_sided_limits",
    "reference_data",
    "reproduction_table",
    "rx_impulses",
    "trapezoid_impulse",
    "to_housing_axes",
]


#: The paper's crank speed ω1 [rad/s] (5 Hz; period 0.2 s).
MO100_OMEGA1 = 31.416

_TWO_PI = 2.0 * math.pi
_LIMIT_NODES = np.array([1.0, 2.0, 3.0, 4.0]) * 1e-3
"""Distances [rad] from the change point of the samples the one-sided limits come from."""


def load_mo100() -> Mechanism:
    """The hammer's model file ``examples/mo100_hammer.toml``, loaded.

    Returns
    -------
    Mechanism
    """
    import excavkin

    return excavkin.load(excavkin.example_path("mo100_hammer"))


def _mech(mech: Mechanism | None) -> Mechanism:
    return load_mo100() if mech is None else mech


def _angle(v: tuple[float, float]) -> float:
    return math.atan2(v[1], v[0])


def mirror_center_of_mass(mech: Mechanism | None = None) -> Mechanism:
    """The hammer with the rocker's centre of mass S mirrored about the line D->C.

    The paper's figures are lost, and ∠CDS = α does not say on which side of D->C the centre
    of mass lies. The model file puts S on the clockwise side (the side eqs. (8)-(14) describe
    with the printed α > 0, see ``docs/papers/mo100.md``); this returns the other reading:
    the same hammer, with S reflected in the line D->C of the sketch. Rx, Ry (in the housing
    axes of each reading, `housing_axes_angle` +50 deg instead of -50 deg), R12 and H do
    not depend on the side; R03 does.

    Parameters
    ----------
    mech : Mechanism, optional
        The hammer; default `load_mo100`.

    Returns
    -------
    Mechanism
        A new mechanism; ``mech`` is not changed.
    """
    import excavkin

    model = _mech(mech).model
    d, c = np.asarray(model.points["D"]), np.asarray(model.points["C"])
    e = (c - d) / np.linalg.norm(c - d)
    bodies = []
    for body in model.bodies:
        if body.name == "rocker":
            if body.center_of_mass is None:
                raise ValueError("the rocker of the MO-100 model has no center_of_mass")
            v = np.asarray(body.center_of_mass) - d
            s = d + 2.0 * float(np.dot(v, e)) * e - v
            body = dataclasses.replace(body, center_of_mass=(float(s[0]), float(s[1])))
        bodies.append(body)
    return excavkin.Mechanism(dataclasses.replace(model, bodies=tuple(bodies)))


def housing_axes_angle(mech: Mechanism | None = None) -> float:
    """Angle of the paper's housing x axis (D->S at impact) in the model's frame axes [rad].

    ``angle(A->D) + angle(D->S) - angle(D->C)``, read from the model's points and the rocker's
    centre of mass (a rigid offset, so any sketch position gives it). -50 deg for the model
    file (S on the clockwise side of D->C).

    Parameters
    ----------
    mech : Mechanism, optional
        The hammer; default `load_mo100`.

    Returns
    -------
    float
    """
    m = _mech(mech).model
    pts = m.points
    rocker = next(b for b in m.bodies if b.name == "rocker")
    if rocker.center_of_mass is None:
        raise ValueError("the rocker of the MO-100 model has no center_of_mass")
    a, d, c = (np.asarray(pts[k]) for k in ("A", "D", "C"))
    s = np.asarray(rocker.center_of_mass)
    ad, dc, ds = d - a, c - d, s - d
    offset = _angle((ds[0], ds[1])) - _angle((dc[0], dc[1]))
    return float(np.angle(np.exp(1j * (_angle((ad[0], ad[1])) + offset))))


def to_housing_axes(v: npt.ArrayLike, theta_h: float) -> FloatArray:
    """Frame components of vectors → housing components (rotation by ``-theta_h``).

    Parameters
    ----------
    v : array_like, shape (n, 2)
        Vectors in frame axes.
    theta_h : float
        `housing_axes_angle` [rad].

    Returns
    -------
    ndarray, shape (n, 2)
    """
    arr = np.asarray(v, dtype=np.float64)
    c, s = math.cos(theta_h), math.sin(theta_h)
    return np.stack([c * arr[:, 0] + s * arr[:, 1], -s * arr[:, 0] + c * arr[:, 1]], axis=-1)


def reference_data(mech: Mechanism | None = None, omega1: float = MO100_OMEGA1) -> ref.MO100Data:
    """The reference module's data built from the model file (same mechanism, same numbers).

    Parameters
    ----------
    mech : Mechanism, optional
        The hammer; default `load_mo100`.
    omega1 : float
        Crank speed [rad/s].

    Returns
    -------
    excavkin.papers.mo100.reference.MO100Data
        Lengths from ``[lengths]``, ``l_s`` and ``alpha`` from the rocker's centre of mass,
        ``m3`` and the centroidal ``inertia`` from the rocker (the engine's J is about S).
        ``alpha`` is signed like the reference's: positive when S lies clockwise of D->C (the
        model file, +50 deg), negative for the other side (`mirror_center_of_mass`).
    """
    m = _mech(mech).model
    ln = m.lengths
    rocker = next(b for b in m.bodies if b.name == "rocker")
    if rocker.center_of_mass is None or rocker.mass is None or rocker.inertia is None:
        raise ValueError("the rocker of the MO-100 model needs mass, inertia, center_of_mass")
    d, c = np.asarray(m.points["D"]), np.asarray(m.points["C"])
    ds, dc = np.asarray(rocker.center_of_mass) - d, c - d
    # angle from D->S to D->C: positive when S is clockwise of D->C
    alpha = float(np.angle(np.exp(1j * (_angle((dc[0], dc[1])) - _angle((ds[0], ds[1]))))))
    return ref.MO100Data(
        l1=ln[("A", "B")],
        l2=ln[("B", "C")],
        l3=ln[("D", "C")],
        l0=ln[("A", "D")],
        l_s=float(np.hypot(*ds)),
        alpha=alpha,
        m3=rocker.mass,
        inertia=rocker.inertia,
        omega1=omega1,
        inertia_axis="centroid",
    )


@dataclass(frozen=True, slots=True)
class MO100Run:
    """The engine's hammer quantities under the paper's names, each shape ``(n,)`` (SI).

    Attributes
    ----------
    phi : ndarray, shape (n,)
        Crank angle [rad]; ``t = phi / omega1`` [s] is ``t``.
    t : ndarray, shape (n,)
        Time [s].
    psi : ndarray, shape (n,)
        Rocker angle of D->C from A->D [rad].
    rx, ry : ndarray, shape (n,)
        Resultant of the pin forces *on the housing* (``ForceResult.resultant("housing")``)
        in housing axes [N].
    p_n, p_tau : ndarray, shape (n,)
        The paper's P_u^n and P_u^tau [N] from the engine's d'Alembert force ``-m3 a_S``:
        ``p_n`` its component along D->S, ``p_tau`` minus its component along the CCW normal
        of D->S (so signed like eps3, as printed in eq (1)).
    m_u : ndarray, shape (n,)
        The paper's M_u = I eps3 [N m]: minus the engine's d'Alembert couple ``-J eps3``.
    torque : ndarray, shape (n,)
        Crank driving torque [N m] (CCW on the crank).
    omega1 : float
        Crank speed [rad/s].
    theta_h : float
        `housing_axes_angle` [rad].
    forces : ForceResult
        The engine's full result.
    """

    phi: FloatArray
    t: FloatArray
    psi: FloatArray
    rx: FloatArray
    ry: FloatArray
    p_n: FloatArray
    p_tau: FloatArray
    m_u: FloatArray
    torque: FloatArray
    omega1: float
    theta_h: float
    forces: ForceResult

    def __len__(self) -> int:
        return int(self.phi.shape[0])


def mo100_run(
    phi: npt.ArrayLike, mech: Mechanism | None = None, omega1: float = MO100_OMEGA1
) -> MO100Run:
    """Solve the hammer's kinematics and kinetostatics at crank angles ``phi``.

    The crank turns at constant speed (`ConstantSpeedCrank`,
    ``phi = omega1 t``); loads: inertia only (``loads=[]``).

    Parameters
    ----------
    phi : array_like, shape (n,)
        Crank angles [rad]. Samples at ``0 (mod 2 pi)`` come back NaN with the engine's status
        "dead position at dyad C": use `cycle_grid` and `one_sided_limits`.
    mech : Mechanism, optional
        The hammer; default `load_mo100`.
    omega1 : float
        Crank speed [rad/s].

    Returns
    -------
    MO100Run
    """
    m = _mech(mech)
    p = np.asarray(phi, dtype=np.float64)
    if p.ndim != 1:
        raise ValueError(f"phi must have shape (n,), got {p.shape}")
    crank = ConstantSpeedCrank(omega1)
    t = p / omega1
    state = crank.evaluate(t)
    fr = m.solve({"crank": state.s}, {"crank": state.v}, {"crank": state.a}, time=t, loads=[])
    kin = fr.kinematics
    theta_h = housing_axes_angle(m)
    r = to_housing_axes(fr.resultant("housing"), theta_h)
    j = fr.system.bodies.index("rocker")
    force, couple = dalembert_loads(kin, fr.mass)
    f = force[:, j]
    d, c = kin.point("D")[0], kin.point("C")[0]
    psi = np.arctan2(c[:, 1] - d[:, 1], c[:, 0] - d[:, 0])
    a = fr.mass.com[j]
    off = math.atan2(float(a[1]), float(a[0]))  # angle D->C -> D->S
    u = np.stack([np.cos(psi + off), np.sin(psi + off)], axis=-1)
    nrm = np.stack([-u[:, 1], u[:, 0]], axis=-1)
    return MO100Run(
        phi=p,
        t=t,
        psi=psi,
        rx=r[:, 0],
        ry=r[:, 1],
        p_n=np.sum(f * u, axis=-1),
        p_tau=-np.sum(f * nrm, axis=-1),
        m_u=-couple[:, j],
        torque=fr.torque("crank"),
        omega1=omega1,
        theta_h=theta_h,
        forces=fr,
    )


def cycle_grid(n: int) -> FloatArray:
    """Open grid of one crank turn without the change point: ``2 pi k / n``, ``k = 1 ... n-1``.

    Parameters
    ----------
    n : int
        Number of intervals (>= 2); step ``360 / n`` deg.

    Returns
    -------
    ndarray, shape (n - 1,)
    """
    if n < 2:
        raise ValueError("cycle_grid needs n >= 2")
    return np.arange(1, n, dtype=np.float64) * (_TWO_PI / n)


def _extrapolate(vals: FloatArray) -> FloatArray:
    """Cubic through ``vals[j]`` at ``_LIMIT_NODES[j]``, evaluated at 0; vals shape (4, k)."""
    x = _LIMIT_NODES
    w = np.array(
        [np.prod([-x[k] / (x[j] - x[k]) for k in range(4) if k != j]) for j in range(4)]
    )  # (4, -6, 4, -1) for equal spacing
    return np.asarray(np.tensordot(w, vals, axes=1), dtype=np.float64)


@dataclass(frozen=True, slots=True)
class OneSided:
    """The engine's one-sided limits at the change point.

    Attributes
    ----------
    before, after : dict of str to float
        ``phi -> 2 pi -`` (the blow) and ``phi -> 0 +`` (the rebound): ``"rx"``, ``"ry"``,
        ``"p_n"``, ``"p_tau"``, ``"m_u"``, ``"torque"`` and ``"u31"`` (rocker speed / omega1).
    """

    before: dict[str, float]
    after: dict[str, float]


_KEYS = ("rx", "ry", "p_n", "p_tau", "m_u", "torque")


def one_sided_limits(mech: Mechanism | None = None, omega1: float = MO100_OMEGA1) -> OneSided:
    """The engine's values at the change point, from each side, by extrapolation.

    The cubic through the engine's samples at 1, 2, 3, 4 mrad from the change point (on one
    side) evaluated at 0 (weights 4, -6, 4, -1): truncation error of order
    ``f''''(xi) (1 mrad)^4`` plus the engine's round-off at 1 mrad (about ``1e-16 / phi^2``
    relative, amplified 15 times) — about 1e-8 relative together for this hammer, against
    the reference's exact limits.

    Parameters
    ----------
    mech : Mechanism, optional
        The hammer; default `load_mo100`.
    omega1 : float
        Crank speed [rad/s].

    Returns
    -------
    OneSided
    """
    m = _mech(mech)
    phi = np.concatenate([_TWO_PI - _LIMIT_NODES, _LIMIT_NODES])
    run = mo100_run(phi, m, omega1)
    omega3 = run.forces.kinematics.body("rocker")[1]
    cols = {k: getattr(run, k) for k in _KEYS}
    cols["u31"] = omega3 / omega1
    out: list[dict[str, float]] = [{}, {}]
    for k, v in cols.items():
        lim = _extrapolate(np.stack([v[:4], v[4:]], axis=1))
        out[0][k], out[1][k] = float(lim[0]), float(lim[1])
    return OneSided(before=out[0], after=out[1])


# ----------------------------------------------------------------------------------------------
# impulses


def _trapz(y: FloatArray, x: FloatArray) -> float:
    return float(np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(x)))


@dataclass(frozen=True, slots=True)
class Lobe:
    """One lobe of a force component between two zero crossings (or the cycle's ends).

    Attributes
    ----------
    start, stop : float
        Crank angles [rad].
    impulse : float
        Integral of the force over the lobe [N s].
    """

    start: float
    stop: float
    impulse: float


def lobes(phi: FloatArray, f: FloatArray, omega1: float) -> list[Lobe]:
    """Split ``f(phi)`` at its zero crossings and integrate each lobe (trapezoid, ``dt``).

    Crossings are placed by linear interpolation inside the interval where ``f`` changes sign,
    and that interval's trapezoid is split there.

    Parameters
    ----------
    phi : ndarray, shape (n,)
        Increasing crank angles [rad] (closed by the one-sided limits at the ends).
    f : ndarray, shape (n,)
        Force [N].
    omega1 : float
        Crank speed [rad/s] (``dt = dphi / omega1``).

    Returns
    -------
    list of Lobe
    """
    sign_change = np.nonzero(f[:-1] * f[1:] < 0.0)[0]
    cuts = phi[sign_change] - f[sign_change] * (phi[sign_change + 1] - phi[sign_change]) / (
        f[sign_change + 1] - f[sign_change]
    )
    x = np.insert(phi, sign_change + 1, cuts)
    y = np.insert(f, sign_change + 1, 0.0)
    bounds = [0, *(sign_change + 1 + np.arange(sign_change.size)).tolist(), x.size - 1]
    out = []
    for a, b in zip(bounds[:-1], bounds[1:], strict=True):
        out.append(Lobe(float(x[a]), float(x[b]), _trapz(y[a : b + 1], x[a : b + 1] / omega1)))
    return out


def _closed_cycle(
    n: int, mech: Mechanism | None, omega1: float
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """phi (n + 1,) over [0, 2 pi] and rx, ry with the one-sided limits at the ends."""
    m = _mech(mech)
    run = mo100_run(cycle_grid(n), m, omega1)
    lim = one_sided_limits(m, omega1)
    phi = np.concatenate([[0.0], run.phi, [_TWO_PI]])
    rx = np.concatenate([[lim.after["rx"]], run.rx, [lim.before["rx"]]])
    ry = np.concatenate([[lim.after["ry"]], run.ry, [lim.before["ry"]]])
    return phi, rx, ry


@dataclass(frozen=True, slots=True)
class RxImpulses:
    """Impulses of the housing force over one cycle ``0+ ... 2 pi -``.

    Attributes
    ----------
    lobes : list of Lobe
        Lobes of Rx between its zero crossings.
    positive, negative, net : float
        Sums of the positive and negative lobes of Rx, and the net x-impulse [N s].
    sy : float
        Net y-impulse over the cycle [N s].
    """

    lobes: list[Lobe]
    positive: float
    negative: float
    net: float
    sy: float


def rx_impulses(
    n: int = 72_000, mech: Mechanism | None = None, omega1: float = MO100_OMEGA1
) -> RxImpulses:
    """Net x-impulse of the housing force over a cycle, and its lobes (engine).

    Parameters
    ----------
    n : int
        Intervals over the cycle (default 0.005 deg).
    mech : Mechanism, optional
        The hammer; default `load_mo100`.
    omega1 : float
        Crank speed [rad/s].

    Returns
    -------
    RxImpulses
    """
    phi, rx, ry = _closed_cycle(n, mech, omega1)
    lb = lobes(phi, rx, omega1)
    pos = sum(lo.impulse for lo in lb if lo.impulse > 0.0)
    neg = sum(lo.impulse for lo in lb if lo.impulse < 0.0)
    return RxImpulses(lb, pos, neg, _trapz(rx, phi / omega1), _trapz(ry, phi / omega1))


def main_ry_lobe(
    n: int = 20_000, mech: Mechanism | None = None, omega1: float = MO100_OMEGA1
) -> Lobe:
    """The main (positive, pre-impact) lobe of Ry and its impulse S (engine).

    The lobe starts at the last zero crossing of Ry before the blow — bracketed on a 0.1 deg
    grid over 300...340 deg, then bisected with the engine to 1e-13 rad — and ends at the
    change point ``2 pi -`` (its one-sided limit closes the grid).

    Parameters
    ----------
    n : int
        Intervals of the trapezoid rule over the lobe.
    mech : Mechanism, optional
        The hammer; default `load_mo100`.
    omega1 : float
        Crank speed [rad/s].

    Returns
    -------
    Lobe
    """
    m = _mech(mech)
    coarse = np.radians(np.arange(300.0, 340.0001, 0.1))
    ry = mo100_run(coarse, m, omega1).ry
    k = np.nonzero((ry[:-1] < 0.0) & (ry[1:] >= 0.0))[0]
    if k.size == 0:
        raise ValueError("main_ry_lobe: Ry does not cross zero upwards between 300 and 340 deg")
    lo, hi = float(coarse[k[-1]]), float(coarse[k[-1] + 1])
    while hi - lo > 1e-13:
        # ten-way bisection per engine call
        x = np.linspace(lo, hi, 11)
        y = mo100_run(x, m, omega1).ry
        j = int(np.nonzero(y >= 0.0)[0][0])
        lo, hi = float(x[j - 1]), float(x[j])
    phi = np.linspace(hi, _TWO_PI, n + 1)[:-1]
    ry_lobe = np.append(mo100_run(phi, m, omega1).ry, one_sided_limits(m, omega1).before["ry"])
    phi = np.append(phi, _TWO_PI)
    return Lobe(hi, _TWO_PI, _trapz(ry_lobe, phi / omega1))


def trapezoid_impulse(
    start_deg: float,
    stop_deg: float,
    step_deg: float,
    mech: Mechanism | None = None,
    omega1: float = MO100_OMEGA1,
) -> float:
    """Ry impulse by the trapezoid rule on a coarse crank-angle grid, as the paper did (engine).

    Grid ``start_deg, start_deg + step_deg, ..., stop_deg``; a node at 360 deg takes the
    engine's one-sided limit before the blow (Ry -> 0 there).

    Parameters
    ----------
    start_deg, stop_deg : float
        Window, ``0 < start_deg < stop_deg <= 360`` [deg].
    step_deg : float
        Step [deg]; the window must be a whole number of steps.
    mech : Mechanism, optional
        The hammer; default `load_mo100`.
    omega1 : float
        Crank speed [rad/s].

    Returns
    -------
    float
        Impulse [N s].
    """
    n = round((stop_deg - start_deg) / step_deg)
    if n < 1 or not math.isclose(start_deg + n * step_deg, stop_deg, abs_tol=1e-9):
        raise ValueError("trapezoid_impulse: the window must be a whole number of steps")
    if not 0.0 < start_deg < stop_deg <= 360.0:
        raise ValueError("trapezoid_impulse: needs 0 < start_deg < stop_deg <= 360")
    m = _mech(mech)
    phi = np.radians(np.linspace(start_deg, stop_deg, n + 1))
    inner = phi < _TWO_PI - 1e-12
    ry = np.empty(phi.shape)
    ry[inner] = mo100_run(phi[inner], m, omega1).ry
    if not inner.all():
        ry[~inner] = one_sided_limits(m, omega1).before["ry"]
    return _trapz(ry, phi / omega1)


# ----------------------------------------------------------------------------------------------
# the half-sine fit and the table


@dataclass(frozen=True, slots=True)
class FitRow:
    """One reading of the half-sine fit, eqs (15)-(16): ``mu = 2 H / S``, ``t1 = T - pi / mu``.

    Attributes
    ----------
    reading : str
        How H and S are obtained.
    h, s, mu, t1 : float
        Amplitude [N], impulse [N s], frequency [1/s], pulse start [s].
    """

    reading: str
    h: float
    s: float
    mu: float
    t1: float


def _fit(reading: str, h: float, s: float, period: float) -> FitRow:
    mu, t1 = ref.half_sine_fit(h, s, period)
    return FitRow(reading, h, s, mu, t1)


def engine_fits(
    mech: Mechanism | None = None, omega1: float = MO100_OMEGA1, lobe: Lobe | None = None
) -> list[FitRow]:
    """H, mu, t1 under the readings of the paper's procedure, all from the engine.

    1. H = max Ry on the 10 deg grid (the paper's Fig. 5 grid), S = the main Ry lobe (exact
       window: its zero crossing to the blow, fine trapezoid) — *our* numbers;
    2. H = the continuous maximum of Ry, S = the main lobe;
    3. H on the 10 deg grid, S = 10 deg trapezoid 310...360 deg (the paper's grid throughout);
    4. H on the 10 deg grid, S = 5 deg trapezoid 320...360 deg (the reading closest to the
       printed mu, t1; nothing in the paper confirms it);
    5. H on the 10 deg grid, S = the whole-cycle Ry impulse (momentum of the blow).

    Parameters
    ----------
    mech : Mechanism, optional
        The hammer; default `load_mo100`.
    omega1 : float
        Crank speed [rad/s].
    lobe : Lobe, optional
        `main_ry_lobe`, if already computed.

    Returns
    -------
    list of FitRow
    """
    m = _mech(mech)
    period = _TWO_PI / omega1
    grid = np.radians(np.arange(10.0, 351.0, 10.0))
    ry_grid = mo100_run(grid, m, omega1).ry
    i = int(np.argmax(ry_grid))
    h_grid = float(ry_grid[i])
    h_cont = _continuous_max(m, omega1)[1]
    lb = lobe or main_ry_lobe(mech=m, omega1=omega1)
    s10 = trapezoid_impulse(310.0, 360.0, 10.0, m, omega1)
    s5 = trapezoid_impulse(320.0, 360.0, 5.0, m, omega1)
    sy = rx_impulses(mech=m, omega1=omega1).sy
    where = f"{math.degrees(float(grid[i])):.0f}°"
    lobe_txt = f"main lobe {math.degrees(lb.start):.2f}…360°"
    return [
        _fit(f"H: 10° grid (at {where}); S: {lobe_txt}", h_grid, lb.impulse, period),
        _fit(f"H: continuous max; S: {lobe_txt}", h_cont, lb.impulse, period),
        _fit("H: 10° grid; S: 10° trapezoid 310…360°", h_grid, s10, period),
        _fit("H: 10° grid; S: 5° trapezoid 320…360°", h_grid, s5, period),
        _fit("H: 10° grid; S: whole cycle (blow momentum)", h_grid, sy, period),
    ]


def _continuous_max(m: Mechanism, omega1: float) -> tuple[float, float]:
    """(phi, Ry) at the largest Ry (engine; 1e-4 deg grid near the 0.01 deg maximum)."""
    phi = np.radians(np.arange(330.0, 359.0, 0.01))
    ry = mo100_run(phi, m, omega1).ry
    k = int(np.argmax(ry))
    fine = np.linspace(phi[k] - 2e-4, phi[k] + 2e-4, 401)
    ry_f = mo100_run(fine, m, omega1).ry
    j = int(np.argmax(ry_f))
    return float(fine[j]), float(ry_f[j])


@dataclass(frozen=True, slots=True)
class ReproductionRow:
    """One row of ``excavkin reproduce mo100``: the paper, the engine, the reference.

    Attributes
    ----------
    quantity : str
        Symbol and reading.
    unit : str
        Display unit (SI).
    paper : float or None
        The published value (None: not published).
    engine : float
        The general engine's value.
    reference : float
        The paper's formulas (`excavkin.papers.mo100.reference`) under the same reading.
    """

    quantity: str
    unit: str
    paper: float | None
    engine: float
    reference: float


def reproduction_table(
    mech: Mechanism | None = None, omega1: float = MO100_OMEGA1
) -> list[ReproductionRow]:
    """Paper vs engine vs reference for H, mu, t1, S and the impulses of Rx and Ry.

    Parameters
    ----------
    mech : Mechanism, optional
        The hammer; default `load_mo100`.
    omega1 : float
        Crank speed [rad/s].

    Returns
    -------
    list of ReproductionRow
    """
    m = _mech(mech)
    data = reference_data(m, omega1)
    period = data.period
    lb = main_ry_lobe(mech=m, omega1=omega1)
    fits = engine_fits(m, omega1, lb)
    imp = rx_impulses(mech=m, omega1=omega1)
    lim = one_sided_limits(m, omega1)

    # reference under the same readings
    grid = np.radians(np.arange(10.0, 351.0, 10.0))
    h_ref = float(np.max(ref.housing_force(grid, data)[1]))
    fine = np.radians(np.arange(340.0, 355.0, 1e-4))
    h_ref_c = float(np.max(ref.housing_force(fine, data)[1]))
    phi0_ref, s_ref = ref.ry_main_lobe(data)
    s10_ref = ref.ry_impulse_trapezoid(310.0, 360.0, 10.0, data)
    s5_ref = ref.ry_impulse_trapezoid(320.0, 360.0, 5.0, data)
    mu_ref, t1_ref = ref.half_sine_fit(h_ref, s_ref, period)
    mu10_ref, t110_ref = ref.half_sine_fit(h_ref, s10_ref, period)
    mu5_ref, t15_ref = ref.half_sine_fit(h_ref, s5_ref, period)
    pos_ref, neg_ref, net_ref = ref.rx_lobe_impulses(data)
    sx_ref, sy_ref = ref.cycle_impulse(data)
    k_before, k_after = ref.impact_limits(data)
    rx_before_ref = float(ref.housing_force(np.array([_TWO_PI]), data, "before")[0][0])
    s_paper = 2.0 * ref.PAPER_H / ref.PAPER_MU
    mu_p, t1_p = ref.half_sine_fit(ref.PAPER_H, s_paper, period)

    f1, f2, f3, f4, _ = fits
    return [
        ReproductionRow("H = max Ry, 10° grid", "N", ref.PAPER_H, f1.h, h_ref),
        ReproductionRow("H, continuous max of Ry", "N", None, f2.h, h_ref_c),
        ReproductionRow(
            "start of the main Ry lobe", "deg", None, math.degrees(lb.start), math.degrees(phi0_ref)
        ),
        ReproductionRow("S, main Ry lobe (exact window)", "N s", s_paper, lb.impulse, s_ref),
        ReproductionRow("mu = 2H/S (H 10° grid, S main lobe)", "1/s", ref.PAPER_MU, f1.mu, mu_ref),
        ReproductionRow("t1 = T - pi/mu (idem)", "s", ref.PAPER_T1, f1.t1, t1_ref),
        ReproductionRow("S, 10° trapezoid 310…360°", "N s", s_paper, f3.s, s10_ref),
        ReproductionRow("mu (H 10° grid, S 10° trapezoid)", "1/s", ref.PAPER_MU, f3.mu, mu10_ref),
        ReproductionRow("t1 (idem)", "s", ref.PAPER_T1, f3.t1, t110_ref),
        ReproductionRow("S, 5° trapezoid 320…360°", "N s", s_paper, f4.s, s5_ref),
        ReproductionRow("mu (H 10° grid, S 5° trapezoid)", "1/s", ref.PAPER_MU, f4.mu, mu5_ref),
        ReproductionRow("t1 (idem)", "s", ref.PAPER_T1, f4.t1, t15_ref),
        ReproductionRow("mu from the paper's H and S = 2H/mu", "1/s", ref.PAPER_MU, mu_p, mu_p),
        ReproductionRow("t1 (idem)", "s", ref.PAPER_T1, t1_p, t1_p),
        ReproductionRow("Rx impulse, positive lobes", "N s", None, imp.positive, pos_ref),
        ReproductionRow("Rx impulse, negative lobes", "N s", None, imp.negative, neg_ref),
        ReproductionRow("Rx impulse, net over a cycle", "N s", 0.0, imp.net, sx_ref),
        ReproductionRow("Ry impulse, net over a cycle", "N s", None, imp.sy, sy_ref),
        ReproductionRow("Rx at the blow (2π−)", "N", None, lim.before["rx"], rx_before_ref),
        ReproductionRow("u31 before the blow (2π−)", "", None, lim.before["u31"], k_before),
        ReproductionRow("u31 after the blow (0+)", "", None, lim.after["u31"], k_after),
    ]
