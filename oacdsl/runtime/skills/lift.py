"""``lift(h, o, t)``: take the held object up and away from what it touches.

The end of a tool's work (a sponge lifted off the plate it wiped, a knife out of the
cucumber it cut) and of a hold on a support: rise ``height`` straight up in ``duration``,
hold still; it fails when the object left the hand or still touches ``t``.
"""

from __future__ import annotations

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.motion import Motion, raised
from oacdsl.runtime.skills.base import SkillContext, cm
from oacdsl.skills import SIGNATURES

__all__ = ["lift", "SIGNATURE"]

SIGNATURE = SIGNATURES["lift"]
D = SIGNATURE.defaults()


def lift(
    ctx: SkillContext,
    hand: str,
    obj: str,
    target: str,
    *,
    height: float = D["height"],
    duration: float = D["duration"],
) -> None:
    """Raise the held ``obj`` ``height`` (m) off ``target`` in ``duration`` (s)."""
    world = ctx.world
    side = ctx.require_held(hand, obj)
    if target not in world.layout.bodies:
        raise RuntimeFailure(f"lift: {target!r} is no object of the scene")
    m = Motion(ctx, side)
    ctx.ctl.activity = f"lifting {obj} off {target}"
    ctx.check_reachable(side, raised(m.here(), height), f"{cm(height)} above {obj}'s place")
    m.rise(height, duration)
    m.hold_still()
    if world.held[side] != obj:
        raise RuntimeFailure(f"lift: {hand} lost {obj}")
    if world.touching(obj, target):
        raise RuntimeFailure(f"lift: {obj} still touches {target} after rising {cm(height)}")
