"""Typed errors and warnings.

Every error a user can cause names *where* (file, table, entry, sample) and *what*: the CLI prints
``str(error)`` as one paragraph and exits non-zero, never a traceback.
"""

from __future__ import annotations

import difflib
from collections.abc import Collection, Iterable, Sequence


class ExcavkinError(Exception):
    """Base of all errors excavkin raises on purpose."""


class ModelError(ExcavkinError):
    """A mechanism description is wrong: unknown names, bad units, impossible geometry.

    Parameters
    ----------
    problem : str
        What is wrong, in one sentence.
    table, entry : str, optional
        Where in the model (``"bodies"``, ``"rocker"``).
    source : str, optional
        The file the model came from.
    """

    def __init__(
        self,
        problem: str,
        *,
        table: str | None = None,
        entry: str | None = None,
        source: str | None = None,
    ) -> None:
        self.problem = problem
        self.table = table
        self.entry = entry
        self.source = source
        super().__init__(self._text())

    def _text(self) -> str:
        where = []
        if self.source:
            where.append(self.source)
        if self.table:
            where.append(f"[{self.table}]")
        if self.entry:
            where.append(f"{self.entry!r}")
        prefix = " ".join(where)
        return f"{prefix}: {self.problem}" if prefix else self.problem

    def with_source(self, source: str) -> ModelError:
        """Return a copy of this error that also names the file.

        Parameters
        ----------
        source : str
            The file the model came from.

        Returns
        -------
        ModelError
            An error of the same type, problem, table and entry.
        """
        err = type(self).__new__(type(self))
        ModelError.__init__(err, self.problem, table=self.table, entry=self.entry, source=source)
        return err


class UnitError(ModelError):
    """A quantity has a wrong, missing or unknown unit.

    Parameters
    ----------
    problem, table, entry, source
        As for `ModelError`.
    """


class MobilityError(ModelError):
    """The driver count does not match the mobility, or a sub-chain is over/under-constrained.

    Parameters
    ----------
    problem, table, entry, source
        As for `ModelError`.
    """


class AssemblyError(ModelError):
    """The mechanism cannot be assembled at its sketch with the given lengths.

    Parameters
    ----------
    problem, table, entry, source
        As for `ModelError`.
    """


class InputError(ExcavkinError):
    """A solve request is wrong: an unknown driver, mismatched array shapes, a bad value."""


class SolveFailure(ExcavkinError):
    """Some samples could not be solved (no closure, dead position) and the caller asked to stop.

    Parameters
    ----------
    message : str
        What failed, in one paragraph.

    Attributes
    ----------
    result : object
        The partial result, with its per-sample status.
    """

    def __init__(self, message: str, result: object) -> None:
        self.result = result
        super().__init__(message)


class ExcavkinWarning(UserWarning):
    """Base of excavkin's warnings."""


class SingularityWarning(ExcavkinWarning):
    """Some samples lie at a dead (singular) position."""


class UnknownNameError(InputError, KeyError):
    """A name (point, body, driver, column, ...) that the object does not have.

    It is a `KeyError` too, so ``except KeyError`` keeps working; its message lists the
    closest known names.
    """

    def __str__(self) -> str:  # KeyError would quote the message
        return str(self.args[0]) if self.args else ""


def did_you_mean(name: str, known: Iterable[str]) -> str:
    """``"; did you mean 'rocker'?"`` for the closest known names, or ``""``.

    Parameters
    ----------
    name : str
        The name given.
    known : iterable of str
        The names it could have meant.

    Returns
    -------
    str
        The hint, naming up to three close names, or ``""`` where none is close.
    """
    close = difflib.get_close_matches(name, list(known), n=3, cutoff=0.6)
    return f"; did you mean {' or '.join(repr(c) for c in close)}?" if close else ""


def require_known(what: str, names: Iterable[str], known: Collection[str]) -> None:
    """Refuse the first of ``names`` that is not among ``known`` (`unknown_name`).

    Parameters
    ----------
    what : str
        What kind of name they are (``"parameter"``, ``"crane column"``).
    names : iterable of str
        The names given.
    known : collection of str
        The names there are, in the order the message lists them.

    Raises
    ------
    UnknownNameError
    """
    for name in names:
        if name not in known:
            raise unknown_name(what, name, list(known))


def unknown_name(what: str, name: str, known: Sequence[str]) -> UnknownNameError:
    """``no <what> 'name'; did you mean …? (known: …)``, as an error to raise.

    Parameters
    ----------
    what : str
        What kind of name it is (``"point"``, ``"column"``).
    name : str
        The name given.
    known : sequence of str
        The names there are; the first 30 are listed.

    Returns
    -------
    UnknownNameError
        The error, not raised.
    """
    hint = did_you_mean(name, known)
    shown = ", ".join(known[:30]) + (", …" if len(known) > 30 else "")
    return UnknownNameError(f"no {what} {name!r}{hint} (known: {shown or 'none'})")
