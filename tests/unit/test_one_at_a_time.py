"""Every generator of kernel source parses under the process's one lock
(`excavkin.kinematics.one_at_a_time`): CPython 3.11's AST construction is not safe in two
threads at once (a study's chunks asked for their kernel together, and one parse raised
``SystemError: AST constructor recursion depth mismatch``)."""

from __future__ import annotations

import ast
import threading
from collections.abc import Callable

import pytest

import excavkin
from excavkin.kinematics import compiled, compiled_tangents, one_at_a_time, split, vectorise


def _held_at_every_parse(monkeypatch: pytest.MonkeyPatch, make: Callable[[], object]) -> list[bool]:
    """For each `ast.parse` while ``make()`` runs: whether the lock was held (another thread
    could not take it)."""
    real = ast.parse
    seen: list[bool] = []

    def parse(*args: object, **kwargs: object) -> ast.AST:
        free: list[bool] = []

        def probe() -> None:
            got = one_at_a_time._lock.acquire(blocking=False)
            if got:
                one_at_a_time._lock.release()
            free.append(got)

        t = threading.Thread(target=probe)
        t.start()
        t.join()
        seen.append(not free[0])
        return real(*args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(ast, "parse", parse)
    make()
    return seen


def test_each_generator_parses_holding_the_lock(monkeypatch: pytest.MonkeyPatch) -> None:
    plan = excavkin.load(excavkin.example_path("fourbar")).plan
    text = compiled.source(plan, write_at_rest=False)
    vectorise.vectorised.cache_clear()
    vectorise.written_rows.cache_clear()
    split.split.cache_clear()
    compiled_tangents._source.cache_clear()
    from excavkin.gpu import DeviceKernel, device_source

    makers = [
        lambda: vectorise.vectorised(text, False),
        lambda: vectorise.written_rows(vectorise.vectorised(text, False, True)),
        lambda: split.split(text.replace("range(", "range(", 1) + "\n"),
        lambda: compiled_tangents.source(plan),
        lambda: DeviceKernel(None, device_source(text)),
    ]
    for make in makers:
        seen = _held_at_every_parse(monkeypatch, make)
        monkeypatch.undo()
        assert seen and all(seen), makers.index(make)  # (every maker parses)


def test_the_lock_is_reentrant_and_free_after() -> None:
    @one_at_a_time.one_at_a_time
    def inner() -> int:
        return 1

    @one_at_a_time.one_at_a_time
    def outer() -> int:
        return inner() + 1

    assert outer() == 2
    assert one_at_a_time._lock.acquire(blocking=False)
    one_at_a_time._lock.release()
