"""Files written whole or not at all, and checked before any work.

A file is written to a temporary file beside the target and moved into place only when
complete, so an interrupted or failed run never leaves a half-written file, and an existing
file is replaced only when asked (``force``).
"""

from __future__ import annotations

import glob
import os
import signal
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path

from excavkin.errors import ExcavkinError


class OutputError(ExcavkinError):
    """An output file cannot be written."""


def check_target(path: str | Path, *, force: bool, suffixes: tuple[str, ...] | None = None) -> Path:
    """Check, before any work, that ``path`` may be written.

    Raises
    ------
    OutputError
        If it exists and ``force`` is false, its folder does not exist, or its suffix is not one
        of ``suffixes``.
    """
    p = Path(path)
    if suffixes is not None and p.suffix.lower() not in suffixes:
        raise OutputError(f"{p}: the output must end in {' or '.join(suffixes)}")
    if p.exists() and not force:
        raise OutputError(f"{p} exists; pass --force to replace it")
    if not p.parent.exists():
        raise OutputError(f"{p}: the folder {p.parent} does not exist")
    if p.exists() and p.is_dir():
        raise OutputError(f"{p} is a folder")
    return p


#: the temporary file's name beside a target: ``.NAME.excavkin-PID.tmp.SUFFIX``
_TMP = ".{name}.excavkin-{pid}.tmp{suffix}"


def write_atomic(path: str | Path, writer: Callable[[Path], None]) -> Path:
    """Call ``writer(tmp)`` to write a temporary file, then move it onto ``path``.

    The temporary file is removed whatever stops the write — an error, Ctrl-C (SIGINT) or
    SIGTERM — and a later write to the same target removes what a killed run (SIGKILL, a
    power cut) left, once its process is gone.
    """
    p = Path(path)
    remove_leftovers(p)
    tmp = p.parent / _TMP.format(name=p.name, pid=os.getpid(), suffix=p.suffix)
    with _terminate_as_exit():
        try:
            writer(tmp)
            # give the file the mode a plain open() would
            umask = os.umask(0)
            os.umask(umask)
            os.chmod(tmp, 0o666 & ~umask)
            os.replace(tmp, p)
        except BaseException:
            tmp.unlink(missing_ok=True)
            raise
    return p


def remove_leftovers(target: Path) -> list[Path]:
    """Remove the temporary files of earlier writes to ``target`` whose process is gone."""
    removed = []
    for leftover in target.parent.glob(f".{glob.escape(target.name)}.excavkin-*.tmp*"):
        pid_text = leftover.name[len(target.name) + 11 :].split(".tmp", 1)[0]
        if pid_text.isdigit() and not _alive(int(pid_text)):
            leftover.unlink(missing_ok=True)
            removed.append(leftover)
    return removed


def _alive(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # someone else's: leave it
        return True
    return True


@contextmanager
def _terminate_as_exit() -> Iterator[None]:
    """While a file is written, SIGTERM unwinds like Ctrl-C does, so the file is removed."""

    def stop(signum: int, frame: object) -> None:
        raise SystemExit(128 + signum)

    try:
        previous = signal.signal(signal.SIGTERM, stop)
    except ValueError:  # not the main thread: signals are the main thread's to handle
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)
