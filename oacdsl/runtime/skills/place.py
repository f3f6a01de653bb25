"""``place``: put the held object down where it was picked up, feeling for the support.

The hand carries the object above its pick-up spot, lowers it slowly and stops when
the wrist force/torque sensor feels the support (a change of more than
:data:`CONTACT_FORCE_N` since the descent began), opens the hand, releases the weld
and withdraws along the grasp's approach direction.
"""

from __future__ import annotations

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.skills.base import SkillContext
from oacdsl.runtime.transforms import make_T

__all__ = ["place", "CONTACT_FORCE_N", "lower_until_contact"]

#: Force change (N) at the wrist that counts as "the object touches the support".
CONTACT_FORCE_N = 3.0
HOVER_M = 0.04
DESCENT_SPEED_M_S = 0.05


def lower_until_contact(
    ctx: SkillContext,
    side: str,
    t_hand: np.ndarray,
    depth_m: float,
    what: str,
    force_n: float = CONTACT_FORCE_N,
) -> np.ndarray:
    """Lower hand ``side`` from ``t_hand`` by up to ``depth_m`` until the wrist's force changed
    by more than ``force_n`` (N). Returns the hand pose where contact was felt; raises when
    nothing was felt.
    """
    ctl = ctx.ctl
    goal = make_T(t_hand[:3, :3], t_hand[:3, 3] - np.array([0.0, 0.0, depth_m]))
    felt = ctl.move(
        side,
        goal,
        depth_m / DESCENT_SPEED_M_S,
        guard=lambda: float(np.linalg.norm(ctl.force_change(side))) > force_n,
    )
    if not felt:
        raise RuntimeFailure(f"{what}: the wrist felt no contact after lowering {depth_m * 100:.0f} cm")
    return ctl.ik.frame(f"grasp_{side}")


def place(ctx: SkillContext, hand: str, obj: str, *, force: float = CONTACT_FORCE_N) -> None:
    """Set the held ``obj`` down; the descent stops when the wrist feels ``force`` (N)."""
    world, ctl = ctx.world, ctx.ctl
    side = ctx.require_held(hand, obj)
    t_obj, t_obj_in_hand = ctx.held_pose(side, obj)
    origin, approach = ctx.picked.get(obj, (t_obj, np.array([0.0, 0.0, -1.0])))
    xy = origin[:2, 3]
    support = ctx.support_height(xy, exclude=obj)
    target_obj = make_T(origin[:3, :3], (xy[0], xy[1], support + HOVER_M))
    hover = target_obj @ np.linalg.inv(t_obj_in_hand)
    ctl.activity = f"carrying {obj} to its place"
    ctx.check_reachable(side, hover, f"the place of {obj}")
    ctx.carry(side, hover, {obj})
    ctl.wait(0.2)
    ctl.activity = f"setting {obj} down"
    lower_until_contact(ctx, side, hover, HOVER_M + 0.03, f"placing {obj}", force)
    ctl.activity = f"releasing {obj}"
    world.release(side)
    ctl.open_hand(side, 0.4)
    ctx.picked.pop(obj, None)
    ctl.activity = "withdrawing"
    now = ctl.ik.frame(f"grasp_{side}")
    back = make_T(now[:3, :3], now[:3, 3] - 0.12 * approach + np.array([0.0, 0.0, 0.03]))
    ctl.move(side, back, 0.8)
    up = make_T(now[:3, :3], back[:3, 3] + np.array([0.0, 0.0, 0.08]))
    ctl.move(side, up, 0.6)
