"""The cams' profiles in the drawings (issue 26): the pitch curve of a roller, the envelope of a
flat face, carried by the cam's turn; in the matplotlib drawing, its animation and the report's
figure."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from numpy.testing import assert_allclose

import excavkin
from excavkin import Body, CamFollower, Mechanism, Model, RotaryDriver
from excavkin.outputs.cam_profiles import POINTS, cam_profiles
from excavkin.outputs.scene import scene_of

DATA = Path(__file__).parents[1] / "reference" / "data"
TURNS = np.radians([0.0, 37.0, 130.0, 250.0, 400.0, -75.0])


def solved(file: str, face: str = "") -> excavkin.KinematicResult:
    text = (DATA / file).read_text()
    if face:
        text = text.replace('face = "roller"', f'face = "{face}"')
    mech = excavkin.loads(text, file)
    return mech.solve({"shaft": mech.sketch_values()["shaft"] + TURNS})


def turned(path: np.ndarray, centre: np.ndarray, angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    d = path - centre
    return centre + np.stack([c * d[:, 0] - s * d[:, 1], s * d[:, 0] + c * d[:, 1]], axis=1)


@pytest.mark.parametrize(
    ("file", "face", "trace"),
    [("disc_cam.toml", "", "F1"), ("disc_cam.toml", "flat", "F1"), ("cam_rocker.toml", "", "B")],
)
def test_a_profile_turns_with_its_cam_and_holds_its_follower(
    file: str, face: str, trace: str
) -> None:
    res = solved(file, face)
    scene, _ = scene_of(res, (), "mm")
    o = res.plan.points.index("O")
    f = res.plan.points.index(trace)
    first = cam_profiles(scene, 0)[0]
    assert first.shape == (POINTS, 2)
    for i, turn in enumerate(TURNS):
        profile = cam_profiles(scene, i)[0]
        # the same curve, turned rigidly by the cam's turn about its pivot
        assert_allclose(profile, turned(first, scene.xy[0, o], turn), atol=1e-9)
        if face == "flat":  # no point of the cam passes the face, and one touches it
            e = np.array([0.0, 1.0])
            height = (profile - scene.xy[i, o]) @ e
            reach = (scene.xy[i, f] - scene.xy[i, o]) @ e
            assert height.max() <= reach + 1e-9
            assert height.max() >= reach - 1e-3  # within the polyline's step
        else:  # the roller's centre is on its pitch curve
            gaps = np.hypot(*(profile - scene.xy[i, f]).T)
            assert gaps.min() <= 1e-9 * scene.size + 1e-9


def test_an_eccentric_under_a_flat_face_is_a_circle() -> None:
    """A flat face square to its guide over a disc whose lift is simple harmonic,
    s = e·(1 − cos θ), is driven by a circle of radius R = a + e whose centre is e from the
    shaft (the eccentric of a Scotch yoke): the face's envelope must be that circle."""
    e, a = 0.005, 0.035

    def law(t):  # type: ignore[no-untyped-def]
        return e * (1 - np.cos(t)), e * np.sin(t), e * np.cos(t)

    model = Model(
        name="eccentric and flat face",
        points={"O": (0.0, 0.0), "G1": (0.0, -0.1), "G2": (0.0, 0.3), "C": (0.02, 0.0),
                "F1": (0.0, a), "F2": (0.0, 0.2)},
        bodies=(Body("frame", ("O", "G1", "G2"), ground=True), Body("cam", ("O", "C")),
                Body("valve", ("F1", "F2"))),
        rotary=(RotaryDriver("shaft", body="cam", pivot="O", reference="frame"),),
        cams=(CamFollower("lift", "cam", "valve", "frame", ("G1", "G2"), law, face="flat"),),  # type: ignore[arg-type]
    )  # fmt: skip
    mech = Mechanism(model)
    res = mech.solve({"shaft": mech.sketch_values()["shaft"] + TURNS})
    scene, _ = scene_of(res, (), "mm")
    for i, turn in enumerate(TURNS):
        profile = cam_profiles(scene, i)[0]
        centre = profile[:-1].mean(axis=0)  # evenly spaced round the circle
        assert_allclose(np.hypot(*(profile - centre).T), (a + e) * 1e3, rtol=1e-12)
        want = -e * 1e3 * np.array([-np.sin(turn), np.cos(turn)])  # −e·ê turned by θ
        assert_allclose(centre, want, atol=1e-12)


def test_drawings_animations_and_the_report_show_the_profiles() -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from excavkin.outputs.drawing import draw_mechanism
    from excavkin.outputs.report.mechanism import mechanism_figure

    res = solved("disc_cam.toml", "flat")
    scene, _ = scene_of(res, (), "mm")
    fig, ax = plt.subplots()
    try:
        drawing = draw_mechanism(res, ax=ax, sample=0)
        assert len(drawing.profiles) == 2  # the profile and the face
        assert all(line in drawing.artists() for line in drawing.profiles)
        drawing.set_sample(3)
        x, y = drawing.profiles[0].get_data()
        assert_allclose(np.stack([x, y], axis=1), cam_profiles(scene, 3)[0], atol=1e-12)
    finally:
        plt.close(fig)
    figure = mechanism_figure(res)
    named = [t for t in figure.data if t.name == "cam profile"]
    assert len(named) == 2
    assert_allclose(np.asarray(named[0].x, dtype=float), cam_profiles(scene, 0)[0][:, 0], atol=1e-6)
    frame = figure.frames[2]
    assert sum(t.name == "cam profile" for t in frame.data) == 2
