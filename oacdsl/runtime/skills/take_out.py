"""``take_out(h, o, c)``: lift the held object straight up until it clears the container.

A stir ends with the spoon touching the cup; a person then takes it out. The object first
slides against the wall away from the other hand (which may hold the container) and
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
#: Gap left between the object's base and the container's wall when it rests there, m.
WALL_GAP_M = 0.003
#: How far the object then moves to the hand's side, m.
ASIDE_M = 0.10


def _against_far_wall(ctx: SkillContext, side: str, obj: str, container: str) -> None:
    """Slide the held object's base against the container's wall on the side away from the
    other hand (a cup held by it): the contact is then with the container, not that hand."""
    world, ctl = ctx.world, ctx.ctl
    other = "l" if side == "r" else "r"
    centre = world.body_pose(container)[:2, 3]
    away = centre - world.frame_pose(f"grasp_{other}")[:2, 3]
    if world.held.get(other) != container or float(np.linalg.norm(away)) < 1e-6:
        return
    away /= np.linalg.norm(away)
    base = world.body_pose(obj)[:2, 3]
    room = ctx.body(container).inner_radius - ctx.body(obj).radius - WALL_GAP_M
    goal = centre + away * max(room, 0.0)
    now = ctl.ik.goal(side)
    shift = np.array([*(goal - base), 0.0])
    ctl.activity = f"resting {obj} against the far wall of {container}"
    ctl.move(side, make_T(now[:3, :3], now[:3, 3] + shift), 0.6)


def take_out(ctx: SkillContext, hand: str, obj: str, container: str, *,
             clear: float = CLEAR_M, duration: float = TAKE_OUT_S) -> None:
    """Raise ``obj`` (held by ``hand``) until its base is ``clear`` (m) above ``container``'s
    top, then move it :data:`ASIDE_M` to the hand's side."""
    world, ctl = ctx.world, ctx.ctl
    side = ctx.require_held(hand, obj)
    _against_far_wall(ctx, side, obj, container)
    ctl.activity = f"resting {obj} in {container}"
    ctl.wait(SETTLE_S)  # still where the stir left it, touching: the contact is seen before it ends
    top = float(world.body_pose(container)[2, 3] + ctx.body(container).height)
    base = float(world.body_pose(obj)[2, 3])
    rise = max(top + clear - base, clear)
    ctl.activity = f"taking {obj} out of {container}"
    now = ctl.ik.goal(side)
    up = now[:3, 3] + np.array([0.0, 0.0, rise])
    ctl.move(side, make_T(now[:3, :3], up), duration)
    aside = up + np.array([0.0, -ASIDE_M if side == "r" else ASIDE_M, 0.0])
    ctl.move(side, make_T(now[:3, :3], aside), 0.5 * duration)
    ctl.wait(0.3)
    if world.held[side] != obj:
        raise RuntimeFailure(f"take_out: {hand} lost {obj} on the way up")
