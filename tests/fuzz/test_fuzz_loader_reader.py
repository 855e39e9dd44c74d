"""Fuzz the wheel-loader machine file: a mutated file is read and rated, or refused with one
message naming the file and exit status 2 — never a traceback, never a hang."""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st

import excavkin
from tests.fuzz.test_fuzz_readers import FUZZ, check_outcome, mutate

LOADER = excavkin.example_path("wheel_loader_machine").read_text()
MODEL = excavkin.example_path("wheel_loader").read_text()


@FUZZ
@given(data=st.data(), command=st.sampled_from(["ranges", "breakout", "tipping"]))
def test_mutated_loader_machine_files(tmp_path_factory, data, command) -> None:
    folder = tmp_path_factory.mktemp("loader")
    (folder / "wheel_loader.toml").write_text(MODEL)
    path = folder / "machine.toml"
    path.write_text(mutate(LOADER, data))
    check_outcome(["loader", command, str(path)], str(path))
