"""``stroke``: strokes of a held tool along an object, each one way (a peeler along a cucumber,
a knife pushing pieces across a board into a bowl).

Where ``wipe`` goes to and fro across a surface's middle, a stroke goes along the target's
length, one way, and comes back pressed lightly: the tool (kept as the hand holds it) is
brought onto the target's top at one end of the stroke, lowered until the two touch, pressed
``press`` into it and drawn ``length`` along it in ``period`` seconds; it then slides back
on the target with the press eased (:meth:`~oacdsl.runtime.motion.Motion.slide_back`: lifted
back through the air, the tool left the target between strokes, a change of the world's
state the demonstration does not have) for the next one, ``strokes`` times; every slide keeps
the contact (lowered while the two do not touch). It stays on the target after the last (the
OAC's effect ``o <-> t``).

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
from oacdsl.runtime.motion import TUNING, Motion, OtherHand
from oacdsl.runtime.shapes import lowest_z, world_corners
from oacdsl.runtime.skills.base import SkillContext, cm
from oacdsl.runtime.transforms import make_T
from oacdsl.skills import SIGNATURES

__all__ = ["stroke", "stroke_direction", "SIGNATURE"]

SIGNATURE = SIGNATURES["stroke"]
D = SIGNATURE.defaults()
#: Height of the tool above the target's top over the start of the strokes, m.
LIFT_M = 0.03


def _half_lengths(body_corners: np.ndarray, u: np.ndarray) -> tuple[float, float]:
    """(middle along ``u``, half the extent along ``u``) of the corners (m)."""
    d = body_corners[:, :2] @ u[:2]
    return float(0.5 * (d.max() + d.min())), float(0.5 * (d.max() - d.min()))


def _clear_of(ctx: SkillContext, side: str, t_hand: np.ndarray, u: np.ndarray, obj: str) -> float:
    """How far along ``u`` (m) the hand at ``t_hand`` (its tool's middle at 0 along ``u``) may
    go before its collision boxes come within the tuning's hand clearance of ``obj``."""
    from oacdsl.runtime.handgap import hand_box_poses

    boxes = hand_box_poses(side, t_hand, ctx.ctl.fingers[side])
    signs = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float)
    front = max(float(((t_box[:3, :3] @ (signs * half).T).T + t_box[:3, 3])[:, :2].dot(u[:2]).max())
                for t_box, half in boxes)
    near = float(world_corners(ctx.body(obj), ctx.world.body_pose(obj))[:, :2].dot(u[:2]).min())
    return near - front - TUNING.hand_clearance_m


def _towards(u: np.ndarray) -> str:
    """A horizontal direction in the robot's words."""
    if abs(float(u[0])) >= abs(float(u[1])):
        return "away from the robot" if u[0] > 0 else "towards the robot"
    return "to the robot's left" if u[1] > 0 else "to the robot's right"


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
    strokes: float = D["strokes"],
    length: float = D["length"],
    period: float = D["period"],
    press: float = D["press"],
    force: float = D["force"],
) -> None:
    """``strokes`` strokes of the held ``tool`` along ``target``, each ``length`` (m) in ``period``
    (s), pressed ``press`` (m) into it; fail when the wrist feels ``force`` (N) on the way down
    (something else in the way). The tool stays on the target."""
    world, ctl, t = ctx.world, ctx.ctl, TUNING
    side = ctx.require_held(hand, tool)
    if target not in world.layout.bodies or not ctx.body(target).solids:
        raise RuntimeFailure(f"stroke: {target!r} is no object of the scene")
    other = "l" if side == "r" else "r"
    m = Motion(ctx, side, OtherHand.STEADY if world.held.get(other) is not None else OtherHand.IDLE)

    u = stroke_direction(ctx, side, target)
    c = world_corners(ctx.body(target), world.body_pose(target))
    top = float(c[:, 2].max())
    mid, half = _half_lengths(c, u)
    across = 0.5 * (c.min(axis=0) + c.max(axis=0))
    across = across[:2] - float(across[:2] @ u[:2]) * u[:2]  # the middle line along u
    t_tool, tool_in_hand = ctx.held_pose(side, tool)
    own = world_corners(ctx.body(tool), t_tool)
    _, tool_half = _half_lengths(own, u)
    tip = np.array([*(own.min(axis=0)[:2] + own.max(axis=0)[:2]) / 2, lowest_z(ctx.body(tool), t_tool)])
    room = max(0.0, 2 * (half - tool_half - t.end_margin_m))
    run = min(length, room)
    if run < t.end_margin_m:
        raise RuntimeFailure(
            f"stroke: {target} is too short for strokes of {tool} along it"
            f" ({cm(2 * half)} long, {tool} {cm(2 * tool_half)})"
        )
    end = mid + half - tool_half - t.end_margin_m  # where the tool's middle stops, along u

    def hand_at(along: float, height: float) -> np.ndarray:
        """T_world_grasp with the tool's lowest point ``height`` above the target's top, its
        middle ``along`` (m) along u on the target's middle line."""
        shift = np.array([*(across + along * u[:2]), top + height]) - tip
        return make_T(t_tool[:3, :3], t_tool[:3, 3] + shift) @ np.linalg.inv(tool_in_hand)

    held = world.held.get(other)
    if held is not None and held != target:  # the stroking hand stops short of what the other holds
        end = min(end, _clear_of(ctx, side, hand_at(0.0, 0.0), u, held))
        run = min(run, end - (mid - half + tool_half + t.end_margin_m))
        if run < t.end_margin_m:
            raise RuntimeFailure(
                f"stroke: no room for strokes of {tool} on {target} before {held}: they go along"
                f" {target}'s longest side ({_towards(u)}, towards {held}, which the other hand holds) and"
                f" stop where the hand comes within {cm(t.hand_clearance_m)} of it, {cm(max(run, 0.0))}"
                f" after they start; {held} held beyond that end of {target} leaves room"
                " (an object stands with its x axis away from the robot, docs/language.md)"
            )
    start = end - run
    ctl.activity = f"bringing {tool} over {target}"
    above = hand_at(start, LIFT_M)
    ctx.check_reachable(side, above, f"the start of the strokes on {target}")
    ctx.check_reachable(side, hand_at(end, 0.0), f"the end of the strokes on {target}")
    m.carry(above, {tool, target}, t.carry_s)
    n = max(1, round(strokes))
    on = m.touching(tool, target)
    ctl.activity = f"bringing {tool} onto {target}"
    # straight to ``press`` below the target's top, not stopped at the first touch: a tool
    # stopped there bounced off for 0.1 s before the press brought it back
    if not m.approach(hand_at(start, -press), m.felt(force), wait_for=on):
        why = "; something else is in the way" if m.force_n() > force else ""
        raise RuntimeFailure(
            f"stroke: {tool} did not reach {target} (the wrist felt {m.force_n():.0f} N{why})"
        )
    stroke_m = np.array([*(run * u[:2]), 0.0])
    for k in range(n):
        ctl.activity = f"stroking {target} with {tool} ({k + 1})"
        m.slide(stroke_m, period, keep_contact=on)
        if k == n - 1:
            break
        ctl.activity = f"taking {tool} back along {target}"
        m.slide_back(-stroke_m, period, on, press)
    if not (m.hold_still(t.contact_wait_s, m.touching(tool, target)) or world.touching(tool, target)):
        raise RuntimeFailure(f"stroke: {tool} left {target} during its last stroke")
