"""Start-up time of the command line: ``excavkin --help`` against the interpreter's own start.

Run: ``python benchmarks/bench_startup.py [REPEAT]``. Prints the median and the best wall time
over REPEAT runs (default 10) of ``python -c pass`` (the floor: the interpreter and its site
packages), of ``python -m excavkin --help``, of the ``excavkin`` console script's ``--help`` and
of ``excavkin COMMAND --help`` for each command, all with this interpreter. Target: the
top-level help in ≤ 0.15 s. The floor is printed beside it because it is much of that time and
excavkin cannot lower it. The programs run in turn, so that a change in the machine's load falls
on all alike (on a busy machine the best time is the nearer to an idle one's); each runs with
its bytecode cached (in a temporary folder), as an installed package has it, even where the
environment says not to write bytecode. Not a test: machines differ.
"""

from __future__ import annotations

import functools
import os
import shutil
import statistics
import subprocess
import sys
import sysconfig
import tempfile
from collections.abc import Mapping
from pathlib import Path

from timing import times_in_turn

TARGET = 0.15
COMMANDS = [
    *(["check"], ["demo"], ["report"], ["simulate"], ["solve"], ["tolerance"]),
    *(["excavator"], ["excavator", "ranges"], ["reproduce"], ["reproduce", "mo100"]),
]


def console_script() -> str | None:
    """The ``excavkin`` script installed beside this interpreter (else on the PATH)."""
    beside = Path(sysconfig.get_path("scripts")) / "excavkin"
    return str(beside) if beside.is_file() else shutil.which("excavkin")


def programs() -> dict[str, list[str]]:
    """What is timed, by label: the floor first, then the top-level help."""
    python = sys.executable
    out = {
        "python -c pass (the floor)": [python, "-c", "pass"],
        "python -m excavkin --help": [python, "-m", "excavkin", "--help"],
    }
    script = console_script()
    if script:
        out["excavkin --help (console script)"] = [script, "--help"]
    for args in COMMANDS:
        out[f"excavkin {' '.join(args)} --help"] = [python, "-m", "excavkin", *args, "--help"]
    return out


def main(repeat: int = 10) -> float:
    with tempfile.TemporaryDirectory() as cache:
        env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
        return measure(repeat, {**env, "PYTHONPYCACHEPREFIX": cache})


def measure(repeat: int, env: Mapping[str, str]) -> float:
    cmds = programs()
    runs = [
        functools.partial(subprocess.run, cmd, check=True, stdout=subprocess.DEVNULL, env=env)
        for cmd in cmds.values()
    ]
    for run in runs:
        run()  # write the bytecode, warm the file cache
    times = times_in_turn(runs, repeat)
    medians = [statistics.median(t) for t in times]
    print(f"start-up, {repeat} runs each ({sys.executable})")
    print(f"  {'':<33}  median     best   (median over the floor)")
    for label, t, median in zip(cmds, times, medians, strict=True):
        print(f"  {label:<33}: {median:6.3f} s {min(t):6.3f} s   ({median - medians[0]:+.3f} s)")
    print(f"  target: python -m excavkin --help ≤ {TARGET} s")
    if "excavkin --help (console script)" not in cmds:
        print("  (no excavkin console script installed)")
    return medians[1]


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 10)
