"""``take_out(h, o, c)``: lift the held object straight up until it clears the container.

A stir ends with the spoon touching the cup; a person then takes it out. The object first
rests there for :data:`SETTLE_S` (a still contact, as an observer needs to see one); the hand keeps
its orientation and rises until the held object's base is ``clear`` above the top of
``c`` (read from the simulation now, a container held by the other hand included), in
``duration``, then moves the object ``aside`` to its own side (the right hand to the
robot's right), so that the object no longer hangs over the container when both are put
down. It fails when the hand loses the object on the way.
"""

from __future__ import annotations

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.skills.base import SkillContext
from oacdsl.runtime.transforms import make_T

__all__ = ["take_out", "CLEAR_M", "TAKE_OUT_S"]

#: How far above the container's top the object's base ends, m.
CLEAR_M = 0.03
#: Time to lift it out, s.
TAKE_OUT_S = 1.0


#: How long the object first rests where it is (touching the container), s: longer than the
#: closed loop's merge window (1 s), so that an observer sees the contact start and end apart.
SETTLE_S = 1.2
#: How far the object then moves to the hand's side, m.
ASIDE_M = 0.10


def take_out(ctx: SkillContext, hand: str, obj: str, container: str, *,
             clear: float = CLEAR_M, duration: float = TAKE_OUT_S) -> None:
    """Raise ``obj`` (held by ``hand``) until its base is ``clear`` (m) above ``container``'s
    top, then move it :data:`ASIDE_M` to the hand's side."""
    world, ctl = ctx.world, ctx.ctl
    side = ctx.require_held(hand, obj)
    ctl.activity = f"resting {obj} in {container}"
    ctl.wait(SETTLE_S)  # still where the stir left it, touching: the contact is seen before it ends
    top = float(world.body_pose(container)[2, 3] + ctx.body(container).height)
    base = float(world.body_pose(obj)[2, 3])
    rise = max(top + clear - base, clear)
    ctl.activity = f"taking {obj} out of {container}"
    now = ctl.ik.target(side) if ctl.ik.active[side] else ctl.ik.frame(f"grasp_{side}")
    up = now[:3, 3] + np.array([0.0, 0.0, rise])
    ctl.move(side, make_T(now[:3, :3], up), duration)
    aside = up + np.array([0.0, -ASIDE_M if side == "r" else ASIDE_M, 0.0])
    ctl.move(side, make_T(now[:3, :3], aside), 0.5 * duration)
    ctl.wait(0.3)
    if world.held[side] != obj:
        raise RuntimeFailure(f"take_out: {hand} lost {obj} on the way up")
