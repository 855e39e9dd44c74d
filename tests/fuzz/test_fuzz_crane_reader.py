"""Fuzz the crane machine files: a mutated file (or its model) is read and rated, or refused
with one message naming the file and exit status 2 — never a traceback, never a hang."""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st

import excavkin
from tests.fuzz.test_fuzz_readers import FUZZ, VALUES, check_outcome, mutate

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


#: the stability criterion by factored loads, appended to a machine file
STABILITY = [
    "[stability]",
    'criterion = "factors"',
    "hook_load_factor = 1.3",
    "jib_weight_factor = 0.2",
]


@FUZZ
@given(
    data=st.data(),
    name=st.sampled_from(sorted(CRANES)),
    line=st.integers(0, len(STABILITY) - 1),
    action=st.sampled_from(["value", "delete", "junk", "duplicate", "key"]),
)
def test_mutated_stability_tables(tmp_path_factory, data, name, line, action) -> None:
    """A mutated ``[stability]`` table: the chart rated, or one message naming the file."""
    machine, model = CRANES[name]
    lines = list(STABILITY)
    if action == "value" and "=" in lines[line]:
        key = lines[line].split("=", 1)[0]
        lines[line] = f"{key}= {data.draw(VALUES, label='value')}"
    elif action == "delete":
        del lines[line]
    elif action == "duplicate":
        lines.insert(line, lines[line])
    elif action == "key":
        lines.insert(line + 1, data.draw(st.sampled_from(["gamma = 1", "share = 0.85"])))
    else:
        lines.insert(line, data.draw(st.sampled_from(["[", "]]", "x =", "= 1", "[stability]"])))
    folder = tmp_path_factory.mktemp("crane")
    (folder / f"{name}.toml").write_text(model)
    path = folder / "machine.toml"
    path.write_text(machine + "\n" + "\n".join(lines) + "\n")
    check_outcome(["crane", "chart", str(path), *COMMANDS["chart"]], str(folder))
