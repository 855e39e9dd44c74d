"""Values made once for a solve plan object: its kernel's source, its constants' table, a
study kernel's rows. A plan holds arrays and is not hashable, so a value is kept by the
plan's ``id`` — with the plan itself, so that the id of a plan since freed is never taken for
another's — and a few plans' at most (a process that makes many plans does not grow)."""

from __future__ import annotations

import threading
from collections.abc import Hashable
from typing import TYPE_CHECKING, Generic, TypeVar

if TYPE_CHECKING:
    from excavkin.structure.plan import SolvePlan

__all__ = ["PlanMemo"]

V = TypeVar("V")


class PlanMemo(Generic[V]):
    """Values by plan object and key, ``most`` at most (all forgotten when full), safe from
    several threads.

    Parameters
    ----------
    most : int, default 16

    Examples
    --------
    >>> import excavkin
    >>> plan = excavkin.load(excavkin.example_path("fourbar")).plan
    >>> memo: PlanMemo[str] = PlanMemo()
    >>> memo.get(plan, "source") is None
    True
    >>> memo.put(plan, "text", "source")
    'text'
    >>> memo.get(plan, "source"), memo.get(plan, "other")
    ('text', None)
    """

    def __init__(self, most: int = 16) -> None:
        self._most = most
        self._lock = threading.Lock()
        self._kept: dict[tuple[int, Hashable], tuple[SolvePlan, V]] = {}

    def get(self, plan: SolvePlan, key: Hashable = None) -> V | None:
        """The value kept for ``plan`` and ``key``, or None.

        Parameters
        ----------
        plan : SolvePlan
        key : hashable, optional

        Returns
        -------
        object or None
        """
        with self._lock:
            kept = self._kept.get((id(plan), key))
        return kept[1] if kept is not None and kept[0] is plan else None

    def put(self, plan: SolvePlan, value: V, key: Hashable = None) -> V:
        """Keep ``value`` for ``plan`` and ``key``; returns it.

        Parameters
        ----------
        plan : SolvePlan
        value : object
        key : hashable, optional

        Returns
        -------
        object
            ``value``.
        """
        with self._lock:
            if len(self._kept) >= self._most:
                self._kept.clear()
            self._kept[(id(plan), key)] = (plan, value)
        return value
