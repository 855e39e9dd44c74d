"""A long table as a folder of Parquet parts, encoded on threads.

One Parquet file is written by one thread: pyarrow encodes a row group's columns one after
another and gives no threaded encoder to hand them to, so a table of many columns streamed to
one file is bounded by that thread, however many cores solve it. A folder of parts is how a
table is split for writers in parallel (as Arrow's datasets, Dask and Spark write theirs):
each part of the stream becomes its own file, ``part-000000.parquet``, ``part-000001.parquet``
…, in the stream's order, every file with the same schema (columns, units and kinds), and the
files are encoded and written on a pool of threads (Arrow releases the GIL) while the next
parts are solved. ``pandas.read_parquet(folder)`` or ``pyarrow.parquet.read_table(folder)``
reads the table whole, its rows in order.

The folder is made whole or not at all (`excavkin.io.files.write_folder_atomic`): the parts
are written into a temporary folder beside it, which takes its name when the last part is
written; a failed or stopped run leaves nothing. An existing folder is replaced only with
``force``, and only if it holds nothing but parts.
"""

from __future__ import annotations

import os
import re
from collections import deque
from collections.abc import Iterable, Sequence
from concurrent.futures import Future, ThreadPoolExecutor
from pathlib import Path
from typing import TYPE_CHECKING

from excavkin.io.files import OutputError, check_folder_target, write_folder_atomic
from excavkin.outputs.tables import Rows, TableWriter, select_frame

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["MAX_PARTS", "PART", "check_parts_target", "part_threads", "write_parts"]

#: a part's file name, numbered in the stream's order
PART = "part-{:06d}.parquet"

#: parts a folder holds at most (their names sort in the stream's order)
MAX_PARTS = 10**6

_PART_NAME = re.compile(r"part-\d{6}\.parquet")


def part_threads() -> int:
    """Threads that encode parts: one a core this process may use, at most 16 (each holds
    one part's Arrow arrays while it writes them).

    Returns
    -------
    int
    """
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    return max(1, min(cores or 1, 16))


def check_parts_target(path: str | Path, *, force: bool) -> Path:
    """Check, before any work, that a folder of parts may be made at ``path``.

    Parameters
    ----------
    path : str or Path
        The folder.
    force : bool
        Whether an existing folder of parts may be replaced.

    Returns
    -------
    Path

    Raises
    ------
    OutputError
        A name ending in ``.csv`` (parts are Parquet), something there without ``force``, a
        file or a folder of other files there, or a missing parent folder.
    """
    p = Path(path)
    if p.suffix.lower() == ".csv":
        raise OutputError(f"{p}: parts are Parquet files; name the folder without .csv")
    return check_folder_target(p, force=force, replaceable=holds_only_parts)


def holds_only_parts(folder: Path) -> bool:
    """Whether every entry of ``folder`` is a regular file named as a part.

    Parameters
    ----------
    folder : Path

    Returns
    -------
    bool
    """
    return all(
        _PART_NAME.fullmatch(entry.name) is not None and entry.is_file(follow_symlinks=False)
        for entry in os.scandir(folder)
    )


def write_parts(
    frames: Iterable[pd.DataFrame],
    path: str | Path,
    *,
    force: bool = False,
    columns: Sequence[str] | None = None,
    threads: int | None = None,
) -> Path:
    """Write frames as a folder of Parquet parts, one file a frame, encoded on threads.

    Parameters
    ----------
    frames : iterable of pandas.DataFrame
        The table's parts in order, as `excavkin.outputs.tables.write_tables` takes them:
        every frame has the first one's columns; the first's ``attrs`` give units and kinds.
    path : str or Path
        The folder to make (`check_parts_target`).
    force : bool
        Replace an existing folder of parts.
    columns : sequence of str, optional
        Only these columns of every frame (names or glob patterns, as ``write_table``).
    threads : int, optional
        Parts encoded at once (default `part_threads`); memory holds at most this many frames'
        Arrow arrays, and one more being made.

    Returns
    -------
    Path
        The folder.

    Raises
    ------
    OutputError
        As `check_parts_target`; a frame with other columns than the first; no frame at all.
    UnknownNameError
        A name or pattern in ``columns`` that matches no column (nothing is written).
    """
    p = check_parts_target(path, force=force)
    workers = part_threads() if threads is None else threads
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise OutputError(f"threads must be a whole number ≥ 1, not {threads!r}")

    def write(tmp: Path) -> None:
        first: TableWriter | None = None
        pending: deque[Future[None]] = deque()
        with ThreadPoolExecutor(workers) as pool:
            try:
                for k, frame in enumerate(frames):
                    if k == MAX_PARTS:
                        raise OutputError(f"{p}: more than {MAX_PARTS:,} parts; write larger parts")
                    selected = select_frame(frame, columns)
                    if first is None:
                        first = TableWriter(tmp / PART.format(0), parquet=True)
                    elif [str(c) for c in selected.columns] != first.columns:
                        raise OutputError(f"{p}: a part of the table has other columns")
                    rows = first.rows_of(selected)  # Arrow arrays made here, encoded on the pool
                    if len(pending) >= workers:
                        pending.popleft().result()
                    pending.append(pool.submit(_write_part, first, tmp / PART.format(k), rows))
                while pending:
                    pending.popleft().result()
            finally:
                for job in pending:  # what stopped the table: the parts not begun are dropped
                    job.cancel()
        if first is None:
            raise OutputError(f"{p}: no table to write")

    return write_folder_atomic(p, write, holds_only_parts)


def _write_part(first: TableWriter, path: Path, rows: Rows) -> None:
    """Encode and write one part to ``path``, and close its file (on a pool thread): the
    first part into the file ``first`` opened, every other one into a sibling of it."""
    with first if path == first.path else first.sibling(path) as out:
        out.write_rows(rows)
