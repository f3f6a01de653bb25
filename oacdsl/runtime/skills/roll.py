"""``roll``: move an object both hands hold to and fro on what is below it (a rolling pin).

Both hands hold the one object (``grasp_both(h1, o, h2, o)``). They bring it down together
until either wrist feels the support (``force``) or it touches an object of the scene, press
it ``press`` further into it, and move it ``strokes`` times ``length`` to either side of where
it came down, across its long axis (a rolling pin's to and fro over the dough), ``period``
seconds per stroke there and back, and end where they started, the object still on the
support and in both hands: ``place_both(h1, o, h2, o)`` puts it down (straight down from
where it is) and lets go. Both hands move as one: the same motion for each, in lockstep.
"""

from __future__ import annotations

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.motion import TUNING
from oacdsl.runtime.motion.both import move_both
from oacdsl.runtime.shapes import long_axis, lowest_z, world_corners
from oacdsl.runtime.skills.base import SkillContext, cm
from oacdsl.runtime.transforms import MIN_JERK_PEAK, make_T

__all__ = ["roll", "ROLL_STROKES", "ROLL_LENGTH_M", "ROLL_PERIOD_S", "roll_direction"]

#: Default number of strokes (there and back).
ROLL_STROKES = 3
#: Default distance to either side of the middle, m.
ROLL_LENGTH_M = 0.06
#: Default time of one stroke there and back, s.
ROLL_PERIOD_S = 1.6
#: How far it is pressed into the support, m (pressed 4 mm, its friction on the way there
#: and back swung the wrist forces by some 50 N).
PRESS_M = 0.002
#: Wrist force change that stops the descent when the objects do not touch first, N (the two
#: hands on one object feel some 12 N of each other while they move).
FORCE_N = 15.0
#: Height of the object above the target's top before it comes down onto it, m.
HOVER_M = 0.03
#: How far below the gap left under the object the hands are sent to seat it on the target, m,
#: and how many times.
SEAT_M = 0.001
SEAT_TRIES = 3
#: How far below the target's top the descent is aimed (it stops on the touch), m.
BELOW_M = 0.03


def roll_direction(ctx: SkillContext, obj: str) -> np.ndarray:
    """The horizontal unit direction of the strokes: across the object's long axis, away from
    the robot (world frame)."""
    t = ctx.world.body_pose(obj)
    along = t[:3, :3] @ long_axis(ctx.body(obj))
    u = np.cross(np.array([0.0, 0.0, 1.0]), along)
    if float(np.linalg.norm(u[:2])) < 1e-6:  # standing upright: rolled forward and back
        u = np.array([1.0, 0.0, 0.0])
    u = np.array([u[0], u[1], 0.0]) / float(np.linalg.norm(u[:2]))
    return u if u[0] >= 0 else -u


def roll(
    ctx: SkillContext,
    h1: str,
    obj: str,
    h2: str,
    target: str,
    *,
    strokes: float = ROLL_STROKES,
    length: float = ROLL_LENGTH_M,
    period: float = ROLL_PERIOD_S,
    press: float = PRESS_M,
    force: float = FORCE_N,
) -> None:
    """Roll ``obj``, held by ``h1`` and ``h2``, on ``target``: ``strokes`` times ``length`` (m) to
    either side, ``period`` (s) per stroke, pressed ``press`` (m) into it; the descent stops
    when they touch or a wrist feels ``force`` (N)."""
    world, ctl = ctx.world, ctx.ctl
    sides = (ctx.require_held(h1, obj), ctx.require_held(h2, obj))
    if sides[0] == sides[1]:
        raise RuntimeFailure(f"roll needs two different hands ({h1} given twice)")
    if target not in world.layout.bodies or not ctx.body(target).solids:
        raise RuntimeFailure(f"roll: {target!r} is no object of the scene")
    starts = {s: ctl.ik.goal(s) for s in sides}

    def shifted(dx: np.ndarray) -> dict[str, np.ndarray]:
        return {s: make_T(t[:3, :3], t[:3, 3] + dx) for s, t in starts.items()}

    def top() -> float:
        return float(world_corners(ctx.body(target), world.body_pose(target))[:, 2].max())

    def low() -> float:
        return lowest_z(ctx.body(obj), world.body_pose(obj))

    # over the target's middle, HOVER_M above its top
    mine = world_corners(ctx.body(obj), world.body_pose(obj))
    theirs = world_corners(ctx.body(target), world.body_pose(target))
    over = 0.5 * (theirs.min(axis=0) + theirs.max(axis=0)) - 0.5 * (mine.min(axis=0) + mine.max(axis=0))
    over[2] = max(0.0, top() + HOVER_M - low())
    ctl.activity = f"carrying {obj} over {target}"
    move_both(ctl, shifted(over), 1.5)
    starts = shifted(over)
    ctl.wait(0.3)  # the two hands settle on the one object before the wrists are watched

    def felt() -> bool:
        pushed = any(float(np.linalg.norm(ctl.force_change(s))) > force for s in sides)
        return world.touching(obj, target) or pushed

    ctl.activity = f"bringing {obj} onto {target}"
    depth = low() - top() + BELOW_M
    seconds = MIN_JERK_PEAK * depth / TUNING.set_down_speed_m_s
    stopped = move_both(ctl, shifted(np.array([0.0, 0.0, -depth])), seconds, dict.fromkeys(sides, felt))
    if not any(stopped.values()):
        raise RuntimeFailure(f"roll: {obj} did not reach {target} after going down {cm(depth)}")
    # where the hands stopped; the arms spring back a few mm when they stop, and a wrist may
    # have felt the motion rather than the target: down again (guarded) by the gap left under
    # the object, then ``press``
    starts = {s: ctl.ik.target(s) for s in sides}
    for _ in range(SEAT_TRIES):
        ctl.wait(0.2)
        if world.touching(obj, target):
            break
        gap = max(0.0, low() - top()) + SEAT_M
        move_both(ctl, shifted(np.array([0.0, 0.0, -gap])), 0.2 + gap / TUNING.set_down_speed_m_s)
        starts = shifted(np.array([0.0, 0.0, -gap]))
    if not world.touching(obj, target):
        raise RuntimeFailure(f"roll: {obj} did not reach {target} ({(low() - top()) * 1000:.0f} mm above it)")
    down = np.array([0.0, 0.0, -press])
    move_both(ctl, shifted(down), 0.3)
    ctl.wait(0.2)
    u = roll_direction(ctx, obj)
    ctl.activity = f"rolling {obj} on {target}"
    for _ in range(max(1, round(strokes))):
        for sign, share in ((1.0, 0.25), (-1.0, 0.5), (0.0, 0.25)):
            move_both(ctl, shifted(down + sign * length * u), share * period)
    for hand, s in zip((h1, h2), sides, strict=True):
        if world.held[s] != obj:
            raise RuntimeFailure(f"roll: {hand} lost {obj}")
    if not (ctl.wait(0.3, until=lambda: world.touching(obj, target)) or world.touching(obj, target)):
        raise RuntimeFailure(f"roll: {obj} left {target} while it rolled")
