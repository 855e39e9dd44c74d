r"""Soil-cutting resistance: Zelenin's, Balovnev's and McKyes's models (SI inside).

Each model gives the force of the soil on a cutting tool of width w moving at depth d below a
level free surface, in the **cut frame**: ``along`` opposes the tool's motion, ``normal``
pushes the tool into the soil (away from the free surface)::

          free surface (level)        q (surcharge)
      ────────────────┐   ___________________________
                      │  /  β failure plane    wedge
        cutting face  │ /
        (rake α)     ╲│/ d
                      ● → motion (along)
                      ↓ normal

The rake (cutting) angle α is between the cutting face, from the edge back along the teeth,
and the path behind the edge (α = 90°: a vertical face; α < 90°: the face leans back).

**Zelenin** (Зеленин А. Н., «Основы разрушения грунтов механическими способами», 1968) —
the empirical law, in its own units (kgf, cm, m, degrees)::

    P [kgf] = C · (h [cm])^1.35 · (1 + 2.6·w [m]) · (1 + 0.0075·α [deg]) · z · x

C the number of blows of the DorNII dynamic densitometer (soil strength), h the thickness of
the cut (here the depth d), w the width, α the cutting angle, z and x the source's factors for
the teeth and the side walls (1 = none). P is tangential; the normal part is taken as ψ·P
(``normal_ratio``).

**Balovnev** (Баловнев В. И., «Новые методы расчета сопротивлений резанию грунтов», 1981)
— the bucket form carried by the English-language literature on resistive-force models: a
passive stress state in front of the cutting face, A(x) its coefficient on a face at angle x::

    H = w·d·A(α)·(1 + cot α·tan δ)·(γd/2 + c·cot φ + q)                    cutting face
      + w·e·A(α_e)·(1 + tan δ·cot α_e)·(γe/2 + c·cot φ + q + γd·(1−sin φ)/(1+sin φ))
                                                                               blunt edge
      + d·A(π/2)·(2s + 4·l_s·tan δ)·(γd/2 + c·cot φ + q)                      side walls
    V = H·cot(α + δ)

    A(x) = (1 − sin φ·cos 2x)/(1 − sin φ)                              x ≤ x₀
         = cos δ·(cos δ + √(sin²φ − sin²δ))/(1 − sin φ)
           · exp((2x − π + δ + asin(sin δ/sin φ))·tan φ)               x > x₀
    x₀  = (π − δ − asin(sin δ/sin φ))/2

γ = ρg, c cohesion, φ internal and δ soil–metal friction, q surcharge, e and α_e the blunt
edge's thickness and angle, s and l_s the side walls' thickness and length. x₀ is where the
two branches of A meet (the Rankine zone and the log-spiral fan); with δ = 0 and x = π/2,
A = (1 + sin φ)/(1 − sin φ), Rankine's passive coefficient.

**McKyes** (McKyes E., «Soil Cutting and Tillage», 1985; Hettiaratchi & Reece) — the
fundamental earthmoving equation of a wide blade, from the equilibrium of a soil wedge between
the face and a planar failure surface at angle β::

    P = w·(γ·d²·N_γ + c·d·N_c + q·d·N_q + c_a·d·N_a)
    D   = cos(α+δ) + sin(α+δ)·cot(β+φ)  = sin(α+δ+β+φ)/sin(β+φ)
    N_γ = (cot α + cot β)/(2D)          N_c = (1 + cot β·cot(β+φ))/D
    N_q = (cot α + cot β)/D             N_a = (1 − cot α·cot(β+φ))/D
    H = P·sin(α+δ) + c_a·d·w·cot α      V = P·cos(α+δ) − c_a·d·w

with β the failure angle that minimises P (searched here per point, not read from charts),
c_a the soil–metal adhesion. P acts on the face at δ from its normal.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike

from excavkin.arrays import FloatArray as F
from excavkin.errors import InputError

Model = Literal["zelenin", "balovnev", "mckyes"]
MODELS: tuple[str, ...] = ("zelenin", "balovnev", "mckyes")

#: kilogram-force (N), Zelenin's unit of force
KGF = 9.80665
STANDARD_GRAVITY = 9.80665


@dataclass(frozen=True, slots=True)
class Soil:
    """A soil's properties for the three models (SI).

    Attributes
    ----------
    name : str
    density : float
        Bulk density ρ (kg/m³); γ = ρg.
    friction_angle : float
        Internal friction φ (rad).
    cohesion : float
        c (Pa).
    metal_friction : float
        Soil–metal friction δ (rad).
    adhesion : float
        Soil–metal adhesion c_a (Pa).
    blows : float
        Zelenin's C: blows of the DorNII dynamic densitometer.
    surcharge : float
        q on the free surface (Pa).
    """

    name: str
    density: float
    friction_angle: float
    cohesion: float
    metal_friction: float
    adhesion: float
    blows: float
    surcharge: float = 0.0

    def __post_init__(self) -> None:
        # a soil has weight and a strength count: zero would erase its resistance unsaid
        for key in ("density", "blows"):
            v = getattr(self, key)
            if not (np.isfinite(v) and v > 0.0):
                raise InputError(f"soil {self.name!r}: {key} must be finite and > 0, not {v!r}")
        for key in ("cohesion", "adhesion", "surcharge"):
            v = getattr(self, key)
            if not (np.isfinite(v) and v >= 0.0):
                raise InputError(f"soil {self.name!r}: {key} must be finite and ≥ 0, not {v!r}")
        for key in ("friction_angle", "metal_friction"):
            v = getattr(self, key)
            if not (np.isfinite(v) and 0.0 <= v < 0.5 * np.pi):
                raise InputError(f"soil {self.name!r}: {key} must be in [0°, 90°), not {v!r} rad")

    def unit_weight(self, g: float = STANDARD_GRAVITY) -> float:
        """γ = ρg (N/m³).

        Parameters
        ----------
        g : float, default 9.80665
            Gravity (m/s²).

        Returns
        -------
        float
            The soil's unit weight (N/m³).
        """
        return self.density * g


def _deg(a: float) -> float:
    return float(np.radians(a))


#: soil categories: ENGINEERING ESTIMATES of typical values (handbook ranges for each kind of
#: soil), not a source's table; give measured values where they are known
SOILS: dict[str, Soil] = {
    s.name: s
    for s in (
        Soil("sand", 1600.0, _deg(32.0), 0.0, _deg(22.0), 0.0, 3.0),
        Soil("loam", 1750.0, _deg(26.0), 10e3, _deg(20.0), 3e3, 7.0),
        Soil("clay", 1900.0, _deg(20.0), 30e3, _deg(16.0), 8e3, 12.0),
        Soil("heavy_clay", 2000.0, _deg(16.0), 60e3, _deg(14.0), 15e3, 24.0),
    )
}


def soil(name: str, **overrides: Any) -> Soil:
    """A soil of `SOILS` by name, with some properties replaced (SI)."""
    if name not in SOILS:
        raise InputError(f"unknown soil {name!r}; known soils: {', '.join(SOILS)}")
    unknown = (set(overrides) - set(Soil.__dataclass_fields__)) | ({"name"} & set(overrides))
    if unknown:
        raise InputError(f"unknown soil properties: {', '.join(sorted(unknown))}")
    return replace(SOILS[name], **overrides)


@dataclass(frozen=True, slots=True)
class Tool:
    """The cutting tool (bucket) as the models see it (SI).

    Attributes
    ----------
    width : float
        Cutting width w (m).
    teeth, walls : float
        Zelenin's factors z (teeth) and x (side walls); 1 for none.
    normal_ratio : float
        ψ: Zelenin's normal part as a fraction of the tangential.
    edge_thickness, edge_angle : float
        Balovnev's blunt edge e (m) and its angle α_e (rad); e = 0: a sharp edge.
    wall_thickness, wall_length : float
        Balovnev's side walls s and l_s (m); 0: no side walls.
    """

    width: float
    teeth: float = 1.0
    walls: float = 1.0
    normal_ratio: float = 0.0
    edge_thickness: float = 0.0
    edge_angle: float = 0.5 * np.pi
    wall_thickness: float = 0.0
    wall_length: float = 0.0

    def __post_init__(self) -> None:
        if not (np.isfinite(self.width) and self.width > 0.0):
            raise InputError(f"tool width must be finite and > 0, not {self.width!r}")
        # teeth and walls are Zelenin's factors z and x (1 for none), not counts: zero would
        # erase the resistance
        for key in ("teeth", "walls"):
            v = getattr(self, key)
            if not (np.isfinite(v) and v > 0.0):
                raise InputError(
                    f"tool {key} (Zelenin's factor, 1 for none) must be finite and > 0, not {v!r}"
                )
        for key in ("edge_thickness", "wall_thickness", "wall_length"):
            v = getattr(self, key)
            if not (np.isfinite(v) and v >= 0.0):
                raise InputError(f"tool {key} must be finite and ≥ 0, not {v!r}")
        if not np.isfinite(self.normal_ratio):
            raise InputError(f"tool normal_ratio must be finite, not {self.normal_ratio!r}")
        if not (np.isfinite(self.edge_angle) and 0.0 < self.edge_angle < np.pi):
            raise InputError(f"tool edge_angle must be in (0°, 180°), not {self.edge_angle!r}")


@dataclass(frozen=True, slots=True)
class Resistance:
    """Soil resistance on the tool at n points, in the cut frame.

    Attributes
    ----------
    along : ndarray, shape (n,)
        Opposing the motion (N).
    normal : ndarray, shape (n,)
        Pushing the tool into the soil (N; < 0 lifts it out).
    failure_angle : ndarray, shape (n,)
        McKyes's β (rad); NaN for the other models.
    """

    along: F
    normal: F
    failure_angle: F


# --------------------------------------------------------------------------------- Zelenin
def zelenin(depth: ArrayLike, rake: ArrayLike, s: Soil, tool: Tool) -> Resistance:
    """Zelenin's cutting resistance (module docstring), shape (n,) inputs → N.

    Parameters
    ----------
    depth : array_like, shape (n,)
        Thickness of the cut (m); ≤ 0: out of the soil, no resistance.
    rake : array_like, shape (n,)
        Cutting angle α (rad).
    s : Soil
    tool : Tool
    """
    d = np.maximum(np.asarray(depth, dtype=np.float64), 0.0)
    a = np.asarray(rake, dtype=np.float64)
    h_cm = 100.0 * d
    kgf = s.blows * h_cm**1.35 * (1.0 + 2.6 * tool.width) * (1.0 + 0.0075 * np.degrees(a))
    along = KGF * kgf * tool.teeth * tool.walls
    return Resistance(along, tool.normal_ratio * along, np.full_like(along, np.nan))


# -------------------------------------------------------------------------------- Balovnev
def balovnev_a(x: ArrayLike, phi: float, delta: float) -> F:
    """Balovnev's passive coefficient A(x) of a face at angle x (rad), shape of x."""
    if not 0.0 < phi < 0.5 * np.pi:
        raise InputError(f"Balovnev's model needs 0 < φ < 90°, not φ = {np.degrees(phi):g}°")
    if delta > phi:
        raise InputError(
            f"Balovnev's model needs δ ≤ φ, not δ = {np.degrees(delta):g}° > "
            f"φ = {np.degrees(phi):g}°"
        )
    x = np.asarray(x, dtype=np.float64)
    sp = np.sin(phi)
    mu = np.arcsin(np.sin(delta) / sp)
    x0 = 0.5 * (np.pi - delta - mu)
    rankine = (1.0 - sp * np.cos(2.0 * x)) / (1.0 - sp)
    fan = (
        np.cos(delta)
        * (np.cos(delta) + np.sqrt(sp**2 - np.sin(delta) ** 2))
        / (1.0 - sp)
        * np.exp((2.0 * x - np.pi + delta + mu) * np.tan(phi))
    )
    return np.asarray(np.where(x <= x0, rankine, fan))


def balovnev(
    depth: ArrayLike, rake: ArrayLike, s: Soil, tool: Tool, *, g: float = STANDARD_GRAVITY
) -> Resistance:
    """Balovnev's bucket resistance (module docstring), shape (n,) inputs → N.

    Parameters
    ----------
    depth : array_like, shape (n,)
        Depth of the edge below the free surface (m); ≤ 0: no resistance.
    rake : array_like, shape (n,)
        Cutting angle α (rad), in (0, π).
    s : Soil
    tool : Tool
    g : float
        Gravity (m/s²).
    """
    d = np.maximum(np.asarray(depth, dtype=np.float64), 0.0)
    a = np.asarray(rake, dtype=np.float64)
    phi, delta = s.friction_angle, s.metal_friction
    gam = s.unit_weight(g)
    td = np.tan(delta)
    balovnev_a(0.5 * np.pi, phi, delta)  # its limits on φ and δ first, before c·cot φ
    base = s.cohesion / np.tan(phi) + s.surcharge
    e, ae = tool.edge_thickness, tool.edge_angle
    ka = (1.0 - np.sin(phi)) / (1.0 + np.sin(phi))
    with np.errstate(divide="ignore", invalid="ignore"):
        face = tool.width * d * balovnev_a(a, phi, delta) * (1.0 + td / np.tan(a))
        face = face * (0.5 * gam * d + base)
        edge = tool.width * e * balovnev_a(ae, phi, delta) * (1.0 + td / np.tan(ae))
        edge = edge * (0.5 * gam * e + base + gam * d * ka)
        walls = d * balovnev_a(0.5 * np.pi, phi, delta)
        walls = walls * (2.0 * tool.wall_thickness + 4.0 * tool.wall_length * td)
        walls = walls * (0.5 * gam * d + base)
        along = np.where(d > 0.0, face + edge + walls, 0.0)
        normal = along / np.tan(a + delta)
    return Resistance(along, normal, np.full_like(along, np.nan))


# ---------------------------------------------------------------------------------- McKyes
@dataclass(frozen=True, slots=True)
class McKyesFactors:
    """McKyes's N factors at a failure angle, each shape (n,)."""

    gamma: F
    c: F
    q: F
    a: F


def mckyes_factors(rake: ArrayLike, beta: ArrayLike, phi: float, delta: float) -> McKyesFactors:
    """The N factors (module docstring) at rake α and failure angle β (rad), broadcast."""
    a = np.asarray(rake, dtype=np.float64)
    b = np.asarray(beta, dtype=np.float64)
    with np.errstate(divide="ignore", invalid="ignore"):
        D = np.sin(a + delta + b + phi) / np.sin(b + phi)
        ca, cb, cbp = 1.0 / np.tan(a), 1.0 / np.tan(b), 1.0 / np.tan(b + phi)
        return McKyesFactors(
            (ca + cb) / (2.0 * D), (1.0 + cb * cbp) / D, (ca + cb) / D, (1.0 - ca * cbp) / D
        )


def _mckyes_p(a: F, b: F, d: F, s: Soil, w: float, gam: float, phi: float, delta: float) -> F:
    N = mckyes_factors(a, b, phi, delta)
    per = gam * d**2 * N.gamma + s.cohesion * d * N.c + s.surcharge * d * N.q
    return np.asarray(w * (per + s.adhesion * d * N.a))


def mckyes_failure_angle(
    depth: ArrayLike, rake: ArrayLike, s: Soil, tool: Tool, *, g: float = STANDARD_GRAVITY
) -> F:
    """The failure angle β that minimises P at each point (rad), shape (n,).

    β ranges over (0, π − α − δ − φ), where the wedge's equilibrium has a positive
    denominator D; a grid of 257 angles brackets the least P and a golden-section search
    narrows it to round-off. NaN where that range is empty (α + δ + φ ≥ π).
    """
    d = np.atleast_1d(np.maximum(np.asarray(depth, dtype=np.float64), 0.0))
    a = np.atleast_1d(np.asarray(rake, dtype=np.float64))
    d, a = np.broadcast_arrays(d, a)
    phi, delta, gam, w = s.friction_angle, s.metal_friction, s.unit_weight(g), tool.width
    top = np.pi - a - delta - phi
    ok = top > 0.0
    top = np.where(ok, top, 1.0)
    dd = np.where(d > 0.0, d, 1.0)  # β of a vanishing cut: the limit d → 0⁺ (same shape)
    t = np.linspace(0.0, 1.0, 257)[1:-1]
    grid = top[:, None] * t[None, :]
    p = _mckyes_p(a[:, None], grid, dd[:, None], s, w, gam, phi, delta)
    p = np.where(np.isfinite(p) & (p > 0.0), p, np.inf)
    k = np.argmin(p, axis=1)
    step = top / 256.0
    lo = np.maximum(grid[np.arange(len(k)), k] - step, 1e-12 * top)
    hi = np.minimum(grid[np.arange(len(k)), k] + step, top * (1.0 - 1e-12))
    r = 0.5 * (np.sqrt(5.0) - 1.0)
    x1, x2 = hi - r * (hi - lo), lo + r * (hi - lo)
    f1 = _mckyes_p(a, x1, dd, s, w, gam, phi, delta)
    f2 = _mckyes_p(a, x2, dd, s, w, gam, phi, delta)
    for _ in range(90):  # (0.618)^90 of one grid step: below round-off
        left = f1 < f2  # the least P lies in [lo, x2], else in [x1, hi]
        hi = np.where(left, x2, hi)
        lo = np.where(left, lo, x1)
        fresh = np.where(left, hi - r * (hi - lo), lo + r * (hi - lo))
        fn = _mckyes_p(a, fresh, dd, s, w, gam, phi, delta)
        x1, x2 = np.where(left, fresh, x2), np.where(left, x1, fresh)
        f1, f2 = np.where(left, fn, f2), np.where(left, f1, fn)
    return np.asarray(np.where(ok, 0.5 * (lo + hi), np.nan))


def mckyes(
    depth: ArrayLike, rake: ArrayLike, s: Soil, tool: Tool, *, g: float = STANDARD_GRAVITY
) -> Resistance:
    """McKyes's fundamental earthmoving equation (module docstring), shape (n,) → N.

    Parameters
    ----------
    depth : array_like, shape (n,)
        Depth of the edge below the free surface (m); ≤ 0: no resistance.
    rake : array_like, shape (n,)
        Rake angle α (rad), in (0, π).
    s : Soil
    tool : Tool
    g : float
        Gravity (m/s²).
    """
    d = np.atleast_1d(np.maximum(np.asarray(depth, dtype=np.float64), 0.0))
    a = np.atleast_1d(np.asarray(rake, dtype=np.float64))
    d, a = np.broadcast_arrays(d, a)
    beta = mckyes_failure_angle(d, a, s, tool, g=g)
    phi, delta, w = s.friction_angle, s.metal_friction, tool.width
    P = _mckyes_p(a, beta, d, s, w, s.unit_weight(g), phi, delta)
    with np.errstate(divide="ignore", invalid="ignore"):
        adh = s.adhesion * d * w
        along = P * np.sin(a + delta) + adh / np.tan(a)
        normal = P * np.cos(a + delta) - adh
    out = d > 0.0
    return Resistance(
        np.where(out, along, 0.0), np.where(out, normal, 0.0), np.asarray(beta, dtype=np.float64)
    )


@dataclass(frozen=True, slots=True)
class ShearPlane:
    """The stresses on McKyes's failure plane at the least force, each shape (n,).

    Attributes
    ----------
    angle : ndarray
        The failure (shear) angle β (rad).
    normal_stress : ndarray
        σ, the intact soil's normal stress on the wedge across the plane (Pa, > 0 pressing).
    shear_stress : ndarray
        τ, its shear stress opposing the wedge's slip (Pa); τ = c + σ·tan φ (Mohr–Coulomb at
        failure).
    """

    angle: F
    normal_stress: F
    shear_stress: F


def mckyes_shear_plane(
    depth: ArrayLike, rake: ArrayLike, s: Soil, tool: Tool, *, g: float = STANDARD_GRAVITY
) -> ShearPlane:
    """The normal and shear stress on McKyes's failure plane (mean over the plane).

    The wedge between the face and the plane is in equilibrium under the tool's force on it
    (P at δ from the face's normal, and the adhesion c_a·d·w/sin α along the face), its weight
    γ·w·d²·(cot α + cot β)/2, the surcharge q·w·d·(cot α + cot β) and the intact soil's force
    across the plane, whose components on the plane's normal and along it, over the plane's
    area w·d/sin β, are σ and τ.

    Parameters
    ----------
    depth : array_like, shape (n,)
        Depth of the edge below the free surface (m); > 0.
    rake : array_like, shape (n,)
        Rake angle α (rad), in (0, π).
    s : Soil
    tool : Tool
    g : float
        Gravity (m/s²); 0 for a cut where the soil's weight is left out (rock).

    Returns
    -------
    ShearPlane
    """
    d = np.atleast_1d(np.asarray(depth, dtype=np.float64))
    a = np.atleast_1d(np.asarray(rake, dtype=np.float64))
    d, a = np.broadcast_arrays(d, a)
    if not (d > 0.0).all():
        raise InputError("the stresses on the failure plane need a depth > 0")
    b = mckyes_failure_angle(d, a, s, tool, g=g)
    phi, delta, w = s.friction_angle, s.metal_friction, tool.width
    P = _mckyes_p(a, b, d, s, w, s.unit_weight(g), phi, delta)
    # the tool's force on the wedge, in x along the motion and y up: P along the face's
    # normal (sin α, cos α) turned by δ towards the edge, and the adhesion down the face
    adh = s.adhesion * d * w / np.sin(a)
    tx = P * np.sin(a + delta) + adh * np.cos(a)
    ty = P * np.cos(a + delta) - adh * np.sin(a)
    top = d * (1.0 / np.tan(a) + 1.0 / np.tan(b))
    down = 0.5 * s.unit_weight(g) * w * d * top + s.surcharge * w * top
    fx, fy = -tx, -(ty - down)  # the intact soil's force on the wedge balances the rest
    area = d * w / np.sin(b)
    normal = (-fx * np.sin(b) + fy * np.cos(b)) / area
    shear = -(fx * np.cos(b) + fy * np.sin(b)) / area
    return ShearPlane(np.asarray(b), np.asarray(normal), np.asarray(shear))


def cohesion_from_ucs(ucs: float, friction_angle: float) -> float:
    """The Mohr–Coulomb cohesion of a material of unconfined compressive strength ``ucs``
    (Pa) and internal friction φ (rad): c = UCS·(1 − sin φ)/(2·cos φ).

    The uniaxial test's Mohr circle (σ₃ = 0, σ₁ = UCS; centre UCS/2, radius UCS/2) touches
    the failure line τ = c + σ·tan φ: the centre's distance to the line,
    (c + (UCS/2)·tan φ)·cos φ, equals the radius.

    Parameters
    ----------
    ucs : float
        Pa, > 0.
    friction_angle : float
        φ (rad), in [0, π/2).

    Returns
    -------
    float
        c (Pa).
    """
    if not (np.isfinite(ucs) and ucs > 0.0):
        raise InputError(f"the compressive strength must be finite and > 0, not {ucs!r}")
    if not (np.isfinite(friction_angle) and 0.0 <= friction_angle < 0.5 * np.pi):
        raise InputError(f"φ must be in [0°, 90°), not {friction_angle!r} rad")
    return float(ucs * (1.0 - np.sin(friction_angle)) / (2.0 * np.cos(friction_angle)))


def resistance(
    model: str,
    depth: ArrayLike,
    rake: ArrayLike,
    s: Soil,
    tool: Tool,
    *,
    g: float = STANDARD_GRAVITY,
) -> Resistance:
    """The resistance of the named model (``"zelenin"``, ``"balovnev"``, ``"mckyes"``).

    Parameters
    ----------
    model : {"zelenin", "balovnev", "mckyes"}
        The resistance model (module docstring).
    depth : array_like, shape (n,)
        Depth of the cut (m): its thickness for Zelenin, the edge's depth below the free
        surface for the others; ≤ 0: out of the soil, no resistance.
    rake : array_like, shape (n,)
        Cutting (rake) angle α (rad); in (0, π) for Balovnev's and McKyes's models.
    s : Soil
        The soil's properties.
    tool : Tool
        The cutting tool.
    g : float, default 9.80665
        Gravity (m/s²); Zelenin's empirical model does not use it.

    Returns
    -------
    Resistance
        Along and normal forces on the tool at each point (N), in the cut frame.

    Raises
    ------
    InputError
        An unknown model, or a soil outside a model's limits (Balovnev's φ and δ).
    """
    if model == "zelenin":
        return zelenin(depth, rake, s, tool)
    if model == "balovnev":
        return balovnev(depth, rake, s, tool, g=g)
    if model == "mckyes":
        return mckyes(depth, rake, s, tool, g=g)
    raise InputError(f"unknown soil model {model!r}; known models: {', '.join(MODELS)}")
