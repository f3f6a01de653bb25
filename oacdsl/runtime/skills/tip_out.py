"""``tip_out(h, o, c, b)``: the held tool out of the container it is in, tipped over it (a ladle
emptied into the cup it scooped into), turned back and brought into another container.

Composition: rise until the tool's lowest point is the tuning's ``above_rim_m`` over ``c``'s
top; turn the hand about a horizontal axis through its grasp point by ``tilt`` in
``duration`` (no faster than :data:`~oacdsl.runtime.retarget.TURN_SPEED_RAD_S`, the arms'
joint speed), hold still a moment, and turn it back; then ``touch``'s way into ``b``
(carried over it, a guarded approach until they touch or the wrist feels ``force``),
pressed ``press`` on. The axis is the horizontal direction, among the tuning's
``tip_axis_tries``, whose fully tipped pose the whole-body IK reaches (within the reach
tolerance of the best) and along which the swinging tool keeps farthest from the other hand.
The other hand keeps its goal fixed while it holds something (the cup tipped into stays where
it is).

``tilt`` and ``duration`` come from the demonstration (the tool's tilt relative to ``c``
and how long it took to rise, :mod:`oacdsl.matching.demoparams`). It fails when the tool
still touches ``c`` or does not reach ``b``.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.motion import TUNING, Motion, OtherHand, other_side
from oacdsl.runtime.retarget import TURN_SPEED_RAD_S
from oacdsl.runtime.shapes import highest_z, lowest_z, world_corners
from oacdsl.runtime.skills.base import REACH_TOLERANCE_M, SkillContext
from oacdsl.runtime.skills.touch import bring_onto
from oacdsl.runtime.transforms import make_T, rot_axis
from oacdsl.skills import SIGNATURES

__all__ = ["tip_out", "SIGNATURE"]

SIGNATURE = SIGNATURES["tip_out"]
D = SIGNATURE.defaults()


def tip_out(
    ctx: SkillContext,
    hand: str,
    tool: str,
    source: str,
    target: str,
    *,
    tilt: float = D["tilt"],
    duration: float = D["duration"],
    hover: float = D["hover"],
    force: float = D["force"],
    press: float = D["press"],
) -> None:
    """Take the held ``tool`` out of ``source``, tip it ``tilt`` (rad) over it in ``duration`` (s)
    and back, then lower it into ``target`` from ``hover`` (m) above until they touch (fail when
    the wrist feels ``force``, N, first) and press ``press`` (m) on."""
    world, t = ctx.world, TUNING
    side = ctx.require_held(hand, tool)
    for name in (source, target):
        if name not in world.layout.bodies or not ctx.body(name).solids:
            raise RuntimeFailure(f"tip_out: {name!r} is no object of the scene")
    keep = world.held.get(other_side(side)) is not None
    m = Motion(ctx, side, OtherHand.STEADY if keep else OtherHand.IDLE)
    body = ctx.body(tool)
    top = highest_z(ctx.body(source), world.body_pose(source))
    rise = max(top + t.above_rim_m - lowest_z(body, world.body_pose(tool)), 0.0)
    ctx.ctl.activity = f"taking {tool} out of {source}"
    m.rise(rise, t.lift_s)
    m.hold_still(t.pause_s)
    if world.touching(tool, source):
        raise RuntimeFailure(f"tip_out: {tool} still touches {source} after rising")

    start = m.here()

    def tipped(axis: np.ndarray, angle: float) -> np.ndarray:
        """The hand turned ``angle`` about ``axis`` (world, horizontal) through its grasp point."""
        return make_T(rot_axis(axis, angle) @ start[:3, :3], start[:3, 3])

    axes = [np.array([math.cos(a), math.sin(a), 0.0])
            for a in np.arange(t.tip_axis_tries) * math.tau / t.tip_axis_tries]
    axis = _axis(ctx, side, tool, axes, tipped, tilt)
    seconds = max(duration, abs(tilt) / TURN_SPEED_RAD_S)
    ctx.ctl.activity = f"tipping {tool} over {source}"
    m.along(lambda s: tipped(axis, tilt * s), seconds)
    m.hold_still(t.pause_s)
    m.along(lambda s: tipped(axis, tilt * (1.0 - s)), seconds)
    if not bring_onto(ctx, m, tool, target, hover, force):
        raise RuntimeFailure(f"tip_out: {tool} did not reach {target} (the wrist felt {m.force_n():.0f} N)")
    m.press(press)
    if world.touching(tool, source):
        raise RuntimeFailure(f"tip_out: {tool} still touches {source}")
    if world.held[side] != tool:
        raise RuntimeFailure(f"tip_out: {hand} lost {tool}")


def _axis(ctx: SkillContext, side: str, tool: str, axes: list[np.ndarray],
          tipped: Callable[[np.ndarray, float], np.ndarray], tilt: float) -> np.ndarray:
    """The axis to tip about: among those whose fully tipped pose the whole-body IK reaches within
    the reach tolerance of the best, the one that keeps the swinging tool farthest from the other
    hand (the hand that holds the cup it is tipped over)."""
    _, tool_in_hand = ctx.held_pose(side, tool)
    body = ctx.body(tool)
    other = ctx.world.frame_pose(f"grasp_{other_side(side)}")[:3, 3]
    reach = [ctx.reach_error(side, tipped(u, tilt)) for u in axes]

    def clearance(u: np.ndarray) -> float:
        gaps = (world_corners(body, tipped(u, a) @ tool_in_hand) - other
                for a in np.linspace(0.0, tilt, TUNING.tip_pose_tries))
        return min(float(np.linalg.norm(g, axis=1).min()) for g in gaps)

    near = [u for u, r in zip(axes, reach, strict=True) if r <= min(reach) + REACH_TOLERANCE_M]
    return max(near, key=clearance)
