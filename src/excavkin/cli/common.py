"""Shared pieces of the command line: value parsing, error reporting, progress.

Every subcommand module of `excavkin.cli` exposes a ``click.Command`` named ``command``;
`excavkin.cli` finds them itself. Errors are one clear paragraph on stderr and a non-zero
exit, never a traceback: wrap a command's body in `handle_errors`. NumPy is imported only
inside the functions that need it: a wing's command group imports this module, and listing the
groups (``excavkin --help``) must stay fast.
"""

from __future__ import annotations

import functools
import math
import os
import sys
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

import click

from excavkin.errors import ExcavkinError, UnitError

if TYPE_CHECKING:
    pass

T = TypeVar("T", bound=Callable[..., Any])

#: exit status when a model, an input or an output is wrong
EXIT_USAGE = 2
#: exit status when some samples failed (no closure, dead position) and --keep-going is off
EXIT_SAMPLES = 3
#: exit status when the reader of stdout went away (``| head``): a shell's 128 + SIGPIPE
EXIT_PIPE = 141


def backend_option(fn: T) -> T:
    """The ``--backend`` option of a command that solves (`excavkin.backends`)."""
    from excavkin.backends import BACKENDS

    return click.option(
        "--backend",
        type=click.Choice(BACKENDS),
        default="auto",
        show_default=True,
        help="Where the solves run: numba (one compiled loop, compiled once per model and "
        "kept on disk), numpy, or auto (a compiled kernel whenever one is ready, else NumPy).",
    )(fn)


def fail(message: str, code: int = EXIT_USAGE) -> None:
    """Print ``message`` as an error paragraph and exit."""
    click.echo(f"excavkin: error: {message}", err=True)
    sys.exit(code)


def end_on_closed_stdout() -> None:
    """Exit quietly, as a Unix tool killed by SIGPIPE does, once stdout's reader has gone
    (``excavkin check fourbar | head -1``): no message, exit status `EXIT_PIPE`."""
    try:  # what is still buffered for stdout can go nowhere: send it to /dev/null
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (OSError, ValueError, AttributeError):  # no real stdout (a test's runner)
        pass
    sys.exit(EXIT_PIPE)


def handle_errors(fn: T) -> T:
    """Turn excavkin's errors (and file-system errors) into a message and a non-zero exit."""

    @functools.wraps(fn)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        try:
            return fn(*args, **kwargs)
        except ExcavkinError as exc:
            fail(str(exc))
        except BrokenPipeError:
            end_on_closed_stdout()
        except OSError as exc:
            fail(f"{exc.filename or ''}: {exc.strerror or exc}".lstrip(": "))
        except MemoryError:
            fail(
                "not enough memory for this many samples; split the sweep into smaller runs "
                "(no output was written)"
            )
        except KeyboardInterrupt:
            fail("interrupted; no output was written", 130)
        return None

    return wrapper  # type: ignore[return-value]


def si_value(text: str, kind: str, what: str, *, hint: bool = True) -> float:
    """Read ``"31.416rad/s"``, ``"50 deg"`` or a bare SI number as an SI float."""
    from excavkin.units import to_si

    text = text.strip()
    try:
        value = float(text)
    except ValueError:
        try:
            value = to_si(text, kind, where=f"{what}: ")
        except UnitError as exc:
            raise UnitError(exc.problem) from None
    if not math.isfinite(value):
        raise ExcavkinError(f"{what}: {text!r} is not a finite number")
    if hint:
        _hint_bare([text], (value, value), kind, what)
    return value


def model_path(text: str, kind: str = "model") -> Path:
    """A model (or machine) file given on the command line: a path, or a built-in example's name
    (`excavkin.source_file`).

    Parameters
    ----------
    text : str
        A path to a ``.toml`` file, or the name of a built-in example (``fourbar``).
    kind : {"model", "machine", "study"}
        Which built-in examples a bare name may name.

    Returns
    -------
    Path

    Raises
    ------
    ModelError
        Neither a file nor a built-in example, with the closest names.
    """
    import excavkin

    return excavkin.source_file(text, kind)


def parse_assignment(text: str, option: str) -> tuple[str, str]:
    """Split ``NAME=VALUE``."""
    name, sep, value = text.partition("=")
    if not sep or not name.strip() or not value.strip():
        raise click.BadParameter(f"expected NAME=VALUE, got {text!r}", param_hint=option)
    return name.strip(), value.strip()


def parse_sweep(text: str, kind: str, what: str, lazy: bool = False) -> Any:
    """``START:STOP:N`` (each end may carry a unit) → N evenly spaced SI values: an array,
    or (``lazy``) an [`excavkin.sweeps.Linspace`][] that makes them part by part."""
    parts = text.split(":")
    if len(parts) != 3:
        raise ExcavkinError(f"{what}: a sweep is START:STOP:N, got {text!r}")
    start = si_value(parts[0], kind, what, hint=False)
    stop = si_value(parts[1], kind, what, hint=False)
    try:
        n = int(parts[2])
    except ValueError:
        raise ExcavkinError(
            f"{what}: the sample count {parts[2]!r} is not a whole number"
        ) from None
    if n < 1:
        raise ExcavkinError(f"{what}: the sample count must be at least 1, got {n}")
    if lazy and n > MAX_SAMPLES:
        raise ExcavkinError(
            f"{what}: {n:,} samples are more than any disk holds; split the sweep into smaller runs"
        )
    if not lazy:
        check_samples(n, what)
    _hint_bare(parts[:2], (start, stop), kind, what)
    if lazy:
        from excavkin.sweeps import Linspace

        return Linspace(start, stop, n)
    import numpy as np

    return np.linspace(start, stop, n)


#: the most samples a sweep may have (each numbered exactly by a double, 2⁵³)
MAX_SAMPLES = 2**53

#: bytes a sample costs at the least in a solve: its inputs, a few points, its table row
MIN_BYTES_PER_SAMPLE = 400


def available_memory() -> int:
    """Physical memory of this machine, bytes (a large default where it cannot be read)."""
    try:
        return int(os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):
        return 1 << 40


def check_samples(n: int, what: str, bytes_per_sample: int = MIN_BYTES_PER_SAMPLE) -> None:
    """Refuse, before anything is allocated, a sample count that cannot fit in memory."""
    need = n * bytes_per_sample
    have = available_memory()
    if need > have:
        raise ExcavkinError(
            f"{what}: {n:,} samples need about {need / 2**30:,.1f} GiB, more than this "
            f"machine's {have / 2**30:,.1f} GiB; split the sweep into smaller runs"
        )


def check_count(
    value: int,
    option: str,
    *,
    least: int,
    most: int,
    samples: int | None = None,
    bytes_per_sample: int = MIN_BYTES_PER_SAMPLE,
    what: str = "samples",
) -> None:
    """Refuse, before any work, a count option (``--samples``, ``--draws``) out of its range,
    or one whose samples cannot fit in this machine's memory.

    Parameters
    ----------
    value : int
        The option's value.
    option : str
        Its name, for the message (``"--samples"``).
    least, most : int
        Its range; ``most`` also bounds the run's time.
    samples : int, optional
        The samples the value makes (a grid's ``value ** 3``); default ``value``.
    bytes_per_sample : int
        Memory a sample holds at once.
    what : str
        What a sample is, for the message ("poses", "points along the dig").

    Raises
    ------
    ExcavkinError
        Naming the option, the value and the limit.
    """
    if value < least or value > most:
        raise ExcavkinError(f"{option} {value:,}: must be at least {least:,} and at most {most:,}")
    n = value if samples is None else samples
    need = n * bytes_per_sample
    have = available_memory()
    if need > have:
        raise ExcavkinError(
            f"{option} {value:,}: {n:,} {what} need about {need / 2**30:,.1f} GiB, more than "
            f"this machine's {have / 2**30:,.1f} GiB; give a smaller {option}"
        )


def _hint_bare(texts: list[str], values: tuple[float, float], kind: str, what: str) -> None:
    """Warn when bare (SI) numbers look like degrees or millimetres."""
    bare = all(is_number(t) for t in texts)
    big = max(abs(v) for v in values)
    if bare and kind == "angle" and big > 4 * math.pi:
        click.echo(
            f"excavkin: warning: {what}: bare numbers are radians; "
            f"{big:g} rad is {big / (2 * math.pi):.1f} turns — write e.g. 360deg for "
            "degrees",
            err=True,
        )
    elif bare and kind == "angular_velocity" and big > 20.0:
        click.echo(
            f"excavkin: warning: {what}: bare numbers are rad/s; {big:g} rad/s is "
            f"{big * 60 / (2 * math.pi):.0f} rpm — write e.g. {big:g}rpm if you meant rpm",
            err=True,
        )
    elif bare and kind == "length" and big > 100.0:
        click.echo(
            f"excavkin: warning: {what}: bare numbers are metres; {big:g} m is long — "
            "write e.g. 2000mm for millimetres",
            err=True,
        )


def is_number(text: str) -> bool:
    """Whether ``text`` reads as a plain float."""
    try:
        float(text)
    except ValueError:
        return False
    return True


#: ``--units-row``, for the commands that write tables
units_row_option = click.option(
    "--units-row",
    is_flag=True,
    help="CSV: a second header row with each column's SI unit (Parquet always keeps them).",
)

RATE_KIND = {"angle": "angular_velocity", "length": "velocity"}
ACCEL_KIND = {"angle": "angular_acceleration", "length": "acceleration"}
JERK_KIND = {"angle": "angular_jerk", "length": "jerk"}
