"""``excavkin reproduce arm``: the vector model of a 3-DOF excavator arm (paper 001), by the engine.

Runs ``examples/arm_vector.toml`` (the reference's ``EXCAVATOR_20T``): the forward problem
(link angles → tooth tip A, its velocity and acceleration), the inverse problem (A and φ3 →
φ1, φ2, both assemblies, with the paper's mixed rate problems) and the cylinder–link
relations of all three cylinders (z, φz, v_r, ωz, a_r, εz). The paper publishes no numbers;
the tables put the engine beside the closed-form reference, and the figures redraw the
paper's Fig. 1 (vector model) and the relations of its Fig. 2 for each cylinder.
"""

from __future__ import annotations

from pathlib import Path

import click
import numpy as np

from excavkin.cli.common import handle_errors
from excavkin.papers.arm_vector.figures import arm_cylinders_figure, arm_vector_figure
from excavkin.papers.arm_vector.study import (
    arm_cylinder_sweep,
    arm_forward,
    arm_inverse,
    arm_reference_agreement,
)
from excavkin.papers.common import PaperRun, text_table
from excavkin.papers.figures import save_png

#: Example motion (ours: the paper gives no numbers), absolute link angles, rates, accelerations.
PHI_DEG = (15.0, -90.0, -165.0)
OMEGA = (0.10, -0.20, 0.30)
EPS = (0.05, -0.10, 0.20)


def _deg(x: float) -> str:
    return f"{np.degrees(x):.4f}"


def _num(x: float) -> str:
    return f"{x:+.5f}"


@click.command("arm")
@click.option(
    "--out-dir",
    default="excavkin-reproduce",
    show_default=True,
    type=click.Path(file_okay=False),
    help="Folder for arm-vector-model.png and arm-cylinders.png (regenerated each run).",
)
@handle_errors
def command(out_dir: str) -> None:
    """Excavator arm vector model: forward, inverse (both solutions), cylinder relations."""
    from excavkin.papers.arm_vector import reference as ref

    dims = ref.EXCAVATOR_20T
    p1, p2, p3 = (float(v) for v in np.radians(PHI_DEG))
    phi = (p1, p2, p3)
    click.echo(
        "Vector model of a 3-DOF excavator arm (seed paper 001)\n"
        "engine: examples/arm_vector.toml (EXCAVATOR_20T: l1 = 5.70, l2 = 2.90, l3 = 1.50 m; "
        "three cylinders); reference: excavkin.papers.arm_vector.reference\n"
        "The paper publishes no numbers (no dimensions, no results): every value is ours.\n"
        f"Pose: φ1, φ2, φ3 = {PHI_DEG[0]:g}°, {PHI_DEG[1]:g}°, {PHI_DEG[2]:g}°; "
        f"ω = {OMEGA} rad/s; ε = {EPS} rad/s²\n"
    )
    fw = arm_forward(phi, OMEGA, EPS)
    xa, ya = ref.arm_position(dims, p1, p2, p3)
    vx, vy = ref.arm_velocity(dims, p1, p2, p3, *OMEGA)
    ax, ay = ref.arm_acceleration(dims, p1, p2, p3, *OMEGA, *EPS)
    rows = [
        (f"{k} (eq. {e})", u, "not published", _num(float(r[0])), _num(float(fw[k][0])))
        for k, e, u, r in (
            ("x_a", 2, "m", xa),
            ("y_a", 2, "m", ya),
            ("v_xa", 3, "m/s", vx),
            ("v_ya", 3, "m/s", vy),
            ("a_xa", 5, "m/s²", ax),
            ("a_ya", 5, "m/s²", ay),
        )
    ]
    click.echo("Forward problem: point A from l1..l3, φ1..φ3 and their rates")
    click.echo(text_table(("quantity", "unit", "paper", "reference", "engine"), rows))

    click.echo(
        "\nInverse problem: (x_A, y_A, φ3) → φ1, φ2, both solutions; then (ω3, v_xA, v_yA) → "
        "ω1, ω2 (eq. 4) and (ε3, a_xA, a_yA) → ε1, ε2 (eq. 6)"
    )
    sols: list[PaperRun] = []
    inv_rows: list[tuple[str, ...]] = []
    for branch in (1, -1):
        iv = arm_inverse(
            (xa, ya),
            p3,
            branch,
            tip_velocity=(vx, vy),
            omega3=OMEGA[2],
            tip_acceleration=(ax, ay),
            eps3=EPS[2],
        )
        sols.append(iv)
        q1, q2 = ref.arm_inverse_position(dims, xa, ya, p3, branch)
        w1, w2 = ref.arm_rates_from_tool(dims, q1, q2, p3, OMEGA[2], vx, vy)
        e1, e2 = ref.arm_accelerations_from_tool(dims, q1, q2, p3, w1, w2, OMEGA[2], EPS[2], ax, ay)
        for k, u, r in (
            ("phi1", "°", q1),
            ("phi2", "°", q2),
            ("omega1", "rad/s", w1),
            ("omega2", "rad/s", w2),
            ("eps1", "rad/s²", e1),
            ("eps2", "rad/s²", e2),
        ):
            show = _deg if u == "°" else _num
            ours = float(iv[k][0])
            inv_rows.append((f"{branch:+d}", k, u, "not published", show(float(r[0])), show(ours)))
    click.echo(text_table(("branch", "quantity", "unit", "paper", "reference", "engine"), inv_rows))

    click.echo("\nCylinder ↔ link relations (eqs. 7-12) at the pose, all three cylinders")
    cyl = ref.arm_cylinder_kinematics(dims, p1, p2, p3, *OMEGA, *EPS)
    cyl_rows: list[tuple[str, ...]] = []
    for link, ck in cyl.items():
        for f, u in (
            ("z", "m"),
            ("phi_z", "°"),
            ("v_r", "m/s"),
            ("omega_z", "rad/s"),
            ("a_r", "m/s²"),
            ("eps_z", "rad/s²"),
            ("a_k", "m/s²"),
        ):
            show = _deg if u == "°" else _num
            val = float(getattr(ck, f)[0])
            eng = float(fw[f"{link}_{f}"][0])
            cyl_rows.append((link, f, u, "not published", show(val), show(eng)))
    click.echo(
        text_table(("cylinder", "quantity", "unit", "paper", "reference", "engine"), cyl_rows)
    )

    agree = arm_reference_agreement()
    click.echo(
        "\nAgreement over 400 random poses in the working range (largest difference / largest "
        "value):"
    )
    click.echo(
        text_table(("problem", "engine vs reference"), [(k, f"{v:.1e}") for k, v in agree.items()])
    )

    folder = Path(out_dir)
    folder.mkdir(parents=True, exist_ok=True)
    sweeps = {link: arm_cylinder_sweep(link) for link in ("boom", "stick", "bucket")}
    written = [
        save_png(arm_vector_figure(sols).figure, folder / "arm-vector-model.png", force=True),
        save_png(arm_cylinders_figure(sweeps).figure, folder / "arm-cylinders.png", force=True),
    ]
    click.echo(f"\nwrote {', '.join(str(p) for p in written)}")
