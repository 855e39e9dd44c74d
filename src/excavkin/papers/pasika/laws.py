"""The follow-up programme of Pasika & Koruniak: which rod motion laws remove the soft shocks.

The paper (seed 003) drives the cylinder–rocker module with the cubic law, finds that the rod's
acceleration jumps at the start and end of the stroke (soft shocks), observes that the
angular accelerations of the cylinder (ε1) and of the rocker (ε3) "copy" the rod's law, and
leaves laws without those jumps as future work. `compare_laws` runs every law of
`LAW_NAMES` through the general engine on the paper's module and
measures, per law:

* peak ``|a21|`` (rod, relative to the cylinder), ``|ε1|``, ``|ε3|`` and ``J·|ε3|``;
* the one-sided values at the ends, ``a21(0⁺)``, ``a21(T⁻)``, ``ε(0⁺)``, ``ε(T⁻)``;
* the exact soft and hard shocks of the rod and of both links
  ([`shock_report`][excavkin.simulation.shocks.shock_report]);
* how closely each link's ε(t) follows a21(t): the Pearson correlation over ``[0, T]``, the
  ratio ``ε/a21`` at the ends, and the share of the velocity term in ε.

Why the links copy the rod's law
--------------------------------
With ``q`` the cylinder length and ``u(q)`` a link angle, ``ω = u'(q)·q'`` and::

    ε = u'(q)·q'' + u''(q)·q'²

At rest (``q' = 0``, the ends of every rest-to-rest law) ``ε = u'(q)·a21`` exactly: the ratio
``ε/a21`` at each end is the geometric gain ``u'`` at that end, the same for every law, so a
law removes the links' soft shocks exactly when it removes the rod's. Inside the stroke the
velocity term ``u''·v21²`` bends ε away from a scaled copy of a21; its share grows with the
law's peak velocity.

Module (spec §4.1; `pasika_module`)::

          B (-a, b) o
                    |\\    rocker ("rocker"), l_AB
                  b | \\
                    |  \\________ A       A on the right of O->B
         B1 o-------+     ____/
               a    O o__/   cylinder + rod ("cyl"), l_OA = l_OA0 + s

``φ1`` is the element angle ``cyl.angle`` (O→A), ``φ3`` the rocker's body angle (B→A).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from excavkin.arrays import FloatArray
from excavkin.errors import InputError
from excavkin.mechanism import Mechanism
from excavkin.model.entities import Body, LinearDriver, Model
from excavkin.motion import LAW_NAMES, get_law
from excavkin.simulation.shocks import ShockReport, shock_report
from excavkin.simulation.timeline import Drive, simulate

if TYPE_CHECKING:
    import pandas as pd

__all__ = [
    "PASIKA_DURATION",
    "PASIKA_MASS",
    "PASIKA_STROKE",
    "LawRow",
    "LawStudy",
    "compare_laws",
    "end_gains",
    "pasika_module",
]


PASIKA_STROKE = 0.5
"""The paper's stroke H [m]."""
PASIKA_DURATION = 5.0
"""The paper's stroke time T [s]."""
PASIKA_MASS = 1000.0
"""Illustrative rocker mass [kg] (the paper gives none; it mentions 1000 kg or more)."""

_SHOCK_FREE_NAMES = ("cylinder", "rocker")


def pasika_module(
    a: float = 0.45,
    b: float = 0.9,
    l_oa0: float = 0.8,
    l_ab: float = 1.2,
    *,
    mass: float | None = PASIKA_MASS,
    inertia: float | None = None,
) -> Mechanism:
    """The cylinder–rocker module with an internal driving link, built in Python.

    Same model as ``examples/pasika_module.toml``: ground points ``O = (0, 0)`` and
    ``B = (−a, b)``, rocker ``B → A`` (its body angle is the paper's φ3), cylinder ``cyl``
    driven between ``O`` and ``A`` with sketch length ``l_oa0``, ``A`` on the right of O→B.

    Parameters
    ----------
    a, b : float
        Frame legs [m].
    l_oa0 : float
        Initial cylinder length O–A [m].
    l_ab : float
        Rocker length [m].
    mass : float or None
        Rocker mass [kg], a uniform bar (illustration; the paper gives none).
    inertia : float or None
        Rocker moment of inertia about its centre [kg·m²]; default ``mass·l_ab²/12``.

    Returns
    -------
    Mechanism

    Raises
    ------
    InputError
        If the triangle O-B-A cannot close.
    """
    l_ob = math.hypot(a, b)
    if not (abs(l_ob - l_ab) < l_oa0 < l_ob + l_ab):
        raise InputError(
            f"the module cannot be assembled: l_OA0 = {l_oa0} m, l_AB = {l_ab} m, "
            f"l_OB = {l_ob:.6g} m"
        )
    # A from O (l_oa0) and B (l_ab), on the right of O->B (angle BOA measured clockwise).
    alpha = math.acos((l_ob**2 + l_oa0**2 - l_ab**2) / (2.0 * l_ob * l_oa0))
    phi1 = math.atan2(b, -a) - alpha
    pa = (l_oa0 * math.cos(phi1), l_oa0 * math.sin(phi1))
    com = (0.5 * (pa[0] - a), 0.5 * (pa[1] + b))
    if inertia is None and mass is not None:
        inertia = mass * l_ab**2 / 12.0
    model = Model(
        "Pasika cylinder-rocker module",
        {"O": (0.0, 0.0), "B": (-a, b), "A": pa},
        (
            Body("ground", ("O", "B"), ground=True),
            Body(
                "rocker",
                ("B", "A"),
                mass=mass,
                inertia=inertia,
                center_of_mass=com if mass is not None else None,
            ),
        ),
        linear=(LinearDriver("cyl", ("O", "A"), "driven"),),
        lengths={("B", "A"): l_ab},
    )
    return Mechanism(model)


def end_gains(
    mech: Mechanism, driver: str, q: Sequence[float], columns: Sequence[str]
) -> FloatArray:
    """First-order transfer functions ``u'(q) = dθ/dq`` of angle columns at driver values ``q``.

    At rest, ``ε = u'(q)·q''`` exactly, so these are the ratios ``ε/q''`` at the ends of any
    rest-to-rest law.

    Parameters
    ----------
    mech : Mechanism
    driver : str
    q : sequence of float, shape (m,)
        Driver values [m or rad].
    columns : sequence of str, shape (k,)
        ω columns (``"rocker.omega"``, ``"cyl.omega"``).

    Returns
    -------
    ndarray, shape (m, k)
    """
    res = mech.solve(
        {driver: np.asarray(q, dtype=np.float64)},
        {driver: np.ones(len(q))},
        {driver: np.zeros(len(q))},
        strict=True,
    )
    return np.stack([np.asarray(res.column(c), dtype=np.float64) for c in columns], axis=1)


@dataclass(frozen=True, slots=True)
class LawRow:
    """One law's results on the module (SI: m/s², rad/s², N·m).

    Attributes
    ----------
    law : str
    c_a : float
        The law's peak-acceleration coefficient ``max|a| = C_a·H/T²``.
    rod_peak, rod_start, rod_end : float
        ``max|a21|``, ``a21(0⁺)``, ``a21(T⁻)``.
    cyl_peak, cyl_start, cyl_end : float
        The same for ε1 (cylinder).
    rocker_peak, rocker_start, rocker_end : float
        The same for ε3 (rocker).
    rocker_torque_peak : float or None
        ``J·max|ε3|`` when the rocker has a moment of inertia.
    rod_soft, link_soft, hard : int
        Soft shocks of the rod's acceleration, of the links' ε (cylinder + rocker), and hard
        shocks of anything.
    corr_cyl, corr_rocker : float
        Pearson correlation of ε1(t), ε3(t) with a21(t) over ``[0, T]``.
    ratio_cyl, ratio_rocker : tuple of float
        ``ε/a21`` at ``0⁺`` and ``T⁻`` (the limit ``u'`` where ``a21 = 0`` there).
    v2_share_cyl, v2_share_rocker : float
        ``max|u''·v21²| / max|ε|``: the weight of the velocity term.
    """

    law: str
    c_a: float
    rod_peak: float
    rod_start: float
    rod_end: float
    cyl_peak: float
    cyl_start: float
    cyl_end: float
    rocker_peak: float
    rocker_start: float
    rocker_end: float
    rocker_torque_peak: float | None
    rod_soft: int
    link_soft: int
    hard: int
    corr_cyl: float
    corr_rocker: float
    ratio_cyl: tuple[float, float]
    ratio_rocker: tuple[float, float]
    v2_share_cyl: float
    v2_share_rocker: float

    @property
    def shock_free(self) -> bool:
        """No soft or hard shock of the rod or of either link."""
        return self.rod_soft == 0 and self.link_soft == 0 and self.hard == 0


@dataclass(frozen=True, slots=True)
class LawStudy:
    """All laws on one module.

    Attributes
    ----------
    rows : tuple of LawRow
        One per law, in the order asked.
    t : ndarray, shape (n,)
        Times [s] of the curves, from ``−T/10`` to ``1.1·T``; ``0`` and ``T`` are samples.
    rod_accel, cyl_eps, rocker_eps : ndarray, shape (n_laws, n)
        a21(t) [m/s²], ε1(t), ε3(t) [rad/s²] (at 0 and T the laws' values inside the motion).
    reports : tuple of ShockReport
        One per law.
    stroke, duration : float
        H [m], T [s].
    gains : ndarray, shape (2, 2)
        ``u'`` at the start and end (rows) for the cylinder and rocker (columns).
    """

    rows: tuple[LawRow, ...]
    t: FloatArray
    rod_accel: FloatArray
    cyl_eps: FloatArray
    rocker_eps: FloatArray
    reports: tuple[ShockReport, ...]
    stroke: float
    duration: float
    gains: FloatArray

    @property
    def laws(self) -> tuple[str, ...]:
        """Law names, in row order."""
        return tuple(r.law for r in self.rows)

    def row(self, law: str) -> LawRow:
        """The row of one law."""
        for r in self.rows:
            if r.law == law:
                return r
        raise KeyError(f"law {law!r} not in the study ({', '.join(self.laws)})")

    def to_frame(self) -> pd.DataFrame:
        """One row per law, every `LawRow` field (ratios split into start/end)."""
        import pandas as pd

        recs = []
        for r in self.rows:
            recs.append(
                {
                    "law": r.law,
                    "C_a": r.c_a,
                    "rod_peak": r.rod_peak,
                    "rod_start": r.rod_start,
                    "rod_end": r.rod_end,
                    "cyl_peak": r.cyl_peak,
                    "cyl_start": r.cyl_start,
                    "cyl_end": r.cyl_end,
                    "rocker_peak": r.rocker_peak,
                    "rocker_start": r.rocker_start,
                    "rocker_end": r.rocker_end,
                    "rocker_torque_peak": r.rocker_torque_peak,
                    "rod_soft_shocks": r.rod_soft,
                    "link_soft_shocks": r.link_soft,
                    "hard_shocks": r.hard,
                    "shock_free": r.shock_free,
                    "corr_cyl": r.corr_cyl,
                    "corr_rocker": r.corr_rocker,
                    "ratio_cyl_start": r.ratio_cyl[0],
                    "ratio_cyl_end": r.ratio_cyl[1],
                    "ratio_rocker_start": r.ratio_rocker[0],
                    "ratio_rocker_end": r.ratio_rocker[1],
                    "v2_share_cyl": r.v2_share_cyl,
                    "v2_share_rocker": r.v2_share_rocker,
                }
            )
        return pd.DataFrame(recs)

    def peaks_table(self) -> tuple[list[str], list[list[str]]]:
        """Header and rows of the comparison table (peaks, end values, shocks), as text."""
        head = [
            "law",
            "C_a",
            "max|a21|",
            "a21(0⁺)",
            "a21(T⁻)",
            "max|ε1|",
            "ε1(0⁺)",
            "ε1(T⁻)",
            "max|ε3|",
            "ε3(0⁺)",
            "ε3(T⁻)",
            "max J·|ε3| [N·m]",
            "soft shocks rod/links",
            "shock-free",
        ]
        rows = []
        for r in self.rows:
            tq = "-" if r.rocker_torque_peak is None else f"{r.rocker_torque_peak:.2f}"
            rows.append(
                [
                    r.law,
                    f"{r.c_a:.4f}",
                    f"{r.rod_peak:.4f}",
                    _f(r.rod_start, 4),
                    _f(r.rod_end, 4),
                    f"{r.cyl_peak:.5f}",
                    _f(r.cyl_start, 5),
                    _f(r.cyl_end, 5),
                    f"{r.rocker_peak:.5f}",
                    _f(r.rocker_start, 5),
                    _f(r.rocker_end, 5),
                    tq,
                    f"{r.rod_soft}/{r.link_soft}",
                    "yes" if r.shock_free else "no",
                ]
            )
        return head, rows

    def copy_table(self) -> tuple[list[str], list[list[str]]]:
        """Header and rows of the "links copy the rod's law" table, as text."""
        head = [
            "law",
            "r(ε1, a21)",
            "r(ε3, a21)",
            "ε1/a21 at 0⁺, T⁻",
            "ε3/a21 at 0⁺, T⁻",
            "v² share ε1",
            "v² share ε3",
        ]
        rows = []
        for r in self.rows:
            rows.append(
                [
                    r.law,
                    f"{r.corr_cyl:.4f}",
                    f"{r.corr_rocker:.4f}",
                    f"{r.ratio_cyl[0]:.4f}, {r.ratio_cyl[1]:.4f}",
                    f"{r.ratio_rocker[0]:.4f}, {r.ratio_rocker[1]:.4f}",
                    f"{r.v2_share_cyl:.1%}",
                    f"{r.v2_share_rocker:.1%}",
                ]
            )
        return head, rows

    def markdown(self) -> str:
        """Both tables as Markdown."""
        out = []
        for head, rows in (self.peaks_table(), self.copy_table()):
            out.append("| " + " | ".join(h.replace("|", "\\|") for h in head) + " |")
            out.append("|" + "---|" * len(head))
            out += ["| " + " | ".join(c for c in row) + " |" for row in rows]
            out.append("")
        return "\n".join(out).rstrip() + "\n"

    def text(self) -> str:
        """Both tables as fixed-width text."""
        blocks = []
        for head, rows in (self.peaks_table(), self.copy_table()):
            widths = [max(len(head[k]), *(len(r[k]) for r in rows)) for k in range(len(head))]
            lines = ["  ".join(h.rjust(w) for h, w in zip(head, widths, strict=True))]
            lines.append("  ".join("-" * w for w in widths))
            lines += ["  ".join(c.rjust(w) for c, w in zip(r, widths, strict=True)) for r in rows]
            blocks.append("\n".join(lines))
        return "\n\n".join(blocks)


def _f(x: float, digits: int) -> str:
    """Signed fixed-point text; values that round to zero print as an unsigned zero."""
    v = round(x, digits)
    return f"{0.0:.{digits}f}" if v == 0.0 else f"{v:+.{digits}f}"


def _corr(x: FloatArray, y: FloatArray) -> float:
    xc, yc = x - x.mean(), y - y.mean()
    den = math.sqrt(float(np.dot(xc, xc)) * float(np.dot(yc, yc)))
    return float(np.dot(xc, yc)) / den if den > 0.0 else math.nan


def compare_laws(
    laws: Sequence[str] = LAW_NAMES,
    *,
    mech: Mechanism | None = None,
    driver: str = "cyl",
    rocker: str = "rocker",
    stroke: float = PASIKA_STROKE,
    duration: float = PASIKA_DURATION,
    initial: float | None = None,
    intervals: int = 1000,
) -> LawStudy:
    """Run each motion law on the module and compare peaks, end values, shocks and shapes.

    Parameters
    ----------
    laws : sequence of str
        Names for [`get_law`][excavkin.motion.get_law] (default parameters), default all.
    mech : Mechanism, optional
        Default `pasika_module` (the paper's data, illustrative rocker mass).
    driver : str
        The driven cylinder (a linear driver); its line's ε is the cylinder's ε1.
    rocker : str
        The rocker body; its ε is ε3.
    stroke, duration : float
        H [m] and T [s] (the paper: 0.5 m, 5 s).
    initial : float, optional
        Cylinder length at the start [m]; default its sketch value.
    intervals : int
        Samples per stroke time ``T`` (the curves have ``1.2·intervals + 1`` samples).

    Returns
    -------
    LawStudy

    Examples
    --------
    >>> study = compare_laws(["cubic", "345"], intervals=200)
    >>> [(r.law, r.shock_free) for r in study.rows]
    [('cubic', False), ('345', True)]
    """
    if mech is None:
        mech = pasika_module()
    if intervals < 10:
        raise InputError(f"intervals must be at least 10, got {intervals}")
    q0 = mech.sketch_values()[driver] if initial is None else initial
    pad = intervals // 10
    t = duration * (np.arange(-pad, intervals + pad + 1, dtype=np.float64) / intervals)
    inside = slice(pad, pad + intervals + 1)
    cols_eps = (f"{driver}.epsilon", f"{rocker}.epsilon")
    cols_om = (f"{driver}.omega", f"{rocker}.omega")
    gains = end_gains(mech, driver, [q0, q0 + stroke], cols_om)
    rows, reports = [], []
    rod, cyl, rock = [], [], []
    for name in laws:
        law = get_law(name, stroke, duration)
        drives = {driver: Drive(law, initial=q0)}
        res = simulate(mech, drives, t=t, strict=True)
        rep = shock_report(mech, drives, res)
        a21 = np.asarray(res.column(f"{driver}.accel"), dtype=np.float64)
        v21 = np.asarray(res.column(f"{driver}.rate"), dtype=np.float64)
        e1 = np.asarray(res.column(cols_eps[0]), dtype=np.float64)
        e3 = np.asarray(res.column(cols_eps[1]), dtype=np.float64)
        rod.append(a21)
        cyl.append(e1)
        rock.append(e3)
        # velocity term u''(q)·q'² of ε: u'' is ε of a solve with unit rate and no acceleration
        q = np.asarray(res.column(f"{driver}.value"), dtype=np.float64)[inside]
        second = mech.solve(
            {driver: q}, {driver: np.ones_like(q)}, {driver: np.zeros_like(q)}, strict=True
        )
        v2 = v21[inside] ** 2
        shares = []
        for col in cols_eps:
            term = np.asarray(second.column(col), dtype=np.float64) * v2
            shares.append(float(np.max(np.abs(term)) / rep.peak(col).magnitude))
        lim = {
            c: (
                rep.limit(c, 0.0, "right") if rep.times.size else math.nan,
                rep.limit(c, duration, "left") if rep.times.size else math.nan,
            )
            for c in (f"{driver}.accel", *cols_eps)
        }
        ratios = []
        for k, col in enumerate(cols_eps):
            pair = []
            for end in (0, 1):
                a_end = lim[f"{driver}.accel"][end]
                pair.append(
                    lim[col][end] / a_end
                    if abs(a_end) > 1e-15 * law.peak_acceleration
                    else float(gains[end, k])
                )
            ratios.append((pair[0], pair[1]))
        rocker_peak = rep.peak(cols_eps[1])
        rows.append(
            LawRow(
                law=name,
                c_a=law.coefficients.c_a,
                rod_peak=rep.peak(f"{driver}.accel").magnitude,
                rod_start=lim[f"{driver}.accel"][0],
                rod_end=lim[f"{driver}.accel"][1],
                cyl_peak=rep.peak(cols_eps[0]).magnitude,
                cyl_start=lim[cols_eps[0]][0],
                cyl_end=lim[cols_eps[0]][1],
                rocker_peak=rocker_peak.magnitude,
                rocker_start=lim[cols_eps[1]][0],
                rocker_end=lim[cols_eps[1]][1],
                rocker_torque_peak=rocker_peak.inertia_torque,
                rod_soft=len([s for s in rep.soft if s.column == f"{driver}.accel"]),
                link_soft=len([s for s in rep.soft if s.column in cols_eps]),
                hard=len(rep.hard),
                corr_cyl=_corr(e1[inside], a21[inside]),
                corr_rocker=_corr(e3[inside], a21[inside]),
                ratio_cyl=ratios[0],
                ratio_rocker=ratios[1],
                v2_share_cyl=shares[0],
                v2_share_rocker=shares[1],
            )
        )
        reports.append(rep)
    return LawStudy(
        tuple(rows),
        t,
        np.array(rod),
        np.array(cyl),
        np.array(rock),
        tuple(reports),
        stroke,
        duration,
        gains,
    )
