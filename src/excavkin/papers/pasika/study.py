r"""Pasika & Koruniak's cylinder–rocker module with an internal driving link, by the engine.

The model ``pasika_module.toml`` is driven by the cylinder length ``l_OA0 + s(t)`` from the
cubic law (`CubicLaw`); this module turns the engine's result into the
paper's quantities, puts the published values beside them, and compares with the closed-form
reference (`excavkin.papers.pasika.reference`), used only for that comparison.

>>> import numpy as np
>>> run = pasika_run(np.array([0.0, 2.5, 5.0]))
>>> np.round(np.degrees(run["phi1"]), 4).tolist()
[34.1497, 45.194, 55.4185]
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import numpy.typing as npt

from excavkin.mechanism import Mechanism
from excavkin.motion.laws import CubicLaw

if TYPE_CHECKING:
    pass

from excavkin.papers.common import (
    PaperRun,
    Published,
    central_differences,
    load_paper_model,
    rel_error,
)

#: Pasika's stroke H [m] and stroke time T [s].
PASIKA_STROKE = 0.5
PASIKA_DURATION = 5.0

#: Times of the spec's §4.3 table [s].
PASIKA_TIMES = (0.0, 1.0, 2.0, 2.5, 3.0, 4.0, 5.0)

#: ``seeds/pasika-internal-driving-link.md`` §4.3: the paper's equations evaluated with its
#: data (its figures, where these curves were published, are missing from the seed). Columns:
#: s [m], v21 [m/s], a21 [m/s²], φ1 [deg], ω1 [1/s], ε1 [1/s²], φ3 [deg], ω3 [1/s], ε3 [1/s²].
PASIKA_SPEC_TABLE: dict[str, tuple[float, ...]] = {
    "s": (0.0, 0.0520, 0.1760, 0.2500, 0.3240, 0.4480, 0.5000),
    "v21": (0.0, 0.0960, 0.1440, 0.1500, 0.1440, 0.0960, 0.0),
    "a21": (0.1200, 0.0720, 0.0240, 0.0, -0.0240, -0.0720, -0.1200),
    "phi1": (34.1497, 36.5876, 42.0704, 45.1940, 48.2516, 53.3038, 55.4185),
    "omega1": (0.0, 0.07697, 0.10758, 0.10916, 0.10306, 0.06808, 0.0),
    "eps1": (0.10034, 0.05235, 0.01131, -0.00470, -0.01963, -0.05098, -0.08530),
    "phi3": (-22.0714, -19.0749, -11.8313, -7.4228, -2.9334, 4.8121, 8.1595),
    "omega3": (0.0, 0.09688, 0.14851, 0.15731, 0.15401, 0.10683, 0.0),
    "eps3": (0.12031, 0.07398, 0.02918, 0.00579, -0.01936, -0.07646, -0.13616),
}

#: Quantity kind of every Pasika column (for display units).
PASIKA_KINDS: dict[str, str] = {
    "t": "time",
    "s": "length",
    "v21": "velocity",
    "a21": "acceleration",
    "l_oa": "length",
    "phi1": "angle",
    "omega1": "angular_velocity",
    "eps1": "angular_acceleration",
    "phi3": "angle",
    "omega3": "angular_velocity",
    "eps3": "angular_acceleration",
    "coriolis": "acceleration",
}


def pasika_run(
    t: npt.ArrayLike,
    mech: Mechanism | None = None,
    *,
    stroke: float = PASIKA_STROKE,
    duration: float = PASIKA_DURATION,
) -> PaperRun:
    """Solve the module over time with the paper's cubic law, eqs. (4)-(6).

    The rod's relative displacement ``s(t)`` enters the engine as the length of the linear
    driver ``cyl`` (O–A), ``l_OA = l_OA0 + s``, with rate ``v21`` and acceleration ``a21``:
    the input is the internal driving link itself. The cylinder's φ1, ω1, ε1 are the
    driver's line O→A (``cyl.angle .omega .epsilon``); the rocker's φ3, ω3, ε3 its body angle
    B→A.

    Parameters
    ----------
    t : array_like, shape (n,)
        Times [s]; the law holds on ``0 <= t <= T`` and the rod rests outside.
    mech : Mechanism, optional
        Default ``examples/pasika_module.toml``.
    stroke, duration : float
        H [m] and T [s].

    Returns
    -------
    PaperRun
        Columns ``t, s, v21, a21, l_oa, phi1, omega1, eps1, phi3, omega3, eps3, coriolis``
        (``coriolis = 2 ω1 v21``, the corrected Coriolis term).
    """
    mech = mech or load_paper_model("pasika_module")
    tt = np.atleast_1d(np.asarray(t, dtype=np.float64))
    law = CubicLaw(stroke, duration).evaluate(tt)
    l0 = mech.sketch_values()["cyl"]
    res = mech.solve({"cyl": l0 + law.s}, {"cyl": law.v}, {"cyl": law.a}, time=tt)
    phi1, omega1, eps1 = (res.column(f"cyl.{q}") for q in ("angle", "omega", "epsilon"))
    phi3, omega3, eps3 = res.body("rocker")
    cols = {
        "t": tt,
        "s": law.s,
        "v21": law.v,
        "a21": law.a,
        "l_oa": res.driver("cyl")[0],
        "phi1": phi1,
        "omega1": omega1,
        "eps1": eps1,
        "phi3": phi3,
        "omega3": omega3,
        "eps3": eps3,
        "coriolis": 2.0 * omega1 * law.v,
    }
    return PaperRun(
        {k: np.asarray(v, dtype=np.float64) for k, v in cols.items()}, PASIKA_KINDS, res
    )


def pasika_derivative_agreement(
    mech: Mechanism | None = None, n: int = 201, h: float = 1e-2
) -> dict[str, float]:
    """The paper's check, redone: analytic ω, ε against numerical differentiation of φ(t).

    The paper differentiated its displacement expressions (2)-(3) numerically twice and found
    the analytic ω and ε within 0.2 %. Here the engine's angles φ1(t), φ3(t) are
    differentiated by 8th-order central differences (step ``h``) at ``n`` times inside
    ``[4h, T − 4h]`` (the stencil must not cross the soft shocks at 0 and T).

    Parameters
    ----------
    mech : Mechanism, optional
        Default ``examples/pasika_module.toml``.
    n : int
        Number of times.
    h : float
        Difference step [s].

    Returns
    -------
    dict of str to float
        ``"omega1", "omega3", "eps1", "eps3"``: the largest difference, relative to the
        largest magnitude of the quantity over the stroke.
    """
    mech = mech or load_paper_model("pasika_module")
    t = np.linspace(4 * h, PASIKA_DURATION - 4 * h, n)
    stencil = t[None, :] + h * np.arange(-4, 5)[:, None]
    shifted = pasika_run(stencil.ravel(), mech)
    exact = pasika_run(t, mech)
    out: dict[str, float] = {}
    for k in ("1", "3"):
        phi = np.unwrap(shifted[f"phi{k}"].reshape(9, n), axis=0)
        d1, d2 = central_differences(phi, h)
        for name, num in ((f"omega{k}", d1), (f"eps{k}", d2)):
            ref = exact[name]
            out[name] = float(np.max(np.abs(num - ref)) / np.max(np.abs(ref)))
    return out


def _fmt(x: float, digits: int = 5) -> str:
    return f"{x:+.{digits}f}" if x != 0.0 else f"{0.0:.{digits}f}"


def pasika_published(mech: Mechanism | None = None) -> list[Published]:
    """What the paper publishes about its results, beside the engine's values.

    The paper's Fig. 3 and Fig. 5 are lost from the seed; its text states the values below.

    Parameters
    ----------
    mech : Mechanism, optional
        Default ``examples/pasika_module.toml``.

    Returns
    -------
    list of Published
    """
    mech = mech or load_paper_model("pasika_module")
    t = np.linspace(0.0, PASIKA_DURATION, 5001)
    run = pasika_run(t, mech)
    i_v = int(np.argmax(run["v21"]))
    fd = pasika_derivative_agreement(mech)
    worst = max(fd.values())
    mono = bool(np.all(np.diff(run["phi1"]) > 0) and np.all(np.diff(run["phi3"]) > 0))
    rows = [
        Published("rod stroke s(T) (Fig. 3)", "0.5 m", f"{run['s'][-1]:.4f} m", "text, Fig. 3"),
        Published(
            "max v21 and its time (Fig. 3)",
            "0.15 m/s at 2.5 s",
            f"{run['v21'][i_v]:.4f} m/s at {t[i_v]:.3f} s",
            "text, Fig. 3",
        ),
        Published(
            "a21 at t = 0 and t = T (Fig. 3)",
            "+0.12 / -0.12 m/s²",
            f"{run['a21'][0]:+.4f} / {run['a21'][-1]:+.4f} m/s²",
            "text, Fig. 3",
        ),
        Published(
            "φ1, φ3 increase monotonically (Fig. 5)",
            "yes",
            "yes" if mono else "no",
            "text, Fig. 5",
        ),
        Published(
            "ε1, ε3 jump at t = 0 and T: soft shocks (Fig. 5)",
            "yes",
            f"Δε1 = {run['eps1'][0]:+.4f} / {-run['eps1'][-1]:+.4f}, "
            f"Δε3 = {run['eps3'][0]:+.4f} / {-run['eps3'][-1]:+.4f} rad/s²",
            "text, Fig. 5",
        ),
        Published(
            "analytic vs numerical ω, ε",
            "≤ 0.2 %",
            f"≤ {100 * worst:.1e} % (8th-order differences of the engine's φ(t))",
            "text",
        ),
    ]
    return rows


def pasika_reference_agreement(run: PaperRun) -> dict[str, float]:
    """Engine against `excavkin.papers.pasika.reference` (eqs. 1-12) on the same samples.

    Parameters
    ----------
    run : PaperRun
        From [`pasika_run`][excavkin.papers.pasika.study.pasika_run].

    Returns
    -------
    dict of str to float
        Per quantity (φ1, φ3, ω1, ω3, ε1, ε3): the largest difference relative to the
        largest magnitude of the reference over the run.
    """
    from excavkin.papers.pasika import reference as ref

    k = ref.kinematics(run["s"], run["v21"], run["a21"])
    refs = {
        "phi1": k.positions.phi1,
        "phi3": k.positions.phi3,
        "omega1": k.velocities.omega1,
        "omega3": k.velocities.omega3,
        "eps1": k.accelerations.eps1,
        "eps3": k.accelerations.eps3,
    }
    return {n: rel_error(run[n], r, n.startswith("phi")) for n, r in refs.items()}
