"""Reference tests: vector model of a 3-DOF excavator arm (seed 001).

Source: seed ``001_57da5d3302d61297.txt`` (title/authors lost) and its specification
``seeds/vector-model-excavator-arm.md`` (cited as "spec §x"). The paper has no numbers; these
tests check the closed forms against high-order finite differences of the positions, loop
closure, forward/inverse identity, and each departure from the print.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest
from numpy.testing import assert_allclose

from excavkin.papers.arm_vector import reference as av

DIMS = av.EXCAVATOR_20T
H = 2e-3  # finite-difference step, s
# 8th-order central differences (Fornberg) on the stencil k = -4..4
D1 = np.array([1 / 280, -4 / 105, 1 / 5, -4 / 5, 0.0, 4 / 5, -1 / 5, 4 / 105, -1 / 280])
D2 = np.array([-1 / 560, 8 / 315, -1 / 5, 8 / 5, -205 / 72, 8 / 5, -1 / 5, 8 / 315, -1 / 560])
K = np.arange(-4, 5, dtype=float)

#: spec §4 synthetic cylinder (a = 0.6, b = 0.9, l1 = 5.7, l1' = 4.2 m, alpha = 8 deg)
SPEC_MOUNT = av.CylinderMount(
    a=0.6, b=0.9, l=5.7, l_prime=4.2, alpha=float(np.radians(8.0)), z_min=1.0, z_max=5.0
)


def _wrap(a: np.ndarray) -> np.ndarray:
    return np.arctan2(np.sin(a), np.cos(a))


def _fd(f: Callable[[float], np.ndarray], angle: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """First and second time derivatives at t = 0 by 8th-order central differences."""
    vals = np.stack([f(k * H) for k in K])  # (9, n)
    if angle:
        vals = _wrap(vals - vals[4])
    return np.tensordot(D1, vals, axes=1) / H, np.tensordot(D2, vals, axes=1) / H**2


def _close(actual: np.ndarray, desired: np.ndarray, rtol: float = 1e-8) -> None:
    """Relative comparison; components near zero are judged against the array's scale."""
    assert_allclose(actual, desired, rtol=rtol, atol=rtol * float(np.max(np.abs(desired))))


def _working_poses(n_per_axis: int = 7) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Absolute angles over the whole working range (all cylinder strokes), shape (n,)."""
    grids = []
    for mount in (DIMS.boom, DIMS.stick, DIMS.bucket):
        z = np.linspace(mount.z_min, mount.z_max, n_per_axis)
        grids.append(av.cylinder_angle_from_length(mount, z))
    p1, r2, r3 = (g.ravel() for g in np.meshgrid(*grids, indexing="ij"))
    return p1, p1 + r2, p1 + r2 + r3


def _rates(n: int, scale: float, seed: int) -> np.ndarray:
    return np.random.default_rng(seed).uniform(-scale, scale, size=(3, n))


# --------------------------------------------------------------------------------------
# positions, loop closure, inverse problem (spec §3.1)
# --------------------------------------------------------------------------------------


def test_working_range_is_assemblable_and_cylinders_hit_their_limits() -> None:
    """Chosen dimensions: every stroke limit maps to a link angle and back (spec §3.4 inverse)."""
    for mount in (DIMS.boom, DIMS.stick, DIMS.bucket):
        z = np.linspace(mount.z_min, mount.z_max, 41)
        psi = av.cylinder_angle_from_length(mount, z)
        assert np.all(np.isfinite(psi))
        assert np.all(np.diff(psi) != 0)  # monotone: no toggle inside the stroke
        z_back, _ = av.cylinder_position(mount, psi)
        assert_allclose(z_back, z, rtol=0, atol=1e-12)


def test_forward_inverse_identity_both_branches() -> None:
    """IK(FK(q), branch(q)) = q and FK(IK(x, b)) = x for b = +1 and -1 (spec §3.1), 1e-10."""
    p1, p2, p3 = _working_poses()
    x, y = av.arm_position(DIMS, p1, p2, p3)
    br = av.arm_branch(p1, p2)
    assert np.all(br == 1)  # the excavator assembly is the "elbow up" branch +1
    q1, q2 = av.arm_inverse_position(DIMS, x, y, p3, branch=1)
    assert_allclose(_wrap(q1 - p1), 0.0, atol=1e-10)
    assert_allclose(_wrap(q2 - p2), 0.0, atol=1e-10)
    for branch in (1, -1):
        q1, q2 = av.arm_inverse_position(DIMS, x, y, p3, branch=branch)
        assert np.all(av.arm_branch(q1, q2) == branch)
        xb, yb = av.arm_position(DIMS, q1, q2, p3)
        # loop closure of eq. (2): both assemblies reach the same tooth tip
        assert_allclose(xb, x, rtol=0, atol=1e-12)
        assert_allclose(yb, y, rtol=0, atol=1e-12)


def test_inverse_unreachable_raises_with_indices() -> None:
    """Unreachable tool pose: clear error naming the sample (spec §6 'inverse position')."""
    x = np.array([5.0, 20.0, 3.0])
    with pytest.raises(av.ArmUnreachableError, match=r"sample\(s\) \[1\]") as info:
        av.arm_inverse_position(DIMS, x, np.zeros(3), np.full(3, -np.pi / 2))
    assert info.value.sample_indices.tolist() == [1]
    with pytest.raises(ValueError, match="branch"):
        av.arm_inverse_position(DIMS, 5.0, 0.0, 0.0, branch=0)


# --------------------------------------------------------------------------------------
# velocities and accelerations (spec §3.2-3.3)
# --------------------------------------------------------------------------------------


def test_forward_velocity_acceleration_vs_fd() -> None:
    """Eqs. (3) and (5) against 8th-order differences of eq. (2), whole working range."""
    p = _working_poses()
    w = _rates(p[0].size, 0.5, 1)
    e = _rates(p[0].size, 1.0, 2)

    def pos(i: int) -> Callable[[float], np.ndarray]:
        def f(t: float) -> np.ndarray:
            q = [p[k] + w[k] * t + 0.5 * e[k] * t**2 for k in range(3)]
            return av.arm_position(DIMS, *q)[i]

        return f

    vx, vy = av.arm_velocity(DIMS, *p, *w)
    ax, ay = av.arm_acceleration(DIMS, *p, *w, *e)
    for i, (v, a) in enumerate(((vx, ax), (vy, ay))):
        d1, d2 = _fd(pos(i))
        _close(v, d1)
        _close(a, d2)


def test_tool_space_rates_vs_fd_of_inverse() -> None:
    """Paper's example: (omega3, v_A) -> (omega1, omega2) and (eps3, a_A) -> (eps1, eps2).

    The tool moves on a quadratic path; phi1(t), phi2(t) come from the inverse position, and
    their differences must equal the closed forms (spec §3.2-3.3), relative 1e-8.
    """
    p1, p2, p3 = _working_poses()
    x0, y0 = av.arm_position(DIMS, p1, p2, p3)
    rng = np.random.default_rng(3)
    vx, vy, w3 = rng.uniform(-0.5, 0.5, size=(3, p1.size))
    ax, ay, e3 = rng.uniform(-1.0, 1.0, size=(3, p1.size))

    def joint(i: int) -> Callable[[float], np.ndarray]:
        def f(t: float) -> np.ndarray:
            x = x0 + vx * t + 0.5 * ax * t**2
            y = y0 + vy * t + 0.5 * ay * t**2
            q3 = p3 + w3 * t + 0.5 * e3 * t**2
            return av.arm_inverse_position(DIMS, x, y, q3, branch=1)[i]

        return f

    w1, w2 = av.arm_rates_from_tool(DIMS, p1, p2, p3, w3, vx, vy)
    e1, e2 = av.arm_accelerations_from_tool(DIMS, p1, p2, p3, w1, w2, w3, e3, ax, ay)
    for i, (w, e) in enumerate(((w1, e1), (w2, e2))):
        d1, d2 = _fd(joint(i), angle=True)
        _close(w, d1)
        _close(e, d2)


def test_paper_route_eq4_artificial_singularity() -> None:
    """Spec §5.3: the paper's (4) divides by sin(phi2); at a horizontal stick it fails while
    the closed form (dividing by sin(phi2 - phi1)) still matches finite differences."""
    p1, p2, p3 = np.array([0.6]), np.array([0.0]), np.array([-1.2])
    w = np.array([[0.2], [-0.3], [0.4]])
    vx, vy = av.arm_velocity(DIMS, p1, p2, p3, *w)
    w1, w2 = av.arm_rates_from_tool(DIMS, p1, p2, p3, w[2], vx, vy)
    assert_allclose([w1[0], w2[0]], [0.2, -0.3], rtol=1e-12)
    printed = av.printed_eq4_omega2(DIMS, p1, p2, p3, w1, w[2], vx)
    assert not np.all(np.isfinite(printed) & np.isclose(printed, -0.3, rtol=1e-6))
    # near (not at) the singularity the printed route loses digits the closed form keeps
    p2n = np.array([1e-13])
    vx, vy = av.arm_velocity(DIMS, p1, p2n, p3, *w)
    printed = av.printed_eq4_omega2(DIMS, p1, p2n, p3, w[0], w[2], vx)
    w1, w2 = av.arm_rates_from_tool(DIMS, p1, p2n, p3, w[2], vx, vy)
    assert_allclose(w2, -0.3, rtol=1e-12)
    assert abs(printed[0] + 0.3) > 1e-6


# --------------------------------------------------------------------------------------
# link + cylinder (spec §3.4-3.6)
# --------------------------------------------------------------------------------------

MOUNTS = {"boom": DIMS.boom, "stick": DIMS.stick, "bucket": DIMS.bucket, "spec": SPEC_MOUNT}


def _mount_psi(mount: av.CylinderMount) -> np.ndarray:
    if mount is SPEC_MOUNT:
        return np.radians(np.linspace(-40.0, 80.0, 61))
    return av.cylinder_angle_from_length(mount, np.linspace(mount.z_min, mount.z_max, 61))


@pytest.mark.parametrize("root", [1, -1])
@pytest.mark.parametrize("name", list(MOUNTS))
def test_cylinder_loop_closure(name: str, root: int) -> None:
    """Eq. (8): (b, -a) + z e^{i phi_z} + l' e^{i(psi - alpha)} = l e^{i psi}, 1e-12 m."""
    m = MOUNTS[name]
    psi = _mount_psi(m)
    z, pz = av.cylinder_position(m, psi, root=root)
    assert np.all(np.sign(z) == root)
    rx = m.b + z * np.cos(pz) + m.l_prime * np.cos(psi - m.alpha) - m.l * np.cos(psi)
    ry = -m.a + z * np.sin(pz) + m.l_prime * np.sin(psi - m.alpha) - m.l * np.sin(psi)
    assert_allclose(rx, 0.0, atol=1e-12)
    assert_allclose(ry, 0.0, atol=1e-12)


@pytest.mark.parametrize("root", [1, -1])
@pytest.mark.parametrize("name", list(MOUNTS))
def test_cylinder_rates_vs_fd(name: str, root: int) -> None:
    """Eqs. (11)-(12): v_r, omega_z, a_r, eps_z vs 8th-order differences of z, phi_z, with
    both roots of z = ±sqrt(c^2 + d^2) (spec §3.5-3.6, §5.4), relative 1e-8."""
    m = MOUNTS[name]
    psi = _mount_psi(m)
    rng = np.random.default_rng(4)
    w = rng.uniform(-0.6, 0.6, psi.size)
    e = rng.uniform(-1.0, 1.0, psi.size)
    ck = av.cylinder_kinematics(m, psi, w, e, root=root)

    def q(t: float) -> np.ndarray:
        return psi + w * t + 0.5 * e * t**2

    dz1, dz2 = _fd(lambda t: av.cylinder_position(m, q(t), root=root)[0])
    dp1, dp2 = _fd(lambda t: av.cylinder_position(m, q(t), root=root)[1], angle=True)
    _close(ck.v_r, dz1)
    _close(ck.a_r, dz2)
    _close(ck.omega_z, dp1)
    _close(ck.eps_z, dp2)
    assert_allclose(ck.a_k, 2.0 * ck.omega_z * ck.v_r, rtol=1e-15)


def test_arm_cylinder_kinematics_absolute_vs_fd() -> None:
    """Boom, stick and bucket cylinders 'analogously' (spec §3.6): absolute phi_z, omega_z,
    eps_z and z, v_r, a_r against differences along a joint trajectory, relative 1e-8."""
    p = _working_poses(5)
    w = _rates(p[0].size, 0.5, 5)
    e = _rates(p[0].size, 1.0, 6)
    res = av.arm_cylinder_kinematics(DIMS, *p, *w, *e)

    def at(t: float) -> dict[str, av.CylinderKinematics]:
        q = [p[k] + w[k] * t + 0.5 * e[k] * t**2 for k in range(3)]
        return av.arm_cylinder_kinematics(DIMS, *q, *w, *e)

    for name in ("boom", "stick", "bucket"):
        ck = res[name]
        dz1, dz2 = _fd(lambda t, n=name: at(t)[n].z)
        dp1, dp2 = _fd(lambda t, n=name: at(t)[n].phi_z, angle=True)
        _close(ck.v_r, dz1)
        _close(ck.a_r, dz2)
        _close(ck.omega_z, dp1)
        _close(ck.eps_z, dp2)
        assert np.all((ck.z >= DIMS.boom.z_min - 1e-9) | (name != "boom"))


def test_misprint_d_spurious_a() -> None:
    """Spec §5.1: printed d = [l cos psi + a - l' cos(psi - alpha)] - b is wrong.

    Regression (spec §4/§5.1 synthetic mount): at psi = 48.5 deg the cylinder angle is
    98.41 deg; with the printed d it comes out 82.47 deg. Corrected = direct pin geometry.
    """
    m = SPEC_MOUNT
    psi = np.radians([48.5])
    cx = m.l * np.cos(psi) - m.l_prime * np.cos(psi - m.alpha)
    cy = m.l * np.sin(psi) - m.l_prime * np.sin(psi - m.alpha)
    direct = np.arctan2(cy + m.a, cx - m.b)  # base pivot at (b, -a)
    z, pz = av.cylinder_position(m, psi)
    assert_allclose(pz, direct, atol=1e-14)
    assert_allclose(z, np.hypot(cx - m.b, cy + m.a), atol=1e-14)
    assert_allclose(np.degrees(pz), 98.41470, atol=1e-5)
    c = m.l * np.sin(psi) + m.a - m.l_prime * np.sin(psi - m.alpha)
    printed = np.arctan2(c, av.printed_cylinder_d(m, psi))
    assert_allclose(np.degrees(printed), 82.46547, atol=1e-5)
    assert np.all(np.abs(printed - direct) > np.radians(10))


def test_misprint_eq9_cos_phiz_quadrant() -> None:
    """Spec §5.2 ('(9) of 001'): cos phi_z = +sqrt(1 - sin^2 phi_z) fails once the cylinder
    leans past vertical; atan2(c, d) agrees with the loop closure and finite differences."""
    m = SPEC_MOUNT
    psi = np.radians([30.0, 60.0])  # phi_z = 85.7 deg (fine) and 105.9 deg (past vertical)
    _, pz = av.cylinder_position(m, psi)
    printed = av.printed_cylinder_phi_z(m, psi)
    assert_allclose(printed[0], pz[0], atol=1e-14)
    assert_allclose(np.degrees(pz[1]), 105.93536, atol=1e-5)
    assert_allclose(np.degrees(printed[1]), 180.0 - 105.93536, atol=1e-5)
    # with the printed angle the x-projection of eq. (8) does not close
    z, _ = av.cylinder_position(m, psi)
    rx = m.b + z * np.cos(printed) + m.l_prime * np.cos(psi - m.alpha) - m.l * np.cos(psi)
    assert abs(rx[1]) > 0.5
    assert abs(rx[0]) < 1e-12


def _eq12_system(
    m: av.CylinderMount, psi: np.ndarray, w: np.ndarray, e: np.ndarray, printed: bool
) -> tuple[np.ndarray, np.ndarray]:
    """Solve the time derivative of (11) for (z'', eps_z), as printed before (12) or complete.

    Printed (seed 001, the system after "Продифференцируем по времени систему уравнений (11)"):
    z'' cos - 2 z' w_z sin - z eps_z sin - l' w^2 cos(psi - a) - l' eps sin(psi - a)
    = -l w^2 cos psi - l eps sin psi, and the y line likewise; the complete derivative of
    z cos(phi_z) also has -z w_z^2 cos(phi_z) (y line: -z w_z^2 sin(phi_z))."""
    z, pz = av.cylinder_position(m, psi)
    v_r, w_z = av.cylinder_velocity(m, psi, w)
    lp, l, a = m.l_prime, m.l, m.alpha
    cp, sp = np.cos(pz), np.sin(pz)
    rhs_x = (
        2 * v_r * w_z * sp
        + lp * (w**2 * np.cos(psi - a) + e * np.sin(psi - a))
        - l * (w**2 * np.cos(psi) + e * np.sin(psi))
    )
    rhs_y = (
        -2 * v_r * w_z * cp
        + lp * (w**2 * np.sin(psi - a) - e * np.cos(psi - a))
        - l * (w**2 * np.sin(psi) - e * np.cos(psi))
    )
    if not printed:
        rhs_x = rhs_x + z * w_z**2 * cp
        rhs_y = rhs_y + z * w_z**2 * sp
    mat = np.stack([np.stack([cp, -z * sp], -1), np.stack([sp, z * cp], -1)], axis=1)
    sol = np.linalg.solve(mat, np.stack([rhs_x, rhs_y], -1)[..., None])[..., 0]
    return sol[:, 0], sol[:, 1]


@pytest.mark.parametrize("name", list(MOUNTS))
def test_misprint_eq12_missing_z_omega_z_squared(name: str) -> None:
    """Docs correction 6 (issue 12): the time derivative of (11), printed just before (12) (from
    which (12) is obtained; (12) itself is lost), has no z omega_z^2 terms: its x line reads
    "cos sin sin sin cos( ) sin( )" with the subscripts of seven z-quantities and four z's
    (z'', z', z', z), where the complete derivative has a fifth, -z omega_z^2 cos(phi_z).

    Solved as printed, the system gives a_r short by exactly z omega_z^2 (eps_z is unaffected:
    the missing terms lie along the cylinder); the complete system equals the reference and the
    8th-order differences of z (relative 1e-8). Spec mount, psi = 48.5 deg, omega = 1 rad/s,
    eps = 0: a_r = -0.48226 m/s^2, printed -1.43942 (z omega_z^2 = 0.95716, 198 % of a_r)."""
    m = MOUNTS[name]
    psi = _mount_psi(m)
    rng = np.random.default_rng(12)
    w = rng.uniform(-0.6, 0.6, psi.size)
    e = rng.uniform(-1.0, 1.0, psi.size)
    ck = av.cylinder_kinematics(m, psi, w, e)
    a_full, e_full = _eq12_system(m, psi, w, e, printed=False)
    a_pr, e_pr = _eq12_system(m, psi, w, e, printed=True)
    _close(a_full, ck.a_r, 1e-12)
    _close(e_full, ck.eps_z, 1e-12)
    dz1, dz2 = _fd(lambda t: av.cylinder_position(m, psi + w * t + 0.5 * e * t**2)[0])
    _close(a_full, dz2)
    centripetal = ck.z * ck.omega_z**2
    _close(a_full - a_pr, centripetal, 1e-12)
    _close(e_pr, e_full, 1e-12)
    assert np.max(np.abs(a_pr - dz2)) > 0.02 * np.max(np.abs(dz2))
    if m is SPEC_MOUNT:
        one = np.radians([48.5])
        a_r = av.cylinder_kinematics(m, one, np.ones(1), np.zeros(1)).a_r
        a_pr1, _ = _eq12_system(m, one, np.ones(1), np.zeros(1), printed=True)
        assert_allclose([a_r[0], a_pr1[0]], [-0.48226, -1.43942], atol=5e-6)


def test_spec_self_consistency_case() -> None:
    """Spec §4: arm l = (5.7, 2.9, 1.4) m and the synthetic cylinder agree with differences."""
    dims = av.ArmDimensions(
        5.7,
        2.9,
        1.4,
        SPEC_MOUNT,
        av.CylinderMount(0.0, 0.0, 2.9, 2.0, 0.1, 1.0, 2.0),
        av.CylinderMount(0.0, 0.0, 1.4, 1.0, 0.1, 1.0, 2.0),
    )
    p = (np.array([0.5, 0.2]), np.array([-1.0, -1.7]), np.array([-2.2, -2.9]))
    w = (np.array([0.1, -0.2]), np.array([0.3, 0.2]), np.array([-0.4, 0.5]))
    e = (np.array([0.5, -0.3]), np.array([0.2, 0.7]), np.array([-0.1, 0.4]))
    vx, vy = av.arm_velocity(dims, *p, *w)
    ax, ay = av.arm_acceleration(dims, *p, *w, *e)
    w1, w2 = av.arm_rates_from_tool(dims, *p, w[2], vx, vy)
    e1, e2 = av.arm_accelerations_from_tool(dims, *p, w1, w2, w[2], e[2], ax, ay)
    assert_allclose(np.stack([w1, w2, e1, e2]), np.stack([w[0], w[1], e[0], e[1]]), rtol=1e-12)


def test_mount_length_must_match_link() -> None:
    """ArmDimensions rejects a cylinder mount built for another link length."""
    with pytest.raises(ValueError, match="stick cylinder"):
        av.ArmDimensions(5.7, 3.0, 1.5, DIMS.boom, DIMS.stick, DIMS.bucket)
