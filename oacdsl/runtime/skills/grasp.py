"""``reach_and_grasp``: approach an object along its declared grasp and close the hand.

The object is lifted by :data:`LIFT_M` afterwards, unless the other hand holds it
already (a hand-over: both hands hold it still, and the other one lets go next).
The grasp *holds by a weld* (a MuJoCo equality constraint between palm and object)
that is switched on only when the hand is at the grasp pose and its fingers touch the
object; see docs/runtime.md for why friction alone was not used.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.model import Grasp
from oacdsl.runtime.grasping import HAND_BELOW_CENTRE_M, GraspPlan
from oacdsl.runtime.hands import CLOSED, PINCH_CLOSED, SQUEEZE_RAD, TOP_PRESHAPE, finger_joint_names
from oacdsl.runtime.motion.approach import other_side_boxes, over_other_side
from oacdsl.runtime.motion.detour import boxes
from oacdsl.runtime.simworld import SimWorld
from oacdsl.runtime.skills.base import Pick, SkillContext, cm, fmt_xyz
from oacdsl.runtime.skills.grasp_choice import (
    HANDS_APART_M,
    clear_pre_grasp,
    grasp_candidates,
    handover_candidates,
    preshape,
)
from oacdsl.runtime.transforms import make_T

__all__ = [
    "HANDS_APART_M",
    "preshape",
    "reach_and_grasp",
    "GraspMotion",
    "plan_grasp",
    "grasp_candidates",
    "clear_pre_grasp",
    "handover_candidates",
    "secure",
    "ease_off",
    "lifted",
    "GRASP_POSE_TOLERANCE_M",
    "LIFT_M",
]

#: How far the hand's grasp centre may be from the planned grasp point when it closes, m.
GRASP_POSE_TOLERANCE_M = 0.07
#: Height an object is lifted after grasping, m.
LIFT_M = 0.10
APPROACH_SPEED_M_S = 0.15
#: How far a hand that came down onto an object is raised again before it closes, m.
EASE_OFF_M = 0.004


@dataclass
class GraspMotion:
    """A planned grasp of ``obj`` by hand ``side``: the way there (``waypoints``: three
    (T_world_grasp, seconds); the first, a climb, takes 0 s when none is needed), the guarded approach
    to ``plan.end`` and what closing needs."""

    hand: str
    side: str
    obj: str
    grasp: Grasp
    plan: GraspPlan
    t_obj: np.ndarray
    supports: frozenset[str]
    handover: bool
    waypoints: list[tuple[np.ndarray, float]]
    approach_s: float
    #: hand parts that must touch (a pinch: fingers and thumb) and those that stop a top approach
    needed: set[str]
    stop: set[str] | None

    @property
    def closed(self) -> dict[str, float]:
        return PINCH_CLOSED if self.grasp.type == "pinch" else CLOSED

    def arrived(self, world: SimWorld) -> bool:
        """The approach's guard: the hand touches the object as the grasp type needs."""
        return (
            world.touching(self.hand, self.obj)
            and self.needed <= (parts := world.hand_parts_touching(self.side, self.obj))
            and (self.stop is None or bool(self.stop & parts))
        )

    def holding(self, world: SimWorld) -> bool:
        """Closing's guard: the fingers (and what a pinch needs) touch the object."""
        return world.fingers_touch(self.side, self.obj) and self.needed <= world.hand_parts_touching(
            self.side, self.obj
        )


def plan_grasp(ctx: SkillContext, hand: str, obj: str, plan: GraspPlan | None = None) -> GraspMotion:
    """Plan how ``hand`` grasps ``obj``: by ``plan``, else by the first of
    :func:`grasp_candidates` the whole-body IK reaches (raises when the hand holds
    something or reaches none)."""
    world, ctl = ctx.world, ctx.ctl
    side = ctx.side(hand)
    if world.held[side] is not None:
        raise RuntimeFailure(f"{hand} already holds {world.held[side]}")
    grasp = ctx.grasp_for(obj)
    t_obj = world.body_pose(obj)
    supports = world.relations().partners(obj) & ctx.objects()
    handover = ctx.other_holder(side, obj) is not None
    if plan is None:
        candidates = handover_candidates(ctx, hand, obj) if handover else grasp_candidates(ctx, hand, obj)
        plan = ctx.first_reachable(side, [(p.grasp, p) for p in candidates], obj)
    current = ctl.ik.frame(f"grasp_{side}")
    via = plan.pre_grasp.copy()
    over = ctx.via_height(current[:3, 3], plan.pre_grasp[:3, 3], {obj}, HAND_BELOW_CENTRE_M)
    via[2, 3] = max(via[2, 3], plan.grasp[2, 3]) + 0.08
    if current[2, 3] > via[2, 3]:
        via[2, 3] = 0.5 * (via[2, 3] + current[2, 3])
    via[2, 3] = max(via[2, 3], over)
    # over the other hand and what it holds too, when the way would meet them (motion/approach.py)
    high = over_other_side(boxes(world, side), other_side_boxes(world, side, {obj}), current[:3, 3],
                           [via[:3, 3], plan.pre_grasp[:3, 3]])
    if high is not None:
        over = max(over, high)
        via[2, 3] = max(via[2, 3], high)
    up = current.copy()
    up[2, 3] = max(over, current[2, 3])  # climb first, then cross over the obstacles
    travel = float(np.linalg.norm(plan.end[:3, 3] - plan.pre_grasp[:3, 3]))
    pinch = grasp.type == "pinch"
    # a pinch comes down until both the finger plate (beside the edge) and the thumb (on top)
    # touch; any other grasp from above until the palm or the finger plate does (the folded
    # thumb, lying under the palm, yields to the object's top)
    stop = {"palm", "fingers"} if grasp.approach == "top" and grasp.type != "rim" and not pinch else None
    return GraspMotion(
        hand,
        side,
        obj,
        grasp,
        plan,
        t_obj,
        supports,
        handover,
        [(up, 0.6 if over > current[2, 3] else 0.0), (via, 1.2), (plan.pre_grasp, 0.6)],
        travel / APPROACH_SPEED_M_S,
        {"fingers", "thumb"} if pinch else set(),
        stop,
    )


def ease_off(ctx: SkillContext, m: GraspMotion) -> np.ndarray | None:
    """After a top approach stopped on the object: the hand pose raised by :data:`EASE_OFF_M`
    (the arm lags its target: ease off what the palm pressed down), else None."""
    if m.stop is None:
        return None
    eased = ctx.ctl.ik.frame(f"grasp_{m.side}")
    eased[2, 3] += EASE_OFF_M
    return eased


def secure(ctx: SkillContext, m: GraspMotion) -> None:
    """After closing: check the hand is at the grasp and touches the object as needed, weld
    it, keep the fingers pressing lightly and remember the pick."""
    world, ctl = ctx.world, ctx.ctl
    side, hand, obj = m.side, m.hand, m.obj
    centre = world.frame_pose(f"grasp_{side}")[:3, 3]
    off = float(np.linalg.norm(centre - m.plan.grasp[:3, 3]))
    if off > GRASP_POSE_TOLERANCE_M:
        raise RuntimeFailure(
            f"could not grasp {obj}: {hand} ended {cm(off)} from the grasp point"
            f" {fmt_xyz(m.plan.grasp[:3, 3])}"
        )
    if not world.fingers_touch(side, obj):
        raise RuntimeFailure(f"could not grasp {obj}: the fingers of {hand} do not touch it")
    missing = m.needed - world.hand_parts_touching(side, obj)
    if missing:
        verb = "do" if len(missing) > 1 else "does"
        raise RuntimeFailure(
            f"could not pinch {obj}: the {' and '.join(sorted(missing))} of {hand} {verb} not touch it"
        )
    world.weld(side, obj)
    # hold the fingers where they met the object, pressing lightly, so that they stay on it
    names = finger_joint_names(side)
    now = world.joint_positions()
    ctl.set_fingers(side, {k: min(now[j] + SQUEEZE_RAD, m.closed[k]) for k, j in names.items()})
    ctx.picked[side] = Pick(obj, m.t_obj, m.plan.approach, m.supports, from_hand=m.handover)


def lifted(ctx: SkillContext, side: str, lift: float) -> np.ndarray:
    """The hand's target raised by ``lift`` (m)."""
    t = ctx.ctl.ik.target(side)
    return make_T(t[:3, :3], t[:3, 3] + np.array([0.0, 0.0, lift]))


def reach_and_grasp(ctx: SkillContext, hand: str, obj: str, *, lift: float = LIFT_M) -> None:
    """Grasp ``obj`` with ``hand`` as its grasp declaration says and lift it by ``lift`` (m)."""
    world, ctl = ctx.world, ctx.ctl
    ctl.activity = f"reaching for {obj}"
    m = plan_grasp(ctx, hand, obj)
    side = m.side
    if m.grasp.approach == "top":
        ctl.set_fingers(side, TOP_PRESHAPE)
    for pose, seconds in m.waypoints:
        if seconds > 0:
            ctl.move(side, pose, seconds)
    ctl.activity = f"approaching {obj}"
    ctl.move(side, m.plan.end, m.approach_s, guard=lambda: m.arrived(world))
    eased = ease_off(ctx, m)
    if eased is not None:
        ctl.move(side, eased, 0.2)
    ctl.activity = f"closing {hand} on {obj}"
    # the weld is switched on the moment the fingers touch the object (if the hand is at the
    # grasp pose): a closing finger would otherwise push a light object out of the hand
    ctl.close_hand(side, until=lambda: m.holding(world), targets=m.closed)
    secure(ctx, m)
    ctl.wait(0.3)
    if m.handover:  # the other hand holds it up: lifting would pull against that hand
        return
    ctl.activity = f"lifting {obj}"
    ctl.move(side, lifted(ctx, side, lift), 1.0)
