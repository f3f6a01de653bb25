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
from oacdsl.runtime.grasping import HAND_BELOW_CENTRE_M, GraspPlan, plan_grasps
from oacdsl.runtime.handgap import hands_gap
from oacdsl.runtime.hands import CLOSED, OPEN, PINCH_CLOSED, SQUEEZE_RAD, TOP_PRESHAPE, finger_joint_names
from oacdsl.runtime.motion.tuning import TUNING
from oacdsl.runtime.simworld import SimWorld
from oacdsl.runtime.skills.base import Pick, SkillContext, cm, fmt_xyz
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
#: Half the hand's width across the fingers, plus a margin: the free corridor an approach needs, m.
HAND_HALF_WIDTH_M = 0.07
#: Room kept between two hands that grasp at once, m: the smallest distance between their
#: collision boxes (palm, fingers, the thumb held out) at the two grasp poses
#: (:func:`~oacdsl.runtime.handgap.hands_gap`), for the IK's tracking error and the approach.
HANDS_APART_M = 0.03
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


def grasp_candidates(ctx: SkillContext, hand: str, obj: str, shared: bool = False) -> list[GraspPlan]:
    """The grasps of ``obj`` by ``hand`` its declaration allows, most natural first, those
    whose approach corridor is free of other objects before the others.

    ``shared``: both hands take the object (a rolling pin). One that is not round is then
    taken at its declared grasp point or at that point mirrored through its axis (offset
    ``(-x, -y, z)``), whichever lies on the hand's own side of the object."""
    side = ctx.side(hand)
    t_obj = ctx.world.body_pose(obj)
    support = ctx.support_height(t_obj[:2, 3], exclude=obj, below=float(t_obj[2, 3]) + 0.01)
    if ctx.other_holder(side, obj) is not None:
        # held up by the other hand (a hand-over): taken as high above its base as if it stood
        # there, so that this hand sets it down later before its own lower edge meets the
        # support (a cup taken 6 cm above its base: the palm met the table first, 60 N)
        support = max(support, float(t_obj[2, 3]))
    top = float(t_obj[2, 3] + t_obj[2, 2] * ctx.body(obj).height)  # upright: its base + height, m
    grasp = ctx.grasp_for(obj)
    plans = plan_grasps(grasp, ctx.body(obj).round, t_obj, side, support_z=support, top_z=top)
    if shared and not ctx.body(obj).round:
        x, y, z = grasp.offset
        mirrored = grasp.model_copy(update={"offset": (-x, -y, z)})
        plans += plan_grasps(mirrored, False, t_obj, side, support_z=support, top_z=top)
        left = ctx.world.frame_pose("grasp_l")[:3, 3] - ctx.world.frame_pose("grasp_r")[:3, 3]
        own = left if side == "l" else -left
        plans = [p for p in plans if float((p.grasp[:3, 3] - t_obj[:3, 3]) @ own) > 0] or plans
    def free(p: GraspPlan) -> bool:
        return ctx.clearance(p.pre_grasp[:3, 3], p.grasp[:3, 3], {obj}) >= HAND_HALF_WIDTH_M

    # the planned approaches whose corridor is free first; then those made free by a shorter
    # approach (clear_pre_grasp: a left hand pouring a cup across its body, taken so, reached
    # it past the bowl, 111 N, where a planned free approach was there); then the others
    clear = [p for p in plans if free(p)]
    moved = [clear_pre_grasp(ctx, p, obj) for p in plans if not free(p)]
    return clear + [p for p in moved if free(p)] + [p for p in moved if not free(p)]


def clear_pre_grasp(ctx: SkillContext, plan: GraspPlan, obj: str) -> GraspPlan:
    """``plan`` with its pre-grasp moved in along the approach, by ``TUNING.pre_grasp_step_m`` at a
    time down to ``TUNING.pre_grasp_min_m`` from the grasp, until the hand there keeps
    :data:`HAND_HALF_WIDTH_M` from every other object's footprint: the hand comes down to its
    pre-grasp from above, and one that starts a side approach over a neighbour came down on it
    (a left hand taking a block past a crate: 83 N). Unchanged when it is clear already, when
    the approach is from above, or when no shorter approach is clear."""
    d = plan.approach
    if abs(float(d[2])) > float(np.hypot(d[0], d[1])):  # from above: the pre-grasp is over the grasp
        return plan
    point = plan.grasp[:3, 3]
    length = float(np.linalg.norm(plan.pre_grasp[:3, 3] - point))
    while length >= TUNING.pre_grasp_min_m:
        pre = point - length * d
        if ctx.clearance(pre, pre, {obj}) >= HAND_HALF_WIDTH_M:
            if np.allclose(pre, plan.pre_grasp[:3, 3]):
                return plan
            return GraspPlan(plan.grasp, make_T(plan.grasp[:3, :3], pre), d, plan.end)
        length -= TUNING.pre_grasp_step_m
    return plan


def handover_candidates(ctx: SkillContext, hand: str, obj: str) -> list[GraspPlan]:
    """The grasps of ``obj`` by ``hand`` while the other hand holds it: its declared grasps and,
    for an object that is not round, the declared point mirrored through its axis; those that
    leave room for the other hand where it holds the object (its hand boxes, as they are,
    :data:`~oacdsl.runtime.skills.bimanual.HANDS_APART_M` apart) come first, the grasp point
    the other hand occupies last (taking it there pressed both hands together: 69 N)."""

    side = ctx.side(hand)
    other = "l" if side == "r" else "r"
    plans = grasp_candidates(ctx, hand, obj, shared=True)
    held = (other, ctx.world.frame_pose(f"grasp_{other}"), ctx.ctl.fingers[other])
    room = [hands_gap((side, p.grasp, preshape(ctx, obj)), held) >= HANDS_APART_M for p in plans]
    return [p for p, ok in zip(plans, room, strict=True) if ok] + [
        p for p, ok in zip(plans, room, strict=True) if not ok
    ]


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


def preshape(ctx: SkillContext, obj: str) -> dict[str, float]:
    """The fingers of a hand coming to grasp ``obj`` (the thumb folded for a grasp from above)."""
    return TOP_PRESHAPE if ctx.grasp_for(obj).approach == "top" else OPEN
