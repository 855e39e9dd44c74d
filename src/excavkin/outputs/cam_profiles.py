"""The profiles of a mechanism's disc cams, for its drawings.

A cam's profile is what its follower touches, as the cam carries it round: each point is the
follower's contact at one turn φ of the cam, carried back to the cam's turn θ at the sample
shown, a rotation by θ − φ about the cam's pivot ``o``::

    P(φ) = o + R(θ − φ)·(C(φ) − o)

All of it is read from the sample's own positions: the carrier's frame there (the guide's
direction ``ê`` and ``n = perp(ê)``), the cam's turn θ (its angle from the carrier's less the
sketch's, in the sketch θ = 0) and the follower's point ``F``, whose place fixes the law's
origin. The contact ``C(φ)`` is:

- a translating roller: the roller's centre ``o + (a + s(φ))·ê + b·n`` — the *pitch curve*
  (``a + s(θ)`` and ``b``: F's coordinates along and across the guide). The model gives no
  roller radius, so the pitch curve is drawn: the profile of a knife edge, the actual
  profile of a roller lying the roller's radius inside it;
- a flat face square to the guide: the envelope of the faces, ``o + (a + s(φ))·ê − s'(φ)·n``
  (the contact lies ``s'`` off the axis, as the contact force does); the face itself is
  drawn too, a segment through F square to the guide;
- an oscillating roller about its pivot ``p``: ``p + r·(cos, sin)(β0 + ψ(φ))`` with ``r`` and
  ``β0 + ψ(θ)`` F's distance and angle from p — again the pitch curve.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from excavkin.model.cams import lift_law
from excavkin.model.gears import pivot_on
from excavkin.outputs.display_units import convert

if TYPE_CHECKING:
    from matplotlib.axes import Axes

    from excavkin.outputs.scene import Scene

__all__ = ["add_cam_profiles", "cam_profiles", "move_cam_profiles"]

#: points on a profile (one every degree, the last repeating the first)
POINTS = 361


def _angle(xy: np.ndarray, p: int, q: int) -> Any:
    """The direction p→q of positions ``xy`` (…, n_points, 2)."""
    d = xy[..., q, :] - xy[..., p, :]
    return np.arctan2(d[..., 1], d[..., 0])


def cam_profiles(scene: Scene, sample: int, n: int = POINTS) -> list[np.ndarray]:
    """Each cam's profile at ``sample``, and a flat face's segment, as polylines.

    Parameters
    ----------
    scene : Scene
        The drawing's geometry.
    sample : int
        The sample shown.
    n : int
        Points on each profile (the last repeats the first).

    Returns
    -------
    list of ndarray, shape (n, 2) or (2, 2)
        In the scene's length unit: per cam its profile (the pitch curve for a roller), and
        after a flat-faced follower's profile its face; NaN where the sample did not solve.
    """
    model = scene.plan.model
    index = {p: i for i, p in enumerate(scene.plan.points)}
    sketch = np.asarray(scene.plan.sketch, dtype=np.float64)
    xy = scene.xy[sample]
    unit = scene.length_unit
    phi = np.linspace(0.0, 2.0 * np.pi, n)
    out: list[np.ndarray] = []
    for cm in model.cams:
        law = lift_law(cm.lift)
        o = index[pivot_on(model, cm.cam, cm.carrier, f"cams.{cm.name}", "cam")]
        cam, carrier = model.body(cm.cam), model.body(cm.carrier)
        c0, c1 = index[cam.points[0]], index[cam.points[1]]
        turn = _angle(xy, c0, c1) - _angle(sketch, c0, c1)
        if not carrier.ground:
            k0, k1 = index[carrier.points[0]], index[carrier.points[1]]
            turn = turn - (_angle(xy, k0, k1) - _angle(sketch, k0, k1))
        s_now = law(np.asarray(turn))[0]
        s, s1, _ = law(phi)
        follower = model.body(cm.follower)
        if cm.along is None:  # oscillating: F swung about the follower's pivot
            swing = index[pivot_on(model, cm.follower, cm.carrier, f"cams.{cm.name}", "follower")]
            f = index[next(p for p in follower.points if index[p] != swing)]
            r = np.hypot(*(xy[f] - xy[swing]))
            beta = _angle(xy, swing, f) - s_now + s
            contact = xy[swing] + r * np.stack([np.cos(beta), np.sin(beta)], axis=1)
            face = None
        else:
            f = index[follower.points[0]]
            l1, l2 = index[cm.along[0]], index[cm.along[1]]
            e = (xy[l2] - xy[l1]) / np.hypot(*(xy[l2] - xy[l1]))
            nrm = np.array([-e[1], e[0]])
            rel = xy[f] - xy[o]
            along = rel @ e - convert(np.float64(s_now), "length", unit)
            h = along + convert(s, "length", unit)
            if cm.face == "flat":
                dh = convert(s1, "length", unit)
                contact = xy[o] + h[:, None] * e - dh[:, None] * nrm
                half = 1.2 * float(np.max(np.abs(dh))) + 0.25 * float(np.max(np.abs(h)))
                face = xy[f] + np.outer([-half, half], nrm)
            else:
                contact = xy[o] + h[:, None] * e + float(rel @ nrm) * nrm
                face = None
        back = turn - phi  # each contact carried from its turn φ to the cam's turn now
        cs, sn = np.cos(back), np.sin(back)
        d = contact - xy[o]
        out.append(xy[o] + np.stack([cs * d[:, 0] - sn * d[:, 1], sn * d[:, 0] + cs * d[:, 1]], 1))
        if face is not None:
            out.append(face)
    return out


def add_cam_profiles(ax: Axes, scene: Scene, sample: int, zorder: float, alpha: float) -> list[Any]:
    """Draw the cams' profiles (and flat faces) at ``sample``.

    Parameters
    ----------
    ax : Axes
        Where.
    scene : Scene
        The drawing's geometry.
    sample : int
        The sample drawn.
    zorder, alpha : float
        As the drawing's.

    Returns
    -------
    list of Line2D
        One line per path of `cam_profiles` (for `move_cam_profiles`).
    """
    out = []
    for path in cam_profiles(scene, sample):
        (line,) = ax.plot(
            path[:, 0], path[:, 1], color="0.2", lw=1.4, zorder=zorder + 0.6, alpha=alpha
        )
        out.append(line)
    return out


def move_cam_profiles(lines: list[Any], scene: Scene, sample: int) -> list[Any]:
    """Move the cams' profiles to ``sample``.

    Parameters
    ----------
    lines : list of Line2D
        From `add_cam_profiles`.
    scene : Scene
        The drawing's geometry.
    sample : int
        The sample shown.

    Returns
    -------
    list of Line2D
        The lines moved.
    """
    for line, path in zip(lines, cam_profiles(scene, sample), strict=True):
        line.set_data(path[:, 0], path[:, 1])
    return lines
