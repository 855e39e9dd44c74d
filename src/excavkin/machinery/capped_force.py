r"""A tool force capped by the cylinders' pressures and by further limits, the binding one named.

With the machine at rest, virtual power over a motion of cylinder c alone (unit rate, the
others held) gives the force each cylinder must carry (> 0 pushes, DESIGN.md §5)::

    f_c = −P·J_c + G_c          J_c = ∂(tool point)/∂L_c (engine, exact),  G_c gravity terms

where P is the force of the soil (or load) on the tool at the tool point. The tool force of the
**working** cylinder w has magnitude F along the direction the tool point moves when w digs,
u = ±J_w/|J_w|, so P = −F·u and::

    F_work = (f_w,max − G_w) / (u·J_w)        f_w,max = p_working·A_bore (extending)
                                                        or −p_working·A_annulus (retracting)

Each **holding** cylinder h must then carry f_h = F·(u·J_h) + G_h, which its port relief bounds
to −p_relief·A_annulus ≤ f_h ≤ p_relief·A_bore; where it would not, F is capped there and that
cylinder's role is named as the limit (ISO 6015 "hydraulic limit"). Further caps (the base
machine's tipping and slipping loads,
[`stability_caps`][excavkin.machinery.capped_force.stability_caps]) lower it again by
[`cap_by`][excavkin.machinery.capped_force.cap_by], each named.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from excavkin.arrays import FloatArray as F
from excavkin.machinery.cylinders import Circuit, Cylinder
from excavkin.machinery.equilibrium import Stability
from excavkin.machinery.machine import StandingMachine


def capped_force(
    J: F,
    G: F,
    w: int,
    dig: float,
    limits: Sequence[tuple[Any, Any]],
    names: Sequence[str],
) -> tuple[F, F, NDArray[np.str_], F, F]:
    """The tool force of cylinder ``w`` capped by the others' limits (module docstring).

    Parameters
    ----------
    J : ndarray, shape (n, 2, c)
        ∂(tool point)/∂L, c cylinders.
    G : ndarray, shape (n, c)
        Gravity terms.
    w : int
        The working cylinder (its column).
    dig : float
        +1 where extending digs, −1 where retracting does.
    limits : sequence of c (pull, push)
        Each cylinder's largest pull (≤ 0) and push (N; scalars or arrays of shape (n,)):
        at working pressure for ``w``, at relief pressure for the others
        ([`pressure_limits`][excavkin.machinery.capped_force.pressure_limits]).
    names : sequence of c str
        The cylinders' roles, which name the binding limit.

    Returns
    -------
    force : ndarray, shape (n,)
        The capped tool force (N); 0 where the holding cylinders cannot even hold the
        gravity terms, NaN where not finite.
    uncapped : ndarray, shape (n,)
        The working cylinder's own limit (N).
    limiting : ndarray of str, shape (n,)
        The role whose limit binds; ``""`` where none is finite.
    cylinder_force : ndarray, shape (n, c)
        Each cylinder's force at the capped tool force (N, > 0 pushing).
    direction : ndarray, shape (n, 2)
        Unit direction of the tool force.
    """
    jw = J[:, :, w]
    norm = np.hypot(jw[:, 0], jw[:, 1])
    with np.errstate(divide="ignore", invalid="ignore"):
        u = dig * jw / norm[:, None]
    proj = np.einsum("ni,nic->nc", u, J)  # u·J_c, (n, 3); proj[:, w] = |J_w|
    pull, push = limits[w]
    f_max = push if dig > 0 else pull
    with np.errstate(divide="ignore", invalid="ignore"):
        F_work = (f_max - G[:, w]) / proj[:, w]
    force = F_work.copy()
    width = max(8, *(len(r) for r in names))
    limiting = np.where(np.isfinite(F_work), names[w], "").astype(f"<U{width}")
    for h in range(len(limits)):
        if h == w:
            continue
        lo, hi = limits[h]
        a = proj[:, h]
        with np.errstate(divide="ignore", invalid="ignore"):
            cap = np.where(
                a > 0.0, (hi - G[:, h]) / a, np.where(a < 0.0, (lo - G[:, h]) / a, np.inf)
            )
        lower = cap < force
        force = np.where(lower, cap, force)
        limiting = np.where(lower, names[h], limiting)
    force = np.where(np.isfinite(force), np.maximum(force, 0.0), np.nan)
    return force, F_work, limiting, force[:, None] * proj + G, u


def gravity_terms(machine: StandingMachine, tr_d: F) -> F:
    """The gravity terms G_c = g·Σ m_k ∂y_k/∂L_c over the machine's mass points (bodies and
    cylinders).

    Parameters
    ----------
    machine : StandingMachine
        Its ``mass_points`` and ``gravity``.
    tr_d : ndarray, shape (n, n_points, 2, c)
        The transfer functions ∂(point)/∂L of the model's points.

    Returns
    -------
    ndarray, shape (n, c)
        N.
    """
    mp = machine.mass_points
    dy = mp.locate(tr_d)[:, :, 1, :]  # (n, k, c)
    return np.asarray(machine.gravity * np.einsum("k,nkc->nc", mp.mass, dy))


def pressure_limits(
    cylinders: Sequence[Cylinder], circuits: Mapping[str, Circuit], w: int
) -> list[tuple[float | F, float | F]]:
    """Each cylinder's largest pull and push: at its circuit's working pressure for the working
    cylinder ``w``, at its port relief pressure for the holding ones.

    Parameters
    ----------
    cylinders : sequence of Cylinder
    circuits : mapping of str to Circuit
        By name; each cylinder names its own.
    w : int
        The working cylinder's index.

    Returns
    -------
    list of (pull, push)
        In the order of ``cylinders`` (N; pull ≤ 0 ≤ push).
    """
    return [
        c.force_limits(circuits[c.circuit].working if h == w else circuits[c.circuit].relief)
        for h, c in enumerate(cylinders)
    ]


def loaded_pressure(cylinders: Sequence[Cylinder], force: F) -> F:
    """The pressure of each cylinder's loaded side: the bore side pushing, the rod side pulling.

    Parameters
    ----------
    cylinders : sequence of Cylinder
        c of them.
    force : ndarray, shape (n, c)
        Forces of all ``count`` cylinders of each (N, > 0 pushing).

    Returns
    -------
    ndarray, shape (n, c)
        Pa; NaN where the force is.
    """
    areas = np.array([[c.bore_area, c.annulus_area] for c in cylinders])
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.asarray(
            np.where(force >= 0.0, force / areas[:, 0], -force / areas[:, 1]), dtype=np.float64
        )


def cap_by(
    force: F, limiting: NDArray[np.str_], limits: Sequence[tuple[NDArray[np.str_], F]]
) -> tuple[F, NDArray[np.str_]]:
    """Lower a force by further caps, naming the one that binds.

    Parameters
    ----------
    force : ndarray, shape (n,)
        The force so far (N).
    limiting : ndarray of str, shape (n,)
        What limits it so far.
    limits : sequence of (names, cap)
        Each a name per sample (shape (n,)) and a cap per sample (N, shape (n,)), applied in
        order.

    Returns
    -------
    force : ndarray, shape (n,)
        The force under every cap.
    limiting : ndarray of str, shape (n,)
        What limits it now.
    """
    force = force.copy()
    limiting = limiting.astype("<U40")
    for names, cap in limits:
        lower = cap < force
        force = np.where(lower, cap, force)
        limiting = np.where(lower, names, limiting)
    return force, limiting


def stability_caps(st: Stability) -> list[tuple[NDArray[np.str_], F]]:
    """The tipping and slipping caps of a load, named per sample (for
    [`cap_by`][excavkin.machinery.capped_force.cap_by]).

    Parameters
    ----------
    st : Stability
        The load's limits at n poses.

    Returns
    -------
    list of (names, cap)
        ``"tipping (LINE)"`` with the tipping load, then ``"slipping"`` with the slipping load.
    """
    tip_name = np.char.add(np.char.add("tipping (", st.tipping_line.astype(str)), ")")
    n = len(st.slipping_load)
    return [(tip_name, st.tipping_load), (np.full(n, "slipping"), st.slipping_load)]
