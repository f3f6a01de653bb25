"""``twist``: turn a held object about its own axis while it touches another (a lid on a bottle).

The object is first brought onto the target as :func:`~oacdsl.runtime.skills.touch.touch`
does, when it does not touch it yet (a lid put on the bottle the other hand holds). It
is then turned by ``angle`` about its own z axis (the axis every shape of the language
stands on; positive: counterclockwise seen from above, as a right-hand thread's lid is
unscrewed; negative: screwed on), in ``duration`` (at least what its strokes and regrasps
need, about :data:`REGRASP_S` each). Each stroke also brings the object's axis back onto the
target's and keeps it pressed lightly on the target's top. A hand turns at most ``stroke``
at a time, as a person's does: between strokes it lets go (the fingers open, the thumb
stays), rises, turns back and takes the object again, which stays on the target. Before it
lets go, the hand slides the object, still held and pressed on, onto the middle of the
target's top (:func:`centre`: the arm lags a turning hand by centimetres, and an object
let go off the middle tipped over the edge). While the other
hand holds something (the bottle), its goal stays fixed, as strong a task as the turning
hand's. With ``lift`` the object is then raised that far off the target (a lid unscrewed
and taken off); without, it stays on the target, touching it (the OAC's effect ``o <-> t``).

Composition: bring onto the target (touch's approach) and press; rotate about its axis with
regrasps (:func:`~oacdsl.runtime.motion.rotate.rotate_on`: the turn is measured on the object
and made up for with more strokes; the regrasps are recorded as internal to the step); fail
when it turned less than :data:`MIN_TURNED` of ``angle``, or the other way; rise ``lift``.
"""

from __future__ import annotations

import math

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.hands import CLOSED, PINCH_CLOSED
from oacdsl.runtime.motion import TUNING, Motion, OtherHand
from oacdsl.runtime.motion.rotate import close_on, rotate_on
from oacdsl.runtime.skills.base import SkillContext, cm
from oacdsl.runtime.skills.touch import bring_onto
from oacdsl.skills import SIGNATURES

__all__ = ["twist", "put_on", "MIN_TURNED", "SIGNATURE"]

SIGNATURE = SIGNATURES["twist"]
D = SIGNATURE.defaults()
#: Least part of ``angle`` the object must really turn.
MIN_TURNED = 0.6


def put_on(ctx: SkillContext, m: Motion, obj: str, target: str) -> None:
    """Bring the held ``obj`` over the middle of ``target`` (the axes in line: a lid over a
    bottle's neck, wherever the other hand holds the bottle) and down until they touch; press."""
    if not bring_onto(ctx, m, obj, target, TUNING.hover_m, TUNING.obstacle_force_n):
        raise RuntimeFailure(f"twist: {obj} did not reach {target} (the wrist felt {m.force_n():.0f} N)")
    m.press()


def twist(
    ctx: SkillContext,
    hand: str,
    obj: str,
    target: str,
    *,
    angle: float = D["angle"],
    duration: float = D["duration"],
    stroke: float = D["stroke"],
    lift: float = D["lift"],
) -> None:
    """Turn the held ``obj`` by ``angle`` (rad) about its own axis on ``target`` in ``duration``
    (s), at most ``stroke`` (rad) per grasp; then raise it ``lift`` (m) off ``target``."""
    world = ctx.world
    side = ctx.require_held(hand, obj)
    if target not in world.layout.bodies or not ctx.body(target).solids:
        raise RuntimeFailure(f"twist: {target!r} is no object of the scene")
    other = "l" if side == "r" else "r"
    m = Motion(ctx, side, OtherHand.STEADY if world.held.get(other) is not None else OtherHand.IDLE)
    if not world.touching(obj, target):
        put_on(ctx, m, obj, target)
    closed = PINCH_CLOSED if ctx.grasp_for(obj).type == "pinch" else CLOSED
    turned = rotate_on(ctx, m, obj, target, angle, duration, stroke, closed)
    if not world.touching(hand, obj):  # the weld holds it; the relation needs the fingers on it
        close_on(ctx, m, obj, closed, "twist")
    if turned * angle < 0 or abs(turned) < MIN_TURNED * abs(angle):
        raise RuntimeFailure(
            f"twist: {obj} turned {math.degrees(turned):.0f}° of {math.degrees(angle):.0f}° on {target}"
        )
    if lift > 0:
        ctx.ctl.activity = f"taking {obj} off {target}"
        m.rise(lift)
        m.hold_still()
        if world.touching(obj, target):
            raise RuntimeFailure(f"twist: {obj} still touches {target} after rising {cm(lift)}")
        if not world.touching(hand, obj):
            close_on(ctx, m, obj, closed, "twist")
        return
    if not m.hold_still(TUNING.contact_wait_s, m.touching(obj, target)) and not world.touching(obj, target):
        raise RuntimeFailure(f"twist: {obj} no longer touches {target} after turning")
