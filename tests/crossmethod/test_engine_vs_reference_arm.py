"""Excavator arm vector model (seed 001): the engine (examples/arm_vector.toml) against the
paper's own equations (1)-(12), reconstructed and corrected (excavkin.papers.arm_vector.reference;
spec seeds/vector-model-excavator-arm.md)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from excavkin.papers import common
from excavkin.papers.arm_vector import reference as ref
from excavkin.papers.arm_vector import study as papers
from excavkin.papers.arm_vector.cli import command
from tests.conftest import assert_rel, fd_derivatives

DIMS = ref.EXCAVATOR_20T
MOUNTS = {"boom": DIMS.boom, "stick": DIMS.stick, "bucket": DIMS.bucket}
CYL_FIELDS = ("z", "phi_z", "v_r", "omega_z", "a_r", "eps_z", "a_k")


@pytest.fixture(scope="module")
def motion() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Poses over the whole working range (a grid of the three link-angle ranges) + rates."""
    rng = np.random.default_rng(2024)
    grids = [np.linspace(*sorted(m.psi_limits), 7) for m in MOUNTS.values()]
    psi = np.stack([g.ravel() for g in np.meshgrid(*grids, indexing="ij")])
    phi = np.cumsum(psi, axis=0)
    return phi, rng.normal(0, 0.3, phi.shape), rng.normal(0, 0.5, phi.shape)


@pytest.fixture(scope="module")
def forward(motion):  # type: ignore[no-untyped-def]
    phi, om, ep = motion
    return papers.arm_forward(tuple(phi), tuple(om), tuple(ep))


def test_model_has_the_reference_dimensions() -> None:
    mech = common.load_paper_model("arm_vector")
    sh = mech.plan.shapes
    assert sh["boom"].distance("O", "J") == pytest.approx(DIMS.l1, rel=1e-15)
    assert sh["stick"].distance("J", "Q") == pytest.approx(DIMS.l2, rel=1e-15)
    assert sh["bucket"].distance("Q", "A") == pytest.approx(DIMS.l3, rel=1e-15)
    # each mount rebuilt from the model's pins: base in the parent frame, rod end in the link's
    for link, (parent, pivot, base, rod, end) in {
        "boom": ("turntable", "O", "P1", "C1", "J"),
        "stick": ("boom", "J", "P2", "C2", "Q"),
        "bucket": ("stick", "Q", "P3", "C3", "A"),
    }.items():
        pts = mech.plan.model.points
        m = MOUNTS[link]
        assert sh[link].distance(rod, end) == pytest.approx(m.l_prime, rel=1e-12)
        assert sh[link].distance(pivot, rod) == pytest.approx(
            np.hypot(m.l - m.l_prime * np.cos(m.alpha), m.l_prime * np.sin(m.alpha)), rel=1e-12
        )
        assert sh[parent].distance(pivot, base) == pytest.approx(np.hypot(m.a, m.b), rel=1e-12)
        assert pts[pivot] != pts[base]


def test_forward_position_velocity_acceleration(motion, forward) -> None:  # type: ignore[no-untyped-def]
    phi, om, ep = motion
    assert forward.result.status.all_ok
    xa, ya = ref.arm_position(DIMS, *phi)
    vx, vy = ref.arm_velocity(DIMS, *phi, *om)
    ax, ay = ref.arm_acceleration(DIMS, *phi, *om, *ep)
    for k, r in (("x_a", xa), ("y_a", ya), ("v_xa", vx), ("v_ya", vy), ("a_xa", ax), ("a_ya", ay)):
        assert_rel(forward[k], r, 1e-9)
    for i in range(3):
        assert_rel(forward[f"phi{i + 1}"], common.wrap(phi[i]), 1e-9)
        assert_rel(forward[f"omega{i + 1}"], om[i], 1e-9)
        assert_rel(forward[f"eps{i + 1}"], ep[i], 1e-9)


@pytest.mark.parametrize("link", ["boom", "stick", "bucket"])
def test_cylinder_link_relations(motion, forward, link: str) -> None:  # type: ignore[no-untyped-def]
    phi, om, ep = motion
    cyl = ref.arm_cylinder_kinematics(DIMS, *phi, *om, *ep)[link]
    for f in CYL_FIELDS:
        expected = np.asarray(getattr(cyl, f))
        got = forward[f"{link}_{f}"]
        if f == "phi_z":
            got = expected + common.wrap(got - expected)
        assert_rel(got, expected, 1e-9)


@pytest.mark.parametrize("branch", [1, -1])
def test_inverse_problem_both_solutions(motion, branch: int) -> None:  # type: ignore[no-untyped-def]
    phi, om, ep = motion
    xa, ya = ref.arm_position(DIMS, *phi)
    vx, vy = ref.arm_velocity(DIMS, *phi, *om)
    ax, ay = ref.arm_acceleration(DIMS, *phi, *om, *ep)
    q1, q2 = ref.arm_inverse_position(DIMS, xa, ya, phi[2], branch)
    w1, w2 = ref.arm_rates_from_tool(DIMS, q1, q2, phi[2], om[2], vx, vy)
    e1, e2 = ref.arm_accelerations_from_tool(DIMS, q1, q2, phi[2], w1, w2, om[2], ep[2], ax, ay)
    run = papers.arm_inverse(
        (xa, ya),
        phi[2],
        branch,
        tip_velocity=(vx, vy),
        omega3=om[2],
        tip_acceleration=(ax, ay),
        eps3=ep[2],
    )
    assert run.result.status.all_ok
    assert np.all(ref.arm_branch(run["phi1"], run["phi2"]) == branch)
    for k, r in (("phi1", q1), ("phi2", q2)):
        assert_rel(r + common.wrap(run[k] - r), r, 1e-9)
    for k, r in (("omega1", w1), ("omega2", w2), ("eps1", e1), ("eps2", e2)):
        assert_rel(run[k], r, 1e-9)
    np.testing.assert_allclose(run["x_a"], xa, rtol=0, atol=1e-12)
    np.testing.assert_allclose(run["y_a"], ya, rtol=0, atol=1e-12)


def test_cylinder_driven_model_is_the_inverse_relation(motion) -> None:  # type: ignore[no-untyped-def]
    """The model file itself (cylinder lengths in): z → ψ (the spec's inverse relation), and
    (v_r, a_r) → (ω, ε)."""
    phi, om, ep = motion
    cyl = ref.arm_cylinder_kinematics(DIMS, *phi, *om, *ep)
    mech = common.load_paper_model("arm_vector")
    res = mech.solve(
        {f"{k}_cyl": cyl[k].z for k in MOUNTS},
        {f"{k}_cyl": cyl[k].v_r for k in MOUNTS},
        {f"{k}_cyl": cyl[k].a_r for k in MOUNTS},
    )
    assert res.status.all_ok
    parent = {"boom": None, "stick": "boom", "bucket": "stick"}
    for i, (link, mount) in enumerate(MOUNTS.items()):
        ang, w, e = res.body(link)
        par = res.body(parent[link])[0] if parent[link] else 0.0
        psi = ref.cylinder_angle_from_length(mount, cyl[link].z)
        assert_rel(psi + common.wrap(ang - par - psi), psi, 1e-9)
        assert_rel(w, om[i], 1e-9)
        assert_rel(e, ep[i], 1e-9)


def test_velocities_accelerations_match_8th_order_differences(motion) -> None:  # type: ignore[no-untyped-def]
    """Along the motion φ(t) = φ + ω t + ε t²/2: the engine's A and cylinder rates against
    differences of the engine's own positions and lengths."""
    phi, om, ep = motion
    sl = slice(0, None, 7)
    p, w, e = phi[:, sl], om[:, sl], ep[:, sl]
    mech = papers.arm_joint_mechanism()
    run = papers.arm_forward(tuple(p), tuple(w), tuple(e), mech)
    keys = [("x_a", "v_xa", "a_xa"), ("y_a", "v_ya", "a_ya")] + [
        (f"{c}_{q}", f"{c}_{r}", f"{c}_{a}")
        for c in MOUNTS
        for q, r, a in (("z", "v_r", "a_r"), ("phi_z", "omega_z", "eps_z"))
    ]

    def at(t: float) -> np.ndarray:
        r = papers.arm_forward(tuple(p + w * t + 0.5 * e * t * t), tuple(w), tuple(e), mech)
        vals = []
        for k, _, _ in keys:
            v = r[k]
            if k.endswith("phi_z"):
                v = run[k] + common.wrap(v - run[k])
            vals.append(v)
        return np.concatenate(vals)

    d1, d2 = fd_derivatives(at, 2e-3)
    assert_rel(d1, np.concatenate([run[k] for _, k, _ in keys]), 1e-9)
    assert_rel(d2, np.concatenate([run[k] for _, _, k in keys]), 1e-8)


def test_printed_d_fails_against_the_engine(forward, motion) -> None:  # type: ignore[no-untyped-def]
    """The print's d (with a spurious +a) gives a boom-cylinder angle unlike the engine's."""
    phi = motion[0]
    c = (
        DIMS.l1 * np.sin(phi[0])
        + DIMS.boom.a
        - DIMS.boom.l_prime * np.sin(phi[0] - DIMS.boom.alpha)
    )
    printed = np.arctan2(c, ref.printed_cylinder_d(DIMS.boom, phi[0]))
    assert np.max(np.abs(common.wrap(printed - forward["boom_phi_z"]))) > np.radians(5)


def test_reproduce_command(tmp_path: Path) -> None:
    out = tmp_path / "out"
    result = CliRunner().invoke(command, ["--out-dir", str(out)])
    assert result.exit_code == 0, result.output
    assert "not published" in result.output
    for name in ("arm-vector-model.png", "arm-cylinders.png"):
        assert (out / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
