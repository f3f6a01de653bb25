"""``hold(h, o)`` and ``retreat(h)``: the small skills of a bimanual sequence.

``hold`` keeps the held object still for ``duration`` and checks that it stayed in the hand
and in place; every later motion of the other hand keeps this hand where it is (its policy
for the other hand), so ``hold`` itself is short. ``retreat`` takes an empty hand up and
back to its home-posture pose, over the objects in the way.
"""

from __future__ import annotations

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.build import home_posture
from oacdsl.runtime.motion import Motion, raised
from oacdsl.runtime.skills.base import SkillContext, cm, fmt_xyz
from oacdsl.skills import SIGNATURES

__all__ = ["hold", "retreat", "home_pose", "SIGNATURES_HERE"]

SIGNATURES_HERE = (SIGNATURES["hold"], SIGNATURES["retreat"])
HOLD, RETREAT = (s.defaults() for s in SIGNATURES_HERE)


def hold(ctx: SkillContext, hand: str, obj: str, *, duration: float = HOLD["duration"]) -> None:
    """Keep ``obj`` still in ``hand`` for ``duration`` (s)."""
    world, ctl = ctx.world, ctx.ctl
    side = ctx.require_held(hand, obj)
    m = Motion(ctx, side)
    ctl.activity = f"holding {obj}"
    start = world.body_pose(obj)[:3, 3].copy()
    ctl.ik.set_hand_target(side, m.here())
    m.hold_still(duration)
    if world.held[side] != obj:
        raise RuntimeFailure(f"hold: {hand} lost {obj}")
    moved = float(np.linalg.norm(world.body_pose(obj)[:3, 3] - start))
    allowed = m.tuning.still_m
    if moved > allowed:
        raise RuntimeFailure(
            f"hold: {obj} moved {cm(moved)} while {hand} held it (allowed {cm(allowed)})"
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


def retreat(ctx: SkillContext, hand: str, *, duration: float = RETREAT["duration"]) -> None:
    """Take the empty ``hand`` back to its home pose in about ``duration`` (s)."""
    world = ctx.world
    side = ctx.side(hand)
    if world.held[side] is not None:
        raise RuntimeFailure(f"retreat: {hand} still holds {world.held[side]} (place it first)")
    m = Motion(ctx, side)
    t = m.tuning
    goal = home_pose(ctx, side)
    ctx.ctl.activity = f"taking {hand} back"
    m.go(raised(m.here(), t.retreat_rise_m), t.retreat_rise_share * duration)
    m.carry(goal, set(), (1 - t.retreat_rise_share) * duration)
    m.hold_still(t.carry_pause_s)
    off = float(np.linalg.norm(world.frame_pose(f"grasp_{side}")[:3, 3] - goal[:3, 3]))
    if off > t.arrive_tolerance_m:
        raise RuntimeFailure(
            f"retreat: {hand} stopped {cm(off)} from its home pose {fmt_xyz(goal[:3, 3])}"
        )
