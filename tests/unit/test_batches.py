"""Large batches: chunking and threads change nothing, to the bit."""

from __future__ import annotations

import numpy as np

import excavkin
from tests.conftest import EXAMPLES


def test_threads_and_chunks_give_identical_results() -> None:
    text = (EXAMPLES / "fourbar.toml").read_text()
    text = text.replace('"O4-B" = 90', '"O4-B" = 90\n"O2-A" = 95')
    mech = excavkin.loads(text)  # non-Grashof: many samples cannot close, spread over chunks
    th = np.linspace(0.0, 8 * np.pi, 150_001)
    one = mech.solve({"crank": th}, rates={"crank": 3.0}, workers=1)
    many = mech.solve({"crank": th}, rates={"crank": 3.0}, workers=2)
    assert (~one.status.ok).sum() > 1000 and one.status.ok.sum() > 1000
    np.testing.assert_array_equal(one.status.code, many.status.code)
    np.testing.assert_array_equal(one.status.step, many.status.step)
    for name in ("positions", "velocities", "accelerations", "body_omega", "transmission"):
        np.testing.assert_array_equal(getattr(one, name), getattr(many, name))
    # each sample equals the same sample solved alone
    for i in (0, 777, 75_000, 150_000):
        alone = mech.solve({"crank": th[i : i + 1]}, rates={"crank": 3.0})
        np.testing.assert_array_equal(alone.positions[0], one.positions[i])
        assert alone.status.code[0] == one.status.code[i]


def test_newton_groups_give_identical_results_on_any_number_of_threads() -> None:
    """The generic solver's passes (its ladders, the samples from them, the rates) run by
    chunks on threads: the result does not depend on how many."""
    from tests.property.test_random_linkages import TRIAD, triad

    mech = excavkin.Mechanism(triad(TRIAD))
    q0 = mech.sketch_values()["crank"]
    th = q0 + np.linspace(-np.pi, 3 * np.pi, 60_001)  # two turns: several chunks of each pass
    th[[5, 30_000]] = np.nan  # inputs that fail, in the middle of the ladders
    one = mech.solve({"crank": th}, rates={"crank": 1.5}, accels={"crank": 0.2}, workers=1)
    many = mech.solve({"crank": th}, rates={"crank": 1.5}, accels={"crank": 0.2}, workers=2)
    assert one.status.ok.sum() == th.size - 2
    np.testing.assert_array_equal(one.status.code, many.status.code)
    for name in ("positions", "velocities", "accelerations", "body_omega", "transmission"):
        np.testing.assert_array_equal(getattr(one, name), getattr(many, name))


def test_a_rate_given_once_is_not_written_per_sample() -> None:
    """A rate or acceleration given as one value is a read-only broadcast (no memory per
    sample), equal to the same value given per sample; one that varies is an array."""
    mech = excavkin.load(EXAMPLES / "fourbar.toml")
    th = np.linspace(0.0, 2 * np.pi, 5000)
    once = mech.solve({"crank": th}, rates={"crank": 3.0}, accels={"crank": -2.0})
    every = mech.solve({"crank": th}, rates={"crank": np.full(th.size, 3.0)},
                       accels={"crank": np.full(th.size, -2.0)})  # fmt: skip
    assert once.input_rates.strides == (0, 0) and not once.input_rates.flags.writeable
    assert every.input_rates.strides != (0, 0)
    for name in ("positions", "velocities", "accelerations", "input_rates", "input_accels"):
        np.testing.assert_array_equal(getattr(once, name), getattr(every, name), err_msg=name)
    np.testing.assert_array_equal(once.to_frame().to_numpy(), every.to_frame().to_numpy())


def test_free_memory_in_huge_pieces_from_buddyinfo() -> None:
    """Free blocks of a huge page's order (2 MiB: 9 with 4 KiB pages) or more are counted,
    smaller ones not, over every zone; text that cannot be read counts nothing."""
    import os
    from pathlib import Path

    from excavkin.kinematics.solve import free_in_huge_pieces

    hpage = Path("/sys/kernel/mm/transparent_hugepage/hpage_pmd_size")
    huge = int(hpage.read_text()) if hpage.exists() else 2**21
    assert os.sysconf("SC_PAGE_SIZE") == 4096 and huge == 2**21, "the orders below assume it"
    text = (
        "Node 0, zone      DMA      0      0      0      0      0      0      0      0      1"
        "      1      3\n"
        "Node 0, zone   Normal  84706  65091  33763   9595   1189    217     95     68     27"
        "    225   2124\n"
    )
    assert free_in_huge_pieces(text) == (1 + 225) * huge + (3 + 2124) * 2 * huge
    assert free_in_huge_pieces("") == 0
    assert free_in_huge_pieces("Node 0, zone Normal 1 2 x") == 0
