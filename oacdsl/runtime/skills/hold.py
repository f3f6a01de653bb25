"""``hold`` and ``retreat``: the small skills of a bimanual sequence.

``hold(h, o)`` keeps the object the hand holds still while the other hand works on it
(a cup held up while the other hand stirs in it): the hand keeps its pose for
``duration`` and the skill checks that the object stayed in the hand and in place.
Every later motion of the other hand keeps this hand where it is (the controller holds
an idle hand's pose), so ``hold`` itself is short.

``retreat(h)`` takes an empty hand back to where it started (the home posture's hand
pose), over the objects in the way, so that it is out of the other hand's way.
"""

from __future__ import annotations

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.build import home_posture
from oacdsl.runtime.skills.base import SkillContext, fmt_xyz
from oacdsl.runtime.transforms import make_T

__all__ = ["hold", "retreat", "HOLD_S", "STILL_M", "RETREAT_S"]

#: How long ``hold`` keeps the hand still, s.
HOLD_S = 0.5
#: How far a held object may drift while it is held still, m.
STILL_M = 0.02
#: Time to take an empty hand back to its home pose, s.
RETREAT_S = 1.6
#: How far an empty hand first rises before it goes home, m.
RISE_M = 0.05


def hold(ctx: SkillContext, hand: str, obj: str, *, duration: float = HOLD_S) -> None:
    """Keep ``obj`` still in ``hand`` for ``duration`` (s)."""
    world, ctl = ctx.world, ctx.ctl
    side = ctx.require_held(hand, obj)
    ctl.activity = f"holding {obj}"
    start = world.body_pose(obj)[:3, 3].copy()
    here = ctl.ik.goal(side)
    ctl.ik.set_hand_target(side, here)
    ctl.wait(duration)
    if world.held[side] != obj:
        raise RuntimeFailure(f"hold: {hand} lost {obj}")
    moved = float(np.linalg.norm(world.body_pose(obj)[:3, 3] - start))
    if moved > STILL_M:
        raise RuntimeFailure(
            f"hold: {obj} moved {moved * 100:.0f} cm while {hand} held it (allowed {STILL_M * 100:.0f} cm)"
        )


def home_pose(ctx: SkillContext, side: str) -> np.ndarray:
    """T_world_grasp of hand ``side`` in the home posture (the IK state is restored)."""
    ik = ctx.ctl.ik
    q = ik.snapshot()
    try:
        ik.set_state(home_posture())
        return ik.frame(f"grasp_{side}")
    finally:
        ik.restore(q)


def retreat(ctx: SkillContext, hand: str, *, duration: float = RETREAT_S) -> None:
    """Take the empty ``hand`` back to its home pose in about ``duration`` (s)."""
    world, ctl = ctx.world, ctx.ctl
    side = ctx.side(hand)
    if world.held[side] is not None:
        raise RuntimeFailure(f"retreat: {hand} still holds {world.held[side]} (place it first)")
    goal = home_pose(ctx, side)
    ctl.activity = f"taking {hand} back"
    now = ctl.ik.goal(side)
    up = make_T(now[:3, :3], now[:3, 3] + np.array([0.0, 0.0, RISE_M]))
    ctl.move(side, up, 0.25 * duration)
    ctx.carry(side, goal, set(), 0.75 * duration)
    ctl.wait(0.2)
    off = float(np.linalg.norm(world.frame_pose(f"grasp_{side}")[:3, 3] - goal[:3, 3]))
    if off > 0.05:
        raise RuntimeFailure(
            f"retreat: {hand} stopped {off * 100:.0f} cm from its home pose {fmt_xyz(goal[:3, 3])}"
        )
