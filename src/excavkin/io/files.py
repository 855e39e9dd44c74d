"""Files read within a size limit, and written whole or not at all, checked before any work.

Every file excavkin reads (a model, a machine, a study, an input table) is opened through
`check_readable` or `read_limited`: only a regular file is read (a FIFO would block
forever, a device such as ``/dev/zero`` never ends, a folder is no file), and never more than
its limit, so that a hostile path ends in one message naming it.

A file is written to a temporary file beside the target and moved into place only when
complete, so an interrupted or failed run never leaves a half-written file, and an existing
file is replaced only when asked (``force``).
"""

from __future__ import annotations

import glob
import os
import shutil
import signal
import stat
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from os import PathLike
from pathlib import Path

from excavkin.errors import ExcavkinError


class OutputError(ExcavkinError):
    """An output file cannot be written."""


class ReadError(ExcavkinError):
    """An input file cannot be read: missing, not a regular file, too large, unreadable.

    Parameters
    ----------
    path : Path
        The file.
    problem : str
        What is wrong with it, in one sentence.
    """

    def __init__(self, path: Path, problem: str) -> None:
        self.path = path
        self.problem = problem
        super().__init__(f"{path}: {problem}")


def _what_it_is(mode: int) -> str:
    if stat.S_ISDIR(mode):
        return "a folder"
    if stat.S_ISFIFO(mode):
        return "a FIFO (named pipe)"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "a device"
    if stat.S_ISSOCK(mode):
        return "a socket"
    return "not a regular file"


def check_readable(path: str | Path, limit: int | None = None, what: str = "the file") -> Path:
    """Check, without opening it, that ``path`` is a regular file of at most ``limit`` bytes.

    Parameters
    ----------
    path : str or Path
    limit : int, optional
        The most bytes the file may hold (no limit when ``None``).
    what : str
        What the file is, for the message ("a model or machine file").

    Returns
    -------
    Path

    Raises
    ------
    ReadError
        Naming the file: missing, a folder, a FIFO, a device, or larger than ``limit``.
    """
    p = Path(path)
    try:
        st = os.stat(p)
    except OSError as exc:
        raise ReadError(p, f"cannot read the file: {exc.strerror or exc}") from None
    if not stat.S_ISREG(st.st_mode):
        raise ReadError(p, f"{_what_it_is(st.st_mode)}, not a file that can be read")
    if limit is not None and st.st_size > limit:
        raise ReadError(p, f"the file is {st.st_size:,} bytes; {what} is at most {limit:,}")
    return p


def read_limited(path: str | Path, limit: int, what: str = "the file") -> bytes:
    """The bytes of a regular file of at most ``limit`` bytes (checked again as it is read, in
    case it grows).

    Parameters
    ----------
    path : str or Path
    limit : int
        The most bytes read.
    what : str
        What the file is, for the message.

    Returns
    -------
    bytes

    Raises
    ------
    ReadError
        As `check_readable`, or when the file cannot be opened or read.
    """
    p = check_readable(path, limit, what)
    try:
        # O_NONBLOCK: a file swapped for a FIFO after the check cannot block the open
        fd = os.open(p, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
        with os.fdopen(fd, "rb") as f:
            if not stat.S_ISREG(os.fstat(f.fileno()).st_mode):
                raise ReadError(p, "not a regular file")
            data = f.read(limit + 1)
    except OSError as exc:
        raise ReadError(p, f"cannot read the file: {exc.strerror or exc}") from None
    if len(data) > limit:
        raise ReadError(p, f"the file is more than {limit:,} bytes; {what} is at most {limit:,}")
    return data


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


def check_folder_target(
    path: str | Path, *, force: bool, replaceable: Callable[[Path], bool]
) -> Path:
    """Check that a folder may be made at ``path`` (`write_folder_atomic`).

    Parameters
    ----------
    path : str or Path
        The folder.
    force : bool
        Whether an existing folder may be replaced.
    replaceable : callable
        ``replaceable(folder) -> bool``: whether an existing folder holds nothing but what
        such a write makes.

    Returns
    -------
    Path

    Raises
    ------
    OutputError
        A missing parent folder; something there without ``force``; a file or a link there,
        or a folder that is not ``replaceable``.
    """
    p = Path(path)
    if not p.parent.exists():
        raise OutputError(f"{p}: the folder {p.parent} does not exist")
    if not (p.exists() or p.is_symlink()):
        return p
    if not force:
        raise OutputError(f"{p} exists; pass --force to replace it")
    if p.is_symlink() or not p.is_dir():
        raise OutputError(f"{p} exists and is not a folder; not replaced")
    if not replaceable(p):
        raise OutputError(
            f"{p} is a folder that holds other files than a table's parts; not replaced"
        )
    return p


def write_folder_atomic(
    path: str | Path,
    writer: Callable[[Path], None],
    replaceable: Callable[[Path], bool],
) -> Path:
    """Call ``writer(tmp)`` to fill a temporary folder, then move it onto ``path``, as
    `write_atomic` does a file: the folder appears whole or not at all.

    An existing folder at ``path`` (checked by `check_target`, with ``force``) is replaced
    only if ``replaceable(path)`` says it holds nothing but what such a write makes: a folder
    a user keeps other files in is never removed.

    Parameters
    ----------
    path : str or Path
        The folder to make.
    writer : callable
        ``writer(tmp)`` writes the folder's files into the existing, empty folder ``tmp``.
    replaceable : callable
        ``replaceable(folder) -> bool``: whether an existing folder may be replaced.

    Returns
    -------
    Path

    Raises
    ------
    OutputError
        An existing folder that is not ``replaceable``, or a file in the folder's place.
    """
    p = check_folder_target(path, force=True, replaceable=replaceable)  # (again: just before)
    remove_leftovers(p)
    tmp = p.parent / _TMP.format(name=p.name, pid=os.getpid(), suffix="")
    old = p.parent / _TMP.format(name=p.name, pid=os.getpid(), suffix=".old")
    with _terminate_as_exit():
        try:
            tmp.mkdir()
            writer(tmp)
            if p.exists():  # moved aside, and back if the new one cannot take its place
                os.replace(p, old)
                try:
                    os.replace(tmp, p)
                except BaseException:
                    os.replace(old, p)
                    raise
                shutil.rmtree(old, ignore_errors=True)
            else:
                os.replace(tmp, p)
        except BaseException:
            shutil.rmtree(tmp, ignore_errors=True)
            raise
    return p


def write_toml_from(
    source: str | PathLike[str],
    out: str | PathLike[str],
    text: Callable[[], str],
    *,
    force: bool,
    itself: str,
) -> Path:
    """Write a ``.toml`` file made from ``source`` to ``out``, whole or not at all; never
    over ``source`` itself.

    Parameters
    ----------
    source : str or path-like
        The file the text is made from.
    out : str or path-like
        The new file.
    text : callable
        ``text() -> str``: the file's text, made once the target is checked.
    force : bool
        Whether an existing ``out`` may be replaced.
    itself : str
        What the error says after ``out`` when it is ``source``.

    Returns
    -------
    Path
        The file written, ``out``.

    Raises
    ------
    OutputError
        ``out`` exists (without ``force``), is ``source``, or is not a ``.toml`` file.
    """
    target = check_target(Path(out), force=force, suffixes=(".toml",))
    if target.exists() and target.resolve() == Path(source).resolve():
        raise OutputError(f"{target} {itself}")
    content = text()

    def write(tmp: Path) -> None:
        tmp.write_text(content, encoding="utf-8")

    return write_atomic(target, write)


def remove_leftovers(target: Path) -> list[Path]:
    """Remove the temporary files of earlier writes to ``target`` whose process is gone."""
    removed = []
    for leftover in target.parent.glob(f".{glob.escape(target.name)}.excavkin-*.tmp*"):
        pid_text = leftover.name[len(target.name) + 11 :].split(".tmp", 1)[0]
        if pid_text.isdigit() and not _alive(int(pid_text)):
            if leftover.is_dir() and not leftover.is_symlink():  # a folder of parts
                shutil.rmtree(leftover, ignore_errors=True)
            else:
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
