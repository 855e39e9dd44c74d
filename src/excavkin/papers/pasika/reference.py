r"""Reference implementation: cylinder-rocker module with an internal driving link (Pasika).

Source
------
V. Pasika, P. Koruniak, *Kinematic analysis of a lever mechanism with an internal driving
link* (Ukrainian). Seed ``003_96a99c0bda704924.txt``; specification
``seeds/pasika-internal-driving-link.md`` (cited below as "spec §x").

Independent reference: NumPy only, SI units, batch axis first, never the general engine.

Mechanism
---------
Hydraulic cylinder 1 pivoted to the frame at O (origin of xOy), rod 2 sliding in it (the
internal driving link, relative displacement ``s``), rocker 3 pivoted to the frame at B and
jointed to the rod at A. **Geometric reading of a, b: B = (-a, +b) relative to O** (legs of the
right triangle O-B-B1); A lies to the right of the directed line O->B. Angles are CCW from +x::

          B (-a, b) o
                    |\    rocker 3, l_AB
                  b | \
                    |  \________ A
         B1 o-------+     ____/
               a    O o__/   cylinder 1 + rod 2, l_OA = l_OA0 + s
                      (0, 0)

    phi1 = angle of O->A,  phi3 = angle of B->A,
    l_OB = sqrt(a^2 + b^2),  gamma2 = arctg(a / b) = angle OBB1.

Data reading (spec §4.1): the scrambled data block is read as a = 0.45 m, b = 0.9 m,
l_OA0 = 0.8 m, l_AB = 1.2 m, H = 0.5 m, T = 5 s; the literal order (l_OA0 = 0.45, l_AB = 0.9,
a = 0.8, b = 1.2) cannot be assembled (0.45 + 0.9 < 1.442).

Equations in computation order
------------------------------
Motion law (4)-(6) (`cubic_law`), any other law may be used instead::

    s = H (3 t^2/T^2 - 2 t^3/T^3),  v21 = 6 H t (T - t)/T^3,  a21 = 6 H (T - 2 t)/T^3

Positions (1)-(3) (`positions`)::

    l_OA = l_OA0 + s                                                        (1)
    gamma1 = arccos[(l_OB^2 + l_AB^2 - l_OA^2) / (2 l_OB l_AB)]   (triangle OAB)
    phi3 = -90 deg + gamma1 + gamma2                                         (2)
    alpha = arccos[(l_OB^2 + l_OA^2 - l_AB^2) / (2 l_OB l_OA)]    (triangle OAB)
    phi1 = 90 deg + gamma2 - alpha                                           (3)

Velocities (7)-(9) (`velocities`), from v_A = v_A^e + v_A^r::

    omega3 = v21 / (l_AB sin(phi1 - phi3))                                   (8)
    omega1 = v21 ctg(phi1 - phi3) / l_OA                                     (9)

Accelerations (10)-(12) (`accelerations`), from
``l_AB (i eps3 - omega3^2) e^{i phi3} = [l_OA (i eps1 - omega1^2) + a21 + 2 i omega1 v21]
e^{i phi1}`` projected along and across O->A::

    eps3 = [a21 - omega1^2 l_OA + omega3^2 l_AB cos(phi1 - phi3)] / (l_AB sin(phi1 - phi3))  (12)
    eps1 = [l_AB (eps3 cos(phi1 - phi3) + omega3^2 sin(phi1 - phi3)) - 2 omega1 v21] / l_OA   (11)

Departures from the print (each proved by a test in
``tests/reference/test_pasika_reference.py``)
---------------------------------------------------------------------------------------
1. Coriolis term: the extraction reads ``a_A^k = 2 omega3 v21``; the transport body is the
   cylinder, so it is ``2 omega1 v21`` (spec §5 item 1). With omega3, eps1 is off by up to
   13.8 % against finite differences (test ``test_coriolis_misprint``).
2. Eq (11) is garbled in the print; it is re-derived from eq (10) as above (test
   ``test_derivatives_vs_finite_differences``).
3. "Triangle OA0B" for gamma1 and alpha is the *current* triangle OAB (spec §5 item 2).
4. The velocity-triangle angle is ``pi/2 + phi3 - phi1`` (the print's unindexed gamma is the
   direction of v_A, spec §5 item 3).

Failures
--------
``on_failure="raise"`` (default) raises `ReferenceAssemblyError` when a triangle
cannot close (|cos| > 1) and `ReferenceSingularityError` when
``|sin(phi1 - phi3)| < singular_tol`` (cylinder collinear with the rocker: dead point);
``on_failure="nan"`` puts NaN in the failed samples and reports them in ``status``
(0 ok, 1 not assemblable, 2 singular).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
import numpy.typing as npt

from excavkin.arrays import FloatArray
from excavkin.papers.errors import ReferenceAssemblyError, ReferenceSingularityError

__all__ = [
    "PASIKA_PAPER",
    "STATUS_NOT_ASSEMBLABLE",
    "STATUS_OK",
    "STATUS_SINGULAR",
    "PasikaAccelerations",
    "PasikaData",
    "PasikaKinematics",
    "PasikaPositions",
    "PasikaVelocities",
    "accelerations",
    "cubic_law",
    "kinematics",
    "phi1_from_stroke",
    "phi3_from_stroke",
    "positions",
    "soft_shock_jumps",
    "stroke_from_phi1",
    "stroke_from_phi3",
    "velocities",
]

IntArray = npt.NDArray[np.int8]
OnFailure = Literal["raise", "nan"]

STATUS_OK = 0
STATUS_NOT_ASSEMBLABLE = 1
STATUS_SINGULAR = 2


@dataclass(frozen=True, slots=True)
class PasikaData:
    """Dimensions and stroke data of the module (spec §4.1 reading, SI units).

    Parameters
    ----------
    a, b : float
        Frame legs [m]: B is at (-a, +b) relative to O.
    l_oa0 : float
        Initial distance O-A (s = 0) [m].
    l_ab : float
        Rocker length B-A [m].
    stroke : float
        Rod stroke H [m].
    duration : float
        Stroke time T [s].
    """

    a: float = 0.45
    b: float = 0.9
    l_oa0: float = 0.8
    l_ab: float = 1.2
    stroke: float = 0.5
    duration: float = 5.0

    def __post_init__(self) -> None:
        for name in ("a", "b", "l_oa0", "l_ab", "stroke", "duration"):
            if not getattr(self, name) > 0.0:
                raise ValueError(f"PasikaData.{name} must be positive, got {getattr(self, name)}")

    @property
    def l_ob(self) -> float:
        """Pivot distance l_OB = sqrt(a^2 + b^2) [m] (implied in the paper)."""
        return math.hypot(self.a, self.b)

    @property
    def gamma2(self) -> float:
        """gamma2 = arctg(a / b) = angle OBB1 [rad]."""
        return math.atan2(self.a, self.b)


PASIKA_PAPER = PasikaData()
"""The paper's data set (spec §4.1 reading)."""


@dataclass(frozen=True, slots=True)
class PasikaPositions:
    """Positions, eqs (1)-(3); arrays of shape ``(n,)``.

    Attributes
    ----------
    l_oa : ndarray, shape (n,)
        Current O-A distance [m].
    gamma1, alpha : ndarray, shape (n,)
        Angles OBA and BOA of triangle OAB [rad].
    gamma2 : float
        Angle OBB1 [rad] (constant).
    phi1, phi3 : ndarray, shape (n,)
        Angles of O->A and B->A from +x [rad].
    status : ndarray of int8, shape (n,)
        0 ok, 1 not assemblable, 2 singular (``sin(phi1 - phi3)`` below tolerance).
    """

    l_oa: FloatArray
    gamma1: FloatArray
    gamma2: float
    alpha: FloatArray
    phi1: FloatArray
    phi3: FloatArray
    status: IntArray


@dataclass(frozen=True, slots=True)
class PasikaVelocities:
    """Velocities, eqs (7)-(9); arrays of shape ``(n,)`` or ``(n, 2)``.

    Attributes
    ----------
    omega1, omega3 : ndarray, shape (n,)
        Angular velocities of cylinder (with rod) and rocker [rad/s], CCW positive.
    v_a, v_a_e, v_a_r : ndarray, shape (n, 2)
        Absolute velocity of A (as a rocker point, omega3 l_AB, perpendicular to BA), transport
        velocity (omega1 l_OA, perpendicular to OA) and relative velocity (v21, along O->A)
        in xOy [m/s]; ``v_a = v_a_e + v_a_r``.
    """

    omega1: FloatArray
    omega3: FloatArray
    v_a: FloatArray
    v_a_e: FloatArray
    v_a_r: FloatArray


@dataclass(frozen=True, slots=True)
class PasikaAccelerations:
    """Accelerations, eqs (10)-(12); arrays of shape ``(n,)`` or ``(n, 2)``.

    Attributes
    ----------
    eps1, eps3 : ndarray, shape (n,)
        Angular accelerations of cylinder and rocker [rad/s^2].
    coriolis : ndarray, shape (n,)
        Signed Coriolis acceleration 2 omega1 v21 along the CCW normal of O->A [m/s^2].
    a_coriolis : ndarray, shape (n, 2)
        The Coriolis acceleration vector in xOy [m/s^2].
    """

    eps1: FloatArray
    eps3: FloatArray
    coriolis: FloatArray
    a_coriolis: FloatArray


@dataclass(frozen=True, slots=True)
class PasikaKinematics:
    """Everything for a batch of rod states; see the component classes for shapes."""

    positions: PasikaPositions
    velocities: PasikaVelocities
    accelerations: PasikaAccelerations

    @property
    def status(self) -> IntArray:
        """Per-sample status, shape (n,): 0 ok, 1 not assemblable, 2 singular."""
        return self.positions.status


def _as_1d(x: npt.ArrayLike, name: str) -> FloatArray:
    arr = np.asarray(x, dtype=np.float64)
    if arr.ndim != 1:
        raise ValueError(f"{name} must have shape (n,), got shape {arr.shape}")
    return arr


def cubic_law(
    t: npt.ArrayLike, data: PasikaData = PASIKA_PAPER
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Rod motion law of uniformly decreasing acceleration, eqs (4)-(6).

    ``s = H (3 t^2/T^2 - 2 t^3/T^3)``, ``v21 = (6 H / T)(t / T)(1 - t / T)``,
    ``a21 = (6 H / T^2)(1 - 2 t / T)`` from the boundary conditions (5)
    ``s(0) = v(0) = 0, s(T) = H, v(T) = 0``. Defined on ``0 <= t <= T``; outside the rod is at
    rest (s = 0 or H, v21 = a21 = 0), so a21 jumps by +6H/T^2 at t = 0 and by +6H/T^2 at
    t = T (the soft shocks, see `soft_shock_jumps`).

    Parameters
    ----------
    t : array_like, shape (n,)
        Time [s].
    data : PasikaData
        Stroke H and duration T.

    Returns
    -------
    s, v21, a21 : ndarray, shape (n,)
        Relative displacement [m], velocity [m/s] and acceleration [m/s^2] of the rod.
    """
    tt = _as_1d(t, "t")
    h, big_t = data.stroke, data.duration
    u = np.clip(tt / big_t, 0.0, 1.0)
    inside = (tt >= 0.0) & (tt <= big_t)
    s = h * u**2 * (3.0 - 2.0 * u)
    v = np.where(inside, 6.0 * h / big_t * u * (1.0 - u), 0.0)
    a = np.where(inside, 6.0 * h / big_t**2 * (1.0 - 2.0 * u), 0.0)
    return s, v, a


def soft_shock_jumps(data: PasikaData = PASIKA_PAPER) -> dict[str, float]:
    """Jumps of the rod and link accelerations at the start and end of the cubic law.

    Jumps are (value just inside the motion) - (value at rest) at t = 0 and
    (value at rest) - (value just inside) at t = T, i.e. "after minus before".

    Parameters
    ----------
    data : PasikaData
        Module data.

    Returns
    -------
    dict of str to float
        ``"a21_start", "a21_end"`` [m/s^2] (both +6H/T^2), ``"eps1_start", "eps1_end",
        "eps3_start", "eps3_end"`` [rad/s^2] (spec §4.3: +0.1003, +0.0853, +0.1203, +0.1362).
    """
    t = np.array([0.0, data.duration])
    s, v, a = cubic_law(t, data)
    acc = accelerations(s, v, a, data)
    return {
        "a21_start": float(a[0]),
        "a21_end": float(-a[1]),
        "eps1_start": float(acc.eps1[0]),
        "eps1_end": float(-acc.eps1[1]),
        "eps3_start": float(acc.eps3[0]),
        "eps3_end": float(-acc.eps3[1]),
    }


def _fail(
    status: IntArray, on_failure: OnFailure, what: str, exc: type[Exception], values: FloatArray
) -> None:
    if on_failure == "raise":
        bad = np.flatnonzero(status)
        raise exc(
            f"Pasika module {what} at sample(s) {bad[:10].tolist()}"
            f"{' ...' if bad.size > 10 else ''} (s = {values[bad[:3]].tolist()} m)"
        )


def positions(
    s: npt.ArrayLike,
    data: PasikaData = PASIKA_PAPER,
    on_failure: OnFailure = "raise",
    singular_tol: float = 1e-7,
) -> PasikaPositions:
    """Positions of cylinder and rocker for rod displacement s, eqs (1)-(3).

    See the module docstring for the equations. ``|cos| <= 1 + 1e-12`` is the assembly check
    (values within the slack are clipped); ``|sin(phi1 - phi3)| < singular_tol`` flags the dead
    point where (8), (9), (11), (12) are singular.

    Parameters
    ----------
    s : array_like, shape (n,)
        Rod displacement relative to the cylinder [m] (any law).
    data : PasikaData
        Module data.
    on_failure : {"raise", "nan"}
        Raise, or return NaN with a ``status`` flag, for failed samples.
    singular_tol : float
        Tolerance on ``|sin(phi1 - phi3)|``. Near the dead point ``sin`` grows like the square
        root of the distance to it, so a stroke that is the dead point up to round-off still
        gives ``sin ~ 2e-8``; 1e-7 flags those, and the rates there are meaningless anyway.

    Returns
    -------
    PasikaPositions
        Arrays of shape (n,).

    Raises
    ------
    ReferenceAssemblyError
        If a triangle cannot close and ``on_failure="raise"``.
    ReferenceSingularityError
        At a dead point and ``on_failure="raise"``.
    """
    if on_failure not in ("raise", "nan"):
        raise ValueError(f"on_failure must be 'raise' or 'nan', not {on_failure!r}")
    ss = _as_1d(s, "s")
    l_oa = data.l_oa0 + ss  # (1)
    l_ob, l_ab, g2 = data.l_ob, data.l_ab, data.gamma2
    cos_g1 = (l_ob**2 + l_ab**2 - l_oa**2) / (2.0 * l_ob * l_ab)
    with np.errstate(divide="ignore", invalid="ignore"):
        cos_al = (l_ob**2 + l_oa**2 - l_ab**2) / (2.0 * l_ob * l_oa)
    status = np.zeros(ss.shape, dtype=np.int8)
    bad = ~((np.abs(cos_g1) <= 1.0 + 1e-12) & (np.abs(cos_al) <= 1.0 + 1e-12) & (l_oa > 0.0))
    status[bad] = STATUS_NOT_ASSEMBLABLE
    if bad.any():
        _fail(status, on_failure, "cannot be assembled (|cos| > 1)", ReferenceAssemblyError, ss)
    gamma1 = np.arccos(np.clip(cos_g1, -1.0, 1.0))
    alpha = np.arccos(np.clip(cos_al, -1.0, 1.0))
    phi3 = -0.5 * math.pi + gamma1 + g2  # (2)
    phi1 = 0.5 * math.pi + g2 - alpha  # (3)
    sing = (np.abs(np.sin(phi1 - phi3)) < singular_tol) & ~bad
    status[sing] = STATUS_SINGULAR
    if sing.any():
        _fail(
            np.where(sing, status, 0).astype(np.int8),
            on_failure,
            "is at a dead point (sin(phi1 - phi3) = 0)",
            ReferenceSingularityError,
            ss,
        )
    nan = status == STATUS_NOT_ASSEMBLABLE
    for arr in (gamma1, alpha, phi1, phi3):
        arr[nan] = np.nan
    return PasikaPositions(
        l_oa=l_oa, gamma1=gamma1, gamma2=g2, alpha=alpha, phi1=phi1, phi3=phi3, status=status
    )


def _unit(angle: FloatArray) -> FloatArray:
    return np.stack([np.cos(angle), np.sin(angle)], axis=-1)


def velocities(
    s: npt.ArrayLike,
    v21: npt.ArrayLike,
    data: PasikaData = PASIKA_PAPER,
    on_failure: OnFailure = "raise",
    singular_tol: float = 1e-7,
) -> PasikaVelocities:
    """Angular velocities and the velocity components of A, eqs (7)-(9).

    ``v_A = v_A^e + v_A^r`` (7); the velocity triangle p-r-a is right-angled at r with angle
    ``pi/2 + phi3 - phi1`` at p, hence ``omega3 = v21 / (l_AB sin(phi1 - phi3))`` (8) and
    ``omega1 = v21 ctg(phi1 - phi3) / l_OA`` (9) (both as printed). Equivalently, the
    imaginary and real parts of ``l_AB i omega3 e^{i(phi3 - phi1)} = i omega1 l_OA + v21``.

    Parameters
    ----------
    s, v21 : array_like, shape (n,)
        Rod displacement [m] and velocity [m/s] relative to the cylinder (any law).
    data : PasikaData
        Module data.
    on_failure : {"raise", "nan"}
        See `positions`; singular samples get NaN with ``"nan"``.
    singular_tol : float
        Tolerance on ``|sin(phi1 - phi3)|``.

    Returns
    -------
    PasikaVelocities
        omega1, omega3 shape (n,); v_a, v_a_e, v_a_r shape (n, 2).
    """
    pos = positions(s, data, on_failure, singular_tol)
    v = _as_1d(v21, "v21")
    dphi = np.where(pos.status == STATUS_OK, pos.phi1 - pos.phi3, np.nan)
    omega3 = v / (data.l_ab * np.sin(dphi))  # (8)
    omega1 = v / (np.tan(dphi) * pos.l_oa)  # (9)
    v_a = (omega3 * data.l_ab)[:, None] * _unit(pos.phi3 + 0.5 * math.pi)
    v_a_e = (omega1 * pos.l_oa)[:, None] * _unit(pos.phi1 + 0.5 * math.pi)
    v_a_r = v[:, None] * _unit(pos.phi1)
    return PasikaVelocities(omega1=omega1, omega3=omega3, v_a=v_a, v_a_e=v_a_e, v_a_r=v_a_r)


def accelerations(
    s: npt.ArrayLike,
    v21: npt.ArrayLike,
    a21: npt.ArrayLike,
    data: PasikaData = PASIKA_PAPER,
    on_failure: OnFailure = "raise",
    singular_tol: float = 1e-7,
) -> PasikaAccelerations:
    """Angular accelerations, eqs (10)-(12), with the corrected Coriolis term 2 omega1 v21.

    Eq (10) ``a_A^n + a_A^tau = a_A^e + a_A^r + a_A^k`` in complex form::

        l_AB (i eps3 - omega3^2) e^{i phi3} = [l_OA (i eps1 - omega1^2) + a21 + 2 i omega1 v21]
                                              e^{i phi1}

    Multiplying by ``e^{-i phi1}``: the real part (along O->A; no eps1, no Coriolis) gives (12),
    the imaginary part (across O->A) gives (11)::

        eps3 = [a21 - omega1^2 l_OA + omega3^2 l_AB cos(phi1 - phi3)] / (l_AB sin(phi1 - phi3))
        eps1 = [l_AB (eps3 cos(phi1 - phi3) + omega3^2 sin(phi1 - phi3)) - 2 omega1 v21] / l_OA

    The print's (11) is garbled and its Coriolis term reads 2 omega3 v21; the transport body is
    the cylinder, rotating with omega1 (spec §5 item 1).

    Parameters
    ----------
    s, v21, a21 : array_like, shape (n,)
        Rod displacement [m], velocity [m/s] and acceleration [m/s^2] (any law).
    data : PasikaData
        Module data.
    on_failure : {"raise", "nan"}
        See `positions`.
    singular_tol : float
        Tolerance on ``|sin(phi1 - phi3)|``.

    Returns
    -------
    PasikaAccelerations
        eps1, eps3, coriolis shape (n,); a_coriolis shape (n, 2).
    """
    pos = positions(s, data, on_failure, singular_tol)
    vel = velocities(s, v21, data, on_failure, singular_tol)
    v = _as_1d(v21, "v21")
    acc = _as_1d(a21, "a21")
    dphi = np.where(pos.status == STATUS_OK, pos.phi1 - pos.phi3, np.nan)
    w1, w3, l_ab, l_oa = vel.omega1, vel.omega3, data.l_ab, pos.l_oa
    eps3 = (acc - w1**2 * l_oa + w3**2 * l_ab * np.cos(dphi)) / (l_ab * np.sin(dphi))  # (12)
    coriolis = 2.0 * w1 * v
    eps1 = (l_ab * (eps3 * np.cos(dphi) + w3**2 * np.sin(dphi)) - coriolis) / l_oa  # (11)
    a_cor = coriolis[:, None] * _unit(pos.phi1 + 0.5 * math.pi)
    return PasikaAccelerations(eps1=eps1, eps3=eps3, coriolis=coriolis, a_coriolis=a_cor)


def kinematics(
    s: npt.ArrayLike,
    v21: npt.ArrayLike,
    a21: npt.ArrayLike,
    data: PasikaData = PASIKA_PAPER,
    on_failure: OnFailure = "raise",
    singular_tol: float = 1e-7,
) -> PasikaKinematics:
    """Positions, velocities and accelerations for any rod law (s, v21, a21).

    Parameters
    ----------
    s, v21, a21 : array_like, shape (n,)
        Rod displacement [m], velocity [m/s], acceleration [m/s^2] relative to the cylinder.
    data : PasikaData
        Module data.
    on_failure : {"raise", "nan"}
        See `positions`.
    singular_tol : float
        Tolerance on ``|sin(phi1 - phi3)|``.

    Returns
    -------
    PasikaKinematics
        Bundle of `PasikaPositions`, `PasikaVelocities` and
        `PasikaAccelerations`; ``.status`` shape (n,).
    """
    return PasikaKinematics(
        positions=positions(s, data, on_failure, singular_tol),
        velocities=velocities(s, v21, data, on_failure, singular_tol),
        accelerations=accelerations(s, v21, a21, data, on_failure, singular_tol),
    )


def phi3_from_stroke(s: npt.ArrayLike, data: PasikaData = PASIKA_PAPER) -> FloatArray:
    """Rocker angle phi3 for stroke s, eq (2) (shortcut of `positions`).

    Parameters
    ----------
    s : array_like, shape (n,)
        Rod displacement [m].
    data : PasikaData
        Module data.

    Returns
    -------
    ndarray, shape (n,)
        phi3 [rad].
    """
    return positions(s, data).phi3


def phi1_from_stroke(s: npt.ArrayLike, data: PasikaData = PASIKA_PAPER) -> FloatArray:
    """Cylinder angle phi1 for stroke s, eq (3) (shortcut of `positions`).

    Parameters
    ----------
    s : array_like, shape (n,)
        Rod displacement [m].
    data : PasikaData
        Module data.

    Returns
    -------
    ndarray, shape (n,)
        phi1 [rad].
    """
    return positions(s, data).phi1


def stroke_from_phi3(phi3: npt.ArrayLike, data: PasikaData = PASIKA_PAPER) -> FloatArray:
    """Inverse of eq (2): stroke s for rocker angle phi3 (spec §6).

    ``gamma1 = phi3 + 90 deg - gamma2``,
    ``l_OA^2 = l_OB^2 + l_AB^2 - 2 l_OB l_AB cos(gamma1)``, ``s = l_OA - l_OA0``. Unique for
    ``gamma1`` in [0, pi] (A to the right of O->B, the branch of eq (2)).

    Parameters
    ----------
    phi3 : array_like, shape (n,)
        Rocker angle [rad].
    data : PasikaData
        Module data.

    Returns
    -------
    ndarray, shape (n,)
        Stroke s [m].

    Raises
    ------
    ReferenceAssemblyError
        If gamma1 falls outside [0, pi] (the other assembly branch).
    """
    p3 = _as_1d(phi3, "phi3")
    gamma1 = p3 + 0.5 * math.pi - data.gamma2
    if np.any((gamma1 < -1e-12) | (gamma1 > math.pi + 1e-12)):
        raise ReferenceAssemblyError("stroke_from_phi3: phi3 is outside the branch of eq (2)")
    l_ob, l_ab = data.l_ob, data.l_ab
    l_oa = np.sqrt(l_ob**2 + l_ab**2 - 2.0 * l_ob * l_ab * np.cos(gamma1))
    return l_oa - data.l_oa0


def stroke_from_phi1(phi1: npt.ArrayLike, data: PasikaData = PASIKA_PAPER) -> FloatArray:
    """Inverse of eq (3): stroke s for cylinder angle phi1.

    ``alpha = 90 deg + gamma2 - phi1`` and, from triangle OAB,
    ``l_OA = l_OB cos(alpha) + sqrt(l_AB^2 - l_OB^2 sin^2(alpha))`` (the ``+`` root: the only
    positive one when ``l_AB > l_OB``, as for the paper's data).

    Parameters
    ----------
    phi1 : array_like, shape (n,)
        Cylinder angle [rad].
    data : PasikaData
        Module data.

    Returns
    -------
    ndarray, shape (n,)
        Stroke s [m].

    Raises
    ------
    ReferenceAssemblyError
        If no triangle exists (``l_OB |sin(alpha)| > l_AB``) or ``alpha`` is outside [0, pi].
    """
    p1 = _as_1d(phi1, "phi1")
    alpha = 0.5 * math.pi + data.gamma2 - p1
    disc = data.l_ab**2 - (data.l_ob * np.sin(alpha)) ** 2
    if np.any(disc < 0.0) or np.any((alpha < -1e-12) | (alpha > math.pi + 1e-12)):
        raise ReferenceAssemblyError("stroke_from_phi1: no triangle OAB for this phi1")
    l_oa = data.l_ob * np.cos(alpha) + np.sqrt(disc)
    return l_oa - data.l_oa0
