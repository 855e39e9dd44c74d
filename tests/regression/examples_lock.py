"""The locked results of every example model: a hash of its table, kinematics and forces.

``python -m tests.regression.examples_lock`` rewrites ``data/examples_lock.json``; do that only
for a change that is meant to alter results, and say so in the commit.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import numpy as np

import excavkin

LOCK = Path(__file__).parent / "data" / "examples_lock.json"
EXAMPLES = Path(__file__).parents[2] / "examples"
N = 97


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


def frame_hash(frame: object) -> str:
    """sha256 of the column names, the status texts and the float64 bytes of every column."""
    import pandas as pd

    assert isinstance(frame, pd.DataFrame)
    h = hashlib.sha256()
    for name in frame.columns:
        h.update(str(name).encode())
        col = frame[name]
        if col.dtype.kind == "f":
            h.update(np.ascontiguousarray(col.to_numpy(np.float64)).tobytes())
        else:
            h.update("\x1f".join(map(str, col.tolist())).encode())
    return h.hexdigest()


def example_hashes() -> dict[str, dict[str, str]]:
    out: dict[str, dict[str, str]] = {}
    for path in sorted(EXAMPLES.glob("*.toml")):
        if path.stem == "excavator_machine":  # a machine file, locked by the excavator tests
            continue
        name = path.stem
        mech = excavkin.load(path)
        values, rates = sweep(mech)
        result = mech.solve(values, rates, workers=1)
        entry = {
            "plan": hashlib.sha256(mech.plan.describe().encode()).hexdigest(),
            "kinematics": frame_hash(result.to_frame()),
        }
        try:  # the model's own loads and gravity, or inertia alone
            forces = mech.forces(result)
        except excavkin.ModelError:  # statically indeterminate: no forces to lock
            pass
        else:
            entry["forces"] = frame_hash(forces.to_frame())
        out[name] = entry
    return out


if __name__ == "__main__":
    LOCK.write_text(json.dumps(example_hashes(), indent=1, sort_keys=True) + "\n")
    print(f"wrote {LOCK}")
