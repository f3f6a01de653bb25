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
from oacdsl.runtime.motion import Motion
from oacdsl.runtime.shapes import world_corners
from oacdsl.runtime.skills.base import SkillContext, cm, fmt_xyz
from oacdsl.runtime.skills.grasp import reach_and_grasp
from oacdsl.runtime.transforms import make_T
from oacdsl.skills import SIGNATURES

__all__ = ["hold_up", "hold_in_front", "SIGNATURE"]

SIGNATURE = SIGNATURES["hold_up"]
D = SIGNATURE.defaults()


def hold_up(
    ctx: SkillContext,
    hand: str,
    obj: str,
    *,
    lift: float = D["lift"],
    forward: float = D["forward"],
    aside: float = D["aside"],
) -> None:
    """Grasp ``obj`` with ``hand``, lift it by ``lift`` (m) and hold its middle ``forward`` (m)
    in front of the robot and ``aside`` (m) to the hand's side."""
    side = ctx.side(hand)
    reach_and_grasp(ctx, hand, obj, lift=lift)
    if ctx.other_holder(side, obj) is not None:  # a hand-over: the other hand holds it too
        return
    hold_in_front(ctx, hand, obj, forward, aside)


def hold_in_front(ctx: SkillContext, hand: str, obj: str, forward: float = D["forward"],
                  aside: float = D["aside"], up: float = 0.0) -> None:
    """Carry ``obj``, held by ``hand``, ``up`` (m) higher than it is, until its middle is
    ``forward`` (m) in front of the robot and ``aside`` (m) to the hand's side."""
    world, ctl = ctx.world, ctx.ctl
    side = ctx.side(hand)
    m = Motion(ctx, side)
    goal_mid = np.array([forward, aside if side == "l" else -aside])
    now = m.here()
    shift = goal_mid - _middle(ctx, obj)
    goal = make_T(now[:3, :3], now[:3, 3] + np.array([shift[0], shift[1], up]))
    ctl.activity = f"holding {obj} up"
    ctx.check_reachable(side, goal, f"the place in front of the robot to hold {obj} up")
    m.carry(goal, {obj}, m.tuning.carry_s)
    m.hold_still(m.tuning.carry_pause_s)
    if world.held[side] != obj:
        raise RuntimeFailure(f"hold_up: {hand} lost {obj}")
    off = float(np.linalg.norm(_middle(ctx, obj) - goal_mid))
    if off > m.tuning.arrive_tolerance_m:
        spot = np.array([goal_mid[0], goal_mid[1], world.body_pose(obj)[2, 3]])
        raise RuntimeFailure(
            f"hold_up: {obj} ended {cm(off)} from where it is held up, {fmt_xyz(spot)}"
        )


def _middle(ctx: SkillContext, obj: str) -> np.ndarray:
    """(x, y) of the middle of ``obj``'s bounding box in the world now, m."""
    c = world_corners(ctx.body(obj), ctx.world.body_pose(obj))
    return 0.5 * (c.min(axis=0) + c.max(axis=0))[:2]
