"""Exact design sensitivities to 10 parameters against the kinematics alone, as ratios measured
in one run.

Run: ``python benchmarks/bench_sensitivities.py [N]`` (needs numba; default N = 10⁶). For the
four-bar and the excavator, N samples of the drivers about the sketch, rates given:

* the kinematics: the NumPy path, the compiled plan, and the default choice at that size
  (the compiled plan once its kernel is compiled — the reference of the target);
* the full state with its derivatives with respect to 10 parameters, by default (at this size
  the compiled tangent kernel, :mod:`excavkin.kinematics.compiled_tangents`), as a ratio to
  each kinematics time. Target ≤ 3× the default kinematics;
* what the derivatives' memory alone costs: fresh arrays of their size written once (10
  tangents of every column: ten times the kinematic result);
* only the derivatives an optimiser of the tool's path would read (``sensitivity_columns``:
  the tool point's position and the transmission angles) — the compiled loop then computes
  and stores no others;
* the NumPy dual-number path at N/10 samples, against the NumPy kinematics at N/10.

Best of several repeats in the same process. Not a test: machines differ; the ratios are what
is tracked.
"""

from __future__ import annotations

import sys

import numpy as np
from timing import best_of

import excavkin
from excavkin.kinematics import compiled_tangents
from excavkin.kinematics.sensitivity import _Tangents


def inputs(mech: excavkin.Mechanism, n: int) -> dict[str, np.ndarray]:
    """Every driver over a range about its sketch value that keeps the linkage closed."""
    rng = np.random.default_rng(0)
    out = {}
    for k, v in mech.sketch_values().items():
        if mech.input_kind(k) == "angle":
            out[k] = (
                rng.uniform(0.0, 2.0 * np.pi, n) if k == "crank" else v + rng.uniform(-0.2, 0.2, n)
            )
        else:
            out[k] = v * (1.0 + rng.uniform(-0.05, 0.05, n))
    return out


#: the tool point of each model
TOOL = {"fourbar": "B", "excavator": "W"}


def one(name: str, n: int) -> tuple[float, float, float]:
    mech = excavkin.load(excavkin.example_path(name))
    names = [p for p in mech.parameters if not p.endswith((".mass", ".inertia"))][:10]
    values = inputs(mech, n)
    rates = {k: 0.5 for k in values}
    small = {k: v[:1000] for k, v in values.items()}
    mech.solve(small, rates, sensitivities=names, backend="numba")  # compile both kernels
    assert compiled_tangents.is_compiled(mech.plan), "the default is not the compiled kernel"
    ok = mech.solve(values, rates).status.ok.mean()
    t_numpy = best_of(lambda: mech.solve(values, rates, backend="numpy"), 3)
    t_comp = best_of(lambda: mech.solve(values, rates, backend="numba"), 3)
    t_kin = best_of(lambda: mech.solve(values, rates), 3)
    t_sens = best_of(lambda: mech.solve(values, rates, sensitivities=names), 3)
    tool = TOOL[name]
    cols = [f"{tool}.x", f"{tool}.y", *(f"{p}.transmission" for p in mech.plan.transmissions)]
    mech.solve(small, rates, sensitivities=names, sensitivity_columns=cols, backend="numba")
    t_some = best_of(
        lambda: mech.solve(values, rates, sensitivities=names, sensitivity_columns=cols), 3
    )

    def memory() -> None:
        out = _Tangents(mech.plan, n, len(names))
        for arr in (out.x, out.v, out.a, out.trans, out.body, out.element):
            arr.fill(0.0)

    t_mem = best_of(memory, 3)
    m = n // 10
    part = {k: v[:m] for k, v in values.items()}
    t_numpy_kin = best_of(lambda: mech.solve(part, rates, backend="numpy"), 3)
    t_numpy_sens = best_of(lambda: mech.solve(part, rates, sensitivities=names, backend="numpy"), 2)
    print(f"{name}, {n:,} samples ({ok:.1%} closed), {len(names)} parameters:")
    print(f"  kinematics: NumPy {t_numpy:.3f} s, compiled {t_comp:.3f} s, default {t_kin:.3f} s")
    r = t_sens / t_kin
    print(
        f"  sensitivities (default: compiled tangents) {t_sens:.3f} s = {r:.2f}× the default "
        f"kinematics (target ≤ 3), {t_sens / t_numpy:.2f}× NumPy's, "
        f"{t_sens / t_comp:.2f}× the compiled plan's"
    )
    print(
        f"  their memory alone, written once: {t_mem:.3f} s = {t_mem / t_kin:.2f}× the kinematics"
    )
    print(
        f"  only {', '.join(cols)}: {t_some:.3f} s = {t_some / t_kin:.2f}× the default kinematics"
    )
    print(
        f"  NumPy dual numbers at {m:,} samples: {t_numpy_sens / t_numpy_kin:.2f}× the NumPy "
        "kinematics"
    )
    return r, t_sens / t_numpy, t_sens / t_comp


def main(n: int = 1_000_000) -> None:
    for name in ("fourbar", "excavator"):
        one(name, n)


if __name__ == "__main__":
    main(int(float(sys.argv[1])) if len(sys.argv) > 1 else 1_000_000)
