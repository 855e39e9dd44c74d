"""The backends at small batches, and what a kernel's first compile and later load cost.

Run: ``python benchmarks/bench_backends.py [N]`` (default N = 10 000 samples). Prints:

- per model (the four-bar, the excavator), the full kinematic state of N samples with rates,
  ``backend="numpy"`` against ``backend="numba"`` with the kernel cached (and what ``"auto"``
  picks and takes): ns a sample, best of rounds taken in turn;
- the first compile of each model's kinematic kernel, in a fresh cache folder (what a user
  waits for once per model structure, announced by the CLI), and the load of that cached
  kernel by a new process (numba's import included), which ``"auto"`` pays once per process;
- with ``--large``: the first compile of larger models' kinematic and forces kernels (chains of
  four-bars of 34, 67, 101 and 301 points, each in a fresh process and cache; a kernel over
  `excavkin.kinematics.vectorise.PASS` statements is compiled in passes, one by one), the
  peak memory and the growth exponent of the compile times, and what ``backend="numba"``
  says of a model over `excavkin.kinematics.compiled.COMPILE_POINTS` points.

Not a test: machines differ; the ratios are what is tracked.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import excavkin
from excavkin import backends
from excavkin.kinematics import compiled

SRC = str(Path(__file__).resolve().parents[1] / "src")


def inputs(mech: excavkin.Mechanism, n: int) -> dict[str, np.ndarray]:
    """A sweep of every driver about its sketch value."""
    out = {}
    for k, v in mech.sketch_values().items():
        span = 0.3 if mech.input_kind(k) == "angle" else 0.03 * v
        out[k] = v + span * np.sin(np.linspace(0.0, 7.0, n) + len(k))
    return out


def per_sample(name: str, n: int, rounds: int = 15) -> None:
    mech = excavkin.load(excavkin.example_path(name))
    values = inputs(mech, n)
    rates = {k: 0.5 for k in values}
    mech.solve(values, rates, backend="numba")  # compiled before (or loaded from the cache)
    picked = backends.choose("auto", compiled.job(mech.plan), n).name
    times: dict[str, list[float]] = {"numpy": [], "numba": [], "auto": []}
    for _ in range(rounds):
        for backend in times:
            t = time.perf_counter()
            mech.solve(values, rates, backend=backend)  # type: ignore[arg-type]
            times[backend].append(time.perf_counter() - t)
    ns = {b: min(t) / n * 1e9 for b, t in times.items()}
    print(
        f"  {name:10s} N = {n:,}: NumPy {ns['numpy']:6.0f} ns/sample, numba (cached) "
        f"{ns['numba']:6.0f}, auto ({picked}) {ns['auto']:6.0f}; NumPy / numba "
        f"{ns['numpy'] / ns['numba']:.2f}×"
    )


FIRST = """
import time, numpy as np, excavkin
mech = excavkin.load(excavkin.example_path({name!r}))
q = {{k: np.full(8, v) for k, v in mech.sketch_values().items()}}
t = time.perf_counter()
mech.solve(q, backend="numba")
print(time.perf_counter() - t)
"""


def first_compile_and_load(name: str) -> None:
    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "EXCAVKIN_CACHE_DIR": cache, "PYTHONPATH": SRC}
        code = FIRST.format(name=name)
        runs = [
            float(subprocess.run([sys.executable, "-c", code], env=env, check=True,
                                 capture_output=True, text=True).stdout)
            for _ in range(3)
        ]  # fmt: skip
    print(
        f"  {name:10s} first compile {runs[0]:5.1f} s (a fresh cache); a new process loading "
        f"the cached kernel {min(runs[1:]):.2f} s"
    )


LARGE = """
import dataclasses, resource, sys, time, numpy as np, excavkin, excavkin.errors
model = excavkin.load(sys.argv[1]).model  # each moving body of a unit mass: forces to compile
bodies = tuple(b if b.ground else dataclasses.replace(b, mass=1.0) for b in model.bodies)
mech = excavkin.Mechanism(dataclasses.replace(model, bodies=bodies))
q = {k: np.full(8, v) for k, v in mech.sketch_values().items()}
t = time.perf_counter()
try:
    kin = mech.solve(q, backend="numba")
    seconds = time.perf_counter() - t
    t = time.perf_counter()
    mech.forces(kin, [excavkin.Gravity()], backend="numba")
    forces = time.perf_counter() - t
    gib = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20
    print(seconds, forces, gib)
except excavkin.errors.InputError as e:
    print("refused:", e)
"""


def large_compiles(points: tuple[int, ...] = (34, 67, 101, 301)) -> None:
    """The kinematic and forces kernels' first compile of chains of four-bars (3·stages + 1
    points), and the growth exponent of each (a least-squares fit of log time on log points)."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the tests' generators
    from tests.models import fourbar_chain

    seen: list[tuple[int, float, float]] = []
    for n in points:
        with tempfile.TemporaryDirectory() as cache:
            model = Path(cache) / "chain.toml"
            model.write_text(fourbar_chain((n - 1) // 3))
            env = {**os.environ, "EXCAVKIN_CACHE_DIR": cache, "PYTHONPATH": SRC}
            run = [sys.executable, "-c", LARGE, str(model)]
            done = subprocess.run(run, env=env, check=True, capture_output=True, text=True)
        out = done.stdout.strip()
        if out.startswith("refused"):
            print(f"  {n:4d} points: {out}")
            continue
        seconds, forces, gib = (float(v) for v in out.split())
        seen.append((n, seconds, forces))
        print(
            f"  {n:4d} points: first compile {seconds:6.1f} s (kinematics), {forces:6.1f} s "
            f"(forces), peak memory {gib:.2f} GiB"
        )
    if len(seen) >= 2:
        logs = np.log(np.array(seen))
        kin = np.polyfit(logs[:, 0], logs[:, 1], 1)[0]
        forces = np.polyfit(logs[:, 0], logs[:, 2], 1)[0]
        print(f"  growth exponent of the compile time: kinematics {kin:.2f}, forces {forces:.2f}")


def main(n: int) -> None:
    print(f"the kinematics at a small batch, {os.cpu_count()} cores")
    for name in ("fourbar", "excavator"):
        per_sample(name, n)
    print("the kinematic kernel: compile once, then load")
    for name in ("fourbar", "excavator"):
        first_compile_and_load(name)


if __name__ == "__main__":
    if "--large" in sys.argv:
        print(f"larger models' kinematic kernels, first compile, {os.cpu_count()} cores")
        large_compiles()
    else:
        main(int(sys.argv[1]) if len(sys.argv) > 1 else 10_000)
