"""``touch(h, o, t)``: bring the held object into contact with another object.

The target is taken where it is when the skill starts: on the table, or held by the other
hand. Composition: carry the held object's box middle over the target's, ``hover`` above
its top; a guarded approach down until the two touch (the wrist feeling ``force`` first
means something else is in the way: a failure saying so); press ``press`` on, so that the
contact lasts while the hand keeps still. A solid target the other hand holds (a cucumber
held on the board) is touched at its far end from that hand.

The other hand (chosen once): steady when it holds something other than the target
container (its goal fixed, as strong as this hand's, so that what it holds does not drift);
idle otherwise (a cup held up keeps the usual hold), or with ``steady 0`` (a sponge held up
while the other hand sets a plate into a rack need not stay put, and its fixed goal made the
whole-body IK push the plate onto the rack with 61-74 N).

Turned as demonstrated (``tilt``, :mod:`oacdsl.runtime.skills.stand`): an object held farther from
its demonstrated end tilt than the tuning's ``reorient_min_rad`` is turned on the way, and into a
slot of a rack when it ends on edge (a plate set into a dish rack).
"""

from __future__ import annotations

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.grasping import HAND_BELOW_CENTRE_M
from oacdsl.runtime.motion import TUNING, Motion, OtherHand, down, other_side
from oacdsl.runtime.shapes import lowest_z, world_corners
from oacdsl.runtime.skills.base import SkillContext, cm
from oacdsl.runtime.skills.stand import needs_turn, set_turned
from oacdsl.runtime.transforms import make_T
from oacdsl.skills import SIGNATURES
from oacdsl.units import format_mm

__all__ = ["touch", "approach_pose", "bring_onto", "SIGNATURE"]

SIGNATURE = SIGNATURES["touch"]
D = SIGNATURE.defaults()


def approach_pose(
    ctx: SkillContext, side: str, obj: str, target: str, hover: float, away: np.ndarray | None = None
) -> tuple[np.ndarray, float]:
    """(T_world_grasp above the target, how far the held object may go down from there, m):
    the held object's box middle over the target's, its lowest point ``hover`` above the
    target's top; it may go down to the target's lowest point. With ``away`` (a world point,
    m), a solid target's far end from it is aimed at instead of its middle: the tuning's end
    margin inside the target's box on the line from ``away`` through its middle."""
    world = ctx.world
    t_obj, obj_in_hand = ctx.held_pose(side, obj)
    body_o, body_t = ctx.body(obj), ctx.body(target)
    tgt = world_corners(body_t, world.body_pose(target))
    top, bottom = float(tgt[:, 2].max()), float(tgt[:, 2].min())
    mid_t = 0.5 * (tgt.min(axis=0) + tgt.max(axis=0))
    if away is not None and not body_t.container:
        u = mid_t[:2] - away[:2]
        if float(np.linalg.norm(u)) > 1e-6:
            u /= np.linalg.norm(u)
            half = 0.5 * (tgt.max(axis=0) - tgt.min(axis=0))[:2]
            reach = min(float(h / abs(c)) for h, c in zip(half, u, strict=True) if abs(c) > 1e-6)
            mid_t[:2] += u * max(reach - TUNING.end_margin_m, 0.0)
    own = world_corners(body_o, t_obj)
    mid_o = 0.5 * (own.min(axis=0) + own.max(axis=0)) - t_obj[:3, 3]
    above = t_obj[2, 3] - lowest_z(body_o, t_obj)
    origin = np.array([mid_t[0] - mid_o[0], mid_t[1] - mid_o[1], top + hover + above])
    goal = make_T(t_obj[:3, :3], origin) @ np.linalg.inv(obj_in_hand)
    return goal, hover + (top - bottom)


def bring_onto(
    ctx: SkillContext,
    m: Motion,
    obj: str,
    target: str,
    hover: float,
    force: float,
    away: np.ndarray | None = None,
) -> bool:
    """Carry the held ``obj`` over ``target`` and approach it from above until they touch or
    the wrist feels ``force`` (N); True when they touch."""
    ctx.ctl.activity = f"bringing {obj} over {target}"
    above, depth = approach_pose(ctx, m.side, obj, target, hover, away)
    ctx.check_reachable(m.side, above, f"the top of {target}")
    m.carry(above, {obj, target}, m.tuning.carry_s)
    m.hold_still(m.tuning.pause_s)
    ctx.ctl.activity = f"bringing {obj} onto {target}"
    return m.approach(
        down(above, depth), m.contact_or_force(obj, target, force), wait_for=m.touching(obj, target)
    )


def touch(
    ctx: SkillContext,
    hand: str,
    obj: str,
    target: str,
    *,
    hover: float = D["hover"],
    force: float = D["force"],
    press: float = D["press"],
    steady: float = D["steady"],
    tilt: float = D["tilt"],
) -> None:
    """Lower the held ``obj`` onto ``target`` from ``hover`` (m) above it until they touch,
    then press it ``press`` (m) further on; fail when the wrist feels ``force`` (N) first.
    ``steady`` 0: the other hand keeps the controller's usual hold instead of a fixed goal.
    ``tilt`` (rad): how far its axis is to end from the target's (turned on the way when it is
    held farther from that than the tuning's ``reorient_min_rad``: :mod:`.stand`)."""
    world = ctx.world
    side = ctx.require_held(hand, obj)
    if target not in world.layout.bodies or not ctx.body(target).solids:
        raise RuntimeFailure(f"touch: {target!r} is no object of the scene")
    if world.touching(obj, target):
        return
    other = other_side(side)
    held_target = world.held.get(other) == target
    keep = steady and world.held.get(other) is not None and not (held_target and ctx.body(target).container)
    m = Motion(ctx, side, OtherHand.STEADY if keep else OtherHand.IDLE)
    away = world.frame_pose(f"grasp_{other}")[:3, 3] if keep and held_target else None
    if needs_turn(ctx, obj, target, tilt, m.tuning.reorient_min_rad):
        touched = set_turned(ctx, m, obj, target, tilt, hover, force)
    else:
        touched = bring_onto(ctx, m, obj, target, hover, force, away)
    if touched:
        m.press(press)
        return
    others = sorted(world.relations().partners(obj) - {hand})
    raise RuntimeFailure(
        f"touch: {obj} did not reach {target} (the wrist felt {m.force_n():.0f} N;"
        f" {obj} touches {', '.join(others) or 'nothing else'}{short_of(ctx, side, obj, target)})"
    )


def short_of(ctx: SkillContext, side: str, obj: str, target: str) -> str:
    """Where the held ``obj``'s lowest point stopped above ``target`` (its floor when it is a
    container, else its top) and, when the hand is then down at a container's rim (within the
    tuning's ``rim_clearance_m`` above it), what reaches deeper: a grasp farther up the tool (the
    hand reaches :data:`HAND_BELOW_CENTRE_M` below its grasp centre and is kept clear of the rim;
    KIT Scoop's ladle held 20 cm up stopped 1 mm above a 14 cm bowl's floor)."""
    world = ctx.world
    body_t = ctx.body(target)
    corners = world_corners(body_t, world.body_pose(target))
    top, bottom = float(corners[:, 2].max()), float(corners[:, 2].min())
    low = lowest_z(ctx.body(obj), ctx.held_pose(side, obj)[0])
    floor = bottom + body_t.floor if body_t.container else top
    what = f"the floor of {target}" if body_t.container else f"{target}'s top"
    text = f"; its lowest point stopped {format_mm(low - floor)} above {what}"
    grasp_z = float(world.frame_pose(f"grasp_{side}")[2, 3])
    if body_t.container and low < top and grasp_z - HAND_BELOW_CENTRE_M < top + TUNING.rim_clearance_m:
        text += (f", the hand at {target}'s rim: held {cm(grasp_z - low)}"
                 f" above its lowest point, {obj} reaches no deeper; a grasp farther up it"
                 f" (a larger grasp offset) does")
    return text
