"""Write result tables: whole or not at all.

A table is written to a temporary file beside the target and moved into place only when
complete, so an interrupted or failed run never leaves a half-written file, and an existing
file is replaced only when asked (``force``).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from excavkin.io.files import OutputError, check_target, remove_leftovers, write_atomic

if TYPE_CHECKING:
    import pandas as pd

TABLE_SUFFIXES = (".csv", ".parquet")

__all__ = [
    "TABLE_SUFFIXES",
    "OutputError",
    "check_target",
    "remove_leftovers",
    "units_of",
    "write_atomic",
    "write_table",
]


def units_of(frame: pd.DataFrame) -> dict[str, str]:
    """The SI unit of every column whose kind the table's ``attrs`` record (``""`` otherwise)."""
    from excavkin.kinematics.columns import si_unit

    kinds = frame.attrs.get("excavkin.kinds", {})
    return {str(c): si_unit(kinds.get(str(c), "")) for c in frame.columns}


def write_table(
    frame: pd.DataFrame, path: str | Path, *, force: bool = False, units_row: bool = False
) -> Path:
    """Write ``frame`` as CSV or Parquet (by suffix), atomically.

    Every table is SI with plain column names. Floats are written as the shortest text that
    reads back to the same double. A Parquet file keeps each column's unit and kind and the
    model's name in its schema metadata (``excavkin.units``, ``excavkin.kinds``,
    ``excavkin.model``); a CSV file may carry the units as a second header row
    (``units_row``).
    """
    import json

    p = check_target(path, force=force, suffixes=TABLE_SUFFIXES)
    units = units_of(frame)
    if p.suffix.lower() == ".parquet":
        try:
            import pyarrow as pa
            import pyarrow.parquet as pq
        except ImportError:
            raise OutputError(
                f"{p}: writing Parquet needs pyarrow "
                "(pip install 'excavkin[parquet]'), or write .csv"
            ) from None

        def parquet(tmp: Path) -> None:
            out = frame.copy(deep=False)
            if "status" in out:
                out["status"] = out["status"].astype(str)
            table = pa.Table.from_pandas(out, preserve_index=False)
            meta = {
                **(table.schema.metadata or {}),
                b"excavkin.units": json.dumps(units).encode(),
                b"excavkin.kinds": json.dumps(frame.attrs.get("excavkin.kinds", {})).encode(),
                b"excavkin.model": str(frame.attrs.get("excavkin.model", "")).encode(),
            }
            pq.write_table(table.replace_schema_metadata(meta), tmp)

        return write_atomic(p, parquet)

    def csv(tmp: Path) -> None:
        with open(tmp, "w", newline="", encoding="utf-8") as f:
            if units_row:
                frame.head(0).to_csv(f, index=False)
                f.write(",".join(units.get(str(c), "") for c in frame.columns) + "\n")
                frame.to_csv(f, index=False, header=False)
            else:
                frame.to_csv(f, index=False)

    return write_atomic(p, csv)
