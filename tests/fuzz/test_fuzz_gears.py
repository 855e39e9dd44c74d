"""Fuzz the [gears], [racks] and [cams] tables: mutated model files with gear trains, racks and
cams end in success or in exit 2 with one ``excavkin: error:`` line naming the file."""

from __future__ import annotations

from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from tests.fuzz.test_fuzz_readers import FUZZ, check_outcome, mutate

DATA = Path(__file__).parents[1] / "reference" / "data"
MODELS = ["planetary_21_43_108.toml", "rack_on_arm.toml", "disc_cam.toml", "cam_rocker.toml"]


@pytest.mark.parametrize("name", MODELS)
def test_mutated_models_with_meshes(tmp_path_factory: pytest.TempPathFactory, name: str) -> None:
    text = (DATA / name).read_text()

    @FUZZ
    @given(data=st.data())
    def run(data: st.DataObject) -> None:
        path = tmp_path_factory.mktemp("mesh") / name
        path.write_text(mutate(text, data))
        check_outcome(["check", str(path)], str(path))

    run()
