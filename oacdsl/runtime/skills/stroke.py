"""``stroke``: strokes of a held tool along an object, each one way (a peeler along a cucumber,
a knife pushing pieces across a board into a bowl).

Where ``wipe`` goes to and fro across a surface's middle, a stroke goes along the target's
length, one way, and comes back through the air: the tool (kept as the hand holds it) is
brought onto the target's top at one end of the stroke, lowered until the two touch, pressed
``press`` into it and drawn ``length`` along it in ``period`` seconds; it then rises
:data:`LIFT_M`, goes back and comes down again for the next one, ``strokes`` times. It stays
on the target after the last (the OAC's effect ``o <-> t``).

The direction is the target's longest horizontal axis (a box's length, in its pose now),
pointed, in this order: away from the other hand when that hand holds the target (peeling
towards the cucumber's free end); towards what the other hand holds otherwise (the pieces
pushed off the board towards the bowl held at its edge); else away from the robot. The
strokes end :data:`END_MARGIN_M` inside the target's end and are as long as the target
allows. While the other hand holds anything, its goal stays fixed, as strong a task as
the stroking hand's (as ``touch`` does).
"""

from __future__ import annotations

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.skills.base import SkillContext
from oacdsl.runtime.skills.bimanual import mover
from oacdsl.runtime.skills.place import MIN_JERK_PEAK
from oacdsl.runtime.skills.shapes import lowest_z, world_corners
from oacdsl.runtime.transforms import make_T

__all__ = ["stroke", "STROKES", "STROKE_LENGTH_M", "STROKE_PERIOD_S", "stroke_direction"]

#: Default number of strokes.
STROKES = 3
#: Default length of a stroke, m.
STROKE_LENGTH_M = 0.08
#: Default time of one stroke along the target, s.
STROKE_PERIOD_S = 0.8
#: How far the tool is pressed into the target while it strokes, m.
PRESS_M = 0.004
#: Height of the tool above the target's top on its way back, m.
LIFT_M = 0.03
#: How far inside the target's ends the strokes stay, m.
END_MARGIN_M = 0.01
#: Wrist force change on the way down that means something else is in the way, N.
FORCE_N = 15.0
#: Peak speed of a descent onto the target, m/s.
DESCENT_SPEED_M_S = 0.08


def _half_lengths(body_corners: np.ndarray, u: np.ndarray) -> tuple[float, float]:
    """(middle along ``u``, half the extent along ``u``) of the corners (m)."""
    d = body_corners[:, :2] @ u[:2]
    return float(0.5 * (d.max() + d.min())), float(0.5 * (d.max() - d.min()))


def stroke_direction(ctx: SkillContext, side: str, target: str) -> np.ndarray:
    """The horizontal unit direction of the strokes on ``target`` (module doc), world frame."""
    world = ctx.world
    t_tgt = world.body_pose(target)
    c = world_corners(ctx.body(target), t_tgt)
    axes = [t_tgt[:3, 0], t_tgt[:3, 1]]
    flat = [np.array([a[0], a[1], 0.0]) / max(float(np.hypot(a[0], a[1])), 1e-9) for a in axes]
    u = max(flat, key=lambda a: _half_lengths(c, a)[1])
    mid = 0.5 * (c.min(axis=0) + c.max(axis=0))
    other = "l" if side == "r" else "r"
    held = world.held.get(other)
    if held == target:  # away from the hand that holds it
        toward = mid - world.frame_pose(f"grasp_{other}")[:3, 3]
    elif held is not None:  # towards what the other hand holds
        toward = world.body_pose(held)[:3, 3] - mid
    else:  # away from the robot
        toward = np.array([1.0, 0.0, 0.0])
    return u if float(u @ toward) >= 0 else -u


def stroke(
    ctx: SkillContext,
    hand: str,
    tool: str,
    target: str,
    *,
    strokes: float = STROKES,
    length: float = STROKE_LENGTH_M,
    period: float = STROKE_PERIOD_S,
    press: float = PRESS_M,
    force: float = FORCE_N,
) -> None:
    """``strokes`` strokes of the held ``tool`` along ``target``, each ``length`` (m) in ``period``
    (s), pressed ``press`` (m) into it; fail when the wrist feels ``force`` (N) on the way down
    (something else in the way). The tool stays on the target."""
    world, ctl = ctx.world, ctx.ctl
    side = ctx.require_held(hand, tool)
    if target not in world.layout.bodies or not ctx.body(target).solids:
        raise RuntimeFailure(f"stroke: {target!r} is no object of the scene")
    other = "l" if side == "r" else "r"
    go = mover(ctl, side, ctl.ik.goal(other) if world.held.get(other) is not None else None)

    u = stroke_direction(ctx, side, target)
    t_tgt = world.body_pose(target)
    c = world_corners(ctx.body(target), t_tgt)
    top = float(c[:, 2].max())
    mid, half = _half_lengths(c, u)
    across = 0.5 * (c.min(axis=0) + c.max(axis=0))
    across = across[:2] - float(across[:2] @ u[:2]) * u[:2]  # the middle line along u
    t_tool, tool_in_hand = ctx.held_pose(side, tool)
    own = world_corners(ctx.body(tool), t_tool)
    tool_mid, tool_half = _half_lengths(own, u)
    tip = np.array([*(own.min(axis=0)[:2] + own.max(axis=0)[:2]) * 0.5, lowest_z(ctx.body(tool), t_tool)])
    room = max(0.0, 2 * (half - tool_half - END_MARGIN_M))
    run = min(length, room)
    if run < 0.01:
        raise RuntimeFailure(
            f"stroke: {target} is too short for strokes of {tool} along it"
            f" ({2 * half * 100:.0f} cm long, {tool} {2 * tool_half * 100:.0f} cm)"
        )
    end = mid + half - tool_half - END_MARGIN_M  # where the tool's middle stops, along u

    def hand_at(along: float, height: float) -> np.ndarray:
        """T_world_grasp with the tool's lowest point ``height`` above the target's top, its
        middle ``along`` (m) along u on the target's middle line."""
        point = np.array([*(across + along * u[:2]), top + height])
        shift = point - tip
        t_obj = make_T(t_tool[:3, :3], t_tool[:3, 3] + shift)
        return t_obj @ np.linalg.inv(tool_in_hand)

    start, finish = end - run, end
    ctl.activity = f"bringing {tool} over {target}"
    above = hand_at(start, LIFT_M)
    ctx.check_reachable(side, above, f"the start of the strokes on {target}")
    ctx.check_reachable(side, hand_at(finish, 0.0), f"the end of the strokes on {target}")
    for pose, seconds in ctx.carry_path(side, above, {tool, target}, 1.6):
        if seconds > 0:
            go(pose, seconds)
    for k in range(max(1, round(strokes))):
        ctl.activity = f"bringing {tool} onto {target} (stroke {k + 1})"
        # straight to ``press`` below the target's top, not stopped at the first touch: a tool
        # stopped there bounced off for 0.1 s before the press brought it back
        pressed = hand_at(start, -press)
        go(
            pressed,
            MIN_JERK_PEAK * (LIFT_M + press) / DESCENT_SPEED_M_S,
            guard=lambda: float(np.linalg.norm(ctl.force_change(side))) > force,
        )
        if not (ctl.wait(0.2, until=lambda: world.touching(tool, target)) or world.touching(tool, target)):
            felt = float(np.linalg.norm(ctl.force_change(side)))
            why = "; something else is in the way" if felt > force else ""
            raise RuntimeFailure(f"stroke: {tool} did not reach {target} (the wrist felt {felt:.0f} N{why})")
        ctl.activity = f"stroking {target} with {tool} ({k + 1})"
        drawn = pressed.copy()
        drawn[:3, 3] += np.array([*(run * u[:2]), 0.0])
        go(drawn, period)
        if k == max(1, round(strokes)) - 1:
            break
        ctl.activity = f"taking {tool} back over {target}"
        up = drawn.copy()
        up[2, 3] += LIFT_M + press
        go(up, 0.3)
        go(hand_at(start, LIFT_M), 0.5)
    if not (ctl.wait(0.3, until=lambda: world.touching(tool, target)) or world.touching(tool, target)):
        raise RuntimeFailure(f"stroke: {tool} left {target} during its last stroke")
