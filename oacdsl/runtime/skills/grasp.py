"""``reach_and_grasp``: approach an object along its declared grasp and close the hand.

The object is lifted by :data:`LIFT_M` afterwards, unless the other hand holds it
already (a hand-over: both hands hold it still, and the other one lets go next).
The grasp *holds by a weld* (a MuJoCo equality constraint between palm and object)
that is switched on only when the hand is at the grasp pose and its fingers touch the
object; see docs/runtime.md for why friction alone was not used.
"""

from __future__ import annotations

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.grasping import HAND_BELOW_CENTRE_M, plan_grasps
from oacdsl.runtime.hands import CLOSED, PINCH_CLOSED, TOP_PRESHAPE, finger_joint_names
from oacdsl.runtime.skills.base import Pick, SkillContext, fmt_xyz
from oacdsl.runtime.transforms import make_T

__all__ = ["reach_and_grasp", "GRASP_POSE_TOLERANCE_M", "LIFT_M"]

#: How far the hand's grasp centre may be from the planned grasp point when it closes, m.
GRASP_POSE_TOLERANCE_M = 0.07
#: Height an object is lifted after grasping, m.
LIFT_M = 0.10
APPROACH_SPEED_M_S = 0.15
#: Half the hand's width across the fingers, plus a margin: the free corridor an approach needs, m.
HAND_HALF_WIDTH_M = 0.07
#: How far a hand that came down onto an object is raised again before it closes, m.
EASE_OFF_M = 0.004
#: How much further than where they touched the object the fingers are told to close, rad.
SQUEEZE_RAD = 0.08


def reach_and_grasp(ctx: SkillContext, hand: str, obj: str, *, lift: float = LIFT_M) -> None:
    """Grasp ``obj`` with ``hand`` as its grasp declaration says and lift it by ``lift`` (m)."""
    world, ctl = ctx.world, ctx.ctl
    side = ctx.side(hand)
    if world.held[side] is not None:
        raise RuntimeFailure(f"{hand} already holds {world.held[side]}")
    grasp = ctx.grasp_for(obj)
    t_obj = world.body_pose(obj)
    supports = world.relations().partners(obj) & ctx.objects()
    handover = ctx.other_holder(side, obj) is not None
    support = ctx.support_height(t_obj[:2, 3], exclude=obj)
    ctl.activity = f"reaching for {obj}"
    plans = plan_grasps(grasp, ctx.body(obj).round, t_obj, side, support_z=support)
    # approaches whose corridor (pre-grasp to grasp) keeps the hand off other objects first
    free = [ctx.clearance(p.pre_grasp[:3, 3], p.grasp[:3, 3], {obj}) >= HAND_HALF_WIDTH_M for p in plans]
    plans = [p for p, ok in zip(plans, free, strict=True) if ok] + [
        p for p, ok in zip(plans, free, strict=True) if not ok
    ]
    plan = ctx.first_reachable(side, [(p.grasp, p) for p in plans], obj)
    current = ctl.ik.frame(f"grasp_{side}")
    via = plan.pre_grasp.copy()
    over = ctx.via_height(current[:3, 3], plan.pre_grasp[:3, 3], {obj}, HAND_BELOW_CENTRE_M)
    via[2, 3] = max(via[2, 3], plan.grasp[2, 3]) + 0.08
    if current[2, 3] > via[2, 3]:
        via[2, 3] = 0.5 * (via[2, 3] + current[2, 3])
    via[2, 3] = max(via[2, 3], over)
    if grasp.approach == "top":
        ctl.set_fingers(side, TOP_PRESHAPE)
    if over > current[2, 3]:  # climb first, then cross over the obstacles
        up = current.copy()
        up[2, 3] = over
        ctl.move(side, up, 0.6)
    ctl.move(side, via, 1.2)
    ctl.move(side, plan.pre_grasp, 0.6)
    travel = float(np.linalg.norm(plan.end[:3, 3] - plan.pre_grasp[:3, 3]))
    ctl.activity = f"approaching {obj}"
    pinch = grasp.type == "pinch"
    needed = {"fingers", "thumb"} if pinch else set()
    # a pinch comes down until both the finger plate (beside the edge) and the thumb (on top)
    # touch; any other grasp from above until the palm or the finger plate does (the folded
    # thumb, lying under the palm, yields to the object's top)
    stop = {"palm", "fingers"} if grasp.approach == "top" and grasp.type != "rim" and not pinch else None
    ctl.move(
        side,
        plan.end,
        travel / APPROACH_SPEED_M_S,
        guard=lambda: (
            world.touching(hand, obj)
            and needed <= (parts := world.hand_parts_touching(side, obj))
            and (stop is None or bool(stop & parts))
        ),
    )
    if stop is not None:  # the arm lags its target: ease off what the palm pressed down
        eased = ctl.ik.frame(f"grasp_{side}")
        eased[2, 3] += EASE_OFF_M
        ctl.move(side, eased, 0.2)
    ctl.activity = f"closing {hand} on {obj}"
    # the weld is switched on the moment the fingers touch the object (if the hand is at the
    # grasp pose): a closing finger would otherwise push a light object out of the hand
    closed = PINCH_CLOSED if pinch else CLOSED
    ctl.close_hand(
        side,
        until=lambda: world.fingers_touch(side, obj) and needed <= world.hand_parts_touching(side, obj),
        targets=closed,
    )
    centre = world.frame_pose(f"grasp_{side}")[:3, 3]
    off = float(np.linalg.norm(centre - plan.grasp[:3, 3]))
    if off > GRASP_POSE_TOLERANCE_M:
        raise RuntimeFailure(
            f"could not grasp {obj}: {hand} ended {off * 100:.0f} cm from the grasp point"
            f" {fmt_xyz(plan.grasp[:3, 3])}"
        )
    if not world.fingers_touch(side, obj):
        raise RuntimeFailure(f"could not grasp {obj}: the fingers of {hand} do not touch it")
    missing = needed - world.hand_parts_touching(side, obj)
    if missing:
        verb = "do" if len(missing) > 1 else "does"
        raise RuntimeFailure(
            f"could not pinch {obj}: the {' and '.join(sorted(missing))} of {hand} {verb} not touch it"
        )
    world.weld(side, obj)
    # hold the fingers where they met the object, pressing lightly, so that they stay on it
    names = finger_joint_names(side)
    now = world.joint_positions()
    ctl.set_fingers(side, {k: min(now[j] + SQUEEZE_RAD, closed[k]) for k, j in names.items()})
    ctl.wait(0.3)
    ctx.picked[side] = Pick(obj, t_obj, plan.approach, supports)
    if handover:  # the other hand holds it up: lifting would pull against that hand
        return
    ctl.activity = f"lifting {obj}"
    lifted = make_T(ctl.ik.target(side)[:3, :3], ctl.ik.target(side)[:3, 3] + np.array([0.0, 0.0, lift]))
    ctl.move(side, lifted, 1.0)
