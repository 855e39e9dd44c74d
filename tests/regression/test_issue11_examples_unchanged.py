"""Issue 11: moving code into wings and typed columns leaves every example's numbers unchanged."""

from __future__ import annotations

import json

import pytest

from tests.regression.examples_lock import LOCK, example_hashes

LOCKED = json.loads(LOCK.read_text())


@pytest.fixture(scope="module")
def now() -> dict[str, dict[str, str]]:
    return example_hashes()


@pytest.mark.parametrize("name", sorted(LOCKED))
def test_example_results_are_bit_identical(name: str, now: dict[str, dict[str, str]]) -> None:
    assert now[name] == LOCKED[name]


def test_every_example_is_locked(now: dict[str, dict[str, str]]) -> None:
    assert sorted(now) == sorted(LOCKED)
