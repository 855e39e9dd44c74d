"""Rest-to-rest motion laws for a driver moving a stroke ``H`` in a time ``T``.

Every law is written in normalised form, ``u = (t - t0) / T`` in ``[0, 1]``::

    s(t) = H * f(u)          v(t) = H / T * f'(u)
    a(t) = H / T**2 * f''(u) j(t) = H / T**3 * f'''(u)

with ``f(0) = 0``, ``f(1) = 1`` and ``f'(0) = f'(1) = 0``. The peak coefficients
``C_v = max|f'|``, ``C_a = max|f''|`` and ``C_j = max|f'''|`` are exact (see
[`MotionLaw.coefficients`][excavkin.motion.laws.MotionLaw.coefficients] and
``docs/motion-laws.md``).

Conventions
-----------
* SI units: ``H`` in m (or rad for an angular driver), ``T`` and ``t`` in s.
* Outside ``[t0, t0 + T]`` a law holds its end values: ``s = 0`` before, ``s = H`` after,
  ``v = a = j = 0``. The closed interval ``[t0, t0 + T]`` uses the formulas, so the values
  *at* the ends show the soft shocks: for the cubic law ``a(t0) = 6 H / T**2`` while
  ``a`` just before ``t0`` is 0.
* Jerk is the analytic derivative of ``a`` inside each piece. Where ``a`` jumps (the ends of
  the cubic and harmonic laws, the corners of the trapezoidal law) the Dirac part of the jerk
  is **not** represented; the jumps are reported by
  [`MotionLaw.acceleration_jumps`][excavkin.motion.laws.MotionLaw.acceleration_jumps] and
  by the values of ``a`` at the ends.
* Piecewise laws use left-closed pieces ``[u_k, u_k+1)``; the last piece is closed. At an
  interior breakpoint the value of the right piece is returned.

::

    s ^                      ____ H
      |                 _.-''
      |             _.-'
      |         _.-'
      |____..-''
      +--------+------------------+--> t
      0       t0               t0 + T

The package, one module a concern:

* `base` — [`MotionLaw`][excavkin.motion.laws.MotionLaw], its state, peaks and jumps;
* `polynomial` — cubic, 3-4-5, 4-5-6-7;
* `trigonometric` — cycloidal, harmonic;
* `modified` — modified trapezoid, modified sine;
* `limited` — trapezoidal, S-curve;
* `dwell` — a dwell;
* `profile` — laws one after the other;
* `registry` — the laws by name.
"""

from excavkin.motion.laws.base import AccelerationJump, MotionLaw, MotionState, PeakCoefficients
from excavkin.motion.laws.dwell import Dwell, dwell
from excavkin.motion.laws.limited import SCurveLaw, TrapezoidalLaw
from excavkin.motion.laws.modified import ModifiedSineLaw, ModifiedTrapezoidLaw
from excavkin.motion.laws.polynomial import CubicLaw, Poly345Law, Poly4567Law
from excavkin.motion.laws.profile import Profile, Segment
from excavkin.motion.laws.registry import LAW_NAMES, get_law
from excavkin.motion.laws.trigonometric import CycloidalLaw, HarmonicLaw

__all__ = [
    "LAW_NAMES",
    "AccelerationJump",
    "CubicLaw",
    "CycloidalLaw",
    "Dwell",
    "HarmonicLaw",
    "ModifiedSineLaw",
    "ModifiedTrapezoidLaw",
    "MotionLaw",
    "MotionState",
    "PeakCoefficients",
    "Poly345Law",
    "Poly4567Law",
    "Profile",
    "SCurveLaw",
    "Segment",
    "TrapezoidalLaw",
    "dwell",
    "get_law",
]
