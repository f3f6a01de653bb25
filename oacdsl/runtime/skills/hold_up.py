"""``hold_up``: take an object and hold it up in front of the robot, on the hand's side.

What a person does with a plate they are about to wipe, or a bottle they are about to
open: grasp it, lift it off its support and bring it in front of the body, where the other
hand can work on it. The object is grasped as its grasp declaration says and lifted by
``lift``; then it is carried, at that height, until the middle of its bounding box is
``forward`` in front of the robot's base and ``aside`` to the hand's side of the robot's
middle (the right hand to the right), over the objects near the way.

Why it exists (KIT Wipe, docs/kit.md): a plate held up where it stood, out on the table,
keeps the left arm stretched, and the right arm cannot then reach the sponge 30 cm to
the right; with the plate held near the body the whole-body IK reaches both.
"""

from __future__ import annotations

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.skills.base import SkillContext, fmt_xyz
from oacdsl.runtime.skills.grasp import reach_and_grasp
from oacdsl.runtime.skills.shapes import world_corners
from oacdsl.runtime.transforms import make_T

__all__ = ["hold_up", "HOLD_LIFT_M", "HOLD_FORWARD_M", "HOLD_ASIDE_M", "HOLD_S"]

#: How high the object is lifted off its support, m.
HOLD_LIFT_M = 0.20
#: Where its middle is held: this far in front of the robot's base (x), m …
HOLD_FORWARD_M = 0.50
#: … and this far to the hand's side of the robot's middle (y), m.
HOLD_ASIDE_M = 0.10
#: Time to carry it there, s.
HOLD_S = 1.6
#: How far the object's middle may end from the spot (the arm lags, the IK compromises), m.
HOLD_TOLERANCE_M = 0.05


def hold_up(
    ctx: SkillContext,
    hand: str,
    obj: str,
    *,
    lift: float = HOLD_LIFT_M,
    forward: float = HOLD_FORWARD_M,
    aside: float = HOLD_ASIDE_M,
) -> None:
    """Grasp ``obj`` with ``hand``, lift it by ``lift`` (m) and hold its middle ``forward`` (m)
    in front of the robot and ``aside`` (m) to the hand's side."""
    world, ctl = ctx.world, ctx.ctl
    side = ctx.side(hand)
    reach_and_grasp(ctx, hand, obj, lift=lift)
    if ctx.other_holder(side, obj) is not None:  # a hand-over: the other hand holds it too
        return
    goal_mid = np.array([forward, aside if side == "l" else -aside])
    now = ctl.ik.goal(side)
    shift = goal_mid - _middle(ctx, obj)
    goal = make_T(now[:3, :3], now[:3, 3] + np.array([shift[0], shift[1], 0.0]))
    ctl.activity = f"holding {obj} up"
    ctx.check_reachable(side, goal, f"the place in front of the robot to hold {obj} up")
    ctx.carry(side, goal, {obj}, HOLD_S)
    ctl.wait(0.2)
    if world.held[side] != obj:
        raise RuntimeFailure(f"hold_up: {hand} lost {obj}")
    off = float(np.linalg.norm(_middle(ctx, obj) - goal_mid))
    if off > HOLD_TOLERANCE_M:
        spot = np.array([goal_mid[0], goal_mid[1], world.body_pose(obj)[2, 3]])
        raise RuntimeFailure(
            f"hold_up: {obj} ended {off * 100:.0f} cm from where it is held up, {fmt_xyz(spot)}"
        )


def _middle(ctx: SkillContext, obj: str) -> np.ndarray:
    """(x, y) of the middle of ``obj``'s bounding box in the world now, m."""
    c = world_corners(ctx.body(obj), ctx.world.body_pose(obj))
    return 0.5 * (c.min(axis=0) + c.max(axis=0))[:2]
