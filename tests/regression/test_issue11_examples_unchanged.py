"""Issue 11: moving code into wings and typed columns leaves every example's numbers unchanged
(to 1e-11 of each column's scale; the plans exactly)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from tests.regression.examples_lock import LOCK, VALUES, example_tables

LOCKED = json.loads(LOCK.read_text())
with np.load(VALUES) as _data:
    LOCKED_VALUES = {k: _data[k] for k in _data.files}


@pytest.fixture(scope="module")
def now() -> dict[str, dict[str, object]]:
    return example_tables()


@pytest.mark.parametrize("name", sorted(LOCKED))
def test_example_results_are_unchanged(name: str, now: dict[str, dict[str, object]]) -> None:
    locked, current = LOCKED[name], now[name]
    assert current["plan"] == locked["plan"]
    assert ("forces" in current) == ("forces" in locked)
    for part in ("kinematics", "forces"):
        if part not in locked:
            continue
        cols, status, vals = current[part]  # type: ignore[misc]
        assert cols == locked[part]["columns"]
        assert status == locked[part]["status"]
        ref = LOCKED_VALUES[f"{name}.{part}"]
        assert np.array_equal(np.isnan(vals), np.isnan(ref))
        scale = np.nanmax(np.abs(ref), axis=0, initial=0.0)
        diff = np.abs(np.nan_to_num(vals - ref))
        assert np.all(diff <= 1e-11 * np.maximum(scale, 1e-300)), (part, cols)


def test_every_example_is_locked(now: dict[str, dict[str, object]]) -> None:
    assert sorted(now) == sorted(LOCKED)
