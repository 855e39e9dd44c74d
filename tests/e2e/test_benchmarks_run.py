"""Every benchmark runs: each script of ``benchmarks/`` on a few samples, as a user runs it, to
the end (its figures mean nothing at this size; a benchmark that no longer runs is what is
caught — one once failed on its last table, after its measurements)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
BENCHMARKS = ROOT / "benchmarks"

#: each script and its arguments for a run of seconds
SMALL = {
    "bench_backends.py": ["2000"],
    "bench_cams.py": ["2000"],
    "bench_check.py": ["30", "60"],
    "bench_compiled.py": ["20000"],
    "bench_designs.py": ["2000"],
    "bench_files.py": [],
    "bench_forces_growth.py": ["11", "31"],
    "bench_kinematics.py": ["20000"],
    "bench_kinetostatics.py": ["20000"],
    "bench_newton.py": ["20000"],
    "bench_sensitivities.py": ["2000"],
    "bench_startup.py": ["1"],
    "bench_study.py": ["200", "--repeat=1"],
    "bench_threads.py": ["20000", "2"],
}


def test_every_benchmark_is_listed() -> None:
    assert sorted(SMALL) == sorted(p.name for p in BENCHMARKS.glob("bench_*.py"))


@pytest.mark.parametrize("script", sorted(SMALL))
def test_a_benchmark_runs_to_its_end(script: str) -> None:
    env = {
        **os.environ,
        "PYTHONPATH": os.pathsep.join([str(ROOT / "src"), os.environ.get("PYTHONPATH", "")]),
    }
    r = subprocess.run(
        [sys.executable, str(BENCHMARKS / script), *SMALL[script]],
        cwd=ROOT, env=env, capture_output=True, text=True, timeout=600,
    )  # fmt: skip
    assert r.returncode == 0, (script, r.stderr[-3000:])
    assert r.stdout.strip(), script
    assert "Traceback" not in r.stderr, (script, r.stderr[-3000:])
