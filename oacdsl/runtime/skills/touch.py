"""``touch``: bring the held object into contact with another object.

The target is taken where it is when the skill starts: on the table, or held by the
other hand (a cup held up). The held object keeps its orientation; it is carried so that
the middle of its bounding box is above the middle of the target's, ``hover`` above the
target's top, and lowered until the simulation reports the two touching (a carton's
spout on a cup's rim, a spoon in a cup, a sponge on a plate, a knife on a cucumber). The
wrist force is a safety net: a change of more than ``force`` before the objects touch
means something else is in the way, and the skill fails saying so.
"""

from __future__ import annotations

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.skills.base import SkillContext
from oacdsl.runtime.skills.place import MIN_JERK_PEAK
from oacdsl.runtime.skills.shapes import lowest_z, world_corners
from oacdsl.runtime.transforms import make_T

__all__ = ["touch", "HOVER_M", "TOUCH_FORCE_N", "TOUCH_SPEED_M_S", "approach_pose"]

#: Height of the held object's lowest point above the target's top before the descent, m.
HOVER_M = 0.04
#: Wrist force change that stops the descent when the objects do not touch first, N.
TOUCH_FORCE_N = 8.0
#: How far the held object is pressed on once it touches, m (the contact lasts while held still).
PRESS_M = 0.003
#: Peak speed of the descent, m/s.
TOUCH_SPEED_M_S = 0.08


def approach_pose(
    ctx: SkillContext, side: str, obj: str, target: str, hover: float
) -> tuple[np.ndarray, float]:
    """(T_world_grasp above the target, how far the held object may go down from there, m):
    the held object's box middle over the target's, its lowest point ``hover`` above the
    target's top; it may go down to the target's lowest point."""
    world = ctx.world
    t_obj, obj_in_hand = ctx.held_pose(side, obj)
    t_tgt = world.body_pose(target)
    body_o, body_t = ctx.body(obj), ctx.body(target)
    tgt = world_corners(body_t, t_tgt)
    top, bottom = float(tgt[:, 2].max()), float(tgt[:, 2].min())
    mid_t = 0.5 * (tgt.min(axis=0) + tgt.max(axis=0))
    own = world_corners(body_o, t_obj)
    mid_o = 0.5 * (own.min(axis=0) + own.max(axis=0)) - t_obj[:3, 3]
    above = t_obj[2, 3] - lowest_z(body_o, t_obj)
    origin = np.array([mid_t[0] - mid_o[0], mid_t[1] - mid_o[1], top + hover + above])
    goal = make_T(t_obj[:3, :3], origin) @ np.linalg.inv(obj_in_hand)
    return goal, hover + (top - bottom)


def touch(
    ctx: SkillContext,
    hand: str,
    obj: str,
    target: str,
    *,
    hover: float = HOVER_M,
    force: float = TOUCH_FORCE_N,
) -> None:
    """Lower the held ``obj`` onto ``target`` from ``hover`` (m) above it until they touch;
    fail when the wrist feels ``force`` (N) first."""
    world, ctl = ctx.world, ctx.ctl
    side = ctx.require_held(hand, obj)
    if target not in world.layout.bodies or not ctx.body(target).solids:
        raise RuntimeFailure(f"touch: {target!r} is no object of the scene")
    if world.touching(obj, target):
        return
    above, depth = approach_pose(ctx, side, obj, target, hover)
    ctl.activity = f"bringing {obj} over {target}"
    ctx.check_reachable(side, above, f"the top of {target}")
    ctx.carry(side, above, {obj, target}, 1.6)
    ctl.wait(0.1)
    ctl.activity = f"bringing {obj} onto {target}"
    down = make_T(above[:3, :3], above[:3, 3] - np.array([0.0, 0.0, depth]))
    ctl.move(
        side,
        down,
        MIN_JERK_PEAK * depth / TOUCH_SPEED_M_S,
        guard=lambda: world.touching(obj, target) or float(np.linalg.norm(ctl.force_change(side))) > force,
    )
    if ctl.wait(0.3, until=lambda: world.touching(obj, target)) or world.touching(obj, target):
        # a light press (PRESS_M further down), so that the contact lasts while the hand keeps still
        now = ctl.ik.target(side) if ctl.ik.active[side] else ctl.ik.frame(f"grasp_{side}")
        ctl.move(side, make_T(now[:3, :3], now[:3, 3] - np.array([0.0, 0.0, PRESS_M])), 0.2)
        return
    felt = float(np.linalg.norm(ctl.force_change(side)))
    others = sorted(world.relations().partners(obj) - {hand})
    raise RuntimeFailure(
        f"touch: {obj} did not reach {target} (the wrist felt {felt:.0f} N;"
        f" {obj} touches {', '.join(others) or 'nothing else'})"
    )
