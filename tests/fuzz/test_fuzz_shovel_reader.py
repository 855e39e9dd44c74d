"""Fuzz the rope-shovel machine files: a mutated file is read and rated, or refused with one
message naming the file and exit status 2 — never a traceback, never a hang."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

import excavkin
from tests.fuzz.test_fuzz_readers import FUZZ, VALUES, check_outcome, mutate

SHOVEL = excavkin.example_path("mining_shovel_machine").read_text()
BACKHOE = excavkin.example_path("eo4112_machine").read_text()
MODEL = excavkin.example_path("mining_shovel").read_text()
BACKHOE_MODEL = excavkin.example_path("rope_shovel").read_text()


@settings(FUZZ, max_examples=40)
@given(data=st.data())
def test_mutated_shovel_machine_files(tmp_path_factory, data) -> None:
    folder = tmp_path_factory.mktemp("shovel")
    (folder / "mining_shovel.toml").write_text(MODEL)
    path = folder / "machine.toml"
    path.write_text(mutate(SHOVEL, data))
    check_outcome(["shovel", "dig", str(path), "--samples", "3"], str(path))


@settings(FUZZ, max_examples=40)
@given(data=st.data())
def test_mutated_backhoe_machine_files(tmp_path_factory, data) -> None:
    folder = tmp_path_factory.mktemp("backhoe")
    (folder / "rope_shovel.toml").write_text(BACKHOE_MODEL)
    path = folder / "machine.toml"
    path.write_text(mutate(BACKHOE, data))
    check_outcome(["shovel", "haul", str(path), "--samples", "3"], str(path))


def _boom_lines(text: str) -> list[int]:
    lines = text.splitlines()
    start = lines.index("[boom]")
    return [k for k in range(start, len(lines)) if "=" in lines[k] or lines[k] == "[boom]"]


@settings(FUZZ, max_examples=40)
@given(data=st.data())
def test_mutated_backhoe_boom_tables(tmp_path_factory, data) -> None:
    """The rope backhoe's [boom] table (its hoist): one of its lines given another value,
    deleted, duplicated, or junk beside it."""
    folder = tmp_path_factory.mktemp("boom")
    (folder / "rope_shovel.toml").write_text(BACKHOE_MODEL)
    lines = BACKHOE.splitlines()
    k = data.draw(st.sampled_from(_boom_lines(BACKHOE)), label="line")
    action = data.draw(st.sampled_from(["value", "delete", "junk", "duplicate"]), label="action")
    if action == "value" and "=" in lines[k]:
        lines[k] = f"{lines[k].split('=', 1)[0]}= {data.draw(VALUES, label='value')}"
    elif action == "delete":
        del lines[k]
    elif action == "duplicate":
        lines.insert(k, lines[k])
    else:
        lines.insert(k, data.draw(st.sampled_from(["[", "x =", "[boom.x]", "[gravity]", "\x00"])))
    path = folder / "machine.toml"
    path.write_text("\n".join(lines) + "\n")
    check_outcome(["shovel", "haul", str(path), "--samples", "3"], str(path))
