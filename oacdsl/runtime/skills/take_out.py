"""``take_out(h, o, c)``: lift the held object straight up until it clears the container.

A stir ends with the spoon touching the cup; a person then takes it out. Composition: slide
against the wall away from the other hand (which may hold the container), hold still, rise
until the object's base is ``clear`` above the top of ``c`` (read now, a container held by
the other hand included) in ``duration``, slide aside to the hand's own side (so that it no
longer hangs over the container when both are put down), hold still. It fails when the hand
loses the object on the way.
"""

from __future__ import annotations

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.motion import Motion, other_side
from oacdsl.runtime.skills.base import SkillContext
from oacdsl.skills import SIGNATURES

__all__ = ["take_out", "SIGNATURE"]

SIGNATURE = SIGNATURES["take_out"]
D = SIGNATURE.defaults()


def _against_far_wall(ctx: SkillContext, m: Motion, obj: str, container: str) -> None:
    """Slide the held object's base against the container's wall on the side away from the
    other hand (a cup held by it): the contact is then with the container, not that hand."""
    world = ctx.world
    other = other_side(m.side)
    centre = world.body_pose(container)[:2, 3]
    away = centre - world.frame_pose(f"grasp_{other}")[:2, 3]
    if world.held.get(other) != container or float(np.linalg.norm(away)) < 1e-6:
        return
    away /= np.linalg.norm(away)
    base = world.body_pose(obj)[:2, 3]
    room = ctx.body(container).inner_radius - ctx.body(obj).radius - m.tuning.gap_m
    ctx.ctl.activity = f"resting {obj} against the far wall of {container}"
    m.slide(np.array([*(centre + away * max(room, 0.0) - base), 0.0]), m.tuning.shift_s)


def take_out(
    ctx: SkillContext,
    hand: str,
    obj: str,
    container: str,
    *,
    clear: float = D["clear"],
    duration: float = D["duration"],
) -> None:
    """Raise ``obj`` (held by ``hand``) until its base is ``clear`` (m) above ``container``'s
    top, then move it aside to the hand's side."""
    world, ctl = ctx.world, ctx.ctl
    side = ctx.require_held(hand, obj)
    m = Motion(ctx, side)
    _against_far_wall(ctx, m, obj, container)
    m.hold_still()
    top = float(world.body_pose(container)[2, 3] + ctx.body(container).height)
    rise = max(top + clear - float(world.body_pose(obj)[2, 3]), clear)
    ctl.activity = f"taking {obj} out of {container}"
    m.rise(rise, duration)
    outward = -1.0 if side == "r" else 1.0  # the right hand to the robot's right
    m.slide(np.array([0.0, outward * m.tuning.aside_m, 0.0]), duration / 2)
    m.hold_still()
    if world.held[side] != obj:
        raise RuntimeFailure(f"take_out: {hand} lost {obj} on the way up")
