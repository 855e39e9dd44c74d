"""Fuzz the crane machine files: a mutated file (or its model) is read and rated, or refused
with one message naming the file and exit status 2 — never a traceback, never a hang."""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st

import excavkin
from tests.fuzz.test_fuzz_readers import FUZZ, check_outcome, mutate

CRANES = {
    name: (
        excavkin.example_path(f"{name}_machine").read_text(),
        excavkin.example_path(name).read_text(),
    )
    for name in ("knuckle_crane", "telescopic_crane", "synchronised_crane")
}
#: each command at its smallest (the chart of a few radii, a coarse range, a short slew)
COMMANDS = {
    "chart": ["--step", "3m", "--sectors", "2"],
    "range": ["--samples", "3"],
    "supports": ["--radius", "6m", "--load", "1t", "--samples", "3"],
}


@FUZZ
@given(
    data=st.data(),
    name=st.sampled_from(sorted(CRANES)),
    command=st.sampled_from(sorted(COMMANDS)),
    which=st.sampled_from(["machine", "model"]),
)
def test_mutated_crane_files(tmp_path_factory, data, name, command, which) -> None:
    machine, model = CRANES[name]
    folder = tmp_path_factory.mktemp("crane")
    if which == "machine":
        machine = mutate(machine, data)
    else:
        model = mutate(model, data)
    (folder / f"{name}.toml").write_text(model)
    path = folder / "machine.toml"
    path.write_text(machine)
    # an error names the file it is in: the machine file or its model, both in this folder
    check_outcome(["crane", command, str(path), *COMMANDS[command]], str(folder))
