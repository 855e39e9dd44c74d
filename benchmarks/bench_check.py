"""``excavkin check`` and the plan compile on large generated models, and how they grow.

Run: ``python benchmarks/bench_check.py [SIZES...]`` (default 1000 3000 10000 points). Two
models of each size, from ``tests/models.py``: a chain of crank-rocker four-bars (each rocker
carries the next stage's crank pin: a dyad and an attach per stage, every pivot on the
ground), a truss (a triangulated strip: each new point a dyad of two bars from the two
before it) and the same truss with one bar of each dyad a driven cylinder (an input a
point). For each:

* **check**: what ``excavkin check`` does, as a library call — read and validate the file,
  compile the plan, assemble the sketch, describe the mechanism and its plan;
* **compile**: the plan compile alone (``compile_plan`` of the validated model);
* **CLI**: ``excavkin check FILE`` started anew, once per model at the largest size.

It prints each time and the growth exponent between consecutive sizes, log(t₂/t₁) /
log(n₂/n₁), measured in the same run (1: linear; target ≤ 1.2). Best of a few repeats in the
same process. Not a test: machines differ; the exponents are what is tracked.
"""

from __future__ import annotations

import math
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

from timing import best_of

import excavkin
from excavkin.io.toml_model import load_model
from excavkin.model.validate import validate
from excavkin.structure.builder import compile_plan

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the tests' model generators
from tests.models import fourbar_chain, truss  # noqa: E402

#: each model by its number of points (the chain's is 3·stages + 1)
MODELS: dict[str, Callable[[int], str]] = {
    "chain": lambda n: fourbar_chain((n - 1) // 3),
    "truss": truss,
    "cylinders": lambda n: truss(n, cylinders=True),
}


def check(path: Path) -> str:
    """What ``excavkin check`` computes, as a library call: its text."""
    mech = excavkin.load(path)
    values = ", ".join(f"{k} = {v:.6g}" for k, v in mech.sketch_values().items())
    return mech.describe() + values


def exponent(t1: float, t2: float, n1: int, n2: int) -> float:
    """The growth exponent between two sizes: t ∝ n^k."""
    return math.log(t2 / t1) / math.log(n2 / n1)


def main(sizes: list[int]) -> dict[str, list[tuple[int, float, float]]]:
    out: dict[str, list[tuple[int, float, float]]] = {}
    with tempfile.TemporaryDirectory() as tmp:
        for kind, make in MODELS.items():
            rows = out.setdefault(kind, [])
            for n in sizes:
                path = Path(tmp) / f"{kind}{n}.toml"
                path.write_text(make(n))
                model = load_model(path)
                validate(model)
                points = len(model.points)
                plan = compile_plan(model)
                assert len(plan.points) == points
                assert plan.mobility.mobility == len(plan.inputs) and not plan.has_newton
                repeat = 3 if n <= 3000 else 2
                t_check = best_of(lambda p=path: check(p), repeat)
                t_plan = best_of(lambda m=model: compile_plan(m), repeat)
                rows.append((points, t_check, t_plan))
                print(
                    f"{kind:9} {points:6,} points: check {t_check:7.3f} s "
                    f"({t_check / points * 1e6:5.0f} µs a point), plan compile {t_plan:6.3f} s",
                    flush=True,
                )
            for (n1, c1, p1), (n2, c2, p2) in zip(rows, rows[1:], strict=False):
                print(
                    f"{kind:9} {n1:,} → {n2:,}: growth exponent check "
                    f"{exponent(c1, c2, n1, n2):.2f}, plan compile {exponent(p1, p2, n1, n2):.2f}"
                    " (target ≤ 1.2)"
                )
            # the command itself, started anew, once at the largest size
            t0 = time.perf_counter()
            run = subprocess.run(
                [sys.executable, "-m", "excavkin", "check", str(path)],
                capture_output=True,
                text=True,
                check=False,
            )
            t_cli = time.perf_counter() - t0
            assert run.returncode == 0, run.stderr
            assert run.stdout.rstrip().endswith("assembles at its sketch")
            print(f"{kind:9} excavkin check of {rows[-1][0]:,} points, end to end: {t_cli:.2f} s")
    return out


if __name__ == "__main__":
    main([int(a) for a in sys.argv[1:]] or [1000, 3000, 10000])
