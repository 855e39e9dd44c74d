"""Shared test helpers: high-order finite differences and model builders."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"

# 8th-order central stencils (Fornberg 1988)
_D1 = np.array([1 / 280, -4 / 105, 1 / 5, -4 / 5, 0.0, 4 / 5, -1 / 5, 4 / 105, -1 / 280])
_D2 = np.array([-1 / 560, 8 / 315, -1 / 5, 8 / 5, -205 / 72, 8 / 5, -1 / 5, 8 / 315, -1 / 560])


def fd_derivatives(fun: Callable[[float], np.ndarray], h: float) -> tuple[np.ndarray, np.ndarray]:
    """First and second derivatives at 0 of ``fun(t)`` by 8th-order central differences."""
    vals = np.stack([fun(k * h) for k in range(-4, 5)])
    d1 = np.tensordot(_D1, vals, axes=1) / h
    d2 = np.tensordot(_D2, vals, axes=1) / (h * h)
    return d1, d2


def assert_rel(actual: np.ndarray, expected: np.ndarray, rtol: float) -> None:
    """Element-wise agreement within ``rtol`` of the largest magnitude of ``expected``."""
    expected = np.asarray(expected)
    scale = max(float(np.max(np.abs(expected))), 1e-300)
    np.testing.assert_allclose(actual, expected, rtol=0, atol=rtol * scale)


@pytest.fixture
def example() -> Callable[[str], Path]:
    def get(name: str) -> Path:
        return EXAMPLES / f"{name}.toml"

    return get
