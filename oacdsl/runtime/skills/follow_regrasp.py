"""``follow``'s regrasps: a turn about the held object's own axis beyond the wrist, in pieces.

When the path's twist is split (:func:`~oacdsl.runtime.follow_turns.split`), :class:`Regrasps`
lets go of the object on the target after each piece and takes it again, turned back
(:func:`~oacdsl.runtime.motion.rotate.regrasp`, the primitive ``twist`` turns with: each is
recorded on the controller as internal to the step, so the verifier does not count it as a
change of the task), and measures the turn the object really made. World frame, metres,
radians.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.bodies import Body
from oacdsl.runtime.hands import CLOSED, PINCH_CLOSED
from oacdsl.runtime.motion import Motion, OtherHand
from oacdsl.runtime.motion.rotate import angle_about, home_pose, regrasp
from oacdsl.runtime.retarget import FOLLOW, Retargeted
from oacdsl.runtime.skills.base import SkillContext

__all__ = ["Regrasps", "rests_on"]


def rests_on(body_o: Body, body_t: Body, t_world_obj: np.ndarray, t_world_target: np.ndarray) -> bool:
    """Whether ``body_o`` may be let go of on ``body_t`` and taken again turned about its own
    axis: round (a grasp turned about its axis holds it as well), standing on a solid top at
    least as wide (not in a container: a spoon let go in a cup falls), its axis within
    ``FOLLOW.rest_tilt_rad`` of the target's."""
    if body_t.container or not body_o.round or body_o.radius > body_t.radius:
        return False
    cos = float(np.clip(t_world_obj[:3, 2] @ t_world_target[:3, 2], -1.0, 1.0))
    return math.acos(cos) <= FOLLOW.rest_tilt_rad


class Regrasps:
    """The regrasps of one ``follow`` along ``plan`` (after the keyframes ``cuts``), from where
    the hand is now (the core's start; the other hand's goal kept at ``keep`` when given).
    ``planned(k)``: where the path puts the object at keyframe ``k`` (T_world_obj). The hand takes
    the object again where it is, which is not quite where the path has it (a regrasp turns it
    back a few degrees, slides it onto the target's middle): the grasp after a regrasp is taken
    relative to the planned pose, so that the next piece goes on from where the hand is
    (made up at once, that difference jerked the object off the target)."""

    def __init__(self, ctx: SkillContext, side: str, obj: str, target: str, keep: np.ndarray | None,
                 plan: Retargeted, cuts: tuple[int, ...], planned: Callable[[int], np.ndarray]) -> None:
        self.ctx, self.side, self.obj, self.target, self.plan, self.cuts = ctx, side, obj, target, plan, cuts
        self.planned = planned
        self.m = Motion(ctx, side, OtherHand.STEADY if keep is not None else OtherHand.IDLE, keep=keep)
        world = ctx.world
        self.axis = world.body_pose(obj)[:3, 2].copy()
        self.home, self.origin = home_pose(ctx, self.m, obj, self.axis)
        self.closed = PINCH_CLOSED if ctx.grasp_for(obj).type == "pinch" else CLOSED
        self.last = world.body_pose(obj)[:3, :3].copy()
        #: the turn the object really made about its axis since the core's start, rad
        self.turned = 0.0

    def _measure(self) -> None:
        now = self.ctx.world.body_pose(self.obj)[:3, :3].copy()
        self.turned += angle_about(self.axis, self.last, now)
        self.last = now

    def start(self, grip: np.ndarray) -> np.ndarray:
        """Before the first piece: take the object again with the grasp centre on its axis when
        it is off by more than the tuning's ``turn_off_axis_m`` (turned about the axis, the hand
        would swing round it, dragging the object off the target); the grasp from then on."""
        aside = self.ctx.world.frame_pose(f"grasp_{self.side}")[:3, 3] - self.origin
        aside -= float(aside @ self.axis) * self.axis
        twists = self.plan.twists_rad
        if float(np.linalg.norm(aside)) <= self.m.tuning.turn_off_axis_m or twists is None:
            return grip
        return self._again(self.plan.core, float(twists[self.cuts[0]] - twists[self.plan.core]))

    def _again(self, k: int, step: float) -> np.ndarray:
        """Take the object again at keyframe ``k`` for a next piece of ``step`` (rad); the new
        grasp (T_obj_grasp) relative to the object where the path has it at ``k``."""
        regrasp(self.ctx, self.m, self.obj, self.target, self.axis, self.home, self.origin, step, self.closed)
        self._measure()
        new: np.ndarray = np.linalg.inv(self.planned(k)) @ self.ctx.ctl.ik.goal(self.side)
        return new

    def after(self, k: int, grip: np.ndarray) -> np.ndarray:
        """Once keyframe ``k`` is reached: take the object again when ``k`` ends a piece; the
        hand's grasp in the object's frame (T_obj_grasp) from then on (``grip`` before)."""
        self._measure()
        if k not in self.cuts:
            return grip
        j = self.cuts.index(k)
        twists = self.plan.twists_rad
        if twists is None:
            return grip
        end = self.cuts[j + 1] if j + 1 < len(self.cuts) else len(twists) - 1
        return self._again(k, float(twists[end] - twists[k]))

    def check(self) -> None:
        """Fail when the object turned the other way, or less than ``FOLLOW.least_turned`` of
        the path's twist."""
        twists = self.plan.twists_rad
        planned = 0.0 if twists is None else float(twists[-1] - twists[self.plan.core])
        if self.turned * planned < 0 or abs(self.turned) < FOLLOW.least_turned * abs(planned):
            raise RuntimeFailure(
                f"follow: {self.obj} turned {math.degrees(self.turned):.0f}° of {math.degrees(planned):.0f}°"
                f" on {self.target}"
            )
