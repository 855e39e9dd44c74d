r"""A rope backhoe's boom held by its hoist: the hoist tackle's pull and the boom-foot pin.

The backhoe's model has the boom as its frame (the paper's: the stick, the bucket linkage and
the drag rope move on it). The boom itself is pinned at its foot O3 to the revolving frame and
held up by the hoist tackle, ``parts`` parts of rope between a block on the boom (P) and the
gantry's sheave (G) on the revolving frame. Its moment balance about the foot gives the
tackle's pull H (all its parts, > 0 pulls P towards G)::

    Σ (r_k − O3) × R_k  +  (c − O3) × m·g  +  (F − O3) × T·u_FL  +  (P − O3) × H·u_PG  =  0

* R_k: the forces of the mechanism on the boom at its points r_k — the general kinetostatics'
  pin forces on the frame (the stick's pin O1, the locked cylinder's pin, the drag rope's pull
  at its sheave F: a linear driver's force reaches the frame through the pin of its end), and
  the reaction of any rotary driver turned against the frame;
* m·g: the boom's weight at its centre of mass c, gravity in the model's frame
  g·(sin β, cos β) for the boom's angle β to the horizontal (the model's frame is the paper's:
  "x forward, y up" turned by π, so +y points down when β = 0, and the paper's X axis runs from
  the stick's pin towards the boom foot, its β > 0 raising the boom's point);
* T·u_FL: the drag rope's free part, from its sheave F on the boom towards the drum's take-off
  L on the revolving frame, one part's tension T;
* H·u_PG: the tackle, u_PG the unit vector from P to G.

The foot pin's force on the boom closes the force balance:
``R_O3 = −(Σ R_k + m·g + T·u_FL + H·u_PG)``. A rope only pulls: where H < 0 the tackle
would have to push, and the sample's status says so.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.kinetostatics import ForceResult

#: the status of a sample whose hoist tackle would have to push
SLACK_HOIST = "slack hoist rope (it would have to push)"
#: the status of a sample whose drag rope would have to push
SLACK_DRAG = "slack drag rope (it would have to push)"


@dataclass(frozen=True, slots=True)
class HoistBalance:
    """The boom's balance over n samples, SI.

    Attributes
    ----------
    pull : ndarray, shape (n,)
        The hoist tackle's pull on the boom, all its parts (N, > 0 pulls).
    tension : ndarray, shape (n,)
        One part's tension, ``pull / parts`` (N).
    foot : ndarray, shape (n, 2)
        The foot pin's force on the boom (N, the model's frame).
    status : ndarray of str, shape (n,)
        The forces' status: ``"slack drag rope (it would have to push)"`` where the drag
        rope's tension is negative, else ``"slack hoist rope (it would have to push)"`` where
        the pull is.
    """

    pull: F
    tension: F
    foot: F
    status: np.ndarray

    @property
    def ok(self) -> np.ndarray:
        """Samples whose status is ``"ok"``, shape (n,)."""
        return np.asarray(self.status == "ok")


def _cross(a: F, b: F) -> F:
    return np.asarray(a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0])


def _unit(a: tuple[float, float], b: tuple[float, float]) -> F:
    d = np.subtract(b, a, dtype=float)
    return np.asarray(d / np.hypot(*d))


@dataclass(frozen=True, slots=True)
class Boom:
    """A rope backhoe's boom: its foot, weight, hoist tackle and the drag rope's lead.

    Every point is in the model's frame (the boom's), m.

    Attributes
    ----------
    foot : (float, float)
        The boom-foot pin O3.
    mass : float
        kg.
    centre : (float, float)
        The boom's centre of mass.
    block : (float, float)
        The hoist tackle's block on the boom, P.
    gantry : (float, float)
        The gantry's sheave the tackle runs to, G (on the revolving frame).
    parts : int
        Parts of rope between P and G.
    angle : float
        The boom's angle to the horizontal, β (rad; the paper's β_ст, > 0 raises its point).
    sheave : str
        The model's point where the drag rope leaves the boom (its sheave F).
    lead : (float, float)
        The drum's take-off the drag rope runs to from the sheave, L (on the revolving frame).
    gravity : float
        m/s².
    """

    foot: tuple[float, float]
    mass: float
    centre: tuple[float, float]
    block: tuple[float, float]
    gantry: tuple[float, float]
    parts: int
    angle: float
    sheave: str
    lead: tuple[float, float]
    gravity: float = 9.80665

    @property
    def down(self) -> F:
        """The direction of gravity in the model's frame, (sin β, cos β), shape (2,)."""
        return np.array([np.sin(self.angle), np.cos(self.angle)])

    @property
    def hoist_arm(self) -> float:
        """The tackle's moment arm about the foot, ``(P − O3) × u_PG`` (m, > 0 counter-clockwise
        in the model's frame)."""
        return float(_cross(np.subtract(self.block, self.foot), _unit(self.block, self.gantry)))

    def balance(self, forces: ForceResult, drag_tension: F) -> HoistBalance:
        """The hoist tackle's pull and the foot pin's force (module docstring).

        Parameters
        ----------
        forces : ForceResult
            The general kinetostatics of the backhoe's model (the boom its frame).
        drag_tension : ndarray, shape (n,)
            One part of the drag rope's tension (N): its free part's pull on the sheave.

        Returns
        -------
        HoistBalance
        """
        sy = forces.system
        ground = sy.ground
        x = forces.kinematics.positions
        o3 = np.asarray(self.foot, dtype=float)
        n = len(forces)
        total = np.zeros((n, 2))
        moment = np.zeros(n)
        for k, (i, j) in enumerate(sy.slots):
            if j != ground:
                continue
            f = forces.pin_force[:, k]
            total += f
            moment += _cross(x[:, i] - o3, f)
        for k, (_, body, ref) in enumerate(sy.rotary):
            moment += forces.driver_torque[:, k] * ((body == ground) - (ref == ground))
        weight = self.mass * self.gravity * self.down
        total += weight
        moment += float(_cross(np.subtract(self.centre, o3), weight))
        f_pt = x[:, sy.points.index(self.sheave)]
        lead = np.asarray(self.lead, dtype=float) - f_pt
        lead_force = (
            np.asarray(drag_tension, dtype=float)[:, None]
            * lead
            / np.hypot(lead[:, 0], lead[:, 1])[:, None]
        )
        total += lead_force
        moment += _cross(f_pt - o3, lead_force)
        pull = -moment / self.hoist_arm
        total += pull[:, None] * _unit(self.block, self.gantry)
        labels = forces.status_labels().astype(object)
        labels[(np.asarray(drag_tension) < 0.0) & (labels == "ok")] = SLACK_DRAG
        labels[(pull < 0.0) & (labels == "ok")] = SLACK_HOIST
        return HoistBalance(pull, pull / self.parts, -total, np.asarray(labels, dtype=str))
