"""One generator of kernel source at a time in a process.

The generators rewrite source through Python's `ast`. CPython 3.11 makes AST objects with a
recursion count kept for the whole interpreter, not for each thread, and two threads parsing
at once can leave it unbalanced: ``ast.parse`` then raises ``SystemError: AST constructor
recursion depth mismatch`` (CPython issue 106905). A study's chunks, each on a thread of its
own, ask for their kernel's source at the same moment (seen once in the suite). Each
generator takes this lock (re-entrant: one calls another), so that no two parse together;
generating source is Python holding the GIL anyway, so the lock costs no parallelism.
"""

from __future__ import annotations

import functools
import threading
from collections.abc import Callable
from typing import ParamSpec, TypeVar

__all__ = ["one_at_a_time"]

P = ParamSpec("P")
R = TypeVar("R")

_lock = threading.RLock()


def one_at_a_time(fn: Callable[P, R]) -> Callable[P, R]:
    """``fn`` run under the process's one lock of source generators (below a cache, so that
    a cached result is read without it waiting).

    Parameters
    ----------
    fn : callable
        A function that parses or unparses Python source with `ast`.

    Returns
    -------
    callable
        ``fn``, holding the lock while it runs.
    """

    @functools.wraps(fn)
    def locked(*args: P.args, **kwargs: P.kwargs) -> R:
        with _lock:
            return fn(*args, **kwargs)

    return locked
