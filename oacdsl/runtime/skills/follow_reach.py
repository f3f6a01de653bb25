"""Whether ``follow``'s path is in the arm's reach, and the variant of it that is.

Before the object moves, the whole-body IK is asked for the core's keyframes with the other
hand's goal as it will be (docs/runtime.md, "follow"): the usual orientation weight, then the
orientation a soft wish, the core moved across the target by where the IK left the hand, then
shrunk (:data:`~oacdsl.runtime.retarget.FOLLOW`). World frame, metres, radians.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.retarget import FOLLOW, Retargeted, shifted, shrunk
from oacdsl.runtime.skills.base import SkillContext

__all__ = ["HandAt", "reachable"]

#: The hand's pose (T_world_grasp) at a keyframe of a variant of the path, raised by a height (m).
HandAt = Callable[[Retargeted, int, float], np.ndarray]


def reachable(ctx: SkillContext, side: str, keep: np.ndarray | None, plan: Retargeted, hand_at: HandAt,
               what: str, to_frame: Callable[[np.ndarray], np.ndarray], room: float | None,
               obj_point: np.ndarray) -> tuple[Retargeted, float]:
    """``(plan, orientation weight)``: the first of ``plan``'s variants whose keyframes the
    whole-body IK reaches with the other hand's goal at ``keep``: each orientation weight, then the
    core moved across the target by where the IK left the hand, then shrunk (module doc)."""
    ik = ctx.ctl.ik
    other = "l" if side == "r" else "r"
    n, c = len(plan.times_s), plan.core
    checks = sorted({c, c + (n - c) // 3, c + 2 * (n - c) // 3, n - 1})

    def miss(r: Retargeted, weight: float) -> tuple[float, float, np.ndarray]:
        """The worst keyframe's (distance, angle) and the mean offset the IK left (world), m."""
        limit = FOLLOW.reach_rad if weight == FOLLOW.orientation_weights[0] else math.pi
        worst, offsets = (0.0, 0.0), []
        with ik.trial():
            if keep is not None:
                ik.set_hand_target(other, keep)
            for k in checks:
                goal = hand_at(r, k, 0.0)
                ik.set_hand_target(side, goal, orientation_weight=weight)
                ik.converge(150, tolerance_m=5e-4)
                res = ik.residual(side)
                got = ik.frame(f"grasp_{side}")
                offsets.append(got[:3, 3] - goal[:3, 3])
                # a keyframe of the core counts as reached while the object stays over its target
                at = r.positions_m[k] + to_frame((got @ obj_point)[:3] - (goal @ obj_point)[:3])
                over = room is not None and k >= c and float(np.linalg.norm(at[:2])) <= room
                if (res.position_m > FOLLOW.reach_m and not over) or res.angle_rad > limit:
                    worst = max(worst, (res.position_m, res.angle_rad))
        return worst[0], worst[1], np.mean(offsets, axis=0)

    best: tuple[float, float, Retargeted, float] | None = None
    for factor in FOLLOW.shrink:
        r = plan if factor == 1.0 else shrunk(plan, factor)
        for weight in FOLLOW.orientation_weights:
            d, a, off = miss(r, weight)
            variants = [(d, a, r)]
            if d or a:  # the core moved where the IK left the hand
                moved = shifted(r, to_frame(off), room)
                variants.append((*miss(moved, weight)[:2], moved))
            for dv, av, rv in variants:
                if dv == 0.0 and av == 0.0:
                    return rv, weight
                if best is None or dv < best[0]:
                    best = (dv, av, rv, weight)
    if best is None or best[0] > FOLLOW.give_up_m:
        far = best[0] if best is not None else math.inf
        raise RuntimeFailure(
            f"follow: {what} is out of reach, even shrunk to {FOLLOW.shrink[-1]:g}: the best whole-body IK"
            f" solution leaves the hand {far * 100:.0f} cm from a keyframe"
        )
    # near enough: the soft IK gets as close as it can, the guarded approach and the step's
    # effect judge the rest
    return best[2], best[3]
