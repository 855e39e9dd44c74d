"""Write result tables: whole or not at all.

A table is written to a temporary file beside the target and moved into place only when
complete, so an interrupted or failed run never leaves a half-written file, and an existing
file is replaced only when asked (``force``).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from excavkin.io.files import OutputError, check_target, remove_leftovers, write_atomic

if TYPE_CHECKING:
    import pandas as pd

TABLE_SUFFIXES = (".csv", ".parquet")

__all__ = [
    "TABLE_SUFFIXES",
    "OutputError",
    "check_target",
    "remove_leftovers",
    "select_frame",
    "units_of",
    "write_atomic",
    "write_table",
]


def units_of(frame: pd.DataFrame) -> dict[str, str]:
    """The SI unit of every column whose kind the table's ``attrs`` record (``""`` otherwise)."""
    from excavkin.kinematics.columns import si_unit

    kinds = frame.attrs.get("excavkin.kinds", {})
    return {str(c): si_unit(kinds.get(str(c), "")) for c in frame.columns}


def select_frame(frame: pd.DataFrame, columns: Sequence[str] | None) -> pd.DataFrame:
    """Only the columns of ``frame`` that ``columns`` asks for, in the frame's order, with
    ``status`` always, their kinds kept in ``attrs``.

    Parameters
    ----------
    frame : pandas.DataFrame
        A result's table (``to_frame()``).
    columns : sequence of str or None
        Column names or glob patterns (``"B.*"``, ``"*.x"``); None keeps every column.

    Returns
    -------
    pandas.DataFrame
        The selected columns (views, not copies); ``frame`` itself when ``columns`` is None.

    Raises
    ------
    UnknownNameError
        A name or pattern that matches no column, with the nearest column's name.
    """
    from excavkin.kinematics.columns import select_columns

    if columns is None:
        return frame
    kept = select_columns([str(c) for c in frame.columns], columns)
    attrs = dict(frame.attrs)
    bare = frame.copy(deep=False)
    bare.attrs = {}  # (else pandas deep-copies them into the selection, column by column)
    out = bare[kept]
    kinds = attrs.get("excavkin.kinds")
    if isinstance(kinds, dict):
        attrs["excavkin.kinds"] = {c: k for c, k in kinds.items() if c in set(kept)}
    out.attrs.update(attrs)
    return out


def write_table(
    frame: pd.DataFrame,
    path: str | Path,
    *,
    force: bool = False,
    units_row: bool = False,
    columns: Sequence[str] | None = None,
) -> Path:
    """Write ``frame`` as CSV or Parquet (by suffix), atomically.

    Every table is SI with plain column names. Floats are written as the shortest text that
    reads back to the same double (a whole number with ``.0``, so that readers take the
    column as floats), NaN as an empty field, infinities as ``inf`` and ``-inf``. A Parquet
    file keeps each column's unit and kind and the model's name in its schema metadata
    (``excavkin.units``, ``excavkin.kinds``, ``excavkin.model``, and ``excavkin.motion``:
    static forces or transfer functions, where the table says so); a CSV file may carry the
    units as a second header row (``units_row``).

    Parameters
    ----------
    frame : pandas.DataFrame
        A result's table (``to_frame()``), SI; its ``attrs`` give the units and kinds.
    path : str or Path
        The file to write, ending in ``.csv`` or ``.parquet``.
    force : bool, default False
        Replace the file if it exists.
    units_row : bool, default False
        CSV: a second header row with each column's SI unit.
    columns : sequence of str, optional
        Write only these columns (names or glob patterns such as ``"B.*"`` or ``"*.x"``), in
        the table's order, ``status`` always (`select_frame`). Default: every column.

    Returns
    -------
    Path
        The file written.

    Raises
    ------
    OutputError
        Another suffix, an existing file without ``force``, a missing folder, or a folder
        in the file's place.
    UnknownNameError
        A name or pattern in ``columns`` that matches no column (nothing is written).
    """
    return write_tables([frame], path, force=force, units_row=units_row, columns=columns)


def write_tables(
    frames: Iterable[pd.DataFrame],
    path: str | Path,
    *,
    force: bool = False,
    units_row: bool = False,
    columns: Sequence[str] | None = None,
) -> Path:
    """Write frames one after another as one table
    ([`write_table`][excavkin.outputs.tables.write_table]), atomically: the
    file appears when the last frame is written, and not at all if making a frame fails.

    Memory is bounded by a frame: a table of any length is written part by part, each
    frame as the next rows (Parquet: its row groups; CSV: its lines). Every frame has the
    first one's columns; the first's ``attrs`` give the units and kinds. ``columns``, as for
    `write_table`, selects the columns of every frame.
    """
    p = check_target(path, force=force, suffixes=TABLE_SUFFIXES)
    parquet = p.suffix.lower() == ".parquet"

    def write(tmp: Path) -> None:
        # each frame is made Arrow arrays here, as it is made, and encoded and written on a
        # thread of its own while the next one is made (Arrow releases the GIL): a solve and
        # a write overlap, two frames at most in memory; the file's bytes are those of
        # writing the frames one after another
        with (
            TableWriter(tmp, parquet=parquet, units_row=units_row) as out,
            ThreadPoolExecutor(1) as writer,
        ):
            pending: Future[None] | None = None
            for frame in frames:
                rows = out.rows_of(select_frame(frame, columns))
                if pending is not None:
                    pending.result()
                pending = writer.submit(out.write_rows, rows)
            if pending is not None:
                pending.result()

    return write_atomic(p, write)


@dataclass(frozen=True, slots=True)
class Rows:
    """A frame's columns as Arrow arrays, ready to be written (`TableWriter.rows_of`).

    Attributes
    ----------
    names : list of str
    arrays : list of pyarrow.Array
    length : int
        The frame's rows.
    """

    names: list[str]
    arrays: list[Any]
    length: int


class TableWriter:
    """A table written part by part: ``write(frame)`` appends the frame's rows.

    Use it on a temporary file inside `write_atomic` (as `write_tables` does),
    so that a table stopped halfway is never left. The first frame fixes the columns, their
    units and kinds; the file is complete when the writer is closed.

    Parameters
    ----------
    path : Path
    parquet : bool
        Parquet (row groups of each frame's rows), else CSV.
    units_row : bool
        CSV: a second header row with each column's SI unit.
    """

    def __init__(self, path: Path, *, parquet: bool, units_row: bool = False) -> None:
        pa = _pyarrow(path)
        self.path = path
        self.parquet = parquet
        self.units_row = units_row
        self.columns: list[str] | None = None
        self.rows = 0
        self._parquet: Any = None
        self._schema: Any = None
        self._text: list[str] = []
        self._file: Any = None if parquet else pa.OSFile(str(path), "wb")

    def __enter__(self) -> TableWriter:
        return self

    def __exit__(self, kind: type[BaseException] | None, *exc: object) -> None:
        if kind is None:
            self.close()
        else:  # what stopped the table is the error, not the table's lack of rows
            self._release()

    def write(self, frame: pd.DataFrame) -> None:
        """Append the frame's rows (`rows_of`, then `write_rows`).

        Parameters
        ----------
        frame : pandas.DataFrame
            The first frame's columns, in order (the first frame fixes them).
        """
        self.write_rows(self.rows_of(frame))

    def rows_of(self, frame: pd.DataFrame) -> Rows:
        """The frame's columns as Arrow arrays, checked against the table's (the first frame
        fixes them, and starts the file): called for the frames in order, as `write_rows`
        is, though the two may run side by side on two threads, a frame apart.

        Parameters
        ----------
        frame : pandas.DataFrame

        Returns
        -------
        Rows
        """
        names = [str(c) for c in frame.columns]
        if self.columns is None:
            self.columns = names
            self._start(frame)
        elif names != self.columns:
            raise OutputError(f"{self.path}: a part of the table has other columns")
        return Rows(names, [_arrow_column(column) for column in _columns(frame)], len(frame))

    def write_rows(self, rows: Rows) -> None:
        """Append rows made by `rows_of`: a Parquet row group, or CSV lines.

        Parameters
        ----------
        rows : Rows
        """
        import pyarrow as pa

        if self.parquet:
            table = pa.Table.from_arrays(rows.arrays, names=rows.names)
            self._parquet.write_table(table.cast(self._parquet.schema))
        else:
            _write_csv_rows(self._file, rows.arrays, rows.names)
        self.rows += rows.length

    def _start(self, frame: pd.DataFrame) -> None:
        import json

        import pyarrow as pa
        import pyarrow.parquet as pq

        units = units_of(frame)
        if not self.parquet:
            header = _csv_line(self.columns or [])
            if self.units_row:
                header += _csv_line([units.get(c, "") for c in self.columns or []])
            self._file.write(header.encode("utf-8"))
            return
        schema = pa.schema(
            [
                (str(c), _arrow_column(column.iloc[:0]).type)
                for c, column in zip(frame.columns, _columns(frame), strict=True)
            ],
            metadata={
                b"excavkin.units": json.dumps(units).encode(),
                b"excavkin.kinds": json.dumps(frame.attrs.get("excavkin.kinds", {})).encode(),
                b"excavkin.model": str(frame.attrs.get("excavkin.model", "")).encode(),
                **(
                    {b"excavkin.motion": str(frame.attrs["excavkin.motion"]).encode()}
                    if "excavkin.motion" in frame.attrs
                    else {}
                ),
            },
        )
        # dictionaries only for text: tried on every float column they cost 3× the time
        self._schema = schema
        self._text = [f.name for f in schema if pa.types.is_string(f.type)]
        self._parquet = pq.ParquetWriter(str(self.path), schema, use_dictionary=self._text)

    def sibling(self, path: Path) -> TableWriter:
        """A writer of the same table to another Parquet file: its columns, schema (units and
        kinds) and encodings fixed by this one's first frame, so that the files are parts of
        one table (`excavkin.outputs.table_parts.write_parts`). This writer may be closed
        already.

        Parameters
        ----------
        path : Path
            The other file.

        Returns
        -------
        TableWriter
        """
        import pyarrow.parquet as pq

        if not self.parquet or self._schema is None:
            raise OutputError(f"{self.path}: a sibling needs a Parquet table already started")
        other = TableWriter(path, parquet=True)
        other.columns = self.columns
        other._schema = self._schema
        other._text = self._text
        other._parquet = pq.ParquetWriter(str(path), self._schema, use_dictionary=self._text)
        return other

    def close(self) -> None:
        """Finish the file (a CSV file with no frame written is empty; a Parquet one cannot
        be: without a frame its columns are unknown)."""
        self._release()
        if self.parquet and self.columns is None:
            raise OutputError(f"{self.path}: no table to write")

    def _release(self) -> None:
        if self._parquet is not None:
            self._parquet.close()
            self._parquet = None
        if self._file is not None:
            self._file.close()
            self._file = None


def _columns(frame: pd.DataFrame) -> list[pd.Series]:
    """The frame's columns, in order. Taken from a view of the frame without its ``attrs``:
    pandas deep-copies a frame's ``attrs`` into every column taken from it, and the attrs
    hold each column's unit and kind, so that taking every column one by one would cost the
    square of their number (minutes for a model of a thousand points)."""
    bare = frame.copy(deep=False)
    bare.attrs = {}
    return [bare.iloc[:, i] for i in range(bare.shape[1])]


def _pyarrow(path: Path) -> Any:
    try:
        import pyarrow as pa
    except ImportError:
        raise OutputError(f"{path}: writing tables needs pyarrow (pip install pyarrow)") from None
    return pa


def _arrow_column(series: pd.Series) -> Any:
    """A column as Arrow: numbers as they are (NaN a null), categories and text as text."""
    import pandas as pd
    import pyarrow as pa

    if isinstance(series.dtype, pd.CategoricalDtype):
        codes = series.cat.codes.to_numpy()
        labels = pa.array([str(c) for c in series.cat.categories], type=pa.string())
        return pa.DictionaryArray.from_arrays(codes, labels).cast(pa.string())
    values = series.to_numpy()
    if values.dtype.kind in "OUST":
        return pa.array(values, type=pa.string(), from_pandas=True)
    return pa.array(values, from_pandas=True)


#: characters that make a CSV field need quotes
_SPECIAL = (",", '"', "\n", "\r")


def _csv_line(cells: list[str]) -> str:
    """One CSV line, quoted where a cell needs it (Python's csv module, as pandas writes)."""
    import csv
    import io

    out = io.StringIO()
    csv.writer(out, lineterminator="\n").writerow(cells)
    return out.getvalue()


def _csv_text(array: Any) -> Any:
    """A column's CSV text. Floats: the shortest text that reads back to the same double
    (Arrow's: "0.1", "1.5e-7", "1e+21"), a whole number with ".0" ("3.0", not the "3" that
    readers take for an integer), NaN a null (an empty field), ``inf`` and ``-inf``. A column
    of one value throughout (a ground point's) is formatted once."""
    import numpy as np
    import pyarrow as pa
    import pyarrow.compute as pc

    if not pa.types.is_floating(array.type):
        return array
    values = array.to_numpy(zero_copy_only=False)
    if array.null_count == 0 and len(values) > 1:
        bits = values.view(np.int64)
        if (bits == bits[0]).all():
            return pa.repeat(_csv_text(array.slice(0, 1))[0], len(values))
    text = pc.cast(array, pa.string())
    with np.errstate(invalid="ignore"):
        whole = np.isfinite(values) & (values == np.trunc(values))
    if not whole.any():
        return text
    point = pc.binary_join_element_wise(text, ".0", "")
    if whole.all() and not pc.any(pc.match_substring(text, "e")).as_py():
        return point
    fix = pc.and_(pa.array(whole), pc.invert(pc.match_substring(text, "e")))
    return pc.if_else(fix, point, text)


def _write_csv_rows(sink: Any, arrays: list[Any], names: list[str]) -> None:
    """Rows of a CSV file (no header). The columns' text is made on a thread per core
    (Arrow's formatting releases the GIL) and written by Arrow; the rare row with a text cell
    that needs quotes (a comma in a status) is written by Python's csv module, quoted as
    pandas would."""
    import csv
    import io
    import os
    from concurrent.futures import ThreadPoolExecutor

    import numpy as np
    import pyarrow as pa
    import pyarrow.compute as pc
    import pyarrow.csv as pcsv

    with ThreadPoolExecutor(min(os.cpu_count() or 1, 8)) as pool:
        texts = list(pool.map(_csv_text, arrays))
    table = pa.Table.from_arrays(texts, names=names)
    if not table.num_rows:
        return
    quoted = np.zeros(table.num_rows, dtype=bool)
    for col, given in zip(texts, arrays, strict=True):
        if pa.types.is_string(given.type) and len(col):
            for ch in _SPECIAL:
                quoted |= pc.fill_null(pc.match_substring(col, ch), False).to_numpy(
                    zero_copy_only=False
                )
    plain = pcsv.WriteOptions(include_header=False, quoting_style="none")
    # runs of rows alike: [start, stop) with or without quotes
    cuts = [0, *(np.flatnonzero(np.diff(quoted)) + 1).tolist(), table.num_rows]
    for start, stop in zip(cuts[:-1], cuts[1:], strict=True):
        run = table.slice(start, stop - start)
        if not quoted[start]:
            pcsv.write_csv(run, sink, plain)
            continue
        out = io.StringIO()
        cells = [pc.cast(c, pa.string()).to_pylist() for c in run.columns]
        csv.writer(out, lineterminator="\n").writerows(zip(*cells, strict=True))
        sink.write(out.getvalue().encode("utf-8"))
