"""``touch``: bring the held object into contact with another object.

The target is taken where it is when the skill starts: on the table, or held by the
other hand (a cup held up). The held object keeps its orientation; it is carried so that
the middle of its bounding box is above the middle of the target's, ``hover`` above the
target's top, and lowered until the simulation reports the two touching (a carton's
spout on a cup's rim, a spoon in a cup, a sponge on a plate, a knife on a cucumber). The
wrist force is a safety net: a change of more than ``force`` before the objects touch
means something else is in the way, and the skill fails saying so. A solid target the
other hand holds (a cucumber held on the board) is touched at its far end from that hand.
While the other hand holds anything but the target container (a cup held up keeps the
controller's usual hold), its goal stays fixed where it was, as strong a task as the
moving hand's: otherwise every motion re-anchors it where the torso dragged it, and what
it holds drifts. With ``steady 0`` it keeps that usual hold: a sponge held up in the air
while the other hand sets a plate into a rack (KIT Wipe) need not stay put, and its fixed
goal made the whole-body IK push the plate onto the rack with 61-74 N.
"""

from __future__ import annotations

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.skills.base import SkillContext
from oacdsl.runtime.skills.bimanual import mover
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
#: How far inside its far end a solid target held by the other hand is touched, m (the
#: knife on the cucumber's free end, away from the hand holding it).
END_MARGIN_M = 0.01
#: Peak speed of the descent, m/s.
TOUCH_SPEED_M_S = 0.08


def approach_pose(
    ctx: SkillContext, side: str, obj: str, target: str, hover: float, away: np.ndarray | None = None
) -> tuple[np.ndarray, float]:
    """(T_world_grasp above the target, how far the held object may go down from there, m):
    the held object's box middle over the target's, its lowest point ``hover`` above the
    target's top; it may go down to the target's lowest point. With ``away`` (a world point,
    m), a solid target's far end from it is aimed at instead of its middle: :data:`END_MARGIN_M`
    inside the target's box on the line from ``away`` through its middle."""
    world = ctx.world
    t_obj, obj_in_hand = ctx.held_pose(side, obj)
    t_tgt = world.body_pose(target)
    body_o, body_t = ctx.body(obj), ctx.body(target)
    tgt = world_corners(body_t, t_tgt)
    top, bottom = float(tgt[:, 2].max()), float(tgt[:, 2].min())
    mid_t = 0.5 * (tgt.min(axis=0) + tgt.max(axis=0))
    if away is not None and not body_t.container:
        u = mid_t[:2] - away[:2]
        if float(np.linalg.norm(u)) > 1e-6:
            u /= np.linalg.norm(u)
            half = 0.5 * (tgt.max(axis=0) - tgt.min(axis=0))[:2]
            reach = min(float(h / abs(c)) for h, c in zip(half, u, strict=True) if abs(c) > 1e-6)
            mid_t[:2] += u * max(reach - END_MARGIN_M, 0.0)
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
    press: float = PRESS_M,
    steady: float = 1.0,
) -> None:
    """Lower the held ``obj`` onto ``target`` from ``hover`` (m) above it until they touch,
    then press it ``press`` (m) further on; fail when the wrist feels ``force`` (N) first.
    ``steady`` 0: the other hand keeps the controller's usual hold instead of a fixed goal."""
    world, ctl = ctx.world, ctx.ctl
    side = ctx.require_held(hand, obj)
    if target not in world.layout.bodies or not ctx.body(target).solids:
        raise RuntimeFailure(f"touch: {target!r} is no object of the scene")
    if world.touching(obj, target):
        return
    other = "l" if side == "r" else "r"
    keep, away = None, None
    held_target = world.held.get(other) == target
    if steady and world.held.get(other) is not None and not (held_target and ctx.body(target).container):
        # the other hand holds a knife, or a solid this one works on (a cucumber on the board):
        # its goal stays fixed while this one moves; a held container (a cup) keeps the
        # controller's usual hold of the idle hand
        keep = ctl.ik.goal(other)
        if held_target:  # the far end of the solid from that hand is touched
            away = world.frame_pose(f"grasp_{other}")[:3, 3]

    go = mover(ctl, side, keep)

    above, depth = approach_pose(ctx, side, obj, target, hover, away)
    ctl.activity = f"bringing {obj} over {target}"
    ctx.check_reachable(side, above, f"the top of {target}")
    for pose, seconds in ctx.carry_path(side, above, {obj, target}, 1.6):
        if seconds > 0:
            go(pose, seconds)
    ctl.wait(0.1)
    ctl.activity = f"bringing {obj} onto {target}"
    down = make_T(above[:3, :3], above[:3, 3] - np.array([0.0, 0.0, depth]))
    go(
        down,
        MIN_JERK_PEAK * depth / TOUCH_SPEED_M_S,
        guard=lambda: world.touching(obj, target) or float(np.linalg.norm(ctl.force_change(side))) > force,
    )
    if ctl.wait(0.3, until=lambda: world.touching(obj, target)) or world.touching(obj, target):
        # a light press (``press`` further down), so that the contact lasts while the hand keeps still
        now = ctl.ik.goal(side)
        go(make_T(now[:3, :3], now[:3, 3] - np.array([0.0, 0.0, press])), 0.2)
        return
    felt = float(np.linalg.norm(ctl.force_change(side)))
    others = sorted(world.relations().partners(obj) - {hand})
    raise RuntimeFailure(
        f"touch: {obj} did not reach {target} (the wrist felt {felt:.0f} N;"
        f" {obj} touches {', '.join(others) or 'nothing else'})"
    )
