"""Exact sensitivities of the forces: the kinetostatic equilibrium differentiated with respect to
the dimensions and masses, by running the same back-substitution on dual numbers.

The positions, accelerations and angular accelerations carry their tangents from the kinematic
sensitivities (`excavkin.kinematics.sensitivity`); the masses, moments of inertia and
centres of mass carry theirs from the parameters. The equilibrium's own back-substitution
along the plan (`excavkin.kinetostatics.structured`) and its dense blocks run on them
unchanged, and so do the gear pairs' radial tooth forces (`excavkin.kinetostatics.gears`; a
model whose meshes the plan cannot take runs the elimination of the whole system,
`excavkin.kinetostatics.equilibrium.dense_solve`), so each force's tangent is the exact
derivative of the solved forces. A load given
as a function of the result (a spring, a damper) is evaluated once more on a result whose
arrays are dual numbers, so that its own dependence on the dimensions is differentiated too; a
function that cannot take them (it converts the arrays, or uses a function the duals do not
carry) is refused by name rather than held fixed.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.kinematics.dual import Dual, seed
from excavkin.kinetostatics.body_loads import body_loads
from excavkin.kinetostatics.equilibrium import dense_solve
from excavkin.kinetostatics.gears import (
    CAM_COLUMNS,
    RACK_COLUMNS,
    pin_updates,
    pitch_fractions,
    tooth_forces,
    with_pitch,
)
from excavkin.kinetostatics.result import winch_drive
from excavkin.kinetostatics.structured import Arithmetic, along_plan, back_substitute
from excavkin.structure.design import expand, mass_items

if TYPE_CHECKING:
    from excavkin.kinematics.result import KinematicResult
    from excavkin.kinetostatics.result import ForceResult

#: samples per pass
CHUNK = 4096


@dataclass(frozen=True, slots=True)
class _Masses:
    """Mass properties as the body loads read them, each a number, an array or a dual."""

    mass: list[Any]
    inertia: list[Any]
    com: list[tuple[Any, Any]]
    base: np.ndarray
    massive: tuple[int, ...]

    def at(self, part: slice) -> _Masses:
        def cut(v: Any) -> Any:
            return v[part] if np.ndim(v) else v

        return _Masses(
            [cut(m) for m in self.mass],
            [cut(i) for i in self.inertia],
            [(cut(s), cut(t)) for s, t in self.com],
            self.base,
            self.massive,
        )


def force_tangents(forces: ForceResult, names: Sequence[str]) -> dict[str, dict[str, F]]:
    """Per parameter, the derivative of every force column of ``forces.to_frame()``.

    ``forces.kinematics`` must carry the kinematic tangents of ``names``
    (``solve(..., sensitivities=names)``).
    """
    kin = forces.kinematics
    assert kin.tangents is not None
    tangents = [kin.tangents[p] for p in names]
    sy, ev = forces.system, forces.evaluated
    n, m = len(kin), len(names)
    x = np.moveaxis(kin.positions, 0, -1)
    a = np.moveaxis(kin.accelerations, 0, -1)
    eps = np.moveaxis(kin.body_epsilon, 0, -1)
    x_t = np.stack([np.moveaxis(t.positions, 0, -1) for t in tangents])
    a_t = np.stack([np.moveaxis(t.accelerations, 0, -1) for t in tangents])
    eps_t = np.stack([np.moveaxis(t.body_epsilon, 0, -1) for t in tangents])
    masses = _dual_masses(forces, names, n)
    ev = _dual_loads(forces, names, n)
    lam = pitch_fractions(kin.plan.model, _dual_values(forces, names, n))
    structured = along_plan(kin.plan, sy)
    out = np.zeros((m, sy.size, n))
    for s in range(0, n, CHUNK):
        part = slice(s, min(s + CHUNK, n))
        if lam:  # gear ratios per design or differentiated: each chunk's pitch points
            sy = with_pitch(forces.system, lam, part)
            structured = along_plan(kin.plan, sy)
        xd = Dual(x[..., part], x_t[..., part])
        with np.errstate(divide="ignore", invalid="ignore"):
            rhs = body_loads(
                sy,
                masses.at(part),  # type: ignore[arg-type]
                ev,
                xd,  # type: ignore[arg-type]
                Dual(a[..., part], a_t[..., part]),  # type: ignore[arg-type]
                Dual(eps[..., part], eps_t[..., part]),  # type: ignore[arg-type]
                part,
            )
            if structured is None:  # meshes the plan cannot take: the whole system, densely
                sol: list[Any] = dense_solve(sy, xd, rhs)[0]  # type: ignore[arg-type]
            else:
                ops = Arithmetic(part.stop - part.start)
                sol = back_substitute(structured, xd, rhs, ops)  # type: ignore[arg-type]
        for col, val in enumerate(sol):
            if isinstance(val, Dual) and val.tan.ndim:
                out[:, col, part] = val.tan
        for col, val in pin_updates(sy, xd, tooth_forces(sy, sol)):
            if isinstance(val, Dual) and val.tan.ndim:
                out[:, col, part] += val.tan
    bad = ~(kin.status.solved & ~forces.singular)
    out[:, :, bad] = np.nan
    return {name: _columns(forces, out[j], x, x_t[j], name) for j, name in enumerate(names)}


def _dual_loads(forces: ForceResult, names: Sequence[str], n: int) -> Any:
    """The evaluated loads, with a unit tangent on each load magnitude among ``names``."""
    import dataclasses

    from excavkin.kinetostatics.loads import PointForce, Torque

    ev = forces.evaluated
    m = len(names)
    dual_result = _dual_result(forces.kinematics, names)

    def with_tangent(value: Any, name: str) -> Any:
        if name not in names:
            return value
        tan = np.zeros((m, n))
        tan[list(names).index(name)] = 1.0
        return Dual(np.broadcast_to(np.asarray(value, dtype=np.float64), (n,)).copy(), tan)

    # evaluate_loads keeps the loads' order: the k-th point force is forces[k], and so on
    pushes = [ld for ld in forces.loads if isinstance(ld, PointForce)]
    couples = [ld for ld in forces.loads if isinstance(ld, Torque)]
    new_forces = []
    for (body, point, fx, fy), ld in zip(ev.forces, pushes, strict=True):
        if callable(ld.value):
            f = _function_tangent(ld, dual_result, (fx, fy), m, n)
            new_forces.append((body, point, f[0], f[1]))
        else:
            fx, fy = with_tangent(fx, f"{ld.name}.Fx"), with_tangent(fy, f"{ld.name}.Fy")
            new_forces.append((body, point, fx, fy))
    new_torques = []
    for (body, reaction, tau), couple in zip(ev.torques, couples, strict=True):
        if callable(couple.value):
            tau = _function_tangent(couple, dual_result, (tau,), m, n)[0]
        else:
            tau = with_tangent(tau, f"{couple.name}.torque")
        new_torques.append((body, reaction, tau))
    return dataclasses.replace(ev, forces=tuple(new_forces), torques=tuple(new_torques))


#: the fields of a kinematic result that carry tangents, for a load function to read
_DUAL_FIELDS = (
    "positions", "velocities", "accelerations", "body_angle", "body_omega", "body_epsilon",
    "inputs", "input_rates", "input_accels", "element_length", "element_rate",
    "element_accel", "element_angle", "element_omega", "element_epsilon", "transmission",
)  # fmt: skip


def _dual_result(kin: KinematicResult, names: Sequence[str]) -> KinematicResult:
    """The result with each array a dual number carrying its tangents to ``names``."""
    import dataclasses

    assert kin.tangents is not None
    duals = {
        f: Dual(getattr(kin, f), np.stack([getattr(kin.tangents[p], f) for p in names]))
        for f in _DUAL_FIELDS
    }
    return dataclasses.replace(kin, tangents=None, **duals)  # type: ignore[arg-type]


def _function_tangent(
    ld: Any, dual_result: KinematicResult, values: tuple[Any, ...], m: int, n: int
) -> list[Any]:
    """A load function's components (as evaluated) with their tangents: the function run on
    the dual result. A function that does not carry them is an error naming the load."""
    from excavkin.errors import InputError

    def refuse(why: str) -> InputError:
        return InputError(
            f"load {ld.name!r}: its value function cannot be differentiated with respect to "
            f"the design ({why}); for force sensitivities write it with NumPy arithmetic, "
            "sqrt, hypot, arctan2, sin and cos on result.point/body/driver arrays, or give "
            "the load as values"
        )

    try:
        out = ld.value(dual_result)
    except Exception as exc:  # the user's function: say whose it was
        raise refuse(f"it raised {type(exc).__name__}: {exc}") from exc
    if not isinstance(out, Dual):
        try:
            np.asarray(out, dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise refuse(f"it converted the arrays: {exc}") from None
        # it read nothing that moves with the design (time, sample count): no tangent
        return list(values)
    parts = [out[..., 0], out[..., 1]] if len(values) == 2 else [out]
    result = []
    for value, part in zip(values, parts, strict=True):
        tan = np.asarray(part.tan, dtype=np.float64) if isinstance(part, Dual) else np.zeros(m)
        if tan.ndim == 1:  # one value for every sample
            tan = tan[:, None]
        val = np.broadcast_to(np.asarray(value, dtype=np.float64), (n,)).copy()
        result.append(Dual(val, np.broadcast_to(tan, (m, n)).copy()))
    return result


def _dual_values(forces: ForceResult, names: Sequence[str], n: int) -> dict[str, Any]:
    """The parameters given, with the tangents of ``names`` seeded, design variables
    expanded."""
    kin = forces.kinematics
    model = kin.plan.model
    from excavkin.structure.design import joint_offsets, parameters

    known = {**parameters(model), **joint_offsets(model)}
    given = dict(kin.parameters or {})
    base = {k: given.get(k, known[k]) for k in names}
    return expand(model, {**given, **seed(base, list(names), n)})


def _dual_masses(forces: ForceResult, names: Sequence[str], n: int) -> _Masses:
    """The mass properties with the tangents of the parameters ``names``."""
    model = forces.kinematics.plan.model
    items = mass_items(model, _dual_values(forces, names, n))
    massive = forces.mass.massive
    return _Masses(
        [it[0] for it in items],
        [it[1] for it in items],
        [(it[2], it[3]) for it in items],
        forces.mass.base,
        massive,
    )


def _columns(forces: ForceResult, tan: F, x: F, x_t: F, parameter: str) -> dict[str, F]:
    """The force columns' derivatives from the unknowns' (``tan``: (size, n)), by name; the
    ground's resultant includes its sliders' normal forces turning with their slides."""
    sy = forces.system
    n = tan.shape[-1]
    pin = tan[: 2 * len(sy.slots)].reshape(len(sy.slots), 2, n)
    e0, s0, t0 = sy.element_col0, sy.slider_col0, sy.torque_col0
    out: dict[str, F] = {}
    for k, (p, b) in enumerate(forces.pins):
        out[f"{p}.{b}.Fx"], out[f"{p}.{b}.Fy"] = pin[k, 0], pin[k, 1]
    for k, e in enumerate(sy.elements):
        out[f"{e[0]}.force"] = tan[e0 + k]
    for k, d in enumerate(sy.rotary):
        out[f"{d[0]}.torque"] = tan[t0 + k]
    for k, g in enumerate(sy.gears):
        out[f"{g[0]}.tooth"] = tan[sy.gear_col0 + k]
    for k, rk in enumerate(sy.racks):
        for c, qty in enumerate(RACK_COLUMNS):
            out[f"{rk[0]}.{qty}"] = tan[sy.rack_col0 + 3 * k + c]
    for cm, col in zip(sy.cams, sy.cam_cols, strict=True):
        for c, qty in enumerate(CAM_COLUMNS[: cm.unknowns]):
            out[f"{cm.name}.{qty}"] = tan[col + c]
    for k, s in enumerate(sy.sliders):
        out[f"{s[0]}.normal"] = tan[s0 + k]
    elements = [e[0] for e in sy.elements]
    sheaved = [r[0] for r in sy.ropes]
    for rope in forces.kinematics.plan.model.ropes:  # tension and winch torque: linear in force
        if rope.over_sheaves:
            dt = tan[sy.rope_col0 + sheaved.index(rope.name)]
        else:
            dt = -tan[e0 + elements.index(rope.name)] / rope.parts
        out[f"{rope.name}.tension"] = dt
        if rope.mode == "winch":  # −T·R/i, R and i parameters of their own
            radius, ratio = winch_drive(rope, forces.kinematics.parameters)
            d = -dt * (radius / ratio)
            if parameter == f"{rope.name}.drum_radius":
                d = d - forces.tension(rope.name) / ratio
            elif parameter == f"{rope.name}.gear_ratio":
                d = d + forces.tension(rope.name) * radius / (ratio * ratio)
            out[f"{rope.name}.torque"] = d
    ground = sy.ground
    rx, ry = np.zeros(n), np.zeros(n)
    for k, (_, j) in enumerate(sy.slots):
        if j == ground:
            rx, ry = rx + pin[k, 0], ry + pin[k, 1]
    for k, (_, _, l1, l2, carrier) in enumerate(sy.sliders):
        if carrier != ground:
            continue
        # −f·n with n = perp(e)/|e|: the product rule on the force and the slide's turn
        slide = Dual(x[l2] - x[l1], (x_t[l2] - x_t[l1])[None])
        length = np.hypot(slide[0], slide[1])  # type: ignore[call-overload]
        nx, ny = -slide[1] / length, slide[0] / length
        f = forces.slider_force[:, k]
        df = tan[s0 + k]
        rx = rx - (df * nx.val + f * nx.tan[0])
        ry = ry - (df * ny.val + f * ny.tan[0])
    name = sy.bodies[ground]
    out[f"{name}.Rx"], out[f"{name}.Ry"] = rx, ry
    return out
