"""``excavkin loader ranges|breakout|tipping``: each command prints its result's summary and
writes its table, equal to the library's; bad input is one message and exit status 2."""

from __future__ import annotations

import pandas as pd
import pytest
from click.testing import CliRunner
from numpy.testing import assert_allclose

from excavkin.cli import main
from excavkin.loader.breakout import breakout
from excavkin.loader.capacity import capacity
from excavkin.loader.dimensions import dimensions
from excavkin.loader.machine_file import load_machine
from excavkin.loader.tipping import static_tipping
from tests.conftest import EXAMPLES

CASES = {
    "ranges": (dimensions, "value", "hinge-pin height at full lift"),
    "breakout": (breakout, "force", "breakout force"),
    "tipping": (static_tipping, "tipping_load", "rated operating capacity"),
    "capacity": (capacity, "lift_capacity", "lift capacity to full height"),
}


@pytest.mark.parametrize("name", list(CASES))
def test_a_loader_command_prints_and_writes_the_librarys_table(tmp_path, name) -> None:
    analysis, column, text = CASES[name]
    out = tmp_path / f"{name}.parquet"
    r = CliRunner().invoke(main, ["loader", name, "wheel_loader_machine", "-o", str(out)])
    assert r.exit_code == 0, r.output
    assert text in r.output and f"wrote {out}" in r.output
    ref = analysis(load_machine(EXAMPLES / "wheel_loader_machine.toml")).to_frame()
    got = pd.read_parquet(out)
    assert_allclose(got[column].to_numpy(float), ref[column].to_numpy(float), rtol=1e-12)
    # the file exists now: refused without --force, replaced with it
    again = CliRunner().invoke(main, ["loader", name, "wheel_loader_machine", "-o", str(out)])
    assert again.exit_code == 2 and "exists" in again.output
    forced = ["loader", name, "wheel_loader_machine", "-o", str(out), "--force"]
    assert CliRunner().invoke(main, forced).exit_code == 0


def test_another_familys_file_is_one_message() -> None:
    r = CliRunner().invoke(main, ["loader", "tipping", "excavator_machine"])
    assert r.exit_code == 2 and "loader machine files" in r.output
    assert "Traceback" not in r.output
