"""Field lookups of machine files, shared by every family's readers (units, ranges, errors
naming the file, the table and the entry)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

from excavkin.errors import ModelError, UnitError
from excavkin.io.toml_model import TomlReader, build_model, load_model
from excavkin.units import to_si

if TYPE_CHECKING:
    from excavkin.model import Model


class MachineReader(TomlReader):
    """The model reader's units and errors, plus the machine file's field lookups."""

    def subtable(self, data: dict[str, Any], key: str, where: str) -> dict[str, Any]:
        t = data.get(key)
        if not isinstance(t, dict):
            raise self.err("is missing or not a table", where)
        return t

    def field_qty(
        self, t: dict[str, Any], key: str, kind: str, table: str, default: float | None = None
    ) -> float:
        if key not in t:
            if default is None:
                raise self.err(f"{key!r} is missing", table)
            return default
        try:
            return to_si(t[key], kind, self.units.get(kind))
        except UnitError as exc:
            raise UnitError(exc.problem, table=table, entry=key, source=self.source) from None

    def bounded(
        self,
        t: dict[str, Any],
        key: str,
        kind: str,
        table: str,
        low: float,
        high: float,
        unit: str,
        *,
        default: float | None = None,
        open_low: bool = True,
    ) -> float:
        """A quantity in SI within its range: `field_qty` checked by
        [`within`][excavkin.machinery.file_fields.within].

        Parameters
        ----------
        t : dict
            The table holding the entry.
        key : str
            The entry.
        kind : str
            Its kind of quantity (``"length"``, ``"pressure"``, …).
        table : str
            The table's name, for messages.
        low, high : float
            The range (SI): more than ``low`` (at least, with ``open_low=False``), at most
            ``high``.
        unit : str
            The SI unit the message writes.
        default : float, optional
            Where the entry is missing; without it, a missing entry is an error.
        open_low : bool
            Whether ``low`` itself is refused.

        Returns
        -------
        float
        """
        value = self.field_qty(t, key, kind, table, default)
        return within(self, value, table, key, low, high, unit, open_low=open_low)

    def text(self, t: dict[str, Any], key: str, table: str, default: str | None = None) -> str:
        v = t.get(key, default)
        if not isinstance(v, str):
            raise self.err(
                f"{key!r} must be a string" if key in t else f"{key!r} is missing",
                table,
                key if key in t else None,
            )
        return v


def within(
    r: MachineReader,
    value: float,
    table: str,
    key: str,
    low: float,
    high: float,
    unit: str,
    *,
    open_low: bool = True,
) -> float:
    """``value`` if ``low < value ≤ high`` (``low ≤`` with ``open_low=False``), else an error
    naming the file, the table and the entry."""
    ok = (value > low if open_low else value >= low) and value <= high
    if not ok:
        side = "more than" if open_low else "at least"
        raise r.err(
            f"{key} = {value:.6g} {unit} must be {side} {low:g} and at most {high:g} {unit}",
            table,
            key,
        )
    return value


#: a machine file's schema, which an inline [model] table takes unless it says otherwise
MODEL_SCHEMA_VERSION = 1


def read_model(r: MachineReader, spec: Any, source: str | None, example: str) -> Model:
    """A machine file's ``model``: a model file's name (beside the machine file) or an inline
    ``[model]`` table, which takes the machine file's units where it gives none.

    Parameters
    ----------
    r : MachineReader
        The machine file.
    spec : str or mapping
        The ``model`` entry.
    source : str, optional
        The machine file's path, for relative model files and messages.
    example : str
        A model file's name for the message of a ``model`` of neither kind
        (``"front.toml"``).

    Returns
    -------
    Model
        Validated (the wing makes it a mechanism: this layer solves through the wing's).

    Raises
    ------
    ModelError
        Naming the machine file and ``model``, and the model's own table and entry.
    """
    if isinstance(spec, str):
        base = Path(source).parent if source else Path.cwd()
        path = base / spec
        if not path.exists():
            raise r.err(f"the model file {str(path)!r} does not exist", entry="model")
        try:
            return load_model(path)
        except ModelError as exc:
            raise r.err(f"the model file it names cannot be used: {exc}", entry="model") from None
    if isinstance(spec, dict):
        inline = dict(spec)
        inline.setdefault("schema_version", MODEL_SCHEMA_VERSION)
        if "units" not in inline and r.units:
            inline["units"] = {
                k: v for k, v in r.units.items() if k in ("length", "angle", "mass", "inertia")
            }
        try:
            return build_model(inline, source)
        except ModelError as exc:
            raise type(exc)(
                exc.problem,
                table=f"model.{exc.table}" if exc.table else "model",
                entry=exc.entry,
                source=source,
            ) from None
    raise r.err(
        f'model must name a model file (model = "{example}") or be a [model] table '
        "with the model's points, bodies and drivers",
        entry="model",
    )


def check_head(r: MachineReader, version: int, allowed: set[str], example: str) -> None:
    """Refuse a machine file of another ``schema_version``, a model file given as a machine
    file, and top-level keys the family does not read.

    Parameters
    ----------
    r : MachineReader
        The machine file.
    version : int
        The schema version the family reads.
    allowed : set of str
        The family's top-level keys.
    example : str
        A model file's name, for the message to a model file given as a machine file.

    Raises
    ------
    ModelError
        Naming the file and the key.
    """
    data = r.data
    ver = data.get("schema_version")
    if type(ver) is not int or ver != version:
        raise r.err(
            f"schema_version = {ver!r} is not supported (this version of excavkin reads {version})"
            if ver is not None
            else f"schema_version is missing (this version reads {version})",
            entry="schema_version",
        )
    unknown = set(data) - allowed
    if unknown and "model" not in data and {"points", "bodies"} & set(data):
        raise r.err(
            "this is a model file (a mechanism's points and bodies), and a machine file is "
            f'expected: one that names its model (model = "{example}"); '
            "`excavkin demo --list` lists the built-in machines"
        )
    if unknown:
        raise r.err(
            f"unknown top-level key{'s' if len(unknown) > 1 else ''} "
            f"{', '.join(sorted(unknown))} (allowed: {', '.join(sorted(allowed))})"
        )
