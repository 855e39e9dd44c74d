"""The locked results of every example model: its plan, and its table of kinematics and forces.

``python -m tests.regression.examples_lock`` rewrites ``data/examples_lock.json`` and
``data/examples_lock.npz``; do that only for a change that is meant to alter results, and say so
in the commit.

The plan is locked exactly (a hash of its description). The numbers are locked to 1e-11 of each
column's largest magnitude, not to the bit: the last bits of ``sin`` and ``cos`` differ between
NumPy builds and processors, and a bit-exact lock would fail on a machine that is not wrong.
"""

from __future__ import annotations

import hashlib
import json
import tomllib
from pathlib import Path

import numpy as np

import excavkin
from excavkin.families import family_of

LOCK = Path(__file__).parent / "data" / "examples_lock.json"
VALUES = LOCK.with_suffix(".npz")
EXAMPLES = Path(__file__).parents[2] / "examples"
N = 97
#: every this-many-th sample is locked (the file stays small)
EVERY = 4


def sweep(mech: excavkin.Mechanism) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    """All inputs moving together: rotary through a turn, linear ±8 % about the sketch."""
    sketch = mech.sketch_values()
    values, rates = {}, {}
    s = np.linspace(0.0, 1.0, N)
    for k, name in enumerate(mech.inputs):
        q0 = sketch[name]
        if mech.input_kind(name) == "angle":
            values[name] = q0 + 2 * np.pi * s
            rates[name] = np.full(N, 10.0 + k)
        else:
            values[name] = q0 * (0.92 + 0.16 * s)
            rates[name] = np.full(N, 0.05 * (k + 1))
    return values, rates


def _table(frame: object) -> tuple[list[str], list[str], np.ndarray]:
    """Float column names, the status texts and the float values (every EVERY-th sample)."""
    import pandas as pd

    assert isinstance(frame, pd.DataFrame)
    names = [str(c) for c in frame.columns if frame[c].dtype.kind == "f"]
    status = [str(s) for s in frame["status"].tolist()[::EVERY]]
    return names, status, frame[names].to_numpy(np.float64)[::EVERY]


def example_tables() -> dict[str, dict[str, object]]:
    """Per example: the plan's hash, and the kinematics and (where determinate) forces tables."""
    out: dict[str, dict[str, object]] = {}
    for path in sorted(EXAMPLES.glob("*.toml")):
        data = tomllib.loads(path.read_text(encoding="utf-8"))
        if family_of(data, str(path)) is not None:  # a machine file, locked by its wing's tests
            continue
        mech = excavkin.load(path)
        values, rates = sweep(mech)
        # the reference path, whatever kernels this machine has compiled: a compiled path
        # equals it to 1e-12 of a column's scale (tests/property, tests/crossmethod), where a
        # column of round-off alone (a locked rate of 1e-17) has no scale to hold it to
        result = mech.solve(values, rates, workers=1, backend="numpy")
        entry: dict[str, object] = {
            "plan": hashlib.sha256(mech.plan.describe().encode()).hexdigest(),
            "kinematics": _table(result.to_frame()),
        }
        try:  # the model's own loads and gravity, or inertia alone
            forces = mech.forces(result, backend="numpy")
        except excavkin.ModelError:  # statically indeterminate: no forces to lock
            pass
        else:
            entry["forces"] = _table(forces.to_frame())
        out[path.stem] = entry
    return out


def write() -> None:
    meta: dict[str, dict[str, object]] = {}
    arrays: dict[str, np.ndarray] = {}
    for name, entry in example_tables().items():
        meta[name] = {"plan": entry["plan"]}
        for part in ("kinematics", "forces"):
            if part in entry:
                cols, status, vals = entry[part]  # type: ignore[misc]
                meta[name][part] = {"columns": cols, "status": status}
                arrays[f"{name}.{part}"] = vals
    LOCK.write_text(json.dumps(meta, indent=1, sort_keys=True) + "\n")
    np.savez_compressed(VALUES, **arrays)


if __name__ == "__main__":
    write()
    print(f"wrote {LOCK} and {VALUES}")
