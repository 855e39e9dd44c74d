"""Shared pieces of the command line: value parsing, error reporting, progress.

Every subcommand module of :mod:`excavkin.cli` exposes a ``click.Command`` named ``command``;
:mod:`excavkin.cli` finds them itself. Errors are one clear paragraph on stderr and a non-zero
exit, never a traceback: wrap a command's body in :func:`handle_errors`.
"""

from __future__ import annotations

import functools
import sys
from collections.abc import Callable
from typing import Any, TypeVar

import click
import numpy as np

from excavkin.errors import ExcavkinError, UnitError
from excavkin.units import to_si

T = TypeVar("T", bound=Callable[..., Any])

#: exit status when a model, an input or an output is wrong
EXIT_USAGE = 2
#: exit status when some samples failed (no closure, dead position) and --keep-going is off
EXIT_SAMPLES = 3


def fail(message: str, code: int = EXIT_USAGE) -> None:
    """Print ``message`` as an error paragraph and exit."""
    click.echo(f"excavkin: error: {message}", err=True)
    sys.exit(code)


def handle_errors(fn: T) -> T:
    """Turn excavkin's errors (and file-system errors) into a message and a non-zero exit."""

    @functools.wraps(fn)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        try:
            return fn(*args, **kwargs)
        except ExcavkinError as exc:
            fail(str(exc))
        except OSError as exc:
            fail(f"{exc.filename or ''}: {exc.strerror or exc}".lstrip(": "))
        except KeyboardInterrupt:
            fail("interrupted; no output was written", 130)
        return None

    return wrapper  # type: ignore[return-value]


def si_value(text: str, kind: str, what: str) -> float:
    """Read ``"31.416rad/s"``, ``"50 deg"`` or a bare SI number as an SI float."""
    text = text.strip()
    try:
        return float(text)
    except ValueError:
        pass
    try:
        return to_si(text, kind, where=f"{what}: ")
    except UnitError as exc:
        raise UnitError(exc.problem) from None


def parse_assignment(text: str, option: str) -> tuple[str, str]:
    """Split ``NAME=VALUE``."""
    name, sep, value = text.partition("=")
    if not sep or not name.strip() or not value.strip():
        raise click.BadParameter(f"expected NAME=VALUE, got {text!r}", param_hint=option)
    return name.strip(), value.strip()


def parse_sweep(text: str, kind: str, what: str) -> np.ndarray:
    """``START:STOP:N`` (each end may carry a unit) → N evenly spaced SI values."""
    parts = text.split(":")
    if len(parts) != 3:
        raise ExcavkinError(f"{what}: a sweep is START:STOP:N, got {text!r}")
    start, stop = si_value(parts[0], kind, what), si_value(parts[1], kind, what)
    try:
        n = int(parts[2])
    except ValueError:
        raise ExcavkinError(
            f"{what}: the sample count {parts[2]!r} is not a whole number"
        ) from None
    if n < 1:
        raise ExcavkinError(f"{what}: the sample count must be at least 1, got {n}")
    return np.linspace(start, stop, n)


RATE_KIND = {"angle": "angular_velocity", "length": "velocity"}
ACCEL_KIND = {"angle": "angular_acceleration", "length": "acceleration"}
