r"""Independent closed-form reference: bucket-turning mechanism of the EO-4112 rope backhoe.

Implements, in pure NumPy, Yu.V. Maksimov, *Kinematic study of the bucket-turning mechanism of
a rope excavator* (seeds ``000_be9f5f3a43aff791.txt`` and its OCR copy
``004_03940173d6e2ea14.txt``), as analysed in ``seeds/maksimov-rope-shovel-bucket.md``
(below: "spec"). Reference for the general engine; it must never import it.

Mechanism (spec §1-2; boom horizontal, beta_boom = 0; Ц2 = link 3 locked, Ц1 = link 10 free)::

      O3 (boom foot)  F (drag sheave)          A        O1 (stick pivot, origin)
   X <-------*-----------*---------------------*---------*          X axis: O1 -> O3
                          \ rope 12 (EF)       \ 3 (AB)  |\ 1 (stick, phi1)
                           \                    B------O2 | lever 2 (O2B) + 5 (O2C), C beyond B
                            \                 C'        \
                             \  6 (CD) runs along the    \ stick (8 = O2E)
                              \ stick to the bucket       \
                               \             D ---------- E  bucket hinge; 7 = ED (bucket)
                                \-------------------------'  10 = HK: cylinder Ц1, K on O2E

* Frame: origin O1, +X towards the boom foot, Y chosen so that the stick angle ``phi1`` lies in
  ``(0, pi)`` (spec §2.1). This frame is the "x right, y up" frame turned by pi, so rotation
  senses are preserved. SI units; batch axis first, inputs and outputs of shape ``(n,)``.
* Four-bar 1 ``O1ABO2``: input stick ``l1`` at ``phi1``; ``phi2`` = polar angle of O2->B,
  ``phi3`` = polar angle of A->B; loop (7) ``l1 e^{i phi1} + l2 e^{i phi2} - l3 e^{i phi3} = l4``.
* Four-bar 2 ``O2CDE`` in the stick frame (origin O2, x1 along O2->E): input
  ``theta = phi2 - phi1 + theta0`` (angle of O2->C), coupler ``phi6`` (C->D), output
  ``phi7p`` = polar angle of E->D (the spec's phi7'), loop
  ``l5 e^{i theta} + l6 e^{i phi6} = l8 + l7 e^{i phi7p}``. ``phi7 = pi - phi7p`` is the
  paper's interior angle ``∠O2ED`` of eq. (13).
* Branch flags: ``phi3 = v + branch1 * delta`` (paper's (6): ``branch1 = +1``) and
  ``phi7p = v2p + branch2 * delta2`` with ``v2p`` the polar angle of E->C (paper's (13):
  ``branch2 = -1``, spec §5.11).

Departures from the print (each proved by a test in
``tests/reference/test_maksimov_reference.py``):

1. (2): ``omega1 = -v_tk / (O1E sin(phi1 + alpha_tk))``; printed ``v_tk/(O1E sin(phi1 - alpha_tk))``
   (spec §5.1). Test ``test_misprint_eq2_rope``.
2. (4), (9), (17) and the arctan/arcsin of (6), (13), (14): atan2 of both projections (spec
   §5.2). Tests ``test_misprint_eq4_quadrant``, ``test_misprint_eq9_arcsin``,
   ``test_misprint_eq17_quadrant``.
3. ``c2 = (l6^2 + l7^2 - l5^2 - l8^2)/(2 l6 l7)``; printed ``+ l8^2`` (spec §5.5). Test
   ``test_misprint_c2_sign``.
4. (13): denominator ``l7 - l6 cos eps2``; printed ``l8 - ...`` (spec §5.6). Test
   ``test_misprint_eq13_index``.
5. (15): input rate ``omega2 - omega1`` (relative, four-bar 2 rides on the stick) instead of
   ``omega2``, and angle ``phi7p = pi - phi7`` instead of phi7 of (13) (spec §5.7-5.8); the
   result is the bucket rate relative to the stick. Tests ``test_misprint_eq15_*``.
6. (16)-(19) and omega10 evaluated with ``phi7p`` (spec §5.8). Test
   ``test_misprint_eq19_phi7_convention``.
7. Not in the paper, supplied: ``phi5 = phi2 + theta0``, the cylinder length
   ``HK = sqrt(KE^2 + EH^2 + 2 KE EH cos phi7p)``, the coupler rate ``omega6`` and the bucket
   angle to the horizon ``beta_boom + phi1 + phi7p + kappa`` (spec §3.6).

Reading of «проекции звеньев 2 и 3 пересекаются» ("the projections of links 2 and 3 cross"):
links 2 and 3 share joint B, so they can meet nowhere else as bare segments. We take the two
non-trivial readings the spec's conventions allow, and the default geometry satisfies both:
(i) link 5 is the straight continuation of link 2 beyond B (``theta0 = 0``, ``l5 > l2``), so
link 3 ends at an *interior* point of the lever 2+5 and the two cross there in the side view;
(ii) in the paper's branch ``phi3 = v + delta`` the contour O1ABO2 is a crossed
(self-intersecting) quadrilateral: link 3 crosses the stick segment O1O2 over the whole working
range. Either makes the linkage "non-classical"; the mechanism works over about a quarter turn
of the stick (``phi1`` = 60..150 deg), turning the bucket about 93 deg relative to the stick.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from excavkin.arrays import FloatArray

__all__ = [
    "EO4112_DRIVE",
    "EO4112_GEOMETRY",
    "BucketMechanismState",
    "FourBar1Position",
    "FourBar2Position",
    "RopeShovelGeometry",
    "WinchDrive",
    "bucket_angle_to_horizon",
    "bucket_mechanism",
    "bucket_mechanism_from_drive",
    "cylinder_c1_position",
    "cylinder_c1_rates",
    "fourbar1_position",
    "fourbar1_rates",
    "fourbar2_position",
    "fourbar2_rates",
    "printed_c2",
    "printed_eq2_omega1",
    "printed_eq4_v",
    "printed_eq9_phi2",
    "printed_eq13_phi7",
    "printed_eq15_omega7",
    "printed_eq17_gamma",
    "printed_eq19_v_c1",
    "rope_speed",
    "rope_triangle",
    "stick_rate_from_rope",
]


def _arr(x: ArrayLike) -> FloatArray:
    return np.atleast_1d(np.asarray(x, dtype=np.float64))


def _sign(flag: int, name: str) -> float:
    if flag not in (1, -1):
        raise ValueError(f"{name} must be +1 or -1, got {flag!r}")
    return float(flag)


def _wrap(a: FloatArray) -> FloatArray:
    return np.asarray(np.arctan2(np.sin(a), np.cos(a)), dtype=np.float64)


@dataclass(frozen=True, slots=True)
class RopeShovelGeometry:
    """Dimensions of the bucket-turning mechanism (spec §2.3). Lengths in m, angles in rad.

    Parameters
    ----------
    l1, l2, l3, l4 : float
        Four-bar 1: O1O2 (stick part), O2B (lever arm 2), AB (locked cylinder Ц2), AO1 (boom).
    l5, l6, l7, l8 : float
        Four-bar 2: O2C (lever arm 5), CD (coupler), ED (bucket arm), EO2 (stick part).
    l9 : float
        EH, bucket arm to the Ц1 attachment H (H on the ray E->D).
    ke : float
        KE, distance of the Ц1 stick pin K from E along the stick (no symbol in the paper).
    l13 : float
        O1F, boom segment from O1 to the drag-rope point F on +X.
    o1e : float or None
        O1E; ``None`` means ``l1 + l8`` (O1, O2, E collinear).
    theta0 : float
        Offset of link 5 from ray O2B (spec §5.9); 0 = C on ray O2B (paper).
    kappa : float
        Angle from ray E->D to the front edge of the bucket side wall (line 11).
    beta_boom : float
        Boom angle beta_ст (the paper analyses 0).
    branch1, branch2 : int
        Assembly flags (+1/-1) of four-bar 1 and 2, see the module docstring.
    phi1_min, phi1_max : float
        Working range of the stick angle.
    """

    l1: float
    l2: float
    l3: float
    l4: float
    l5: float
    l6: float
    l7: float
    l8: float
    l9: float
    ke: float
    l13: float
    o1e: float | None = None
    theta0: float = 0.0
    kappa: float = 0.0
    beta_boom: float = 0.0
    branch1: int = 1
    branch2: int = -1
    phi1_min: float = float(np.radians(60.0))
    phi1_max: float = float(np.radians(150.0))

    @property
    def o1e_length(self) -> float:
        """O1E, m (``l1 + l8`` unless given)."""
        return self.l1 + self.l8 if self.o1e is None else self.o1e


@dataclass(frozen=True, slots=True)
class WinchDrive:
    """Main-winch drag drive (unnumbered formula before eq. (3)).

    Parameters
    ----------
    omega_motor : float
        Winch motor angular speed ω_дв, rad/s.
    r_drum : float
        Drum radius R_б, m.
    gear_ratio : float
        Drum-drive gear ratio i.
    multiplicity : float
        Pulley-block multiplicity a_п.
    """

    omega_motor: float
    r_drum: float
    gear_ratio: float
    multiplicity: float


#: EO-4112-scale geometry (4th size-group rope excavator, bucket ~1 m^3, stick O1E = 2.80 m).
#: The paper gives no numbers: every length is our engineering estimate, chosen by a search
#: over plausible sizes so that, in the paper's branches (branch1 = +1, branch2 = -1,
#: theta0 = 0), both four-bars assemble over phi1 = 60..150 deg with transmission angles
#: >= 39 deg, the bucket turns ~93 deg relative to the stick (the paper's "quarter turn"),
#: C lies beyond B on the lever (l5 > l2) and link 3 crosses the stick. kappa = 0 (side-wall
#: edge parallel to ED) is a placeholder assumption.
EO4112_GEOMETRY = RopeShovelGeometry(
    l1=0.93,
    l2=0.42,
    l3=0.98,
    l4=0.43,
    l5=0.80,
    l6=2.38,
    l7=0.32,
    l8=1.87,
    l9=0.30,
    ke=1.10,
    l13=4.20,
)

#: Drag drive estimate: 750 rpm motor, drum radius 0.25 m, i = 20, two-fall block
#: -> rope speed 0.49 m/s (typical drag speed of the class; not from the paper).
EO4112_DRIVE = WinchDrive(
    omega_motor=750.0 * 2.0 * np.pi / 60.0, r_drum=0.25, gear_ratio=20.0, multiplicity=2.0
)


# --------------------------------------------------------------------------------------
# Rope drive: v_tk, triangle O1FE (1), omega1 (2)
# --------------------------------------------------------------------------------------


def rope_speed(
    omega_motor: ArrayLike, r_drum: float, gear_ratio: float, multiplicity: float
) -> FloatArray:
    """Rope speed ``v_tk = omega_motor R_drum / (i a_p)`` (unnumbered, spec §3.1).

    Parameters
    ----------
    omega_motor : array_like, shape (n,)
        Motor angular speed, rad/s.
    r_drum : float
        Drum radius, m.
    gear_ratio : float
        Gear ratio i of the drum drive.
    multiplicity : float
        Pulley-block multiplicity a_p.

    Returns
    -------
    numpy.ndarray, shape (n,)
        Rope speed, m/s; > 0 when winding (``v_tk = -dFE/dt``).
    """
    return np.asarray(_arr(omega_motor) * r_drum / (gear_ratio * multiplicity), dtype=np.float64)


def rope_triangle(o1e: float, l13: float, phi1: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """Triangle O1FE, eq. (1): ``alpha_tk`` (interior angle at F) and rope length FE.

    ``alpha_tk = atan2(O1E sin phi1, FO1 - O1E cos phi1)``,
    ``FE = sqrt(FO1^2 + O1E^2 - 2 FO1 O1E cos phi1)``.

    Parameters
    ----------
    o1e : float
        O1E, m.
    l13 : float
        FO1, m.
    phi1 : array_like, shape (n,)
        Stick angle, rad.

    Returns
    -------
    alpha_tk, fe : numpy.ndarray, shape (n,)
        Angle (rad) and rope length (m).
    """
    p = _arr(phi1)
    sy = o1e * np.sin(p)
    sx = l13 - o1e * np.cos(p)
    return np.arctan2(sy, sx), np.hypot(sx, sy)


def stick_rate_from_rope(o1e: float, l13: float, phi1: ArrayLike, v_rope: ArrayLike) -> FloatArray:
    """Stick angular velocity from the rope speed, eq. (2) **corrected** (spec §3.1, §5.1).

    Differentiating ``FE^2 = FO1^2 + O1E^2 - 2 FO1 O1E cos phi1`` with ``v_tk = -dFE/dt``
    and using ``FE sin alpha_tk = O1E sin phi1`` gives
    ``omega1 = -v_tk / (O1E sin(phi1 + alpha_tk))``.

    Parameters
    ----------
    o1e : float
        O1E, m.
    l13 : float
        FO1, m.
    phi1 : array_like, shape (n,)
        Stick angle, rad.
    v_rope : array_like, shape (n,)
        Rope speed v_tk, m/s (> 0 winding).

    Returns
    -------
    numpy.ndarray, shape (n,)
        omega1, rad/s.
    """
    p, v = np.broadcast_arrays(_arr(phi1), _arr(v_rope))
    alpha, _ = rope_triangle(o1e, l13, p)
    return np.asarray(-v / (o1e * np.sin(p + alpha)), dtype=np.float64)


def printed_eq2_omega1(o1e: float, l13: float, phi1: ArrayLike, v_rope: ArrayLike) -> FloatArray:
    """Eq. (2) as printed: ``omega1 = v_tk / (O1E sin(phi1 - alpha_tk))`` (wrong, spec §5.1).

    Parameters
    ----------
    o1e, l13 : float
        O1E and FO1, m.
    phi1 : array_like, shape (n,)
        Stick angle, rad.
    v_rope : array_like, shape (n,)
        Rope speed, m/s.

    Returns
    -------
    numpy.ndarray, shape (n,)
        The printed omega1, rad/s.
    """
    p, v = np.broadcast_arrays(_arr(phi1), _arr(v_rope))
    alpha, _ = rope_triangle(o1e, l13, p)
    return np.asarray(v / (o1e * np.sin(p - alpha)), dtype=np.float64)


# --------------------------------------------------------------------------------------
# Four-bar 1, O1ABO2: (3)-(12)
# --------------------------------------------------------------------------------------


class FourBar1Position(NamedTuple):
    """Four-bar O1ABO2 positions; fields of shape (n,), rad.

    Attributes
    ----------
    eps : numpy.ndarray
        ∠O2BA, eq. (5).
    v : numpy.ndarray
        Polar angle of A->O2, eq. (4).
    delta : numpy.ndarray
        ∠O2AB, eq. (3).
    phi3 : numpy.ndarray
        Polar angle of A->B, eq. (6).
    phi2 : numpy.ndarray
        Polar angle of O2->B, eq. (9) via atan2.
    """

    eps: FloatArray
    v: FloatArray
    delta: FloatArray
    phi3: FloatArray
    phi2: FloatArray


def _fourbar(
    li: float, lc: float, lo: float, lg: float, th: FloatArray, branch: float
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
    """Triangle-method four-bar: input li at th, coupler lc, output lo from (lg, 0)."""
    c = (lc**2 + lo**2 - li**2 - lg**2) / (2.0 * lc * lo)
    f = li * lg / (lc * lo)
    with np.errstate(invalid="ignore"):
        eps = np.arccos(c + f * np.cos(th))
    v = np.arctan2(li * np.sin(th), li * np.cos(th) - lg)
    delta = np.arctan2(lc * np.sin(eps), lo - lc * np.cos(eps))
    out = _wrap(v + branch * delta)
    cpl = np.arctan2(lo * np.sin(out) - li * np.sin(th), lg + lo * np.cos(out) - li * np.cos(th))
    return eps, v, delta, out, cpl


def fourbar1_position(
    l1: float, l2: float, l3: float, l4: float, phi1: ArrayLike, branch: int = 1
) -> FourBar1Position:
    """Positions of four-bar O1ABO2 by the triangle method, eqs. (3)-(9) (spec §3.2-3.3).

    ``c = (l2^2 + l3^2 - l1^2 - l4^2)/(2 l2 l3)``, ``f = l1 l4/(l2 l3)``,
    ``cos eps = c + f cos phi1`` (5); ``v = atan2(l1 sin phi1, l1 cos phi1 - l4)`` (4);
    ``delta = atan2(l2 sin eps, l3 - l2 cos eps)`` (3); ``phi3 = v + branch delta`` (6);
    ``phi2 = atan2(l3 sin phi3 - l1 sin phi1, l4 + l3 cos phi3 - l1 cos phi1)`` (8)-(9).

    Parameters
    ----------
    l1, l2, l3, l4 : float
        Link lengths O1O2, O2B, AB, AO1, m.
    phi1 : array_like, shape (n,)
        Stick angle, rad.
    branch : int
        +1 (paper's (6)) or -1.

    Returns
    -------
    FourBar1Position
        NaN where the four-bar cannot be assembled (``|cos eps| > 1``).
    """
    return FourBar1Position(*_fourbar(l1, l2, l3, l4, _arr(phi1), _sign(branch, "branch")))


def fourbar1_rates(
    l1: float,
    l2: float,
    l3: float,
    phi1: ArrayLike,
    phi2: ArrayLike,
    phi3: ArrayLike,
    omega1: ArrayLike,
) -> tuple[FloatArray, FloatArray]:
    """Angular velocities of links 2 and 3, eqs. (10)-(12) (printed forms are correct).

    ``omega3 = omega1 (l1/l3) sin(phi1 - phi2)/sin(phi3 - phi2)`` (11),
    ``omega2 = -omega1 (l1/l2) sin(phi1 - phi3)/sin(phi2 - phi3)`` (12).

    Parameters
    ----------
    l1, l2, l3 : float
        Link lengths, m.
    phi1, phi2, phi3 : array_like, shape (n,)
        Link angles, rad.
    omega1 : array_like, shape (n,)
        Stick angular velocity, rad/s.

    Returns
    -------
    omega2, omega3 : numpy.ndarray, shape (n,)
        Absolute angular velocities of the lever (2 and 5) and of link 3 (Ц2), rad/s.
    """
    p1, p2, p3, w1 = np.broadcast_arrays(*map(_arr, (phi1, phi2, phi3, omega1)))
    w3 = w1 * (l1 / l3) * np.sin(p1 - p2) / np.sin(p3 - p2)
    w2 = -w1 * (l1 / l2) * np.sin(p1 - p3) / np.sin(p2 - p3)
    return w2, w3


def printed_eq4_v(l1: float, l4: float, phi1: ArrayLike) -> FloatArray:
    """Eq. (4) as printed: ``v = arctan(l1 sin phi1/(l1 cos phi1 - l4))`` (loses the quadrant).

    Parameters
    ----------
    l1, l4 : float
        Link lengths, m.
    phi1 : array_like, shape (n,)
        Stick angle, rad.

    Returns
    -------
    numpy.ndarray, shape (n,)
        The printed v, rad.
    """
    p = _arr(phi1)
    return np.asarray(np.arctan(l1 * np.sin(p) / (l1 * np.cos(p) - l4)), dtype=np.float64)


def printed_eq9_phi2(
    l1: float, l2: float, l3: float, phi1: ArrayLike, phi3: ArrayLike
) -> FloatArray:
    """Eq. (9) as printed: ``phi2 = arcsin((l3 sin phi3 - l1 sin phi1)/l2)`` (quadrant loss).

    Parameters
    ----------
    l1, l2, l3 : float
        Link lengths, m.
    phi1, phi3 : array_like, shape (n,)
        Link angles, rad.

    Returns
    -------
    numpy.ndarray, shape (n,)
        The printed phi2, rad.
    """
    p1, p3 = np.broadcast_arrays(_arr(phi1), _arr(phi3))
    return np.asarray(np.arcsin((l3 * np.sin(p3) - l1 * np.sin(p1)) / l2), dtype=np.float64)


# --------------------------------------------------------------------------------------
# Four-bar 2, O2CDE (stick frame): (13)-(15)
# --------------------------------------------------------------------------------------


class FourBar2Position(NamedTuple):
    """Four-bar O2CDE positions in the stick frame; fields of shape (n,), rad.

    Attributes
    ----------
    eps2 : numpy.ndarray
        ∠CDE.
    v2 : numpy.ndarray
        ∠O2EC (paper's v2; ``pi - `` polar angle of E->C when ``sin theta > 0``).
    delta2 : numpy.ndarray
        ∠CED.
    phi7 : numpy.ndarray
        Paper's (13) angle ∠O2ED = ``pi - phi7p`` (wrapped).
    phi7p : numpy.ndarray
        Polar angle of E->D from the stick direction O2->E: bucket angle relative to the stick.
    phi6 : numpy.ndarray
        Polar angle of C->D in the stick frame, eq. (14) via atan2.
    """

    eps2: FloatArray
    v2: FloatArray
    delta2: FloatArray
    phi7: FloatArray
    phi7p: FloatArray
    phi6: FloatArray


def fourbar2_position(
    l5: float, l6: float, l7: float, l8: float, theta: ArrayLike, branch: int = -1
) -> FourBar2Position:
    """Positions of four-bar O2CDE, eqs. (13)-(14) corrected (spec §3.4).

    ``c2 = (l6^2 + l7^2 - l5^2 - l8^2)/(2 l6 l7)`` (print: ``+ l8^2``), ``f2 = l5 l8/(l6 l7)``,
    ``cos eps2 = c2 + f2 cos theta``; ``v2p = atan2(l5 sin theta, l5 cos theta - l8)``;
    ``delta2 = atan2(l6 sin eps2, l7 - l6 cos eps2)`` (print of (13): ``l8`` for ``l7``);
    ``phi7p = v2p + branch delta2``; ``phi7 = pi - phi7p`` (= ``v2 + delta2`` of (13) for
    ``branch = -1``);
    ``phi6 = atan2(l7 sin phi7p - l5 sin theta, l8 + l7 cos phi7p - l5 cos theta)``.

    Parameters
    ----------
    l5, l6, l7, l8 : float
        O2C, CD, ED, EO2, m.
    theta : array_like, shape (n,)
        Angle of O2->C from the stick direction O2->E (``phi2 - phi1 + theta0``), rad.
    branch : int
        -1 (paper's (13), default) or +1.

    Returns
    -------
    FourBar2Position
        NaN where the four-bar cannot be assembled.
    """
    th = _arr(theta)
    eps2, v2p, delta2, phi7p, phi6 = _fourbar(l5, l6, l7, l8, th, _sign(branch, "branch"))
    v2 = np.arctan2(l5 * np.sin(th), l8 - l5 * np.cos(th))
    return FourBar2Position(eps2, v2, delta2, _wrap(np.pi - phi7p), phi7p, phi6)


def fourbar2_rates(
    l5: float,
    l6: float,
    l7: float,
    theta: ArrayLike,
    phi6: ArrayLike,
    phi7p: ArrayLike,
    theta_dot: ArrayLike,
) -> tuple[FloatArray, FloatArray]:
    """Relative rates of four-bar O2CDE, eq. (15) corrected (spec §3.4, §5.7-5.8).

    ``omega7p = theta_dot (l5/l7) sin(theta - phi6)/sin(phi7p - phi6)`` with
    ``theta_dot = omega2 - omega1`` (print: ``omega2``, and ``phi7`` for ``phi7p``);
    ``omega6 = -theta_dot (l5/l6) sin(theta - phi7p)/sin(phi6 - phi7p)`` (analogue of (12)).

    Parameters
    ----------
    l5, l6, l7 : float
        O2C, CD, ED, m.
    theta, phi6, phi7p : array_like, shape (n,)
        Stick-frame angles, rad.
    theta_dot : array_like, shape (n,)
        Lever rate relative to the stick, ``omega2 - omega1``, rad/s.

    Returns
    -------
    omega7p, omega6 : numpy.ndarray, shape (n,)
        Bucket and coupler angular velocities relative to the stick, rad/s.
    """
    th, p6, p7, td = np.broadcast_arrays(*map(_arr, (theta, phi6, phi7p, theta_dot)))
    w7 = td * (l5 / l7) * np.sin(th - p6) / np.sin(p7 - p6)
    w6 = -td * (l5 / l6) * np.sin(th - p7) / np.sin(p6 - p7)
    return w7, w6


def printed_c2(l5: float, l6: float, l7: float, l8: float) -> float:
    """``c2`` as printed: ``(l6^2 + l7^2 - l5^2 + l8^2)/(2 l6 l7)`` (sign error, spec §5.5).

    Parameters
    ----------
    l5, l6, l7, l8 : float
        O2C, CD, ED, EO2, m.

    Returns
    -------
    float
    """
    return (l6**2 + l7**2 - l5**2 + l8**2) / (2.0 * l6 * l7)


def printed_eq13_phi7(l5: float, l6: float, l7: float, l8: float, theta: ArrayLike) -> FloatArray:
    """Eq. (13) as printed (with corrected c2): ``arctan(l6 sin eps2/(l8 - l6 cos eps2)) + v2``.

    Parameters
    ----------
    l5, l6, l7, l8 : float
        O2C, CD, ED, EO2, m.
    theta : array_like, shape (n,)
        Input angle, rad.

    Returns
    -------
    numpy.ndarray, shape (n,)
        The printed ∠O2ED, rad.
    """
    th = _arr(theta)
    c2 = (l6**2 + l7**2 - l5**2 - l8**2) / (2.0 * l6 * l7)
    eps2 = np.arccos(c2 + l5 * l8 / (l6 * l7) * np.cos(th))
    v2 = np.arctan2(l5 * np.sin(th), l8 - l5 * np.cos(th))
    return np.asarray(
        np.arctan(l6 * np.sin(eps2) / (l8 - l6 * np.cos(eps2))) + v2, dtype=np.float64
    )


def printed_eq15_omega7(
    l5: float,
    l7: float,
    phi1: ArrayLike,
    phi2: ArrayLike,
    phi6: ArrayLike,
    phi7: ArrayLike,
    omega2: ArrayLike,
) -> FloatArray:
    """Eq. (15) as printed: ``omega7 = omega2 (l5/l7) sin(phi2 - phi1 - phi6)/sin(phi7 - phi6)``.

    Literal: pass the paper's ``phi7`` (∠O2ED) and ``omega2``; the tests also pass the
    corrected arguments one at a time to isolate the two errors.

    Parameters
    ----------
    l5, l7 : float
        O2C, ED, m.
    phi1, phi2, phi6, phi7 : array_like, shape (n,)
        Angles, rad.
    omega2 : array_like, shape (n,)
        Rate used as the input, rad/s.

    Returns
    -------
    numpy.ndarray, shape (n,)
        The printed omega7, rad/s.
    """
    p1, p2, p6, p7, w2 = np.broadcast_arrays(*map(_arr, (phi1, phi2, phi6, phi7, omega2)))
    return np.asarray(w2 * (l5 / l7) * np.sin(p2 - p1 - p6) / np.sin(p7 - p6), dtype=np.float64)


# --------------------------------------------------------------------------------------
# Cylinder Ц1 (link 10 = HK): (16)-(19)
# --------------------------------------------------------------------------------------


def cylinder_c1_position(ke: float, eh: float, phi7p: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """Ц1 length HK and angle gamma, eqs. (16)-(17) in the phi7p convention (spec §3.5).

    ``gamma = atan2(EH sin phi7p, KE + EH cos phi7p)``,
    ``HK = sqrt(KE^2 + EH^2 + 2 KE EH cos phi7p)``.

    Parameters
    ----------
    ke, eh : float
        KE and EH, m.
    phi7p : array_like, shape (n,)
        Bucket angle relative to the stick, rad.

    Returns
    -------
    hk, gamma : numpy.ndarray, shape (n,)
        Cylinder length l10 (m) and its angle from the stick axis (rad).
    """
    p = _arr(phi7p)
    sx = ke + eh * np.cos(p)
    sy = eh * np.sin(p)
    return np.hypot(sx, sy), np.arctan2(sy, sx)


def cylinder_c1_rates(
    ke: float, eh: float, phi7p: ArrayLike, omega7p: ArrayLike
) -> tuple[FloatArray, FloatArray]:
    """Ц1 stroke speed and angular velocity, eqs. (18)-(19) and the unnumbered omega10.

    ``v_C1 = -omega7p EH sin(phi7p - gamma)``, ``omega10 = omega7p (EH/HK) cos(phi7p - gamma)``.

    Parameters
    ----------
    ke, eh : float
        KE and EH, m.
    phi7p : array_like, shape (n,)
        Bucket angle relative to the stick, rad.
    omega7p : array_like, shape (n,)
        Bucket angular velocity relative to the stick, rad/s.

    Returns
    -------
    v_c1, omega10 : numpy.ndarray, shape (n,)
        ``dHK/dt`` (m/s) and the cylinder angular velocity relative to the stick (rad/s).
    """
    p, w = np.broadcast_arrays(_arr(phi7p), _arr(omega7p))
    hk, gamma = cylinder_c1_position(ke, eh, p)
    return -w * eh * np.sin(p - gamma), w * eh / hk * np.cos(p - gamma)


def printed_eq17_gamma(ke: float, eh: float, phi7: ArrayLike) -> FloatArray:
    """Eq. (17) as printed: ``gamma = arctan(EH sin phi7/(KE + EH cos phi7))`` (quadrant loss).

    Parameters
    ----------
    ke, eh : float
        KE and EH, m.
    phi7 : array_like, shape (n,)
        Angle argument, rad.

    Returns
    -------
    numpy.ndarray, shape (n,)
        The printed gamma, rad.
    """
    p = _arr(phi7)
    return np.asarray(np.arctan(eh * np.sin(p) / (ke + eh * np.cos(p))), dtype=np.float64)


def printed_eq19_v_c1(ke: float, eh: float, phi7: ArrayLike, omega7: ArrayLike) -> FloatArray:
    """Eq. (19) with the paper's phi7 = ∠O2ED of (13) inserted literally (gamma from (17)).

    Parameters
    ----------
    ke, eh : float
        KE and EH, m.
    phi7 : array_like, shape (n,)
        ∠O2ED, rad.
    omega7 : array_like, shape (n,)
        Bucket rate, rad/s.

    Returns
    -------
    numpy.ndarray, shape (n,)
        The printed v_C1, m/s.
    """
    p, w = np.broadcast_arrays(_arr(phi7), _arr(omega7))
    gamma = printed_eq17_gamma(ke, eh, p)
    return np.asarray(-w * eh * np.sin(p - gamma), dtype=np.float64)


# --------------------------------------------------------------------------------------
# Whole mechanism
# --------------------------------------------------------------------------------------


def bucket_angle_to_horizon(
    phi1: ArrayLike, phi7p: ArrayLike, kappa: float = 0.0, beta_boom: float = 0.0
) -> FloatArray:
    """Angle of the bucket side-wall edge 11 to the horizon (promised, not given; spec §3.6).

    ``beta_boom + phi1 + phi7p + kappa``, wrapped to ``(-pi, pi]``, measured in the paper's
    frame (from the horizontal direction O1 -> boom foot, same rotational sense as phi1).

    Parameters
    ----------
    phi1, phi7p : array_like, shape (n,)
        Stick angle and bucket angle relative to the stick, rad.
    kappa : float
        Angle from ray E->D to edge 11, rad.
    beta_boom : float
        Boom angle, rad.

    Returns
    -------
    numpy.ndarray, shape (n,)
        rad.
    """
    p1, p7 = np.broadcast_arrays(_arr(phi1), _arr(phi7p))
    return _wrap(beta_boom + p1 + p7 + kappa)


class BucketMechanismState(NamedTuple):
    """Full state of the bucket-turning mechanism; every field has shape (n,). SI units.

    Attributes
    ----------
    phi1, omega1 : numpy.ndarray
        Stick angle and angular velocity.
    alpha_tk, fe, v_rope : numpy.ndarray
        Rope angle at F, rope length FE, rope speed ``-dFE/dt``.
    eps, v, delta : numpy.ndarray
        Four-bar 1 auxiliary angles.
    phi2, phi3, phi5 : numpy.ndarray
        Absolute angles of links 2, 3 and 5 (``phi5 = phi2 + theta0``).
    omega2, omega3 : numpy.ndarray
        Absolute angular velocities of links 2 (= 5) and 3.
    theta : numpy.ndarray
        Input angle of four-bar 2 relative to the stick.
    eps2, v2, delta2 : numpy.ndarray
        Four-bar 2 auxiliary angles.
    phi6 : numpy.ndarray
        Coupler angle relative to the stick.
    phi7 : numpy.ndarray
        Paper's ∠O2ED (13).
    phi7p : numpy.ndarray
        Bucket angle relative to the stick (handle).
    omega6, omega7p : numpy.ndarray
        Coupler and bucket angular velocities relative to the stick.
    omega7_abs : numpy.ndarray
        Absolute bucket angular velocity ``omega1 + omega7p``.
    bucket_to_horizon : numpy.ndarray
        See `bucket_angle_to_horizon`.
    hk, gamma, v_c1, omega10 : numpy.ndarray
        Ц1 length, angle, stroke speed and angular velocity (relative to the stick).
    """

    phi1: FloatArray
    omega1: FloatArray
    alpha_tk: FloatArray
    fe: FloatArray
    v_rope: FloatArray
    eps: FloatArray
    v: FloatArray
    delta: FloatArray
    phi2: FloatArray
    phi3: FloatArray
    phi5: FloatArray
    omega2: FloatArray
    omega3: FloatArray
    theta: FloatArray
    eps2: FloatArray
    v2: FloatArray
    delta2: FloatArray
    phi6: FloatArray
    phi7: FloatArray
    phi7p: FloatArray
    omega6: FloatArray
    omega7p: FloatArray
    omega7_abs: FloatArray
    bucket_to_horizon: FloatArray
    hk: FloatArray
    gamma: FloatArray
    v_c1: FloatArray
    omega10: FloatArray


def bucket_mechanism(
    geom: RopeShovelGeometry, phi1: ArrayLike, omega1: ArrayLike
) -> BucketMechanismState:
    """Evaluate eqs. (1)-(19) in the paper's order for a stick motion (spec §3).

    Parameters
    ----------
    geom : RopeShovelGeometry
        Mechanism dimensions and branch flags.
    phi1 : array_like, shape (n,)
        Stick angle, rad.
    omega1 : array_like, shape (n,)
        Stick angular velocity, rad/s.

    Returns
    -------
    BucketMechanismState
        NaN where a four-bar cannot be assembled.
    """
    p1, w1 = np.broadcast_arrays(_arr(phi1), _arr(omega1))
    o1e = geom.o1e_length
    alpha, fe = rope_triangle(o1e, geom.l13, p1)
    v_rope = -w1 * o1e * np.sin(p1 + alpha)
    fb1 = fourbar1_position(geom.l1, geom.l2, geom.l3, geom.l4, p1, geom.branch1)
    w2, w3 = fourbar1_rates(geom.l1, geom.l2, geom.l3, p1, fb1.phi2, fb1.phi3, w1)
    theta = _wrap(fb1.phi2 - p1 + geom.theta0)
    fb2 = fourbar2_position(geom.l5, geom.l6, geom.l7, geom.l8, theta, geom.branch2)
    w7, w6 = fourbar2_rates(geom.l5, geom.l6, geom.l7, theta, fb2.phi6, fb2.phi7p, w2 - w1)
    hk, gamma = cylinder_c1_position(geom.ke, geom.l9, fb2.phi7p)
    v_c1, w10 = cylinder_c1_rates(geom.ke, geom.l9, fb2.phi7p, w7)
    return BucketMechanismState(
        phi1=p1,
        omega1=w1,
        alpha_tk=alpha,
        fe=fe,
        v_rope=v_rope,
        eps=fb1.eps,
        v=fb1.v,
        delta=fb1.delta,
        phi2=fb1.phi2,
        phi3=fb1.phi3,
        phi5=_wrap(fb1.phi2 + geom.theta0),
        omega2=w2,
        omega3=w3,
        theta=theta,
        eps2=fb2.eps2,
        v2=fb2.v2,
        delta2=fb2.delta2,
        phi6=fb2.phi6,
        phi7=fb2.phi7,
        phi7p=fb2.phi7p,
        omega6=w6,
        omega7p=w7,
        omega7_abs=w1 + w7,
        bucket_to_horizon=bucket_angle_to_horizon(p1, fb2.phi7p, geom.kappa, geom.beta_boom),
        hk=hk,
        gamma=gamma,
        v_c1=v_c1,
        omega10=w10,
    )


def bucket_mechanism_from_drive(
    geom: RopeShovelGeometry, drive: WinchDrive, phi1: ArrayLike
) -> BucketMechanismState:
    """As `bucket_mechanism`, with omega1 from the winch drive via eq. (2) corrected.

    Parameters
    ----------
    geom : RopeShovelGeometry
        Mechanism dimensions.
    drive : WinchDrive
        Winch parameters (constant motor speed).
    phi1 : array_like, shape (n,)
        Stick angle, rad.

    Returns
    -------
    BucketMechanismState
    """
    p1 = _arr(phi1)
    v = rope_speed(
        np.full_like(p1, drive.omega_motor), drive.r_drum, drive.gear_ratio, drive.multiplicity
    )
    w1 = stick_rate_from_rope(geom.o1e_length, geom.l13, p1, v)
    return bucket_mechanism(geom, p1, w1)
