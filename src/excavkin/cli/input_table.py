"""``--inputs``: a table of samples (CSV or Parquet) read in batches, never whole.

Its columns become [`excavkin.sweeps.Lazy`][] columns: a streamed solve asks for samples in
order, and the table is read a batch at a time as it goes (again from the start when a pass of
the smooth continuation asks for it). Read whole (`read_inputs`), it gives the same
numbers, batch by batch.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.errors import InputError, did_you_mean
from excavkin.mechanism import Mechanism
from excavkin.outputs.tables import TABLE_SUFFIXES
from excavkin.sweeps import Lazy

#: rows read at a time
BATCH = 1 << 16


class InputTable:
    """An ``--inputs`` table: ``<driver>`` (or ``<driver>.value``), ``<driver>.rate``,
    ``<driver>.accel`` and ``t``, one row per sample, SI.

    A CSV may carry the units row that ``--units-row`` writes; it is skipped. Every value must
    be a finite number (checked as the rows are read).

    Parameters
    ----------
    mech : Mechanism
    path : str
    batch : int
        Rows read at a time.
    """

    def __init__(self, mech: Mechanism, path: str, batch: int = BATCH) -> None:
        self.path = path
        self.file = _readable(path)
        self.parquet = self.file.suffix.lower() == ".parquet"
        self.batch = batch
        self.names = self._names()
        self.values: dict[str, Lazy] = {}
        self.rates: dict[str, Lazy] = {}
        self.accels: dict[str, Lazy] = {}
        self.time: Lazy | None = None
        known = [
            *mech.inputs,
            *(f"{d}.{q}" for d in mech.inputs for q in ("value", "rate", "accel")),
        ]
        self._skip = 0
        self._window: tuple[int, int, dict[str, F]] = (0, 0, {})
        self._reader: Iterator[dict[str, F]] | None = None
        self._buffer: list[dict[str, F]] = []
        self._buffered = (0, 0)  # the samples in the buffer
        self.n = self._count()
        _check_unambiguous(self.names, path)
        for col in self.names:
            name, _, qty = col.partition(".")
            column = _Column(self, col)
            if col == "t":
                self.time = column
            elif name in mech.inputs and qty in ("", "value"):
                self.values[name] = column
            elif name in mech.inputs and qty == "rate":
                self.rates[name] = column
            elif name in mech.inputs and qty == "accel":
                self.accels[name] = column
            else:
                raise InputError(
                    f"--inputs {path}: column {col!r} is not an input of {mech.name!r}"
                    f"{did_you_mean(col, known)} (columns: <driver>, <driver>.rate, "
                    f"<driver>.accel, t; inputs: {', '.join(mech.inputs) or 'none'})"
                )
        if not self.n:
            raise InputError(f"--inputs {path}: the table has no samples")

    # ---- the file
    def _names(self) -> list[str]:
        try:
            if self.parquet:
                import pyarrow.parquet as pq

                return [str(c) for c in pq.read_schema(self.file).names]
            import pyarrow.csv as pcsv

            reader = pcsv.open_csv(self.file, convert_options=_text_columns(None))
            names = [str(c) for c in reader.schema.names]
            reader.close()
            return names
        except (OSError, ValueError) as exc:  # pyarrow's errors are ValueErrors
            raise InputError(f"--inputs {self.path}: cannot read the table: {exc}") from None

    def _batches(self) -> Iterator[Any]:
        """The file's record batches, from the start (the units row left in)."""
        try:
            if self.parquet:
                import pyarrow.parquet as pq

                yield from pq.ParquetFile(self.file).iter_batches(batch_size=self.batch)
                return
            import pyarrow.csv as pcsv

            reader = pcsv.open_csv(
                self.file,
                read_options=pcsv.ReadOptions(block_size=1 << 22),
                convert_options=_text_columns(self.names),
            )
            yield from reader
        except (OSError, ValueError) as exc:
            raise InputError(f"--inputs {self.path}: cannot read the table: {exc}") from None

    def _count(self) -> int:
        """The rows (without a units row); a CSV is read through once for it."""
        if self.parquet:
            import pyarrow.parquet as pq

            return int(pq.ParquetFile(self.file).metadata.num_rows)
        rows = 0
        for k, batch in enumerate(self._batches()):
            if k == 0 and batch.num_rows and _units_row(batch):
                self._skip = 1
            rows += batch.num_rows
        return rows - self._skip

    def _rows(self) -> Iterator[dict[str, F]]:
        """The samples' numbers, batch after batch."""
        skip = self._skip
        for batch in self._batches():
            columns = {}
            for name, column in zip(self.names, batch.columns, strict=True):
                columns[name] = _numbers(column.slice(skip), self.path, name)
            skip = 0
            yield columns

    def window(self, start: int, stop: int) -> dict[str, F]:
        """Every column's samples ``start`` … ``stop − 1`` (asked for in order; asking again
        for earlier ones reads the table again from its start)."""
        first, last, held = self._window
        if first <= start and stop <= last:
            return {k: v[start - first : stop - first] for k, v in held.items()}
        if self._reader is None or start < self._buffered[0]:
            self._reader, self._buffer, self._buffered = self._rows(), [], (0, 0)
        # drop what lies before ``start``, read until ``stop``
        while self._buffered[1] < stop:
            try:
                got = next(self._reader)
            except StopIteration:
                raise InputError(
                    f"--inputs {self.path}: the table changed while it was read"
                ) from None
            size = len(next(iter(got.values()))) if got else 0
            self._buffer.append(got)
            self._buffered = (self._buffered[0], self._buffered[1] + size)
        while self._buffer:
            size = len(next(iter(self._buffer[0].values()))) if self._buffer[0] else 0
            if self._buffered[0] + size > start:
                break
            self._buffer.pop(0)
            self._buffered = (self._buffered[0] + size, self._buffered[1])
        base = self._buffered[0]
        joined = {
            name: np.concatenate([b[name] for b in self._buffer])[start - base : stop - base]
            for name in self.names
        }
        self._window = (start, stop, joined)
        return joined


class _Column(Lazy):
    """One column of an `InputTable`."""

    def __init__(self, table: InputTable, name: str) -> None:
        self.table = table
        self.name = name

    @property
    def size(self) -> int:
        return self.table.n

    def values(self, start: int, stop: int) -> F:
        return self.table.window(start, stop)[self.name]


def read_inputs(
    mech: Mechanism, path: str, batch: int = BATCH
) -> tuple[dict[str, F], dict[str, F], dict[str, F], F | None]:
    """The whole table, read batch by batch: values, rates, accelerations and time, SI."""
    table = InputTable(mech, path, batch)

    def whole(columns: dict[str, Lazy]) -> dict[str, F]:
        return {k: np.asarray(v) for k, v in columns.items()}

    time = None if table.time is None else np.asarray(table.time)
    return whole(table.values), whole(table.rates), whole(table.accels), time


def _check_unambiguous(names: list[str], path: str) -> None:
    """Refuse a column given twice, or a driver's value given both as ``<driver>`` and as
    ``<driver>.value``: one of them would be silently dropped."""
    seen: dict[str, str] = {}
    for col in names:
        key = col[: -len(".value")] if col.endswith(".value") else col
        if key in seen:
            first = seen[key]
            what = (
                f"column {col!r} appears twice"
                if first == col
                else f"columns {first!r} and {col!r} both give the value of {key!r}"
            )
            raise InputError(f"--inputs {path}: {what}; keep one, so that no value is dropped")
        seen[key] = col


def _readable(path: str) -> Path:
    """The input table's path, if it exists and ends in .csv or .parquet."""
    p = Path(path)
    if p.suffix.lower() not in TABLE_SUFFIXES:
        raise InputError(f"--inputs {path}: the table must end in .csv or .parquet")
    from excavkin.io.files import ReadError, check_readable

    try:
        return check_readable(p)
    except ReadError as exc:
        raise InputError(f"--inputs {path}: {exc.problem}") from None


def _text_columns(names: list[str] | None) -> Any:
    """CSV cells read as text (a units row, and a cell that is not a number, are told apart
    from numbers afterwards); no cell is a null."""
    import pyarrow as pa
    import pyarrow.csv as pcsv

    return pcsv.ConvertOptions(
        column_types={n: pa.string() for n in names or []},
        strings_can_be_null=False,
        quoted_strings_can_be_null=False,
        null_values=[],
        true_values=[],
        false_values=[],
        auto_dict_encode=False,
    )


def _numbers(column: Any, path: str, name: str) -> F:
    """A column's values as finite floats, or the error naming it."""
    import pyarrow as pa
    import pyarrow.compute as pc

    try:
        if pa.types.is_string(column.type) or pa.types.is_large_string(column.type):
            column = pc.utf8_trim_whitespace(column)
        out = np.asarray(pc.cast(column, pa.float64()).to_numpy(zero_copy_only=False))
    except (pa.ArrowInvalid, pa.ArrowNotImplementedError, ValueError):
        out = np.array([np.nan])
    if not np.isfinite(out).all():
        raise InputError(f"--inputs {path}: column {name!r} holds a value that is not a number")
    return np.asarray(out, dtype=np.float64)


def _units_row(batch: Any) -> bool:
    """A first row of unit names (as ``--units-row`` writes), not of numbers."""
    from excavkin.cli.common import is_number
    from excavkin.units import is_unit_text

    cells = [str(col[0].as_py()) for col in batch.columns]
    return not any(is_number(c) for c in cells) and all(is_unit_text(c) for c in cells)
