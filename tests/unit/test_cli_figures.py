"""A command that writes figures closes them: none is left open in the process (a library
user's session, the tests), and each file is written whole (a temporary file moved into
place), never half."""

from __future__ import annotations

from pathlib import Path

import matplotlib
import pytest

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from click.testing import CliRunner  # noqa: E402

from excavkin.cli import main  # noqa: E402

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _run(args: list[str]) -> str:
    plt.close("all")
    r = CliRunner().invoke(main, args)
    assert r.exit_code == 0, r.output
    assert plt.get_fignums() == [], args  # every figure closed
    return r.output


def test_the_excavators_force_maps_are_closed_once_written(tmp_path: Path) -> None:
    machine = EXAMPLES / "excavator_machine.toml"
    out = _run(["excavator", "stability", str(machine), "--samples", "5", "--map",
                str(tmp_path / "m"), "--swing", "side"])  # fmt: skip
    assert out.count("wrote ") == 5
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "m-limits-arm.png", "m-limits-bucket.png", "m-support.png", "m-tipping-front.png",
        "m-tipping-side.png",
    ]  # fmt: skip


def test_a_shovels_plot_is_written_whole_and_closed(tmp_path: Path) -> None:
    plot = tmp_path / "loads.svg"
    _run(["shovel", "loads", str(EXAMPLES / "mining_shovel_machine.toml"), "--samples", "5",
          "--plot", str(plot)])  # fmt: skip
    assert [p.name for p in tmp_path.iterdir()] == ["loads.svg"]  # no temporary file left
    assert plot.read_text(encoding="utf-8").rstrip().endswith("</svg>")


def test_a_shovels_plot_that_fails_half_written_leaves_no_file(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A figure's write that fails half-way (a full disk) leaves nothing at the target."""
    from matplotlib.figure import Figure

    def half(self: Figure, fname: object, **kwargs: object) -> None:
        Path(str(fname)).write_text("<svg half", encoding="utf-8")
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(Figure, "savefig", half)
    plot = tmp_path / "loads.svg"
    plt.close("all")
    r = CliRunner().invoke(main, ["shovel", "loads", str(EXAMPLES / "mining_shovel_machine.toml"),
                                  "--samples", "5", "--plot", str(plot)])  # fmt: skip
    assert r.exit_code != 0
    assert "No space left on device" in r.output and "Traceback" not in r.output
    assert list(tmp_path.iterdir()) == []  # neither the target nor a temporary file
    assert plt.get_fignums() == []
