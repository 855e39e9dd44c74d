r"""Independent closed-form reference: vector model of a 3-DOF excavator arm (seed paper 001).

Implements, in pure NumPy, the equations of the Russian paper *Vector model and analytical
kinematics of a 3-DOF crawler-excavator arm* (title and authors lost; seed
``001_57da5d3302d61297.txt``), as reconstructed and corrected in
``seeds/vector-model-excavator-arm.md`` (below: "spec"). It is a *reference* for testing the
general engine and must never import it.

Mechanism and conventions (spec §2; sketch not to scale)::

                        stick pivot (boom tip)
        y                    *--------.
        ^        l1 (boom)  /          \  l2 (stick)
        |                  /  phi1      \  phi2 (absolute)
        |                 /              *  bucket pin
        O-------> x      /                \  l3 (bucket), phi3
     boom foot = O      O                  A  tooth tip (x_A, y_A)

    cylinder sub-mechanism (spec §2.2, paper Fig. 2) in the *parent* frame of the link:

        B = link pivot (origin), D = end of the link vector l (angle psi),
        C = rod end on the link, vector C->D = l' at angle psi - alpha,
        P = cylinder base pivot = (b, -a)  (paper: vector a points -y, vector b points +x),
        z = P->C, length z, polar angle phi_z:   a + b + z + l' = l   (eq. 7)

* SI units (m, rad, s); all angles counter-clockwise from +x; batch axis first: every array
  argument has shape ``(n,)`` (scalars broadcast) and every returned array has shape ``(n,)``.
* ``phi1, phi2, phi3`` are **absolute** link angles (spec §2.1). For the cylinder relations
  the driven link's angle ``psi`` is measured in the frame of its parent: boom ``psi = phi1``
  (base frame), stick ``psi = phi2 - phi1`` (boom frame, x along l1), bucket
  ``psi = phi3 - phi2`` (stick frame, x along l2). The paper treats only the boom cylinder and
  calls the other two "analogous"; `arm_cylinder_kinematics` applies eqs. (7)-(12) in the
  parent frames and adds the parent's motion to return absolute cylinder angles and rates.
  Direct-acting bucket cylinder: the paper's simplification (a real bucket cylinder acts
  through a four-bar linkage, spec §3.6).

Departures from the printed paper (each proved by a test in
``tests/reference/test_arm_vector_reference.py``):

1. ``d = l cos psi - l' cos(psi - alpha) - b``; the print has a spurious ``+ a`` (spec §5.1).
   Test: ``test_misprint_d_spurious_a``.
2. ``phi_z = atan2(c, d)``; the print's ``cos phi_z = +sqrt(1 - sin^2 phi_z)`` (before eq. 10)
   loses the quadrant when the cylinder leans past vertical (spec §5.2, "(9) of 001").
   Test: ``test_misprint_eq9_cos_phiz_quadrant``.
3. ``omega_1, omega_2, eps_1, eps_2`` use the substituted closed forms dividing by
   ``sin(phi2 - phi1)`` (the true singularity) instead of the paper's route through (4) and
   (6), which divide by ``sin phi2`` (artificial singularity, spec §5.3). Not a misprint, but
   shown by ``test_paper_route_eq4_artificial_singularity``.
4. ``v_r`` from the closed form instead of "the first equation of (11)" (division by
   ``cos phi_z``, spec §5.3).
5. ``z = ±sqrt(c^2 + d^2)`` (spec §5.4): the sign is exposed as ``root``. ``root = -1`` is the
   same physical cylinder described by a negative length and ``phi_z + pi``; all rate
   formulas stay valid in that description.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from excavkin.arrays import FloatArray

__all__ = [
    "EXCAVATOR_20T",
    "ArmDimensions",
    "ArmUnreachableError",
    "CylinderKinematics",
    "CylinderMount",
    "arm_acceleration",
    "arm_accelerations_from_tool",
    "arm_branch",
    "arm_cylinder_kinematics",
    "arm_inverse_position",
    "arm_position",
    "arm_rates_from_tool",
    "arm_velocity",
    "cylinder_acceleration",
    "cylinder_angle_from_length",
    "cylinder_kinematics",
    "cylinder_position",
    "cylinder_velocity",
    "printed_cylinder_d",
    "printed_cylinder_phi_z",
    "printed_eq4_omega2",
]


def _arr(x: ArrayLike) -> FloatArray:
    """Return ``x`` as a float64 array with at least one dimension (the batch axis)."""
    return np.atleast_1d(np.asarray(x, dtype=np.float64))


def _sign(flag: int, name: str) -> float:
    if flag not in (1, -1):
        raise ValueError(f"{name} must be +1 or -1, got {flag!r}")
    return float(flag)


class ArmUnreachableError(ValueError):
    """The requested tool pose cannot be reached by links ``l1`` and ``l2``.

    Parameters
    ----------
    message : str
        Human-readable explanation.
    sample_indices : numpy.ndarray of int, shape (k,)
        Indices (along the batch axis) of the unreachable samples.
    """

    def __init__(self, message: str, sample_indices: NDArray[np.intp]) -> None:
        super().__init__(message)
        self.sample_indices = sample_indices


@dataclass(frozen=True, slots=True)
class CylinderMount:
    """One "link + hydraulic cylinder" sub-mechanism in the paper's parameters (Fig. 2, eq. 7).

    All quantities are in the *parent* frame of the driven link: origin at the link pivot B,
    x along the parent's reference direction.

    Parameters
    ----------
    a : float
        Length of the paper's vector **a** (points -y), m. The cylinder base pivot is at
        ``(b, -a)`` relative to B. May be negative (base above B).
    b : float
        Length of the paper's vector **b** (points +x), m. May be negative.
    l : float
        Driven-link vector length ``|B->D|`` (the paper's ``l1``), m.
    l_prime : float
        ``|C->D|`` (the paper's ``l1'``), m; C is the rod-end pin on the link.
    alpha : float
        Constant angle between vectors l and l' (``phi' = psi - alpha``), rad.
    z_min, z_max : float
        Retracted and extended pin-to-pin cylinder lengths, m (engineering estimates: the paper
        gives none).
    branch : int
        +1 or -1: assembly branch of `cylinder_angle_from_length` that contains the
        working range ``[z_min, z_max]``.
    """

    a: float
    b: float
    l: float
    l_prime: float
    alpha: float
    z_min: float
    z_max: float
    branch: int = 1

    @classmethod
    def from_pins(
        cls,
        base: tuple[float, float],
        rod: tuple[float, float],
        l: float,
        z_min: float,
        z_max: float,
        branch: int = 1,
    ) -> CylinderMount:
        """Build the mount from pin coordinates.

        Parameters
        ----------
        base : tuple of float
            Cylinder base pivot ``(x, y)`` in the parent frame relative to the pivot B, m.
        rod : tuple of float
            Rod-end pin C ``(x, y)`` in the driven link's own frame (origin B, x along B->D), m.
        l : float
            Link length ``|B->D|``, m.
        z_min, z_max : float
            Cylinder length limits, m.
        branch : int
            See the class docstring.

        Returns
        -------
        CylinderMount
        """
        l_prime = float(np.hypot(l - rod[0], rod[1]))
        alpha = float(np.arctan2(rod[1], l - rod[0]))
        return cls(
            a=-base[1],
            b=base[0],
            l=l,
            l_prime=l_prime,
            alpha=alpha,
            z_min=z_min,
            z_max=z_max,
            branch=branch,
        )

    @property
    def psi_limits(self) -> tuple[float, float]:
        """Link angles (in the parent frame, rad) at ``z_min`` and ``z_max``, in that order."""
        lo, hi = cylinder_angle_from_length(self, np.array([self.z_min, self.z_max]))
        return float(lo), float(hi)


@dataclass(frozen=True, slots=True)
class ArmDimensions:
    """Link lengths and cylinder mounts of the 3-link arm (spec §2).

    Parameters
    ----------
    l1, l2, l3 : float
        Boom (foot pin -> stick pivot), stick (stick pivot -> bucket pin) and bucket
        (bucket pin -> tooth tip A) vector lengths, m.
    boom, stick, bucket : CylinderMount
        Cylinder sub-mechanisms; their ``l`` must equal ``l1``, ``l2``, ``l3`` respectively.
    """

    l1: float
    l2: float
    l3: float
    boom: CylinderMount
    stick: CylinderMount
    bucket: CylinderMount

    def __post_init__(self) -> None:
        for name, mount, length in (
            ("boom", self.boom, self.l1),
            ("stick", self.stick, self.l2),
            ("bucket", self.bucket, self.l3),
        ):
            if not np.isclose(mount.l, length, rtol=0.0, atol=1e-12):
                raise ValueError(f"{name} cylinder mount has l={mount.l}, link length is {length}")


#: ~20 t class hydraulic excavator (Komatsu PC200 / CAT 320 size). Every number is an
#: engineering estimate of that class, not a manufacturer figure (the paper gives none):
#: boom 5.70 m, stick 2.90 m, bucket pin-to-tip 1.50 m; boom cylinder base 0.30 m ahead of and
#: 1.10 m below the boom foot, rod end 2.70 m along the boom and 0.45 m below its axis,
#: length 2.00-3.40 m; stick cylinder base on top of the boom 2.60 m behind the boom tip and
#: 0.75 m above the boom axis, rod end on the stick tail 0.80 m behind the stick pivot,
#: 0.20 m off-axis, length 2.00-3.25 m; bucket cylinder (direct-acting, paper's
#: simplification) base on the stick 2.30 m behind the bucket pin and 0.40 m off-axis, rod end
#: on the bucket lever at (-0.43, 0.22) m in the bucket frame, length 2.00-2.75 m.
#: Resulting working ranges (parent-frame link angles): boom -25.5..51.0 deg, stick
#: -155.2..-56.4 deg, bucket -129.3..-24.5 deg.
EXCAVATOR_20T = ArmDimensions(
    l1=5.70,
    l2=2.90,
    l3=1.50,
    boom=CylinderMount.from_pins((0.30, -1.10), (2.70, -0.45), 5.70, 2.00, 3.40, branch=1),
    stick=CylinderMount.from_pins((-2.60, 0.75), (-0.80, -0.20), 2.90, 2.00, 3.25, branch=-1),
    bucket=CylinderMount.from_pins((-2.30, 0.40), (-0.43, 0.22), 1.50, 2.00, 2.75, branch=-1),
)


# --------------------------------------------------------------------------------------
# Arm: positions, velocities, accelerations (eqs. 1-6)
# --------------------------------------------------------------------------------------


def arm_position(
    dims: ArmDimensions, phi1: ArrayLike, phi2: ArrayLike, phi3: ArrayLike
) -> tuple[FloatArray, FloatArray]:
    """Forward position of the tooth tip A, eq. (2) (spec §3.1).

    ``x_A = sum l_i cos phi_i``, ``y_A = sum l_i sin phi_i``.

    Parameters
    ----------
    dims : ArmDimensions
        Arm dimensions.
    phi1, phi2, phi3 : array_like, shape (n,)
        Absolute link angles, rad.

    Returns
    -------
    x_a, y_a : numpy.ndarray, shape (n,)
        Coordinates of A, m.
    """
    p1, p2, p3 = np.broadcast_arrays(_arr(phi1), _arr(phi2), _arr(phi3))
    x = dims.l1 * np.cos(p1) + dims.l2 * np.cos(p2) + dims.l3 * np.cos(p3)
    y = dims.l1 * np.sin(p1) + dims.l2 * np.sin(p2) + dims.l3 * np.sin(p3)
    return x, y


def arm_velocity(
    dims: ArmDimensions,
    phi1: ArrayLike,
    phi2: ArrayLike,
    phi3: ArrayLike,
    omega1: ArrayLike,
    omega2: ArrayLike,
    omega3: ArrayLike,
) -> tuple[FloatArray, FloatArray]:
    """Velocity of A from the link rates, eq. (3) (spec §3.2).

    ``v_xA = -sum l_i omega_i sin phi_i``, ``v_yA = sum l_i omega_i cos phi_i``.

    Parameters
    ----------
    dims : ArmDimensions
        Arm dimensions.
    phi1, phi2, phi3 : array_like, shape (n,)
        Absolute link angles, rad.
    omega1, omega2, omega3 : array_like, shape (n,)
        Absolute link angular velocities, rad/s.

    Returns
    -------
    v_xa, v_ya : numpy.ndarray, shape (n,)
        Velocity components of A, m/s.
    """
    p1, p2, p3, w1, w2, w3 = np.broadcast_arrays(
        *map(_arr, (phi1, phi2, phi3, omega1, omega2, omega3))
    )
    ls = (dims.l1, dims.l2, dims.l3)
    vx = -sum(
        li * wi * np.sin(pi) for li, wi, pi in zip(ls, (w1, w2, w3), (p1, p2, p3), strict=True)
    )
    vy = sum(
        li * wi * np.cos(pi) for li, wi, pi in zip(ls, (w1, w2, w3), (p1, p2, p3), strict=True)
    )
    return np.asarray(vx, dtype=np.float64), np.asarray(vy, dtype=np.float64)


def arm_acceleration(
    dims: ArmDimensions,
    phi1: ArrayLike,
    phi2: ArrayLike,
    phi3: ArrayLike,
    omega1: ArrayLike,
    omega2: ArrayLike,
    omega3: ArrayLike,
    eps1: ArrayLike,
    eps2: ArrayLike,
    eps3: ArrayLike,
) -> tuple[FloatArray, FloatArray]:
    """Acceleration of A from the link rates, eq. (5) (spec §3.3).

    ``a_xA = -sum l_i (eps_i sin phi_i + omega_i^2 cos phi_i)``,
    ``a_yA = sum l_i (eps_i cos phi_i - omega_i^2 sin phi_i)``.

    Parameters
    ----------
    dims : ArmDimensions
        Arm dimensions.
    phi1, phi2, phi3 : array_like, shape (n,)
        Absolute link angles, rad.
    omega1, omega2, omega3 : array_like, shape (n,)
        Absolute angular velocities, rad/s.
    eps1, eps2, eps3 : array_like, shape (n,)
        Absolute angular accelerations, rad/s^2.

    Returns
    -------
    a_xa, a_ya : numpy.ndarray, shape (n,)
        Acceleration components of A, m/s^2.
    """
    arrs = np.broadcast_arrays(
        *map(_arr, (phi1, phi2, phi3, omega1, omega2, omega3, eps1, eps2, eps3))
    )
    ph, om, ep = arrs[0:3], arrs[3:6], arrs[6:9]
    ls = (dims.l1, dims.l2, dims.l3)
    ax = np.zeros_like(ph[0])
    ay = np.zeros_like(ph[0])
    for li, p, w, e in zip(ls, ph, om, ep, strict=True):
        ax = ax - li * (e * np.sin(p) + w**2 * np.cos(p))
        ay = ay + li * (e * np.cos(p) - w**2 * np.sin(p))
    return ax, ay


def arm_branch(phi1: ArrayLike, phi2: ArrayLike) -> NDArray[np.int8]:
    """Elbow branch flag of a pose, as used by `arm_inverse_position`.

    ``branch = sign(sin(phi1 - phi2))``: +1 is the usual excavator assembly ("elbow up": the
    stick pivot lies counter-clockwise of the line from the boom foot to the bucket pin).
    0 marks the singular, stretched/folded pose.

    Parameters
    ----------
    phi1, phi2 : array_like, shape (n,)
        Absolute boom and stick angles, rad.

    Returns
    -------
    numpy.ndarray of int8, shape (n,)
    """
    p1, p2 = np.broadcast_arrays(_arr(phi1), _arr(phi2))
    return np.asarray(np.sign(np.sin(p1 - p2)), dtype=np.int8)


def arm_inverse_position(
    dims: ArmDimensions,
    x_a: ArrayLike,
    y_a: ArrayLike,
    phi3: ArrayLike,
    branch: int = 1,
) -> tuple[FloatArray, FloatArray]:
    """Inverse position: ``(x_A, y_A, phi3) -> (phi1, phi2)`` (spec §3.1, closed form).

    ``x' = x_A - l3 cos phi3``, ``y' = y_A - l3 sin phi3``, ``D = hypot(x', y')``,
    ``phi1 = atan2(y', x') + branch * arccos((l1^2 + D^2 - l2^2) / (2 l1 D))``,
    ``phi2 = atan2(y' - l1 sin phi1, x' - l1 cos phi1)``.

    Parameters
    ----------
    dims : ArmDimensions
        Arm dimensions.
    x_a, y_a : array_like, shape (n,)
        Tooth-tip coordinates, m.
    phi3 : array_like, shape (n,)
        Absolute bucket angle, rad.
    branch : int
        +1 (default, "elbow up", the excavator assembly; see `arm_branch`) or -1.

    Returns
    -------
    phi1, phi2 : numpy.ndarray, shape (n,)
        Absolute boom and stick angles in ``(-pi, pi]``, rad.

    Raises
    ------
    ArmUnreachableError
        If the bucket pin is farther than ``l1 + l2`` or nearer than ``|l1 - l2|`` from the
        boom foot for any sample (``sample_indices`` lists them).
    """
    sgn = _sign(branch, "branch")
    x, y, p3 = np.broadcast_arrays(_arr(x_a), _arr(y_a), _arr(phi3))
    xw = x - dims.l3 * np.cos(p3)
    yw = y - dims.l3 * np.sin(p3)
    dist = np.hypot(xw, yw)
    with np.errstate(divide="ignore", invalid="ignore"):
        cos_beta = (dims.l1**2 + dist**2 - dims.l2**2) / (2.0 * dims.l1 * dist)
    bad = ~(np.abs(cos_beta) <= 1.0)
    if np.any(bad):
        idx = np.flatnonzero(bad)
        raise ArmUnreachableError(
            f"bucket pin out of reach (|l1 - l2| <= D <= l1 + l2 = {dims.l1 + dims.l2:g} m "
            f"violated) at sample(s) {idx.tolist()}, D = {dist[idx].tolist()} m",
            idx,
        )
    phi1 = np.arctan2(yw, xw) + sgn * np.arccos(cos_beta)
    phi1 = np.arctan2(np.sin(phi1), np.cos(phi1))
    phi2 = np.arctan2(yw - dims.l1 * np.sin(phi1), xw - dims.l1 * np.cos(phi1))
    return phi1, phi2


def arm_rates_from_tool(
    dims: ArmDimensions,
    phi1: ArrayLike,
    phi2: ArrayLike,
    phi3: ArrayLike,
    omega3: ArrayLike,
    v_xa: ArrayLike,
    v_ya: ArrayLike,
) -> tuple[FloatArray, FloatArray]:
    """Paper's velocity example: given ``omega3, v_xA, v_yA`` find ``omega1, omega2``.

    Derivation (spec §3.2): project eq. (3) on the normal of link 2 (multiply the complex form
    ``v_A = sum i l_k omega_k e^{i phi_k}`` by ``e^{-i phi2}`` and take the real part)::

        omega1 = [v_xA cos phi2 + v_yA sin phi2 + l3 omega3 sin(phi3 - phi2)]
                 / (l1 sin(phi2 - phi1))
        omega2 = [v_xA cos phi1 + v_yA sin phi1 + l3 omega3 sin(phi3 - phi1)]
                 / (l2 sin(phi1 - phi2))

    This replaces the paper's route through (4), which divides by ``sin phi2`` (artificial
    singularity); the only singularity left is ``sin(phi2 - phi1) = 0``.

    Parameters
    ----------
    dims : ArmDimensions
        Arm dimensions.
    phi1, phi2, phi3 : array_like, shape (n,)
        Absolute link angles, rad.
    omega3 : array_like, shape (n,)
        Absolute bucket angular velocity, rad/s.
    v_xa, v_ya : array_like, shape (n,)
        Velocity of A, m/s.

    Returns
    -------
    omega1, omega2 : numpy.ndarray, shape (n,)
        Absolute boom and stick angular velocities, rad/s.
    """
    p1, p2, p3, w3, vx, vy = np.broadcast_arrays(*map(_arr, (phi1, phi2, phi3, omega3, v_xa, v_ya)))
    w1 = (vx * np.cos(p2) + vy * np.sin(p2) + dims.l3 * w3 * np.sin(p3 - p2)) / (
        dims.l1 * np.sin(p2 - p1)
    )
    w2 = (vx * np.cos(p1) + vy * np.sin(p1) + dims.l3 * w3 * np.sin(p3 - p1)) / (
        dims.l2 * np.sin(p1 - p2)
    )
    return w1, w2


def arm_accelerations_from_tool(
    dims: ArmDimensions,
    phi1: ArrayLike,
    phi2: ArrayLike,
    phi3: ArrayLike,
    omega1: ArrayLike,
    omega2: ArrayLike,
    omega3: ArrayLike,
    eps3: ArrayLike,
    a_xa: ArrayLike,
    a_ya: ArrayLike,
) -> tuple[FloatArray, FloatArray]:
    """Paper's acceleration example: given ``eps3, a_xA, a_yA`` find ``eps1, eps2``.

    Derivation (spec §3.3): eq. (5) is ``a_A = sum l_k (i eps_k - omega_k^2) e^{i phi_k}``;
    with ``A_x = a_xA + sum l_k omega_k^2 cos phi_k + l3 eps3 sin phi3`` and
    ``A_y = a_yA + sum l_k omega_k^2 sin phi_k - l3 eps3 cos phi3``::

        eps1 = (A_x cos phi2 + A_y sin phi2) / (l1 sin(phi2 - phi1))
        eps2 = (A_x cos phi1 + A_y sin phi1) / (l2 sin(phi1 - phi2))

    Parameters
    ----------
    dims : ArmDimensions
        Arm dimensions.
    phi1, phi2, phi3 : array_like, shape (n,)
        Absolute link angles, rad.
    omega1, omega2, omega3 : array_like, shape (n,)
        Absolute angular velocities, rad/s (omega1, omega2 e.g. from
        `arm_rates_from_tool`).
    eps3 : array_like, shape (n,)
        Absolute bucket angular acceleration, rad/s^2.
    a_xa, a_ya : array_like, shape (n,)
        Acceleration of A, m/s^2.

    Returns
    -------
    eps1, eps2 : numpy.ndarray, shape (n,)
        Absolute boom and stick angular accelerations, rad/s^2.
    """
    p1, p2, p3, w1, w2, w3, e3, ax, ay = np.broadcast_arrays(
        *map(_arr, (phi1, phi2, phi3, omega1, omega2, omega3, eps3, a_xa, a_ya))
    )
    l1, l2, l3 = dims.l1, dims.l2, dims.l3
    cx = ax + l1 * w1**2 * np.cos(p1) + l2 * w2**2 * np.cos(p2) + l3 * w3**2 * np.cos(p3)
    cx = cx + l3 * e3 * np.sin(p3)
    cy = ay + l1 * w1**2 * np.sin(p1) + l2 * w2**2 * np.sin(p2) + l3 * w3**2 * np.sin(p3)
    cy = cy - l3 * e3 * np.cos(p3)
    e1 = (cx * np.cos(p2) + cy * np.sin(p2)) / (l1 * np.sin(p2 - p1))
    e2 = (cx * np.cos(p1) + cy * np.sin(p1)) / (l2 * np.sin(p1 - p2))
    return e1, e2


def printed_eq4_omega2(
    dims: ArmDimensions,
    phi1: ArrayLike,
    phi2: ArrayLike,
    phi3: ArrayLike,
    omega1: ArrayLike,
    omega3: ArrayLike,
    v_xa: ArrayLike,
) -> FloatArray:
    """The paper's route, eq. (4): omega2 from the first line of (3), dividing by ``sin phi2``.

    ``omega2 = -(v_xA + l1 omega1 sin phi1 + l3 omega3 sin phi3) / (l2 sin phi2)``.

    Kept for review only: algebraically right, but singular at ``sin phi2 = 0`` (stick
    horizontal), where `arm_rates_from_tool` is regular (spec §5.3).

    Parameters
    ----------
    dims : ArmDimensions
        Arm dimensions.
    phi1, phi2, phi3 : array_like, shape (n,)
        Absolute link angles, rad.
    omega1, omega3 : array_like, shape (n,)
        Boom and bucket angular velocities, rad/s.
    v_xa : array_like, shape (n,)
        x-velocity of A, m/s.

    Returns
    -------
    numpy.ndarray, shape (n,)
        omega2, rad/s (inf/nan at the artificial singularity).
    """
    p1, p2, p3, w1, w3, vx = np.broadcast_arrays(
        *map(_arr, (phi1, phi2, phi3, omega1, omega3, v_xa))
    )
    num = vx + dims.l1 * w1 * np.sin(p1) + dims.l3 * w3 * np.sin(p3)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.asarray(-num / (dims.l2 * np.sin(p2)), dtype=np.float64)


# --------------------------------------------------------------------------------------
# Link + cylinder sub-mechanism (eqs. 7-12)
# --------------------------------------------------------------------------------------


class CylinderKinematics(NamedTuple):
    """Cylinder state of one link + cylinder sub-mechanism; every field has shape (n,).

    Attributes
    ----------
    z : numpy.ndarray
        Pin-to-pin cylinder length, m (signed, see ``root``).
    phi_z : numpy.ndarray
        Cylinder polar angle, rad.
    v_r : numpy.ndarray
        Rod speed relative to the barrel, ``dz/dt``, m/s.
    omega_z : numpy.ndarray
        Cylinder angular velocity, rad/s.
    a_r : numpy.ndarray
        Relative rod acceleration ``d2z/dt2``, m/s^2.
    eps_z : numpy.ndarray
        Cylinder angular acceleration, rad/s^2.
    a_k : numpy.ndarray
        Coriolis acceleration magnitude ``2 omega_z v_r`` of the rod end, m/s^2.
    """

    z: FloatArray
    phi_z: FloatArray
    v_r: FloatArray
    omega_z: FloatArray
    a_r: FloatArray
    eps_z: FloatArray
    a_k: FloatArray


def _cd(mount: CylinderMount, psi: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Auxiliaries c, d of eq. (10) (d corrected: no ``+a``)."""
    c = mount.l * np.sin(psi) + mount.a - mount.l_prime * np.sin(psi - mount.alpha)
    d = mount.l * np.cos(psi) - mount.l_prime * np.cos(psi - mount.alpha) - mount.b
    return c, d


def cylinder_position(
    mount: CylinderMount, psi: ArrayLike, root: int = 1
) -> tuple[FloatArray, FloatArray]:
    """Cylinder length and angle from the link angle, eqs. (8)-(10) corrected (spec §3.4).

    ``c = l sin psi + a - l' sin(psi - alpha)``, ``d = l cos psi - l' cos(psi - alpha) - b``
    (the print's ``+ a`` in ``d`` removed), ``z = root * sqrt(c^2 + d^2)``,
    ``phi_z = atan2(root * c, root * d)`` (instead of the print's ``cos phi_z = +sqrt(...)``).

    Parameters
    ----------
    mount : CylinderMount
        Sub-mechanism parameters.
    psi : array_like, shape (n,)
        Driven-link angle in the parent frame (paper's ``phi1``), rad.
    root : int
        +1 (physical, default) or -1: the paper's ``z = ± sqrt(c^2 + d^2)``. -1 describes the
        same cylinder vector as length ``-z`` at angle ``phi_z + pi``.

    Returns
    -------
    z, phi_z : numpy.ndarray, shape (n,)
        Cylinder length (m) and polar angle in the parent frame (rad).
    """
    sgn = _sign(root, "root")
    c, d = _cd(mount, _arr(psi))
    return sgn * np.hypot(c, d), np.arctan2(sgn * c, sgn * d)


def cylinder_velocity(
    mount: CylinderMount, psi: ArrayLike, omega: ArrayLike, root: int = 1
) -> tuple[FloatArray, FloatArray]:
    """Rod speed and cylinder angular velocity from the link rate, eq. (11) (spec §3.5).

    Solving the differentiated projections (11) by rotating to the cylinder axis::

        v_r     = omega [l' sin(psi - alpha - phi_z) - l sin(psi - phi_z)]
        omega_z = (omega / z) [l cos(psi - phi_z) - l' cos(psi - alpha - phi_z)]

    Parameters
    ----------
    mount : CylinderMount
        Sub-mechanism parameters.
    psi : array_like, shape (n,)
        Link angle in the parent frame, rad.
    omega : array_like, shape (n,)
        Link angular velocity relative to the parent, rad/s.
    root : int
        Sign of the ``z`` root, see `cylinder_position`.

    Returns
    -------
    v_r, omega_z : numpy.ndarray, shape (n,)
        ``dz/dt`` (m/s) and the cylinder angular velocity relative to the parent (rad/s).
    """
    p, w = np.broadcast_arrays(_arr(psi), _arr(omega))
    z, pz = cylinder_position(mount, p, root)
    u = p - pz
    u1 = p - mount.alpha - pz
    v_r = w * (mount.l_prime * np.sin(u1) - mount.l * np.sin(u))
    w_z = w / z * (mount.l * np.cos(u) - mount.l_prime * np.cos(u1))
    return v_r, w_z


def cylinder_acceleration(
    mount: CylinderMount, psi: ArrayLike, omega: ArrayLike, eps: ArrayLike, root: int = 1
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Relative rod acceleration and cylinder angular acceleration, eq. (12) (spec §3.6).

    From the differentiated system (12), projected on the cylinder axis and its normal::

        a_r   = z omega_z^2 + l' [omega^2 cos(psi-alpha-phi_z) + eps sin(psi-alpha-phi_z)]
                            - l  [omega^2 cos(psi-phi_z)       + eps sin(psi-phi_z)]
        eps_z = [l eps cos(psi-phi_z) - l' eps cos(psi-alpha-phi_z)
                 - l omega^2 sin(psi-phi_z) + l' omega^2 sin(psi-alpha-phi_z)
                 - 2 omega_z v_r] / z
        a_k   = 2 omega_z v_r   (Coriolis)

    Parameters
    ----------
    mount : CylinderMount
        Sub-mechanism parameters.
    psi : array_like, shape (n,)
        Link angle in the parent frame, rad.
    omega : array_like, shape (n,)
        Link angular velocity relative to the parent, rad/s.
    eps : array_like, shape (n,)
        Link angular acceleration relative to the parent, rad/s^2.
    root : int
        Sign of the ``z`` root, see `cylinder_position`.

    Returns
    -------
    a_r, eps_z, a_k : numpy.ndarray, shape (n,)
        ``d2z/dt2`` (m/s^2), cylinder angular acceleration relative to the parent (rad/s^2)
        and Coriolis acceleration ``2 omega_z v_r`` (m/s^2).
    """
    p, w, e = np.broadcast_arrays(_arr(psi), _arr(omega), _arr(eps))
    z, pz = cylinder_position(mount, p, root)
    v_r, w_z = cylinder_velocity(mount, p, w, root)
    u = p - pz
    u1 = p - mount.alpha - pz
    lp, l = mount.l_prime, mount.l
    a_r = (
        z * w_z**2
        + lp * (w**2 * np.cos(u1) + e * np.sin(u1))
        - l * (w**2 * np.cos(u) + e * np.sin(u))
    )
    a_k = 2.0 * w_z * v_r
    e_z = (
        l * e * np.cos(u)
        - lp * e * np.cos(u1)
        - l * w**2 * np.sin(u)
        + lp * w**2 * np.sin(u1)
        - a_k
    ) / z
    return a_r, e_z, a_k


def cylinder_kinematics(
    mount: CylinderMount, psi: ArrayLike, omega: ArrayLike, eps: ArrayLike, root: int = 1
) -> CylinderKinematics:
    """All cylinder quantities of eqs. (8)-(12) at once (angles in the parent frame).

    Parameters
    ----------
    mount : CylinderMount
        Sub-mechanism parameters.
    psi, omega, eps : array_like, shape (n,)
        Link angle, angular velocity and acceleration relative to the parent.
    root : int
        Sign of the ``z`` root, see `cylinder_position`.

    Returns
    -------
    CylinderKinematics
        Fields of shape (n,).
    """
    p, w, e = np.broadcast_arrays(_arr(psi), _arr(omega), _arr(eps))
    z, pz = cylinder_position(mount, p, root)
    v_r, w_z = cylinder_velocity(mount, p, w, root)
    a_r, e_z, a_k = cylinder_acceleration(mount, p, w, e, root)
    return CylinderKinematics(z, pz, v_r, w_z, a_r, e_z, a_k)


def cylinder_angle_from_length(
    mount: CylinderMount, z: ArrayLike, branch: int | None = None
) -> FloatArray:
    """Inverse relation: cylinder length -> link angle (spec §3.4, "Inverse").

    ``rho = sqrt(l^2 + l'^2 - 2 l l' cos alpha)`` (pivot to rod end),
    ``kappa = atan2(l' sin alpha, l - l' cos alpha)`` (its angle in the link frame),
    ``P = (b, -a)``; ``psi = arg P - kappa + branch * arccos((rho^2 + |P|^2 - z^2)/(2 rho |P|))``.

    Parameters
    ----------
    mount : CylinderMount
        Sub-mechanism parameters.
    z : array_like, shape (n,)
        Pin-to-pin cylinder length, m (> 0).
    branch : int, optional
        +1 or -1; default ``mount.branch`` (the working assembly).

    Returns
    -------
    numpy.ndarray, shape (n,)
        Link angle in the parent frame, wrapped to ``(-pi, pi]``, rad. NaN where the length
        cannot be assembled.
    """
    sgn = _sign(mount.branch if branch is None else branch, "branch")
    zz = _arr(z)
    rho = np.hypot(
        mount.l - mount.l_prime * np.cos(mount.alpha), mount.l_prime * np.sin(mount.alpha)
    )
    kappa = np.arctan2(
        mount.l_prime * np.sin(mount.alpha), mount.l - mount.l_prime * np.cos(mount.alpha)
    )
    p_len = np.hypot(mount.a, mount.b)
    p_arg = np.arctan2(-mount.a, mount.b)
    cos_g = (rho**2 + p_len**2 - zz**2) / (2.0 * rho * p_len)
    with np.errstate(invalid="ignore"):
        psi = p_arg - kappa + sgn * np.arccos(cos_g)
    return np.asarray(np.arctan2(np.sin(psi), np.cos(psi)), dtype=np.float64)


def printed_cylinder_d(mount: CylinderMount, psi: ArrayLike) -> FloatArray:
    """``d`` as printed (spec §5.1): ``[l cos psi + a - l' cos(psi - alpha)] - b`` (wrong).

    Parameters
    ----------
    mount : CylinderMount
        Sub-mechanism parameters.
    psi : array_like, shape (n,)
        Link angle in the parent frame, rad.

    Returns
    -------
    numpy.ndarray, shape (n,)
        The printed ``d``, m.
    """
    p = _arr(psi)
    return np.asarray(
        mount.l * np.cos(p) + mount.a - mount.l_prime * np.cos(p - mount.alpha) - mount.b,
        dtype=np.float64,
    )


def printed_cylinder_phi_z(mount: CylinderMount, psi: ArrayLike) -> FloatArray:
    """Cylinder angle by the printed route (9)-(10): ``sin phi_z = c/z``, ``cos phi_z = +sqrt``.

    Uses the corrected ``c`` and ``z`` so that only the quadrant loss is shown; the result is
    confined to ``[-pi/2, pi/2]`` (spec §5.2).

    Parameters
    ----------
    mount : CylinderMount
        Sub-mechanism parameters.
    psi : array_like, shape (n,)
        Link angle in the parent frame, rad.

    Returns
    -------
    numpy.ndarray, shape (n,)
        The printed-route cylinder angle, rad.
    """
    c, d = _cd(mount, _arr(psi))
    s = c / np.hypot(c, d)
    return np.asarray(np.arctan2(s, np.sqrt(1.0 - s**2)), dtype=np.float64)


def arm_cylinder_kinematics(
    dims: ArmDimensions,
    phi1: ArrayLike,
    phi2: ArrayLike,
    phi3: ArrayLike,
    omega1: ArrayLike,
    omega2: ArrayLike,
    omega3: ArrayLike,
    eps1: ArrayLike,
    eps2: ArrayLike,
    eps3: ArrayLike,
) -> dict[str, CylinderKinematics]:
    """Boom, stick and bucket cylinders from the absolute arm motion ("analogously", spec §3.6).

    Each cylinder uses eqs. (8)-(12) in its parent frame with the relative link motion
    (``psi = phi_k - phi_{k-1}``, ``omega = omega_k - omega_{k-1}``, ...; ``phi_0 = 0``). The
    returned ``phi_z, omega_z, eps_z`` are converted to **absolute** values by adding the
    parent's angle, rate and acceleration; ``z, v_r, a_r`` are frame-independent. ``a_k`` is
    ``2 omega_z,abs v_r``, the Coriolis acceleration of the rod end in the base frame.

    Parameters
    ----------
    dims : ArmDimensions
        Arm dimensions with the three cylinder mounts.
    phi1, phi2, phi3 : array_like, shape (n,)
        Absolute link angles, rad.
    omega1, omega2, omega3 : array_like, shape (n,)
        Absolute angular velocities, rad/s.
    eps1, eps2, eps3 : array_like, shape (n,)
        Absolute angular accelerations, rad/s^2.

    Returns
    -------
    dict of str to CylinderKinematics
        Keys ``"boom"``, ``"stick"``, ``"bucket"``; every field has shape (n,).
    """
    arrs = np.broadcast_arrays(
        *map(_arr, (phi1, phi2, phi3, omega1, omega2, omega3, eps1, eps2, eps3))
    )
    zero = np.zeros_like(arrs[0])
    ph = (zero, arrs[0], arrs[1], arrs[2])
    om = (zero, arrs[3], arrs[4], arrs[5])
    ep = (zero, arrs[6], arrs[7], arrs[8])
    out: dict[str, CylinderKinematics] = {}
    for k, (name, mount) in enumerate(
        (("boom", dims.boom), ("stick", dims.stick), ("bucket", dims.bucket)), start=1
    ):
        rel = cylinder_kinematics(mount, ph[k] - ph[k - 1], om[k] - om[k - 1], ep[k] - ep[k - 1])
        pz = rel.phi_z + ph[k - 1]
        w_z = rel.omega_z + om[k - 1]
        out[name] = CylinderKinematics(
            z=rel.z,
            phi_z=np.arctan2(np.sin(pz), np.cos(pz)),
            v_r=rel.v_r,
            omega_z=w_z,
            a_r=rel.a_r,
            eps_z=rel.eps_z + ep[k - 1],
            a_k=2.0 * w_z * rel.v_r,
        )
    return out
