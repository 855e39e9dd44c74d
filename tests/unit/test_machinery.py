"""The machinery layer serves a family other than the excavator, and machine families are
registered, not sniffed: a toy two-cylinder family (roles ``lift`` and ``tilt``, a wheel
loader's) against independent computations, and the ``family`` key of machine files."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar

import numpy as np
import pytest
from click.testing import CliRunner
from numpy.testing import assert_allclose

import excavkin
from excavkin.cli import main
from excavkin.errors import InputError, ModelError
from excavkin.excavator.forces import tool_forces
from excavkin.excavator.machine_file import load_machine, loads_machine
from excavkin.families import families, family_of
from excavkin.families import load_machine as load_any_machine
from excavkin.machinery.buckling import buckling, pose_buckling
from excavkin.machinery.capped_force import capped_force
from excavkin.machinery.cylinders import Circuit, Cylinder, cylinder_lengths
from excavkin.machinery.flows import strokes
from excavkin.machinery.pumps import Hydraulics, Pump
from excavkin.machinery.search import maximize_strokes
from tests.conftest import EXAMPLES

ROLES = ("lift", "tilt")


@dataclass(frozen=True, slots=True)
class LoaderHydraulics(Hydraulics):
    roles: ClassVar[tuple[str, ...]] = ROLES


@dataclass
class Loader:
    """The attributes the machinery layer reads of a family's machine, and nothing else."""

    name: str
    roles: tuple[str, ...]
    cylinders: Sequence[Cylinder]
    circuits: Mapping[str, Circuit]
    hydraulics: Hydraulics | None

    @property
    def lengths_min(self) -> np.ndarray:
        return np.array([c.retracted for c in self.cylinders])

    @property
    def lengths_max(self) -> np.ndarray:
        return np.array([c.extended for c in self.cylinders])


def loader() -> Loader:
    cyl = (
        Cylinder("lift", "lift_cyl", 1.2, 0.8, 0.16, 0.09, "main", count=2),
        Cylinder("tilt", "tilt_cyl", 1.5, 0.6, 0.2, 0.1, "main"),
    )
    pumps = (Pump("P1", 3e-3, ("lift", "tilt")), Pump("P2", 1e-3, ("lift",)))
    return Loader(
        "toy loader",
        ROLES,
        cyl,
        {"main": Circuit("main", 25e6, 28e6)},
        LoaderHydraulics(pumps, 1.0, 1.0),
    )


# ---------------------------------------------------------------- a second family's hydraulics
def test_a_family_hydraulics_checks_its_own_roles() -> None:
    with pytest.raises(InputError, match="must feed some of lift, tilt"):
        LoaderHydraulics((Pump("P", 1e-3, ("boom",)),), 1.0, 1.0)
    with pytest.raises(InputError, match="no pump feeds the tilt"):
        LoaderHydraulics((Pump("P", 1e-3, ("lift",)),), 1.0, 1.0)
    h = loader().hydraulics
    assert h is not None
    assert h.flow("lift") == pytest.approx(4e-3) and h.flow("tilt") == pytest.approx(3e-3)
    with pytest.raises(InputError, match="role must be one of lift, tilt"):
        h.flow("bucket")


def test_stroke_times_of_a_two_cylinder_family() -> None:
    m = loader()
    for s, c, q in zip(strokes(m), m.cylinders, (4e-3, 3e-3), strict=True):
        bore = c.count * np.pi / 4 * c.bore**2
        annulus = c.count * np.pi / 4 * (c.bore**2 - c.rod**2)
        assert s.role == c.role
        assert_allclose(
            [s.extend_time, s.retract_time],
            [c.stroke * bore / q, c.stroke * annulus / q],
            rtol=1e-14,
        )


def test_lengths_and_buckling_take_the_family_roles() -> None:
    m = loader()
    with pytest.raises(InputError, match=r"shape \(n, 2\) \(lift, tilt\), got \(4, 3\)"):
        cylinder_lengths(np.zeros((4, 3)), m.roles)
    L = np.array([[1.5, 1.8], [1.9, 2.0]])
    f = np.array([[4e5, -1e5], [6e5, 2e5]])
    got = pose_buckling(m, L, f)
    for i, c in enumerate(m.cylinders):
        ref = buckling(c, L[:, i], f[:, i] / c.count)
        assert_allclose(got[i].safety, ref.safety, rtol=0)
        assert_allclose(got[i].critical, ref.critical, rtol=0)


# ---------------------------------------------------------------- search and capped force
def test_the_stroke_search_works_over_two_cylinders() -> None:
    m = loader()
    target = np.array([1.61, 1.77])  # inside both strokes

    def evaluate(L: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return -np.sum((L - target) ** 2, axis=-1), L

    best, at = maximize_strokes(evaluate, m, (0, 1))
    assert_allclose(at[0], target, atol=1e-9)
    assert best[0] == pytest.approx(0.0, abs=1e-16)


def _largest_feasible(
    proj: np.ndarray, G: np.ndarray, limits: list[tuple[float, float]], w: int, dig: float
) -> float:
    """The largest F ≥ 0 with every cylinder force F·proj + G within its limits (the working
    one only up to its own push or pull), by bisection on feasibility: independent of the
    closed form's caps."""

    def ok(F: float) -> bool:
        f = F * proj + G
        for h, (lo, hi) in enumerate(limits):
            if h == w:
                if (dig > 0 and f[h] > hi * (1 + 1e-15)) or (dig < 0 and f[h] < lo * (1 + 1e-15)):
                    return False
            elif not (lo * (1 + 1e-12) <= f[h] <= hi * (1 + 1e-12)):
                return False
        return True

    lo_f, hi_f = 0.0, 1e9
    if not ok(lo_f):
        return 0.0
    for _ in range(200):
        mid = 0.5 * (lo_f + hi_f)
        lo_f, hi_f = (mid, hi_f) if ok(mid) else (lo_f, mid)
    return lo_f


def test_capped_force_with_other_roles_against_bisection() -> None:
    rng = np.random.default_rng(7)
    n = 40
    J = rng.normal(size=(n, 2, 3))
    G = rng.normal(scale=2e3, size=(n, 3))
    names = ("lift", "tilt", "outrigger_jack")
    limits = [(-1.5e5, 2.0e5), (-1.0e5, 1.2e5), (-0.8e5, 0.9e5)]
    force, uncapped, limiting, cyl_force, u = capped_force(J, G, 1, 1.0, limits, names)
    assert limiting.dtype.itemsize >= np.dtype("<U14").itemsize
    for i in range(n):
        proj = u[i] @ J[i]
        ref = _largest_feasible(proj, G[i], limits, 1, 1.0)
        assert force[i] == pytest.approx(ref, rel=1e-9, abs=1e-6)
        assert_allclose(cyl_force[i], force[i] * proj + G[i], rtol=1e-12, atol=1e-9)
        if ref > 0.0:  # the named limit is the one that binds
            h = names.index(str(limiting[i]))
            lo, hi = limits[h]
            assert min(abs(cyl_force[i, h] - lo), abs(cyl_force[i, h] - hi)) <= 1e-6 * abs(hi)


# ---------------------------------------------------------------- families
def test_the_excavator_registers_its_family() -> None:
    fam = families()["excavator"]
    assert fam.kind == "machine"
    assert excavkin.examples("machine") == [
        "eo4112_machine",
        "excavator_machine",
        "knuckle_crane_machine",
        "mining_shovel_machine",
        "synchronised_crane_machine",
        "telescopic_crane_machine",
        "wheel_loader_machine",
        "wheel_loader_tp_machine",
    ]
    assert family_of({"family": "excavator"}) is fam
    assert family_of({"schema_version": 1, "front": {"boom": "boom"}}) is fam
    assert family_of({"schema_version": 1, "bodies": {}}) is None
    with pytest.raises(ModelError, match=r"family = 'tower' is no known machine family.*excavator"):
        family_of({"family": "tower"}, "m.toml")
    with pytest.raises(ModelError, match="family = 3"):
        family_of({"family": 3})


def test_a_machine_file_without_the_family_key_gives_the_same_figures() -> None:
    path = EXAMPLES / "excavator_machine.toml"
    text = path.read_text(encoding="utf-8")
    assert '\nfamily = "excavator"' in text
    old = loads_machine(text.replace('\nfamily = "excavator"', "\n# no family key"), str(path))
    new = load_machine(path)
    anyone = load_any_machine("excavator_machine")
    L = np.linspace(new.lengths_min, new.lengths_max, 7)
    ref = tool_forces(new, L, "bucket").force
    for m in (old, anyone):
        assert_allclose(tool_forces(m, L, "bucket").force, ref, rtol=0, equal_nan=True)


def test_another_family_is_refused_by_the_excavator_reader(tmp_path: Path) -> None:
    text = (EXAMPLES / "excavator_machine.toml").read_text(encoding="utf-8")
    bad = tmp_path / "crane.toml"
    bad.write_text(text.replace('family = "excavator"', 'family = "crane"'), encoding="utf-8")
    (tmp_path / "excavator.toml").write_text(
        (EXAMPLES / "excavator.toml").read_text(encoding="utf-8"), encoding="utf-8"
    )
    with pytest.raises(ModelError, match="family = 'crane': this reader reads excavator"):
        load_machine(bad)
    r = CliRunner().invoke(main, ["excavator", "ranges", str(bad)])
    assert r.exit_code == 2 and "family = 'crane'" in r.output and "Traceback" not in r.output
    with pytest.raises(ModelError, match="unknown top-level keys base, front"):
        load_any_machine(bad)  # read as a crane's file: the crane's reader names what is off
    tower = tmp_path / "tower.toml"
    tower.write_text(text.replace('family = "excavator"', 'family = "tower"'), encoding="utf-8")
    with pytest.raises(ModelError, match="is no known machine family"):
        load_any_machine(tower)


def test_a_model_file_is_no_machine_file() -> None:
    with pytest.raises(ModelError, match="is no machine file"):
        load_any_machine(EXAMPLES / "fourbar.toml")


def test_a_cylinder_under_another_role_is_refused() -> None:
    from dataclasses import replace

    from excavkin.excavator.machine import Machine

    m = load_machine("excavator_machine")
    cyl = dict(zip(m.roles, m.cylinders, strict=True))
    cyl["arm"] = replace(cyl["arm"], role="bucket")
    with pytest.raises(ModelError, match="the arm cylinder says its role is 'bucket'"):
        Machine(m.mechanism, m.front, cyl, m.circuits)


def test_a_capped_load_names_its_pose_by_the_rule_not_by_round_off() -> None:
    from excavkin.machinery.pin_loads import TIE_RTOL, first_largest

    top = 775847.7217
    v = np.array([1.0, top * (1 - 0.5 * TIE_RTOL), top, -np.inf, top * (1 - 2 * TIE_RTOL)])
    assert first_largest(v) == 1  # the first of the tied poses, not the last bit's winner
    assert first_largest(v, prefer=np.array([9.0, 1.0, 3.0, 99.0, 50.0])) == 2
    assert first_largest(np.array([-np.inf, np.nan])) == 0
    # the tie is relative: a load just outside it is a different load
    assert first_largest(np.array([top * (1 - 2 * TIE_RTOL), top])) == 1
