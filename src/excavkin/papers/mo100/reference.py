r"""Reference implementation: MO-100 crank-rocker hammer (Eremyants & Raiymbekova).

Source
------
V.E. Eremyants, G.M. Raiymbekova, *Determination of reactive forces acting on the manipulator
of excavator EO-2621 with mounted hammer MO-100* (Russian). Seed ``002_5b03dca64f64aae9.txt``;
specification ``seeds/mo100-hammer-reactions.md`` (cited below as "spec §x").

This module is an *independent* reference: it evaluates the paper's own closed-form equations
with NumPy only and never calls the general engine. SI units throughout (m, rad, s, kg, N).
Every function is vectorised over the crank angle ``phi`` of shape ``(n,)``.

Mechanism
---------
Crank 1 (A-B), coupler 2 (B-C, massless), rocker 3 (D-C, mass m3, CoM S), housing 0.
Frame axes x', y' have their origin at A and x' along A->D. ``phi`` is the crank angle of A->B
from x' (counter-clockwise), ``psi`` the angle of D->C and ``beta`` the angle of B->C, both
from x' (counter-clockwise). The linkage is a *change-point* linkage, ``l1 + l2 = l0 + l3``:
at ``phi = 0 (mod 2 pi)`` the four joints are collinear in the order A, B, D, C, the rocker
hits the tool, and ``psi = beta = 0``::

              C (phi ~ 300 deg)
             /  \
          2 /    \ 3            y'
           /      \             ^
     B    /        \            |
      \  /          \           +--> x'
     1 \/            \
        A ----------- D ..... C  (phi = 0: A, B, D, C collinear; impact)
              l0         l3

    l1 = AB = 48 mm,  l2 = BC = 150 mm,  l3 = DC = 120 mm,  l0 = AD = 78 mm,
    lS = DS = 106 mm, alpha = angle CDS = 50 deg.

Housing axes x, y (Fig. 4, deduced in spec §3.4): x along D->S at the impact position, y its
counter-clockwise perpendicular, which points "up", i.e. against the blow. In these axes the
rocker centre of mass is at ``D + lS * exp(i psi)``.

Change point
------------
At ``phi = 0 (mod 2 pi)`` the Assur group (2, 3) is singular (``sin(psi - beta) = 0``) and the
first-order transfer function has two different one-sided limits (spec §3.2)::

    u31(0 -/+) = (-1 -/+ sqrt(lam0 * lam2 / lam3)) / (lam0 - 1)     (-3.8804 / +0.6804)
    u21(0 -/+) = (lam3 * u31(0 -/+) - 1) / lam2
    u31'(0 -/+) = u21'(0 -/+) = 0

(derivation: near the change point the arccos terms of eqs (2)-(3) behave like ``|phi|`` times
an even series, the arctg term is odd, so the first derivative jumps and the second tends to
zero from both sides). Every function takes ``impact_side``: ``"before"`` returns the limit
``phi -> 2 pi -`` (approach to the blow), ``"after"`` the limit ``phi -> 0 +`` (rebound), and
``"auto"`` (default) takes ``phi = 0`` (and negative multiples of 2 pi) as "after" and positive
multiples of 2 pi as "before", so that a sweep ``linspace(0, 2 pi, n)`` covers one closed cycle
from rebound to blow. Only *exact* multiples of 2 pi are treated specially; all other angles go
through the closed forms, which are evaluated in a cancellation-free half-angle form (below)
and are accurate arbitrarily close to the change point. Nothing returns NaN silently.

Departures from the print (each proved by a test in
``tests/reference/test_mo100_reference.py``)
------------------------------------------------------------------------------------------
1. Eqs (4)-(5) (u31, u31') are lost in the extraction; the equivalent standard forms of the
   spec §3.2 are used (tests: ``test_transfer_functions_vs_finite_differences``).
2. Eqs (2)-(3) are evaluated with the arccos written in half-angle (tangent) form with
   cancellation-free factors; this is the same number as the printed arccos, but keeps full
   precision at the change point (test: ``test_eq2_eq3_literal_form_agrees``).
3. Kinetostatic angle sense (spec §5 item 1): with psi, beta from (2)-(3) inserted unchanged,
   the printed chain (9)-(14) gives Ry(350 deg) = 11 769 N instead of H; the Fig. 4 angles have
   the opposite rotational sense. `group_reactions` therefore uses
   ``psi_K = -psi, beta_K = -beta`` by default (``angle_sense="fig4"``); the printed chain then
   returns exactly minus the housing force of `housing_force`
   (tests: ``test_printed_angle_sense_misprint``, ``test_printed_chain_equals_minus_dalembert``).
4. Sign of R12 in (11) and "R10 = R12" in (12) (spec §5 item 2): solving the printed (6)-(7)
   gives R12 with the opposite sign, and Newton's third law gives R10 = -R12. The two slips
   cancel in (13)-(14). The printed pair is kept (it reproduces the paper's Rx, Ry); the
   correctly signed value is returned as ``r12_from_eq6_7`` (test: ``test_r12_sign_misprint``).
5. Eq (15) printed ``H sin(mu t)`` on ``t1 < t < T``; corrected to ``H sin(mu (t - t1))``
   (test: ``test_eq15_printed_form_misprint``).
6. Data typo "lam0 = 2,5": it is lam3 = l3/l1 (test: ``test_data_lambda_typo``).
7. The axis of I is not stated (spec §5 item 5): ``MO100Data.inertia_axis`` selects it; the
   default ``"centroid"`` is the printed reading (M_u = I eps3 together with P_tau at S).

The housing force, impulses and the half-sine fit are in `housing_force`,
`cycle_impulse`, `ry_main_lobe`, `half_sine_fit` and
`paper_comparison`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np
import numpy.typing as npt

from excavkin.arrays import FloatArray
from excavkin.papers.errors import ReferenceAssemblyError

__all__ = [
    "MO100_PAPER",
    "GroupReactions",
    "InertiaLoads",
    "MO100Data",
    "PaperComparisonRow",
    "TransferFunctions",
    "cycle_impulse",
    "group_reactions",
    "half_sine_fit",
    "half_sine_pulse",
    "housing_force",
    "impact_limits",
    "inertia_loads",
    "joint_positions",
    "paper_comparison",
    "position_functions",
    "rx_lobe_impulses",
    "ry_impulse_trapezoid",
    "ry_main_lobe",
    "transfer_functions",
]

ImpactSide = Literal["auto", "before", "after"]

_TWO_PI = 2.0 * math.pi


@dataclass(frozen=True, slots=True)
class MO100Data:
    """Dimensions and mass properties of the MO-100 hammer (paper's data, SI units).

    Parameters
    ----------
    l1, l2, l3, l0 : float
        Crank AB, coupler BC, rocker arm DC and pivot distance AD [m].
    l_s : float
        Pivot-to-centre-of-mass distance DS [m].
    alpha : float
        Angle CDS between the rocker arm and the line DS [rad], signed: positive (the printed
        50 deg) puts S on the side of D->C that eqs. (8)-(14) describe with the Fig. 4 angle
        sense, clockwise of D->C in the frame axes of eqs. (2)-(3) (the engine's model file);
        negative mirrors S about D->C. Rx, Ry and R12 do not depend on the sign; R03^tau,
        R03^n do (``docs/papers/mo100.md``).
    m3 : float
        Rocker mass [kg].
    inertia : float
        Rocker moment of inertia I [kg m^2], about the axis selected by `inertia_axis`.
    omega1 : float
        Constant crank angular velocity [rad/s] (31.416 = 2 pi 5 Hz).
    inertia_axis : {"centroid", "pivot"}
        Axis of `inertia`. ``"centroid"`` (default) is the printed reading: M_u = I eps3 with
        P_tau applied at S. ``"pivot"`` means I is about D; the centroidal value
        ``I - m3 lS^2`` is then used in M_u (spec §5 item 5).
    change_point_rtol : float
        Relative tolerance for recognising ``l1 + l2 = l0 + l3``. Within it the linkage is
        treated as an exact change-point linkage.

    Raises
    ------
    ReferenceAssemblyError
        If the crank cannot make a full turn (a triangle inequality of B-C-D fails).
    ValueError
        If a dimension or mass property is not positive, or ``l0 <= l1``.
    """

    l1: float = 0.048
    l2: float = 0.150
    l3: float = 0.120
    l0: float = 0.078
    l_s: float = 0.106
    alpha: float = math.radians(50.0)
    m3: float = 35.2
    inertia: float = 0.737
    omega1: float = 31.416
    inertia_axis: Literal["centroid", "pivot"] = "centroid"
    change_point_rtol: float = 1e-12

    def __post_init__(self) -> None:
        for name in ("l1", "l2", "l3", "l0", "l_s", "m3", "inertia", "omega1"):
            if not getattr(self, name) > 0.0:
                raise ValueError(f"MO100Data.{name} must be positive, got {getattr(self, name)}")
        if self.l0 <= self.l1:
            raise ValueError("MO100Data needs l0 > l1 (crank shorter than the pivot distance)")
        if self.inertia_axis not in ("centroid", "pivot"):
            raise ValueError(f"inertia_axis must be 'centroid' or 'pivot', not {self.inertia_axis}")
        if self.i_centroid <= 0.0:
            raise ValueError("inertia about the pivot is smaller than m3 * l_s**2")
        tol = self.change_point_rtol * (self.l0 + self.l1 + self.l2 + self.l3)
        # full crank turn: |l2 - l3| <= BD <= l2 + l3 for BD in [l0 - l1, l0 + l1]
        if self.l0 - self.l1 < abs(self.l2 - self.l3) - tol or self.l0 + self.l1 > (
            self.l2 + self.l3 + tol
        ):
            raise ReferenceAssemblyError(
                "MO100Data: the crank cannot make a full turn "
                f"(BD in [{self.l0 - self.l1}, {self.l0 + self.l1}] m, "
                f"needs [{abs(self.l2 - self.l3)}, {self.l2 + self.l3}] m)"
            )

    @property
    def lam0(self) -> float:
        """lambda0 = l0 / l1."""
        return self.l0 / self.l1

    @property
    def lam2(self) -> float:
        """lambda2 = l2 / l1."""
        return self.l2 / self.l1

    @property
    def lam3(self) -> float:
        """lambda3 = l3 / l1 (printed as a second "lambda0 = 2,5")."""
        return self.l3 / self.l1

    @property
    def is_change_point(self) -> bool:
        """True when ``l1 + l2 = l0 + l3`` within `change_point_rtol`."""
        tol = self.change_point_rtol * (self.l0 + self.l1 + self.l2 + self.l3)
        return abs(self.l1 + self.l2 - self.l0 - self.l3) <= tol

    @property
    def period(self) -> float:
        """Cycle period T = 2 pi / omega1 [s]."""
        return _TWO_PI / self.omega1

    @property
    def l_cs(self) -> float:
        """l_CS = sqrt(l3^2 + lS^2 - 2 l3 lS cos(alpha)) [m] (triangle CDS, after eq 8)."""
        return math.sqrt(self.l3**2 + self.l_s**2 - 2.0 * self.l3 * self.l_s * math.cos(self.alpha))

    @property
    def i_centroid(self) -> float:
        """Centroidal moment of inertia I_S used in M_u [kg m^2]."""
        if self.inertia_axis == "centroid":
            return self.inertia
        return self.inertia - self.m3 * self.l_s**2

    @property
    def i_pivot(self) -> float:
        """Moment of inertia about the pivot D, I_S + m3 lS^2 [kg m^2]."""
        return self.i_centroid + self.m3 * self.l_s**2


MO100_PAPER = MO100Data()
"""The paper's data set (§4.1 of the spec)."""


@dataclass(frozen=True, slots=True)
class TransferFunctions:
    """Crank-to-rocker and crank-to-coupler transfer functions, each shape ``(n,)``.

    Attributes
    ----------
    u31, u21 : ndarray, shape (n,)
        d psi / d phi and d beta / d phi [-].
    u31p, u21p : ndarray, shape (n,)
        d^2 psi / d phi^2 and d^2 beta / d phi^2 [-].
    """

    u31: FloatArray
    u21: FloatArray
    u31p: FloatArray
    u21p: FloatArray


@dataclass(frozen=True, slots=True)
class InertiaLoads:
    """Rocker inertia loads of eq (1), each shape ``(n,)``.

    Attributes
    ----------
    p_n : ndarray, shape (n,)
        P_u^n = m3 omega1^2 u31^2 lS [N], along D->S (the d'Alembert centrifugal force points
        away from D, so this is also its signed value along D->S).
    p_tau : ndarray, shape (n,)
        P_u^tau = m3 omega1^2 u31' lS [N] = m3 eps3 lS, signed like eps3 (counter-clockwise
        positive). The d'Alembert tangential force is ``-p_tau`` along the CCW normal of DS.
    m_u : ndarray, shape (n,)
        M_u = I_S omega1^2 u31' [N m] = I_S eps3. The d'Alembert torque is ``-m_u``.
    """

    p_n: FloatArray
    p_tau: FloatArray
    m_u: FloatArray


@dataclass(frozen=True, slots=True)
class GroupReactions:
    """Reactions of the printed kinetostatic chain, eqs (9)-(14), each shape ``(n,)`` [N].

    Attributes
    ----------
    r03_tau, r03_n : ndarray, shape (n,)
        Eqs (9) and (10).
    r12 : ndarray, shape (n,)
        Eq (11) *as printed*.
    r12_from_eq6_7 : ndarray, shape (n,)
        R12 solved from the printed projections (6)-(7): ``-r12`` (spec §5 item 2).
    rx, ry : ndarray, shape (n,)
        Eqs (13), (14) with the printed "R10 = R12" of eq (12).
    """

    r03_tau: FloatArray
    r03_n: FloatArray
    r12: FloatArray
    r12_from_eq6_7: FloatArray
    rx: FloatArray
    ry: FloatArray


@dataclass(frozen=True, slots=True)
class PaperComparisonRow:
    """One row of the paper-vs-ours table.

    Attributes
    ----------
    quantity : str
        Symbol of the published number.
    paper : float
        The published value (SI).
    ours : float
        Our value under `reading`.
    unit : str
        SI unit.
    reading : str
        How our number is obtained (grid, integration window, ...).
    """

    quantity: str
    paper: float
    ours: float
    unit: str
    reading: str

    @property
    def rel_diff(self) -> float:
        """(ours - paper) / |paper|, or ``ours - paper`` if the paper value is 0."""
        return (self.ours - self.paper) / abs(self.paper) if self.paper else self.ours - self.paper


# ----------------------------------------------------------------------------------------------
# change-point handling


def _as_phi(phi: npt.ArrayLike) -> FloatArray:
    arr = np.asarray(phi, dtype=np.float64)
    if arr.ndim != 1:
        raise ValueError(f"phi must have shape (n,), got shape {arr.shape}")
    return arr


def _wrap(phi: FloatArray) -> FloatArray:
    """phi - 2 pi round(phi / 2 pi): exact (Sterbenz) near multiples of the float 2 pi."""
    return phi - _TWO_PI * np.round(phi / _TWO_PI)


def _change_point_masks(
    phi: FloatArray, data: MO100Data, impact_side: ImpactSide
) -> tuple[FloatArray, npt.NDArray[np.bool_], npt.NDArray[np.bool_]]:
    """Return (phi with change points replaced by a harmless value, before-mask, after-mask)."""
    if impact_side not in ("auto", "before", "after"):
        raise ValueError(f"impact_side must be 'auto', 'before' or 'after', not {impact_side!r}")
    if not data.is_change_point:
        none = np.zeros(phi.shape, dtype=np.bool_)
        return phi, none, none
    at_cp = _wrap(phi) == 0.0
    if impact_side == "before":
        before = at_cp
    elif impact_side == "after":
        before = np.zeros(phi.shape, dtype=np.bool_)
    else:
        before = at_cp & (phi > 0.0)
    after = at_cp & ~before
    return np.where(at_cp, 1.0, phi), before, after


def impact_limits(data: MO100Data = MO100_PAPER) -> tuple[float, float]:
    """One-sided limits of u31 at the change point (spec §3.2).

    Parameters
    ----------
    data : MO100Data
        Mechanism data; must be a change-point linkage.

    Returns
    -------
    before, after : float
        ``u31(phi -> 2 pi -)`` and ``u31(phi -> 0 +)``; the roots of
        ``lam3 (lam0 - 1) k^2 + 2 lam3 k - (lam0 + lam3) = 0``, i.e.
        ``(-1 -/+ sqrt(lam0 lam2 / lam3)) / (lam0 - 1)`` (-3.8804 and +0.6804 for the paper).

    Raises
    ------
    ValueError
        If `data` is not a change-point linkage.
    """
    if not data.is_change_point:
        raise ValueError("impact_limits: the linkage has no change point (l1 + l2 != l0 + l3)")
    root = math.sqrt(data.lam0 * data.lam2 / data.lam3)
    return (-1.0 - root) / (data.lam0 - 1.0), (-1.0 + root) / (data.lam0 - 1.0)


# ----------------------------------------------------------------------------------------------
# positions, eqs (2)-(3)


def _triangle(
    phi: FloatArray, data: MO100Data
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Angles of triangle B-D-C (scaled by l1) for crank angle phi.

    Returns ``theta`` (the arctg of eqs (2)-(3)), ``ang_d_sup`` = pi - angle BDC (pi minus the
    arccos of eq 2, so that psi = ang_d_sup - theta keeps full relative precision near 0),
    ``ang_b`` = angle DBC (the arccos of eq 3) and ``ang_c`` = angle BCD = psi - beta. The
    arccos values are computed from the tangent half-angle formula with the factors
    ``d + lam3 - lam2`` etc. written without cancellation:
    ``d - (lam0 - 1) = 4 lam0 sin^2(phi/2) / (d + lam0 - 1)``.
    """
    lam0, lam2, lam3 = data.lam0, data.lam2, data.lam3
    phi = _wrap(phi)
    d = np.sqrt(1.0 + lam0**2 - 2.0 * lam0 * np.cos(phi))
    d0 = lam0 - 1.0
    offset = 0.0 if data.is_change_point else (data.l3 + data.l0 - data.l1 - data.l2) / data.l1
    e = 4.0 * lam0 * np.sin(0.5 * phi) ** 2 / (d + d0) + offset  # d + lam3 - lam2 >= 0
    f1 = np.maximum(d + lam2 - lam3, 0.0)
    f2 = np.maximum(lam2 + lam3 - d, 0.0)
    f3 = d + lam2 + lam3
    e = np.maximum(e, 0.0)
    ang_b = 2.0 * np.arctan2(np.sqrt(f2 * e), np.sqrt(f3 * f1))
    ang_c = 2.0 * np.arctan2(np.sqrt(e * f1), np.sqrt(f3 * f2))
    # pi - angle BDC, written so that it keeps full relative precision near 0
    ang_d_sup = 2.0 * np.arctan2(np.sqrt(f3 * e), np.sqrt(f1 * f2))
    theta = np.arctan(np.sin(phi) / (lam0 - np.cos(phi)))
    return theta, ang_d_sup, ang_b, ang_c


def position_functions(
    phi: npt.ArrayLike, data: MO100Data = MO100_PAPER
) -> tuple[FloatArray, FloatArray]:
    r"""Rocker and coupler angles psi, beta, eqs (2)-(3).

    .. math::

        \psi = \pi - \operatorname{arctg}\frac{\sin\varphi}{\lambda_0 - \cos\varphi}
               - \arccos\frac{\lambda_3^2 - \lambda_2^2 + d^2}{2 \lambda_3 d},\qquad
        \beta = \arccos\frac{\lambda_2^2 - \lambda_3^2 + d^2}{2 \lambda_2 d}
               - \operatorname{arctg}\frac{\sin\varphi}{\lambda_0 - \cos\varphi}

    with ``d^2 = 1 + lam0^2 - 2 lam0 cos(phi)`` (eq 2 as reconstructed in spec §3.1; the
    print's numerator ``lam3^2 - lam2^2 + lam0^2 + 1 - 2 lam0 cos(phi)`` is the same). The
    arccos terms are evaluated in half-angle form (identical values, no loss of precision at the
    change point); ``lam0 > 1`` makes the plain arctg safe.

    Parameters
    ----------
    phi : array_like, shape (n,)
        Crank angle [rad] from A->D, counter-clockwise.
    data : MO100Data
        Mechanism data.

    Returns
    -------
    psi, beta : ndarray, shape (n,)
        Angles of D->C and B->C from A->D [rad]. Both are 0 at the change point; psi lies in
        [0, 122.58 deg] for the paper's data.
    """
    p = _as_phi(phi)
    theta, ang_d_sup, ang_b, _ = _triangle(p, data)
    return ang_d_sup - theta, ang_b - theta


def joint_positions(phi: npt.ArrayLike, data: MO100Data = MO100_PAPER) -> dict[str, FloatArray]:
    """Joint coordinates in the frame axes x' (along A->D), y', origin A.

    Parameters
    ----------
    phi : array_like, shape (n,)
        Crank angle [rad].
    data : MO100Data
        Mechanism data.

    Returns
    -------
    dict of str to ndarray, shape (n, 2)
        Keys ``"A"``, ``"B"``, ``"C"`` (= B + l2 e^{i beta}), ``"C_via_D"``
        (= D + l3 e^{i psi}; equal to ``"C"`` up to round-off: loop closure) and ``"D"`` [m].
    """
    p = _as_phi(phi)
    psi, beta = position_functions(p, data)
    n = p.shape[0]
    a = np.zeros((n, 2))
    d = np.tile(np.array([data.l0, 0.0]), (n, 1))
    b = data.l1 * np.stack([np.cos(p), np.sin(p)], axis=-1)
    c = b + data.l2 * np.stack([np.cos(beta), np.sin(beta)], axis=-1)
    c_d = d + data.l3 * np.stack([np.cos(psi), np.sin(psi)], axis=-1)
    return {"A": a, "B": b, "C": c, "C_via_D": c_d, "D": d}


# ----------------------------------------------------------------------------------------------
# transfer functions, eqs (4)-(5) (lost in print; standard equivalent forms)


_BAND = 1e-3
"""Half-width [rad] of the band around the change point where 0/0 forms are interpolated."""


def _tf_raw(
    p: FloatArray, data: MO100Data
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    p = _wrap(p)
    theta, ang_d_sup, ang_b, ang_c = _triangle(p, data)
    psi = ang_d_sup - theta
    beta = ang_b - theta
    lam2, lam3 = data.lam2, data.lam3
    s_c = np.sin(ang_c)
    c_c = np.cos(ang_c)
    with np.errstate(divide="ignore", invalid="ignore"):
        u31 = np.sin(p - beta) / (lam3 * s_c)
        u21 = np.sin(p - psi) / (lam2 * s_c)
        u31p = (np.cos(p - beta) + lam2 * u21**2 - lam3 * u31**2 * c_c) / (lam3 * s_c)
        u21p = (np.cos(p - psi) + lam2 * u21**2 * c_c - lam3 * u31**2) / (lam2 * s_c)
    return u31, u21, u31p, u21p


def _near_change_point(
    phi: FloatArray, before: npt.NDArray[np.bool_], after: npt.NDArray[np.bool_]
) -> tuple[npt.NDArray[np.bool_], FloatArray, FloatArray]:
    """Band mask, side sign (-1 before, +1 after) and signed distance to the change point."""
    w = _wrap(phi)
    sigma = np.where(before, -1.0, np.where(after, 1.0, np.sign(w)))
    w = np.where(before | after, 0.0, w)
    band = np.abs(w) < _BAND
    return band, sigma, w


def _lagrange(x: FloatArray, xs: FloatArray, ys: FloatArray) -> FloatArray:
    """Polynomial through (xs[j], ys[:, j]) evaluated at x; x shape (m,), ys shape (m, k)."""
    out = np.zeros(x.shape)
    for j in range(xs.shape[0]):
        lj = np.ones(x.shape)
        for k in range(xs.shape[0]):
            if k != j:
                lj = lj * (x - xs[k]) / (xs[j] - xs[k])
        out = out + lj * ys[:, j]
    return out


def _interp_cubic(x: FloatArray, nodes: FloatArray, vals: FloatArray) -> FloatArray:
    """Cubic through (0, 0) and (nodes[j], vals[:, j]), j = 0..2, evaluated at x, shape (m,)."""
    xs = np.concatenate([[0.0], nodes])
    ys = np.concatenate([np.zeros((vals.shape[0], 1)), vals], axis=1)
    return _lagrange(x, xs, ys)


def transfer_functions(
    phi: npt.ArrayLike, data: MO100Data = MO100_PAPER, impact_side: ImpactSide = "auto"
) -> TransferFunctions:
    r"""Transfer functions u31, u21 and their derivatives (the lost eqs (4)-(5)).

    Derivation (spec §3.2): differentiate the loop
    :math:`e^{i\varphi} + \lambda_2 e^{i\beta} = \lambda_0 + \lambda_3 e^{i\psi}` with respect
    to phi, multiply by :math:`e^{-i\beta}` (resp. :math:`e^{-i\psi}`) and take imaginary parts::

        u31 = sin(phi - beta) / (lam3 sin(psi - beta))
        u21 = sin(phi - psi) / (lam2 sin(psi - beta))

    Differentiate again and take real parts::

        u31' = [cos(phi - beta) + lam2 u21^2 - lam3 u31^2 cos(psi - beta)] / (lam3 sin(psi - beta))
        u21' = [cos(phi - psi) + lam2 u21^2 cos(psi - beta) - lam3 u31^2] / (lam2 sin(psi - beta))

    ``psi - beta`` is the triangle angle BCD, computed directly in half-angle form. Near the
    change point the numerators of u31', u21' cancel to O(phi^2) (round-off about
    1e-15 / |phi|), so for ``|phi| < 1e-3 rad`` (mod 2 pi) u31', u21' are taken from the
    cubic through their exact limit 0 and the closed-form values at 1, 2, 3 mrad on the same
    side (error below 1e-12). At exact multiples of 2 pi the one-sided limits are returned
    (see module docstring and `impact_limits`).

    Parameters
    ----------
    phi : array_like, shape (n,)
        Crank angle [rad].
    data : MO100Data
        Mechanism data.
    impact_side : {"auto", "before", "after"}
        Which one-sided limit to return at the change point.

    Returns
    -------
    TransferFunctions
        ``u31, u21, u31p, u21p``, each shape (n,).
    """
    p0 = _as_phi(phi)
    p, before, after = _change_point_masks(p0, data, impact_side)
    u31, u21, u31p, u21p = _tf_raw(p, data)
    if data.is_change_point:
        k_before, k_after = impact_limits(data)
        for mask, k in ((before, k_before), (after, k_after)):
            u31[mask] = k
            u21[mask] = (data.lam3 * k - 1.0) / data.lam2
        # second-order functions: cubic through the exact limit 0 and three raw values
        band, sigma, w = _near_change_point(p0, before, after)
        if band.any():
            nodes = np.array([1.0, 2.0, 3.0]) * _BAND
            side_vals = {sg: _tf_raw(sg * nodes, data) for sg in (-1.0, 1.0)}
            for arr, k in ((u31p, 2), (u21p, 3)):
                vals = np.stack([side_vals[float(sg)][k] for sg in sigma[band]])  # (m, 3)
                arr[band] = _interp_cubic(np.abs(w[band]), nodes, vals)
    return TransferFunctions(u31=u31, u21=u21, u31p=u31p, u21p=u21p)


# ----------------------------------------------------------------------------------------------
# inertia loads, eq (1)


def inertia_loads(
    phi: npt.ArrayLike, data: MO100Data = MO100_PAPER, impact_side: ImpactSide = "auto"
) -> InertiaLoads:
    """Rocker inertia loads, eq (1).

    ``P_u^n = m3 omega1^2 u31^2 lS``, ``P_u^tau = m3 omega1^2 u31' lS``,
    ``M_u = I omega1^2 u31'`` (omega1 constant, so omega3 = omega1 u31 and
    eps3 = omega1^2 u31'). The printed signs are kept: ``p_tau`` and ``m_u`` are signed like
    eps3 (the d'Alembert loads are their negatives). ``I`` is the centroidal value
    `MO100Data.i_centroid`.

    Parameters
    ----------
    phi : array_like, shape (n,)
        Crank angle [rad].
    data : MO100Data
        Mechanism data.
    impact_side : {"auto", "before", "after"}
        One-sided limit at the change point.

    Returns
    -------
    InertiaLoads
        ``p_n, p_tau`` [N] and ``m_u`` [N m], each shape (n,).
    """
    tf = transfer_functions(phi, data, impact_side)
    w2 = data.omega1**2
    return InertiaLoads(
        p_n=data.m3 * w2 * tf.u31**2 * data.l_s,
        p_tau=data.m3 * w2 * tf.u31p * data.l_s,
        m_u=data.i_centroid * w2 * tf.u31p,
    )


# ----------------------------------------------------------------------------------------------
# housing force (convention-free, recommended) and the printed chain (9)-(14)


def housing_force(
    phi: npt.ArrayLike, data: MO100Data = MO100_PAPER, impact_side: ImpactSide = "auto"
) -> tuple[FloatArray, FloatArray]:
    r"""Total force of the mechanism on the housing, in housing axes (spec §3.4).

    With crank and coupler massless, the total force on the housing equals the rocker's
    d'Alembert inertia force :math:`-m_3 a_S`. In housing axes (x along D->S at impact, y its
    CCW normal, pointing up, against the blow) :math:`a_S = l_S (i\varepsilon_3 -
    \omega_3^2) e^{i\psi}`, hence::

        Rx = P_u^n cos(psi) + P_u^tau sin(psi)
        Ry = P_u^n sin(psi) - P_u^tau cos(psi)

    This is independent of I. It equals minus the printed (13)-(14) evaluated with the Fig. 4
    angle sense (see `group_reactions`).

    Parameters
    ----------
    phi : array_like, shape (n,)
        Crank angle [rad].
    data : MO100Data
        Mechanism data.
    impact_side : {"auto", "before", "after"}
        One-sided limit at the change point.

    Returns
    -------
    rx, ry : ndarray, shape (n,)
        Components of the force on the housing [N].
    """
    p = _as_phi(phi)
    psi, _ = position_functions(p, data)
    loads = inertia_loads(p, data, impact_side)
    rx = loads.p_n * np.cos(psi) + loads.p_tau * np.sin(psi)
    ry = loads.p_n * np.sin(psi) - loads.p_tau * np.cos(psi)
    return rx, ry


def _printed_chain(
    phi: FloatArray, data: MO100Data, angle_sense: Literal["fig4", "as_eq2"]
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
    psi, beta = position_functions(phi, data)
    if angle_sense == "fig4":
        psi, beta = -psi, -beta
    loads = inertia_loads(phi, data, "auto")
    pn, pt, mu = loads.p_n, loads.p_tau, loads.m_u
    al, l3, ls = data.alpha, data.l3, data.l_s
    s_pb = np.sin(psi - beta)
    r03t = mu / l3 + pt * (ls / l3 - math.cos(al)) - pn * math.sin(al)  # (9)
    r03n = (  # (10)
        pn * np.sin(psi + al - beta) + pt * np.cos(psi + al - beta) + r03t * np.cos(psi - beta)
    ) / s_pb
    r12 = (pn * math.sin(al) + pt * math.cos(al) + r03t) / s_pb  # (11) as printed
    r10 = r12  # (12) as printed
    rx = r10 * np.cos(al - beta) - r03n * np.cos(psi - al) - r03t * np.sin(psi - al)  # (13)
    ry = r10 * np.sin(al - beta) + r03n * np.sin(psi - al) - r03t * np.cos(psi - al)  # (14)
    return r03t, r03n, r12, rx, ry


def group_reactions(
    phi: npt.ArrayLike,
    data: MO100Data = MO100_PAPER,
    angle_sense: Literal["fig4", "as_eq2"] = "fig4",
    impact_side: ImpactSide = "auto",
) -> GroupReactions:
    r"""Reactions of the Assur group (2, 3) and on the housing, eqs (9)-(14) as printed.

    Computation order::

        R03^tau = M_u / l3 + P^tau (lS / l3 - cos a) - P^n sin a                          (9)
        R03^n = [P^n sin(psi + a - beta) + P^tau cos(psi + a - beta)
                 + R03^tau cos(psi - beta)] / sin(psi - beta)                              (10)
        R12 = [P^n sin a + P^tau cos a + R03^tau] / sin(psi - beta)
            = (M_u + P^tau lS) / (l3 sin(psi - beta))                                      (11)
        R10 = R12                                                                          (12)
        Rx = R12 cos(a - beta) - R03^n cos(psi - a) - R03^tau sin(psi - a)                 (13)
        Ry = R12 sin(a - beta) + R03^n sin(psi - a) - R03^tau cos(psi - a)                 (14)

    (9) follows from the moment equation (8) about C with ``l_CS sin(theta) = lS - l3 cos a``
    and ``l_CS cos(theta) = l3 sin a``. R03, R12 depend on I; Rx, Ry do not.

    Departures from the print: with ``angle_sense="fig4"`` (default) psi and beta enter
    (6)-(14) with the opposite sense to (2)-(3), ``psi_K = -psi, beta_K = -beta`` (spec §5
    item 1); then ``(rx, ry) == -housing_force(phi)``, i.e. the printed Rx, Ry are the force
    of the housing on the mechanism (or Fig. 4's axes point the other way); ``|ry(350 deg)|``
    = 39 899.7 N. ``angle_sense="as_eq2"`` inserts (2)-(3) unchanged, as a naive reading of
    the print does (Ry(350 deg) = 11 769 N; kept only to document the misprint). The sign of
    the printed (11) is opposite to what (6)-(7) give; ``r12_from_eq6_7 = -r12`` is the value
    consistent with (6)-(7) (spec §5 item 2).

    Change point: (10) and (11) are 0/0 there and lose precision near it. For
    ``|phi| < 1e-3 rad`` (mod 2 pi) the values, and at the change point the one-sided limit on
    the chosen side, come from the cubic through the closed-form values at 1, 2, 3, 4 mrad on
    that side (truncation error about 1e-12 f rad^4).

    Parameters
    ----------
    phi : array_like, shape (n,)
        Crank angle [rad].
    data : MO100Data
        Mechanism data.
    angle_sense : {"fig4", "as_eq2"}
        Rotational sense of psi, beta inside (6)-(14).
    impact_side : {"auto", "before", "after"}
        One-sided limit at the change point.

    Returns
    -------
    GroupReactions
        Arrays of shape (n,) [N].
    """
    if angle_sense not in ("fig4", "as_eq2"):
        raise ValueError(f"angle_sense must be 'fig4' or 'as_eq2', not {angle_sense!r}")
    p0 = _as_phi(phi)
    p, before, after = _change_point_masks(p0, data, impact_side)
    out = list(_printed_chain(_wrap(p), data, angle_sense))
    if data.is_change_point:
        band, sigma, w = _near_change_point(p0, before, after)
        if band.any():
            nodes = np.array([1.0, 2.0, 3.0, 4.0]) * _BAND
            side_vals = {sg: _printed_chain(sg * nodes, data, angle_sense) for sg in (-1.0, 1.0)}
            for k in range(5):
                vals = np.stack([side_vals[float(sg)][k] for sg in sigma[band]])  # (m, 4)
                out[k][band] = _lagrange(np.abs(w[band]), nodes, vals)
    r03t, r03n, r12, rx, ry = out
    return GroupReactions(r03_tau=r03t, r03_n=r03n, r12=r12, r12_from_eq6_7=-r12, rx=rx, ry=ry)


# ----------------------------------------------------------------------------------------------
# impulses and the half-sine fit, eqs (15)-(16)


def cycle_impulse(data: MO100Data = MO100_PAPER) -> tuple[float, float]:
    """Exact impulse of (Rx, Ry) over one open cycle 0+ ... 2 pi - (momentum theorem).

    The housing force is the rocker's d'Alembert force ``-m3 a_S``, so its impulse over the
    cycle is ``-m3 [v_S(2 pi -) - v_S(0 +)]``. At the change point ``psi = 0`` and ``v_S`` is
    along y, hence::

        Sx = 0,    Sy = m3 lS omega1 (u31(0 +) - u31(2 pi -))

    (534.6 N s for the paper's data). This is the rocker momentum that the tool takes at each
    blow; the paper's "net Rx impulse is negligible" is exact in this model.

    Parameters
    ----------
    data : MO100Data
        Mechanism data (change-point linkage).

    Returns
    -------
    sx, sy : float
        Impulses [N s].
    """
    k_before, k_after = impact_limits(data)
    return 0.0, data.m3 * data.l_s * data.omega1 * (k_after - k_before)


def ry_impulse_trapezoid(
    start_deg: float,
    stop_deg: float,
    step_deg: float,
    data: MO100Data = MO100_PAPER,
    component: Literal["x", "y"] = "y",
) -> float:
    """Trapezoid-rule impulse of Ry (or Rx) over a crank-angle window, as the paper did.

    The grid is ``start_deg, start_deg + step_deg, ..., stop_deg`` (stop included, so the
    window must be a whole number of steps); time is ``t = phi / omega1``. 360 deg is
    evaluated as the limit before impact, 0 deg as the limit after it.

    Parameters
    ----------
    start_deg, stop_deg : float
        Window in crank degrees, ``0 <= start_deg < stop_deg <= 360``.
    step_deg : float
        Grid step [deg].
    data : MO100Data
        Mechanism data.
    component : {"x", "y"}
        Which force component to integrate.

    Returns
    -------
    float
        Impulse [N s].
    """
    n = round((stop_deg - start_deg) / step_deg)
    if n < 1 or not math.isclose(start_deg + n * step_deg, stop_deg, abs_tol=1e-9):
        raise ValueError("ry_impulse_trapezoid: window must be a whole number of steps")
    phi = np.deg2rad(np.linspace(start_deg, stop_deg, n + 1))
    rx, ry = housing_force(phi, data, "auto")
    r = ry if component == "y" else rx
    return float(np.trapezoid(r, phi / data.omega1))


def _ry_scalar(phi: float, data: MO100Data) -> float:
    return float(housing_force(np.array([phi]), data)[1][0])


def ry_main_lobe(data: MO100Data = MO100_PAPER, n: int = 200_001) -> tuple[float, float]:
    """Start angle and impulse of the main (positive, pre-impact) lobe of Ry.

    The lobe starts at the last zero crossing of Ry before impact (312.2 deg for the paper's
    data; found by bisection between 300 and 340 deg) and ends at impact (2 pi -). The impulse
    is the trapezoid rule on `n` equally spaced points.

    Parameters
    ----------
    data : MO100Data
        Mechanism data.
    n : int
        Number of integration points.

    Returns
    -------
    phi_start : float
        Start of the lobe [rad].
    impulse : float
        Integral of Ry dt over the lobe [N s].
    """
    lo, hi = math.radians(300.0), math.radians(340.0)
    if not (_ry_scalar(lo, data) < 0.0 < _ry_scalar(hi, data)):
        raise ValueError("ry_main_lobe: no sign change of Ry between 300 and 340 deg")
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if _ry_scalar(mid, data) < 0.0:
            lo = mid
        else:
            hi = mid
        if hi - lo < 1e-15:
            break
    phi = np.linspace(hi, _TWO_PI, n)
    _, ry = housing_force(phi, data, "auto")
    return hi, float(np.trapezoid(ry, phi / data.omega1))


def rx_lobe_impulses(data: MO100Data = MO100_PAPER, n: int = 400_001) -> tuple[float, float, float]:
    """Positive and negative impulses of Rx over one cycle, and their sum.

    Trapezoid rule of ``max(Rx, 0)`` and ``min(Rx, 0)`` on `n` points over ``[0, 2 pi]``
    (endpoints as one-sided limits).

    Parameters
    ----------
    data : MO100Data
        Mechanism data.
    n : int
        Number of integration points.

    Returns
    -------
    positive, negative, net : float
        Impulses [N s] (spec: +340.6, -340.8, about -0.3 on a fine grid; exactly 0 in the limit,
        see `cycle_impulse`).
    """
    phi = np.linspace(0.0, _TWO_PI, n)
    rx, _ = housing_force(phi, data, "auto")
    t = phi / data.omega1
    pos = float(np.trapezoid(np.maximum(rx, 0.0), t))
    neg = float(np.trapezoid(np.minimum(rx, 0.0), t))
    return pos, neg, float(np.trapezoid(rx, t))


def half_sine_fit(h: float, s: float, period: float) -> tuple[float, float]:
    """Parameters of the half-sine pulse, eq (16).

    Equal impulse: ``S = int_0^{T - t1} H sin(mu t) dt = (H / mu) [1 - cos(mu (T - t1))]``
    with ``T - t1 = pi / mu`` gives ``mu = 2 H / S`` and ``t1 = T - pi / mu``.

    Parameters
    ----------
    h : float
        Pulse amplitude H [N].
    s : float
        Impulse S [N s].
    period : float
        Cycle period T [s].

    Returns
    -------
    mu : float
        "Frequency" [1/s].
    t1 : float
        Pulse start [s].
    """
    mu = 2.0 * h / s
    return mu, period - math.pi / mu


def half_sine_pulse(t: npt.ArrayLike, h: float, mu: float, t1: float, period: float) -> FloatArray:
    """Half-sine approximation of Ry(t), eq (15) corrected.

    ``Ry = 0`` for ``0 <= t < t1`` and ``Ry = H sin(mu (t - t1))`` for ``t1 <= t <= T``; the
    print has ``H sin(mu t)`` in the second branch, which contradicts the integral that follows
    it and the meaning of t1. Times are taken modulo `period`.

    Parameters
    ----------
    t : array_like, shape (n,)
        Time [s].
    h, mu, t1, period : float
        Amplitude [N], frequency [1/s], start [s] and period [s].

    Returns
    -------
    ndarray, shape (n,)
        Approximated Ry [N].
    """
    tt = np.mod(np.asarray(t, dtype=np.float64), period)
    return np.where(tt >= t1, h * np.sin(mu * (tt - t1)), 0.0)


PAPER_H = 39895.0
"""Published amplitude H [N]."""
PAPER_MU = 170.0
"""Published mu [1/s]."""
PAPER_T1 = 0.1815
"""Published t1 [s]."""


def paper_comparison(
    data: MO100Data = MO100_PAPER, step_deg: float = 10.0
) -> dict[str, PaperComparisonRow]:
    """Table of the paper's published numbers against ours.

    Readings (spec §4.2-4.3):

    * ``H``: maximum of Ry on the ``step_deg`` grid (the paper's Fig. 5 grid; 10 deg gives
      39 899.7 N at 350 deg vs 39 895 N);
    * ``H_continuous``: the true maximum of Ry (40 558 N at 348.5 deg);
    * ``S_implied``: the paper's S is not printed; 2 H / mu = 469.35 N s is implied;
      ours is the main positive lobe of Ry (from its zero crossing, 312.2 deg, to impact);
    * ``mu``, ``t1``: eq (16) with our H (grid) and our S (main lobe);
    * ``mu_paper_S``, ``t1_paper_S``: eq (16) with the paper's H and implied S (checks (16));
    * ``net_x_impulse``: the paper says "negligible" (0); ours is the fine-grid value.

    Parameters
    ----------
    data : MO100Data
        Mechanism data.
    step_deg : float
        Grid step for H [deg].

    Returns
    -------
    dict of str to PaperComparisonRow
    """
    grid = np.deg2rad(np.arange(step_deg, 360.0 + 0.5 * step_deg, step_deg))
    _, ry_grid = housing_force(grid, data)
    i = int(np.argmax(ry_grid))
    h_grid = float(ry_grid[i])
    fine = np.linspace(math.radians(340.0), math.radians(355.0), 150_001)
    _, ry_fine = housing_force(fine, data)
    j = int(np.argmax(ry_fine))
    phi_lobe, s_lobe = ry_main_lobe(data)
    s_paper = 2.0 * PAPER_H / PAPER_MU
    mu, t1 = half_sine_fit(h_grid, s_lobe, data.period)
    mu_p, t1_p = half_sine_fit(PAPER_H, s_paper, data.period)
    _, _, net = rx_lobe_impulses(data)
    rows = [
        PaperComparisonRow(
            "H",
            PAPER_H,
            h_grid,
            "N",
            f"max Ry on a {step_deg:g} deg grid (at {math.degrees(float(grid[i])):.1f} deg)",
        ),
        PaperComparisonRow(
            "H_continuous",
            PAPER_H,
            float(ry_fine[j]),
            "N",
            f"continuous max Ry (at {math.degrees(float(fine[j])):.2f} deg)",
        ),
        PaperComparisonRow(
            "S_implied",
            s_paper,
            s_lobe,
            "N s",
            f"main Ry lobe {math.degrees(phi_lobe):.2f}..360 deg, fine trapezoid",
        ),
        PaperComparisonRow("mu", PAPER_MU, mu, "1/s", "eq (16), H grid, S main lobe"),
        PaperComparisonRow("t1", PAPER_T1, t1, "s", "eq (16), H grid, S main lobe"),
        PaperComparisonRow("mu_paper_S", PAPER_MU, mu_p, "1/s", "eq (16), paper H, S = 2H/mu"),
        PaperComparisonRow("t1_paper_S", PAPER_T1, t1_p, "s", "eq (16), paper H, S = 2H/mu"),
        PaperComparisonRow("net_x_impulse", 0.0, net, "N s", "fine trapezoid over 0..360 deg"),
    ]
    return {r.quantity: r for r in rows}
