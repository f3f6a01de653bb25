"""``lift``: take the held object up and away from what it touches.

The end of a tool's work (a sponge lifted off the plate it wiped, a knife out of the
cucumber it cut) and of a hold on a support (the cucumber lifted off the board): the
hand keeps its orientation and rises ``height`` straight up; the skill checks that the
held object stayed in the hand and no longer touches ``t``.
"""

from __future__ import annotations

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.skills.base import SkillContext
from oacdsl.runtime.transforms import make_T

__all__ = ["lift", "LIFT_M", "LIFT_S"]

#: How far the held object is raised, m.
LIFT_M = 0.12
#: Time to raise it, s.
LIFT_S = 1.0


def lift(ctx: SkillContext, hand: str, obj: str, target: str, *, height: float = LIFT_M,
         duration: float = LIFT_S) -> None:
    """Raise the held ``obj`` ``height`` (m) off ``target`` in ``duration`` (s)."""
    world, ctl = ctx.world, ctx.ctl
    side = ctx.require_held(hand, obj)
    if target not in world.layout.bodies:
        raise RuntimeFailure(f"lift: {target!r} is no object of the scene")
    now = ctl.ik.goal(side)
    up = make_T(now[:3, :3], now[:3, 3] + np.array([0.0, 0.0, height]))
    ctl.activity = f"lifting {obj} off {target}"
    ctx.check_reachable(side, up, f"{height * 100:.0f} cm above {obj}'s place")
    ctl.move(side, up, duration)
    ctl.wait(0.3)
    if world.held[side] != obj:
        raise RuntimeFailure(f"lift: {hand} lost {obj}")
    if world.touching(obj, target):
        raise RuntimeFailure(f"lift: {obj} still touches {target} after rising {height * 100:.0f} cm")
