"""The backend seam (excavkin.backends, excavkin.execution): one rule picks where each workload
runs — the kinematics, their tangents and the forces alike — the backends give the same
numbers, the settings travel as one Execution, compiled= still works with a warning, and
NumPy runs everything when numba cannot be imported."""

from __future__ import annotations

import re
import sys
from collections.abc import Iterator

import numpy as np
import pytest
from click.testing import CliRunner

import excavkin
from excavkin import backends
from excavkin.cli import main
from excavkin.errors import InputError
from excavkin.execution import Execution, current, settings, use
from excavkin.kinematics import compiled, solve_kinematics
from excavkin.kinetostatics import Gravity, PointForce, solve_forces

#: the examples every backend solves (closed-form plans), and the loads of their forces
EXAMPLES = ["fourbar", "slider_crank", "excavator", "wheel_loader"]


@pytest.fixture
def chosen(monkeypatch: pytest.MonkeyPatch) -> list[tuple[str, str]]:
    """(workload, backend) of every choice made while the test runs."""
    seen: list[tuple[str, str]] = []
    choose = backends.choose

    def spy(name: str, job: backends.Job, n: int) -> backends.Backend:
        b = choose(name, job, n)
        seen.append((job.what, b.name))
        return b

    monkeypatch.setattr(backends, "choose", spy)
    return seen


@pytest.fixture
def fresh_cache(tmp_path, monkeypatch: pytest.MonkeyPatch) -> Iterator[None]:  # type: ignore[no-untyped-def]
    """No kernel compiled: an empty cache folder, and none in memory."""
    monkeypatch.setenv("EXCAVKIN_CACHE_DIR", str(tmp_path / "kernels"))
    monkeypatch.setattr(backends, "_kernels", {})
    yield


def sweep(mech: excavkin.Mechanism, n: int) -> dict[str, np.ndarray]:
    out = {}
    for k, v in mech.sketch_values().items():
        span = 0.3 if mech.input_kind(k) == "angle" else 0.03 * v
        out[k] = v + span * np.sin(np.linspace(0.0, 6.0, n) + len(k))
    return out


def close(a: np.ndarray, b: np.ndarray, what: str) -> None:
    """Equal NaN patterns, and every finite value within 1e-12 of its column's scale."""
    a, b = np.asarray(a), np.asarray(b)
    assert np.array_equal(np.isnan(a), np.isnan(b)), what
    scale = np.nanmax(np.abs(b), axis=0, initial=0.0)
    diff = np.abs(np.nan_to_num(a - b))
    assert np.all(diff <= 1e-12 * np.maximum(scale, 1e-300)), what


@pytest.mark.parametrize("name", EXAMPLES)
def test_numba_agrees_with_numpy_on_the_examples(name: str) -> None:
    """Kinematics, tangents and forces of each example, by both backends: statuses equal,
    values to 1e-12 of each column's scale."""
    mech = excavkin.load(excavkin.example_path(name))
    values = sweep(mech, 300)
    rates = {k: 0.4 for k in values}
    names = [p for p in mech.parameters if not p.endswith((".mass", ".inertia"))][:3]
    loads = [*mech.loads, Gravity()] if not mech.loads else list(mech.loads)
    out = {
        b: mech.solve(values, rates, sensitivities=names, loads=loads, backend=b)  # type: ignore[arg-type]
        for b in ("numpy", "numba")
    }
    fast, ref = out["numba"], out["numpy"]
    np.testing.assert_array_equal(fast.kinematics.status.code, ref.kinematics.status.code)
    assert fast.kinematics.status.ok.mean() > 0.5
    for field in ("positions", "velocities", "accelerations", "body_omega", "transmission"):
        close(getattr(fast.kinematics, field), getattr(ref.kinematics, field), field)
    for p in names:
        close(fast.kinematics.tangents[p].positions, ref.kinematics.tangents[p].positions, p)
        close(
            fast.kinematics.tangents[p].accelerations, ref.kinematics.tangents[p].accelerations, p
        )
    for field in ("pin_force", "element_force", "driver_torque"):
        close(getattr(fast, field), getattr(ref, field), field)


def test_auto_takes_a_cached_kernel_at_any_sample_count(chosen: list[tuple[str, str]]) -> None:
    mech = excavkin.load(excavkin.example_path("fourbar"))
    q = {"crank": np.linspace(0.0, 6.0, 50)}
    names = ["A-B"]
    mech.solve(q, sensitivities=names, loads="model", backend="numba")  # every kernel ready
    chosen.clear()
    for n in (1, 50):
        mech.solve({"crank": q["crank"][:n]}, sensitivities=names, loads="model")
    assert chosen == [("kinematics", "numba"), ("tangents", "numba"), ("forces", "numba")] * 2


def test_auto_compiles_nothing_unasked_below_its_size(
    fresh_cache: None, chosen: list[tuple[str, str]]
) -> None:
    mech = excavkin.load(excavkin.example_path("fourbar"))
    mech.solve({"crank": np.linspace(0.0, 6.0, 1000)}, sensitivities=["A-B"], loads="model")
    assert chosen == [("kinematics", "numpy"), ("tangents", "numpy"), ("forces", "numpy")]
    assert not backends._kernels
    job = compiled.job(mech.plan)
    assert backends.choose("auto", job, backends.COMPILE_AT - 1) is backends.NUMPY
    assert backends.choose("auto", job, backends.COMPILE_AT).name == "numba"  # (not run here)


def test_auto_stays_on_numpy_when_told(
    monkeypatch: pytest.MonkeyPatch, chosen: list[tuple[str, str]]
) -> None:
    mech = excavkin.load(excavkin.example_path("fourbar"))
    q = {"crank": np.linspace(0.0, 6.0, 20)}
    mech.solve(q, backend="numba")
    monkeypatch.setenv("EXCAVKIN_COMPILED", "0")
    chosen.clear()
    mech.solve(q)
    assert chosen == [("kinematics", "numpy")]


def test_a_newton_plan_compiles_when_asked_and_auto_takes_it_cached(
    chosen: list[tuple[str, str]], fresh_cache: None
) -> None:
    """One choice for a Newton plan's kinematics (its positions and rates kernels come
    together); its tangents stay in NumPy, and asking numba for them is one clear error."""
    fb = excavkin.load(excavkin.example_path("fourbar"))
    newton = excavkin.Mechanism(fb.model, method="newton")
    q = {"crank": np.linspace(0.0, 1.0, 5)}
    newton.solve(q, sensitivities=["A-B"])
    assert chosen == [("kinematics", "numpy"), ("tangents", "numpy")]
    chosen.clear()
    a = newton.solve(q, backend="numba")
    b = newton.solve(q)  # cached now: "auto" takes it
    assert chosen == [("kinematics", "numba"), ("kinematics", "numba")]
    np.testing.assert_array_equal(a.positions, b.positions)
    with pytest.raises(InputError, match="backend='numba': the tangents .* Newton group"):
        newton.solve(q, sensitivities=["A-B"], backend="numba")


def test_a_newton_plan_on_cuda_is_one_clear_error(monkeypatch: pytest.MonkeyPatch) -> None:
    """Its kernels are compiled for the CPU only: asking for the device says so (here with
    the device taken as usable, whatever this machine has)."""
    from excavkin import gpu

    monkeypatch.setattr(gpu, "why_not", lambda: None)
    fb = excavkin.load(excavkin.example_path("fourbar"))
    newton = excavkin.Mechanism(fb.model, method="newton")
    with pytest.raises(InputError, match="backend='cuda': the kinematics of this plan have no"):
        newton.solve({"crank": np.zeros(3)}, backend="cuda")


def test_cuda_without_a_gpu_is_one_clear_error_and_never_chosen(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Where the CUDA target cannot run (here: told so, whatever this machine has), asking
    for it is one error saying why; "auto" never takes it."""
    from excavkin import gpu

    monkeypatch.setattr(gpu, "why_not", lambda: "no CUDA GPU is usable here")
    mech = excavkin.load(excavkin.example_path("fourbar"))
    with pytest.raises(InputError, match="backend='cuda': no CUDA GPU is usable here"):
        mech.solve({"crank": np.zeros(3)}, backend="cuda")
    with pytest.raises(InputError, match="backend='cuda': no CUDA GPU"):
        mech.forces(mech.solve({"crank": np.zeros(3)}), backend="cuda")
    assert "cuda" not in backends.AUTO
    assert backends.available()["cuda"] == "no CUDA GPU is usable here"
    r = CliRunner().invoke(
        main, ["solve", "fourbar", "--sweep", "crank=0:1:3", "-o", "-", "--backend", "cuda"]
    )
    assert r.exit_code == 2
    assert r.output.strip().splitlines() == [
        "excavkin: error: --backend cuda: no CUDA GPU is usable here; auto chooses what can run"
    ]


def test_an_unknown_backend_is_refused() -> None:
    mech = excavkin.load(excavkin.example_path("fourbar"))
    with pytest.raises(InputError, match="backend must be one of auto, numpy, numba, cuda"):
        mech.solve({"crank": np.zeros(3)}, backend="gpu")  # type: ignore[call-overload]
    with pytest.raises(InputError, match="got 'gpu'"):
        Execution(backend="gpu")


def test_compiled_is_a_deprecated_alias() -> None:
    mech = excavkin.load(excavkin.example_path("fourbar"))
    q = {"crank": np.linspace(0.0, 6.0, 40)}
    for old, new in ((True, "numba"), (False, "numpy")):
        with pytest.warns(DeprecationWarning, match=f"use backend='{new}'") as caught:
            res = mech.solve(q, compiled=old)
        assert caught[0].filename == __file__  # the warning points at the caller's line
        np.testing.assert_array_equal(res.positions, mech.solve(q, backend=new).positions)  # type: ignore[arg-type]
        kin = mech.solve(q, backend="numpy")
        with pytest.warns(DeprecationWarning, match=f"use backend='{new}'"):
            mech.forces(kin, compiled=old)
        with pytest.warns(DeprecationWarning, match=f"use backend='{new}'"):
            solve_forces(kin, [Gravity()], compiled=old)
    with pytest.warns(DeprecationWarning), pytest.raises(InputError, match="not both"):
        mech.solve(q, compiled=True, backend="numpy")


def test_the_settings_travel_as_one_execution(chosen: list[tuple[str, str]]) -> None:
    """The old keywords build an Execution; one given whole does the same; a keyword given
    beside it replaces its field; a bad value is one error."""
    mech = excavkin.load(excavkin.example_path("fourbar"))
    q = {"crank": np.linspace(0.0, 6.0, 5000)}
    seen: list[tuple[int, int]] = []
    run = Execution(
        backend="numpy", workers=2, chunk=700, progress=lambda d, t: seen.append((d, t))
    )
    a = mech.solve(q, execution=run)
    assert seen[-1] == (5000, 5000) and len(seen) == 8  # chunks of 700
    b = mech.solve(q, backend="numpy", workers=1, chunk=5000)
    np.testing.assert_array_equal(a.positions, b.positions)
    assert {c[1] for c in chosen} == {"numpy"}
    q2 = np.asarray(q["crank"]).reshape(1, -1)
    c = solve_kinematics(mech.plan, mech.assembly, q2, np.ones_like(q2), np.zeros_like(q2),
                         backend="numpy", chunk=700, workers=1)  # fmt: skip
    np.testing.assert_array_equal(a.positions, c.positions)
    assert settings(run, workers=1) == Execution("numpy", 1, 700, run.progress)
    assert settings(None, chunk=9) == Execution(chunk=9)
    with pytest.raises(InputError, match="workers must be a whole number of at least 1"):
        mech.solve(q, workers=0)
    for bad in (1.5, "many", True, -3, float("nan")):
        with pytest.raises(InputError, match="chunk must be a whole number"):
            Execution(chunk=bad)  # type: ignore[arg-type]
    assert Execution(chunk=7000.0).chunk_or(1) == 7000  # type: ignore[arg-type]
    with pytest.raises(InputError, match="execution must be an Execution"):
        mech.solve(q, execution="numba")  # type: ignore[call-overload]
    with pytest.raises(AttributeError):
        run.backend = "numba"  # type: ignore[misc]


def test_use_sets_the_settings_of_calls_that_give_none(chosen: list[tuple[str, str]]) -> None:
    mech = excavkin.load(excavkin.example_path("fourbar"))
    q = {"crank": np.linspace(0.0, 6.0, 20)}
    mech.solve(q, backend="numba")
    chosen.clear()
    with use(Execution(backend="numpy")):
        assert current().backend == "numpy"
        mech.solve(q)
        mech.solve(q, backend="numba")  # a call's own keyword wins
    assert current() == Execution()
    assert chosen == [("kinematics", "numpy"), ("kinematics", "numba")]


def test_numpy_runs_everything_when_numba_cannot_be_imported(
    monkeypatch: pytest.MonkeyPatch, chosen: list[tuple[str, str]]
) -> None:
    mech = excavkin.load(excavkin.example_path("excavator"))
    values = sweep(mech, 200)
    loads = [Gravity(), PointForce("dig", "bucket", "W", (-20e3, 5e3))]
    names = ["D.x"]
    ref = mech.solve(values, sensitivities=names, loads=loads, backend="numpy")
    mech.solve(values, sensitivities=names, loads=loads, backend="numba")  # kernels ready
    monkeypatch.setitem(sys.modules, "numba", None)  # `import numba` now fails
    with pytest.raises(ImportError):
        import numba  # noqa: F401
    assert backends.available()["numba"] == "numba cannot be imported (pip install numba)"
    chosen.clear()
    res = mech.solve(values, sensitivities=names, loads=loads)
    assert chosen == [("kinematics", "numpy"), ("tangents", "numpy"), ("forces", "numpy")]
    np.testing.assert_array_equal(res.kinematics.positions, ref.kinematics.positions)
    np.testing.assert_array_equal(res.pin_force, ref.pin_force)
    np.testing.assert_array_equal(
        res.kinematics.tangents["D.x"].positions, ref.kinematics.tangents["D.x"].positions
    )
    with pytest.raises(InputError, match="backend='numba': numba cannot be imported"):
        mech.solve(values, backend="numba")
    r = CliRunner().invoke(
        main, ["solve", "fourbar", "--sweep", "crank=0:1:3", "-o", "-", "--backend", "numba"]
    )
    assert r.exit_code == 2 and "--backend numba: numba cannot be imported" in r.output


def test_a_first_compile_is_announced_with_its_time(
    fresh_cache: None, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A kernel compiled for the first time is logged before and after (the CLI prints the
    log as notes); loaded again, in this process or from the cache folder, it is not."""
    import io

    from excavkin.cli.progress import compile_notes

    loads: list[str] = []

    def load(text: str, key: str) -> backends.Kernel:
        loads.append(key)
        backends.cache_dir().mkdir(parents=True, exist_ok=True)  # as the import makes it
        return lambda *args: None

    monkeypatch.setattr(backends, "_load", load)
    shown = io.StringIO()
    with compile_notes(stream=shown):
        backends.kernel_of("# a source\n", "kinematics")
        backends.kernel_of("# a source\n", "kinematics")  # in memory: nothing to say
    lines = shown.getvalue().splitlines()
    assert len(loads) == 1 and len(lines) == 2, lines
    assert lines[0].startswith("excavkin: note: compiling the kinematics kernel ")
    assert "(once; kept in " in lines[0]
    assert re.fullmatch(
        r"excavkin: note: compiled the kinematics kernel \w+ in \d+\.\d s", lines[1]
    )
    assert backends.is_cached("# a source\n")
    monkeypatch.setattr(backends, "_kernels", {})  # a new process: the marker on disk
    quiet = io.StringIO()
    with compile_notes(stream=quiet):
        backends.kernel_of("# a source\n", "kinematics")
    assert quiet.getvalue() == "" and len(loads) == 2
    with compile_notes(quiet=True, stream=quiet):
        monkeypatch.setattr(backends, "_kernels", {})
        backends.kernel_of("# another\n", "forces")
    assert quiet.getvalue() == ""


def test_a_kernel_past_the_compilers_recursion_is_one_clear_error(
    fresh_cache: None, monkeypatch: pytest.MonkeyPatch
) -> None:
    """numba compiles with room for its recursion (`COMPILE_RECURSION`), the limit put back
    after; a kernel that needs even more is one message naming it, never a traceback."""
    seen: list[int] = []

    def load(text: str, key: str) -> backends.Kernel:
        seen.append(sys.getrecursionlimit())
        raise RecursionError("maximum recursion depth exceeded")

    before = sys.getrecursionlimit()
    monkeypatch.setattr(backends, "_load", load)
    with pytest.raises(InputError, match=r"cannot compile the tangents kernel .*backend='numpy'"):
        backends.kernel_of("# a large source\n", "tangents")
    assert seen == [max(before, backends.COMPILE_RECURSION)]
    assert sys.getrecursionlimit() == before


def test_the_device_rewrite_changes_the_loop_and_nothing_else() -> None:
    """Each workload's generated source, rewritten for the CUDA target: its loop one thread a
    sample, its decorators CUDA's, its two-number max a device function; every other line
    as it was (the simulator test runs them, tests/crossmethod/test_cuda_simulator.py)."""
    from excavkin.gpu import device_source
    from excavkin.kinematics import compiled_tangents
    from excavkin.kinetostatics import compiled as forces
    from excavkin.kinetostatics.inertia import MassProperties
    from excavkin.kinetostatics.loads import evaluate_loads
    from excavkin.kinetostatics.structured import compile_structured

    mech = excavkin.load(excavkin.example_path("excavator"))
    kin = mech.solve({})
    loads = evaluate_loads(mech.model, list(mech.loads), kin)
    structured = compile_structured(mech.plan, mech.statics)
    sources = [
        compiled.source(mech.plan, write_at_rest=False),
        compiled_tangents.source(mech.plan),
        forces.source(structured, MassProperties.of(kin), loads, inertia=True)[0],
    ]
    for text in sources:
        gpu = device_source(text)
        assert gpu.count("i = cuda.grid(1)") == 1 and "numba.njit" not in gpu
        assert re.search(r"\bmax\(", gpu) is None
        kept = [line for line in text.splitlines() if "njit" not in line]
        changed = [line.replace("max(", "_max2(") for line in kept if "for i in range" not in line]
        assert all(line in gpu.splitlines() for line in changed)
    with pytest.raises(ValueError, match="not a generated source"):
        device_source("def kernel(x):\n    return x\n")


def test_studies_and_tolerance_bands_solve_on_the_backend_asked_for(
    tmp_path, chosen: list[tuple[str, str]]
) -> None:  # type: ignore[no-untyped-def]
    """A study's solves, deep in its metrics, and the tolerance bands' solves take the
    backend given to them (the study's here, or in each Dask task: an Execution pickles)."""
    import pickle

    from excavkin.studies.study import run_study
    from excavkin.studies.study_file import load_study
    from excavkin.studies.tolerance import tolerance_bands

    mech = excavkin.load(excavkin.example_path("fourbar"))
    mech.solve({"crank": np.zeros(3)}, sensitivities=["A-B"], backend="numba")  # ready
    spec = tmp_path / "study.toml"
    spec.write_text(
        excavkin.example_path("crank_rocker")
        .read_text()
        .replace('model = "fourbar"', f'model = "{excavkin.example_path("fourbar")}"')
        .replace("samples = 4096", "samples = 4")
    )
    study = load_study(spec)  # (its checks solve a sample or two, on "auto")
    for backend in ("numpy", "numba"):
        chosen.clear()
        run_study(study, tmp_path / f"{backend}.parquet", backend=backend)
        assert chosen and {b for _, b in chosen} == {backend}
        chosen.clear()
        tolerance_bands(
            mech, {"crank": np.linspace(0.0, 1.0, 3)}, tolerances={"A-B": "0.1 mm"}, draws=4,
            backend=backend,
        )  # fmt: skip
        assert ("tangents", backend) in chosen and {b for _, b in chosen} == {backend}
    run = Execution(backend="numpy", workers=2, chunk=100)
    assert pickle.loads(pickle.dumps(run)) == run
