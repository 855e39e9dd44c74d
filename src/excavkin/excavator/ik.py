"""The cylinder lengths that put an excavator's tooth tip at a point with a given bucket angle
(``excavkin excavator ik``): every branch of the closed-form inverse kinematics
([`inverse`][excavkin.excavator.machine.inverse]), each checked against the strokes and the
model's assembly branch, and the first valid one checked by the forward kinematics.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from excavkin.arrays import FloatArray as F
from excavkin.excavator.machine import BRANCHES, InverseSolution, Machine, forward, inverse

#: the cylinder roles, in the order of every length
_ROLES = ("boom", "arm", "bucket")


@dataclass(frozen=True)
class TipTarget:
    """The inverse kinematics of one tip target (`tip_target`).

    Attributes
    ----------
    machine : Machine
    tip : ndarray, shape (2,)
        The target in the model's plane (m).
    angle : float
        The bucket angle: direction of bucket pin → tip, CCW from +x (rad).
    solution : InverseSolution
        Every branch, for n = 1 pose.
    """

    machine: Machine
    tip: F
    angle: float
    solution: InverseSolution

    def branch_name(self, k: int) -> str:
        """The name of branch ``k`` (``"pivot+ link−"``).

        Parameters
        ----------
        k : int
            Its index in `BRANCHES`.

        Returns
        -------
        str
        """
        s1, s2 = BRANCHES[k]
        return f"pivot{'+' if s1 > 0 else '−'} link{'+' if s2 > 0 else '−'}"

    def notes(self, k: int) -> list[str]:
        """Why branch ``k`` is not a valid answer (empty if it is): a cylinder beyond its
        stroke, the model's other assembly branch.

        Parameters
        ----------
        k : int

        Returns
        -------
        list of str
        """
        m, sol = self.machine, self.solution
        lo, hi = m.lengths_min, m.lengths_max
        L = sol.lengths[0, k]
        out = []
        for c, role in enumerate(_ROLES):
            if L[c] < lo[c] - 1e-9 or L[c] > hi[c] + 1e-9:
                out.append(f"{role} beyond stroke ({lo[c] * 1e3:.0f}–{hi[c] * 1e3:.0f})")
        if not sol.model_branch[0, k]:
            out.append("other assembly branch")
        return out

    @property
    def valid(self) -> bool:
        """Whether a branch reaches the target within the strokes on the model's branch.

        Returns
        -------
        bool
        """
        return bool(self.solution.valid[0].any())

    def check(self) -> float:
        """The distance of the first valid branch's forward kinematics from the target (m;
        NaN if none is valid).

        Returns
        -------
        float
        """
        if not self.valid:
            return float("nan")
        k = int(np.argmax(self.solution.valid[0]))
        fk = forward(self.machine, self.solution.lengths[0, k][None, :])
        return float(np.hypot(*(fk.tip[0] - self.tip)))

    def summary(self) -> str:
        """Every branch as ``excavkin excavator ik`` prints it (mm).

        Returns
        -------
        str
        """
        m, sol = self.machine, self.solution
        lines = [
            f"{m.name} — tip at x = {self.tip[0] * 1e3:.0f} mm, y = {self.tip[1] * 1e3:.0f} mm, "
            f"bucket angle {np.degrees(self.angle):.2f}°",
            f"{'branch':<14} {'boom mm':>9} {'arm mm':>9} {'bucket mm':>9}  status",
        ]
        for k in range(len(BRANCHES)):
            name = self.branch_name(k)
            if not sol.reachable[0, k]:
                lines.append(f"{name:<14} {'—':>9} {'—':>9} {'—':>9}  out of reach")
                continue
            L = sol.lengths[0, k]
            status = "; ".join(self.notes(k)) or "valid"
            lines.append(
                f"{name:<14} {L[0] * 1e3:9.1f} {L[1] * 1e3:9.1f} {L[2] * 1e3:9.1f}  {status}"
            )
        if self.valid:
            lines.append(
                f"check: forward kinematics of the first valid solution is {self.check():.1e} m "
                "from the target"
            )
        else:
            lines.append("no valid solution: the pose is out of the working range")
        return "\n".join(lines)


def tip_target(machine: Machine, reach: float, height: float, angle: float) -> TipTarget:
    """Every inverse-kinematics branch for the tooth tip at ``reach`` from the swing axis and
    ``height`` above the ground line, with the bucket at ``angle``.

    Parameters
    ----------
    machine : Machine
    reach, height : float
        The target from the swing axis and above the ground line (m).
    angle : float
        Direction of bucket pin → tip, CCW from +x (rad).

    Returns
    -------
    TipTarget
    """
    tip = np.array([reach + machine.swing_axis, height + machine.ground_line], dtype=np.float64)
    return TipTarget(machine, tip, float(angle), inverse(machine, tip[None, :], np.array([angle])))
