"""A grasp's approach keeps clear of the other hand and of what that hand holds.

The free-corridor check of a grasp (:func:`~oacdsl.runtime.motion.paths.clearance`) sees only
the objects standing on the table. What the other hand holds up, and that hand itself, are
not standing there, yet a hand coming in along its approach meets them just as well: in a
left-handed (mirrored) Peel, the right hand held the cucumber up beside the peeler, and the
left hand, taking the peeler from its own side, came in through the cucumber (66 N on the
right wrist). Here the approaching hand is its collision boxes
(:func:`~oacdsl.runtime.handgap.hand_box_poses`, in the shape it comes in with) moved along
the approach from the pre-grasp to the grasp, and the other side is the boxes of the other
hand and of what it holds, as they are now (:func:`~oacdsl.runtime.motion.detour.boxes`);
the gap is the smallest distance between the two along the way (metres).

The IK's postures along an approach (:func:`approach_postures`) say two more things: whether
the arm lies on what the other hand holds (:func:`arm_room_to`), and whether the whole-body IK
reaches the grasp only with the torso leaning as far as it goes (:func:`torso_margin_rad`). A
left hand taking a lid turned a quarter from its natural heading, beside the bottle the right
hand held up, reached it with the hip's roll at its limit and the arm stretched: the shoulder
lagged its command by 0.2 rad, the folded thumb landing on the lid's top tipped the hand 14°,
and the hand closed so, holding the lid 10-16° tilted once the arm levelled the hand again;
brought onto the bottle, its rim touched the bottle's edge for a moment and sprang off (seed 9
of the ``close_and_open`` example). Taken at its natural heading, the torso upright, it closed
within 6° and the lid went on.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

import numpy as np

from oacdsl.runtime.armar3 import JOINTS, TORSO_JOINTS
from oacdsl.runtime.armroom import room_to_object
from oacdsl.runtime.handgap import hand_box_poses
from oacdsl.runtime.motion.detour import Box, boxes, gap, way_gap
from oacdsl.runtime.motion.tuning import TUNING, Tuning

if TYPE_CHECKING:
    from oacdsl.runtime.grasping import GraspPlan
    from oacdsl.runtime.ik import WholeBodyIK
    from oacdsl.runtime.simworld import SimWorld

__all__ = [
    "approach_gap",
    "approach_postures",
    "arm_room_in",
    "arm_room_to",
    "hand_boxes_at",
    "other_side_boxes",
    "over_other_side",
    "torso_margin_rad",
]

#: The corners of a unit box about the origin, one per row.
_SIGNS = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], dtype=float)
#: (lower, upper) limits of the torso's joints, rad.
_TORSO_LIMITS = {j.name: j.limits for j in JOINTS if j.name in TORSO_JOINTS}


def hand_boxes_at(side: str, t_world_grasp: np.ndarray, fingers: Mapping[str, float]) -> list[Box]:
    """The axis-aligned world boxes around each collision box of hand ``side`` when its grasp
    centre is at ``t_world_grasp`` and its fingers at ``fingers`` (m)."""
    out = []
    for t, half in hand_box_poses(side, t_world_grasp, fingers):
        pts = (_SIGNS * half) @ t[:3, :3].T + t[:3, 3]
        out.append((pts.min(axis=0), pts.max(axis=0)))
    return out


def approach_gap(side: str, plan: GraspPlan, fingers: Mapping[str, float], still: Sequence[Box]) -> float:
    """The smallest gap (m) between hand ``side`` coming in along ``plan`` (pre-grasp to grasp,
    or to the approach's end for an approach from the side; turned as at the grasp, fingers at
    ``fingers``) and the ``still`` boxes; ``inf`` when there are none, negative where they overlap.

    From the side, to the end: the guarded approach goes on past the grasp point until the
    hand touches the object (``plan.end``, up to ``OVERSHOOT_M`` past it), and a hand from the
    side touches it first with its palm. A right hand taking a standing peeler from its side
    closed with its grasp centre 2.4 cm past the grasp point, its palm on the handle, and its
    thumb met the cucumber the left hand held up beside it (0.76 s, an extra + and −), the
    approach having kept 3.1 cm up to the grasp point. From above the hand stops on the
    object's top, at the grasp point (a lid on a bottle the other hand holds: what lies past it
    is the object and what it stands on)."""
    if not still:
        return float("inf")
    start = plan.pre_grasp[:3, 3]
    d = plan.approach
    from_above = abs(float(d[2])) > float(np.hypot(d[0], d[1]))
    stop = plan.grasp if from_above else plan.end
    return way_gap(hand_boxes_at(side, plan.pre_grasp, fingers), still, start, [start, stop[:3, 3]])


def other_side_boxes(world: SimWorld, side: str, exclude: set[str]) -> list[Box]:
    """The boxes of the other hand than ``side`` and of what it holds, now; none while it holds
    something in ``exclude`` (a hand-over: that hand is at the object by necessity, and the
    grasps leaving room for it are chosen by :func:`~oacdsl.runtime.handgap.hands_gap`)."""
    other = "l" if side == "r" else "r"
    if world.held.get(other) in exclude:
        return []
    return boxes(world, other)


def over_other_side(
    moving: Sequence[Box], still: Sequence[Box], start: np.ndarray, points: Sequence[np.ndarray],
    tuning: Tuning = TUNING,
) -> float | None:
    """The height (m) a hand frame now at ``start`` (its boxes ``moving``) must cross at so that
    it passes ``tuning.over_m`` over the ``still`` boxes (the other hand and what it holds),
    when its way through ``points`` (hand positions, world) would come nearer to them than that
    (and nearer than it is now); None when the way keeps clear. A hand going to take a peeler
    crossed over the cucumber the other hand held up, low enough to meet it (66 N)."""
    if not still:
        return None
    need = min(tuning.over_m, gap(moving, still, np.zeros(3)))
    if way_gap(moving, still, start, [start, *points]) >= need:
        return None
    below = float(start[2] - min(lo[2] for lo, _ in moving))  # how far the hand reaches below its frame
    return max(float(hi[2]) for _, hi in still) + below + tuning.over_m


def approach_postures(ik: WholeBodyIK, side: str, plan: GraspPlan) -> list[Mapping[str, float]]:
    """The IK's postures (:meth:`~oacdsl.runtime.ik.WholeBodyIK.joints`) with hand ``side`` at
    ``plan``'s pre-grasp and grasp, reached one after the other from now (the robot unmoved)."""
    return [q for _, q in ik.reach_postures(side, [plan.pre_grasp, plan.grasp])]


def arm_room_in(world: SimWorld, side: str, postures: Sequence[Mapping[str, float]], obj: str) -> float:
    """The smallest room (m, at most 0.1; negative: overlapping) between arm ``side`` with its
    hand in any of ``postures`` and ``obj`` where it is now."""
    pose = world.body_pose(obj)
    return min(room_to_object(world, side, q, obj, pose) for q in postures)


def arm_room_to(world: SimWorld, ik: WholeBodyIK, side: str, plan: GraspPlan, obj: str) -> float:
    """The smallest room (m, at most 0.1; negative: overlapping) between arm ``side`` with its
    hand, in the IK's postures at ``plan``'s pre-grasp and grasp (reached one after the other
    from now), and ``obj`` where it is now: whether the arm coming in along the approach lies
    on what the other hand holds (a left hand taking a peeler from behind laid its forearm on
    the cucumber the right hand held up: 61 N)."""
    return arm_room_in(world, side, approach_postures(ik, side, plan), obj)


def torso_margin_rad(posture: Mapping[str, float]) -> float:
    """How far (rad) the torso joint nearest its limit is from it in ``posture`` (joints it
    lacks count as in the middle): near 0, the whole-body IK leans the torso as far as it goes
    to reach the hand's pose (module docstring)."""
    return min(
        (min(posture[n] - lo, hi - posture[n]) for n, (lo, hi) in _TORSO_LIMITS.items() if n in posture),
        default=float("inf"),
    )
