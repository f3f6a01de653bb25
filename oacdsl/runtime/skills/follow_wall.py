"""``follow`` in a container it is to touch: the hand kept clear of the rim, the contact from the wall.

A tool held upright at its handle (a spoon taken 14 cm up, in a cup 12 cm deep) cannot reach
the container's floor without its hand meeting the rim: the demonstrated path, followed from
where the approach stopped, then circled in the middle of the cup and touched it only now and
then (KIT Stir with ``follow``: no oscillation while in contact; the hand met the rim, two
extra changes). So, as the named ``stir`` does, while the hand is over the container's
opening its lowest point stays the tuning's ``rim_clearance_m`` above the rim
(:func:`clear_of_rim`), and a core that does not touch the container where it runs is pushed
out towards the wall, along the direction from the core's middle to the object's lowest
end, at the tuning's seek speed, until they touch; never beyond where the object's widest part
is ``aim_beyond_m`` past the inner wall, and never back (:class:`WallSeek`, as the slide's seek
lowers a tool onto a surface); each keyframe is pushed along its own direction from the core's
middle and no farther than the wall allows, so the demonstrated circles become circles along
the wall, as the demonstrator's spoon scraped the cup (pushed all one way, a circle off the
middle went through the wall by its diameter: the cup, held by the other hand, was pushed
until that wrist stopped at 60 N; pushed along each keyframe's direction from the axis, a
small circle off the middle became an arc to and fro along the wall, no oscillation).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from oacdsl.runtime.bodies import Body
from oacdsl.runtime.motion import TUNING
from oacdsl.runtime.retarget import MIN_OFFSET_M
from oacdsl.runtime.shapes import hand_reach_below, world_corners
from oacdsl.runtime.skills.base import SkillContext
from oacdsl.runtime.skills.follow_top import lowest_end

__all__ = ["WallSeek", "clear_of_rim"]


def _axis(ctx: SkillContext, target: str) -> tuple[np.ndarray, np.ndarray]:
    """(a point on ``target``'s axis, the axis (world, unit)) now."""
    t = ctx.world.body_pose(target)
    return t[:3, 3].copy(), t[:3, 2].copy()


def _across(v: np.ndarray, axis: np.ndarray) -> np.ndarray:
    return v - float(v @ axis) * axis


def clear_of_rim(ctx: SkillContext, side: str, target: str) -> Callable[[np.ndarray], np.ndarray]:
    """``T_world_grasp`` → the same pose raised as far as hand ``side``'s lowest point (as the
    hand is turned now) needs to stay the tuning's ``rim_clearance_m`` above ``target``'s rim
    while the grasp centre is over the opening (within the rim's radius and the hand's reach
    below its grasp centre of the axis); other poses unchanged."""
    world, body = ctx.world, ctx.body(target)
    below = hand_reach_below(world, side)
    rim = float(world_corners(body, world.body_pose(target))[:, 2].max())

    def raised(pose: np.ndarray) -> np.ndarray:
        centre, axis = _axis(ctx, target)
        if float(np.linalg.norm(_across(pose[:3, 3] - centre, axis))) > body.rim_radius + below:
            return pose
        least = rim + below + TUNING.rim_clearance_m
        if pose[2, 3] >= least:
            return pose
        out = pose.copy()
        out[2, 3] = least
        return out

    return raised


class WallSeek:
    """A container's core pushed out towards its wall until the object touches it (module doc)."""

    def __init__(self, ctx: SkillContext, side: str, obj: str, target: str,
                 core: Sequence[np.ndarray]) -> None:
        """``core``: the object's poses (T_world_obj) along the core, as planned (one or more)."""
        self.ctx, self.obj, self.target = ctx, obj, target
        self.body_o: Body = ctx.body(obj)
        body_t = ctx.body(target)
        #: farthest the object's lowest end may be from the axis, m
        self.reach_m = max(body_t.inner_radius - self.body_o.radius, 0.0) + TUNING.aim_beyond_m
        centre, axis = _axis(ctx, target)
        hand = _across(ctx.world.frame_pose(f"grasp_{side}")[:3, 3] - centre, axis)
        #: where to push a keyframe at the core's middle: the wall away from the hand (as ``stir``)
        self.away = -hand / max(float(np.linalg.norm(hand)), MIN_OFFSET_M)
        #: the middle of the core's lowest ends, across the axis, in the target's frame (m): the
        #: keyframes are pushed out from it (a circle grows about its own centre)
        r_t = ctx.world.body_pose(target)[:3, :3]
        ends = [_across(lowest_end(self.body_o, p) - centre, axis) for p in core]
        self.middle = r_t.T @ np.median(np.array(ends), axis=0)
        #: how far the core is pushed out now, m
        self.out_m = 0.0

    def grow(self, seconds: float) -> None:
        """While the object does not touch the target: push out by the seek speed × ``seconds``."""
        if not self.ctx.world.touching(self.obj, self.target):
            self.out_m = min(self.out_m + TUNING.seek_speed_m_s * seconds, self.reach_m)

    def offset(self, t_world_obj: np.ndarray) -> np.ndarray:
        """How far (world, m) the object at ``t_world_obj`` (a keyframe of the core) is pushed:
        its lowest end moved out by what the seek found, along the direction from the core's
        middle to it (a circle grows about its centre; at the middle, towards the wall away
        from the hand), then brought back in towards the axis as far as it would be beyond
        the wall: the core's circles become circles along the wall, not pushes through it."""
        centre, axis = _axis(self.ctx, self.target)
        end = _across(lowest_end(self.body_o, t_world_obj) - centre, axis)
        middle = self.ctx.world.body_pose(self.target)[:3, :3] @ self.middle
        out = end - middle
        size = float(np.linalg.norm(out))
        to = end + self.out_m * (out / size if size > 0 else self.away)
        far = float(np.linalg.norm(to))
        limit = max(self.reach_m, float(np.linalg.norm(end)))  # (never pulled in past the plan)
        if far > limit:
            to = to * (limit / far)
        return to - end

    def pushed(self, t_world_obj: np.ndarray) -> np.ndarray:
        """``t_world_obj`` (or any pose moving with the object) moved by :meth:`offset`."""
        out = t_world_obj.copy()
        out[:3, 3] += self.offset(t_world_obj)
        return out
