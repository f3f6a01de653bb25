"""Which free spot of the table ``place`` sets an object down on when it may not go back where
it was picked up (taken from the other hand, or what it stood on is held, or something
stands there now).

The candidates are :func:`~oacdsl.runtime.motion.spots.free_spots` (footprints kept apart,
the hand's own side first, nearest first), for a round object also turned about its axis
with the hand (``Tuning.spot_turns_rad``: the hand then stands on another side of it and
withdraws another way). Each is judged by the whole-body IK's postures, not from above: a
spot is taken when the object standing there keeps ``Tuning.arm_room_m`` from the arm and
hand of every take the run's later steps make (``SkillContext.coming``) at that take's
pre-grasp and grasp (:func:`~oacdsl.runtime.armroom.room_to_object`: a cup
set down beside the next cup to be taken was brushed by the fingers taking it), and the hand
reaches it with the arm and hand keeping as much from the table and the other objects at
the hover, where it rests and as it withdraws (:func:`~oacdsl.runtime.armroom.arm_room`: an
elbow laid on a cup beside the way, the back of a hand withdrawing into a neighbour). Spots
that keep only the second come next; when none does, the first the hand reaches, as held.
:func:`spot_near` judges the spots near a wanted place (where the demonstration set the
object down) the same way, and gives None when none passes.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.armroom import arm_room, room_to_object
from oacdsl.runtime.motion import TUNING, other_side, withdrawal
from oacdsl.runtime.motion.spots import free_spots
from oacdsl.runtime.skills.base import REACH_TOLERANCE_M, SkillContext
from oacdsl.runtime.skills.grasp import grasp_candidates
from oacdsl.runtime.transforms import make_T, rot_z

__all__ = ["free_spot", "spot_near", "hand_offsets"]


def free_spot(
    ctx: SkillContext,
    side: str,
    obj: str,
    t_obj_in_hand: np.ndarray,
    r_obj: np.ndarray,
    approach: np.ndarray | None,
) -> tuple[np.ndarray, float]:
    """(x, y) (m) of the free spot where hand ``side`` sets ``obj`` down, and the turn (rad,
    about the vertical) from ``r_obj`` it stands there with (module docstring). Every spot is
    judged where the guarded descent onto it ends (reached only above it, the descent stopped
    short of the table) and, with the other hand holding something, with that hand keeping it
    where it is (reached only by letting the other hand's bottle rise, the lid hung above the
    table). Raises when none is free or reachable."""
    options = _options(ctx, side, obj, t_obj_in_hand, r_obj, approach, None)
    if not options:
        raise RuntimeFailure(f"place: no free spot on the table for {obj}")
    chosen = _judged(ctx, side, obj, options, approach)
    if chosen is not None:
        return chosen
    plain = [o for o in options if o[2] == 0.0][: TUNING.spot_tries]
    plain = [o for o in plain if _with_other(ctx, side, o[0])] or plain
    what = f"a free spot of the table for {obj}"
    return ctx.first_reachable(side, [(o[0], (o[1][:2, 3], 0.0)) for o in plain], what)


def spot_near(
    ctx: SkillContext,
    side: str,
    obj: str,
    t_obj_in_hand: np.ndarray,
    r_obj: np.ndarray,
    approach: np.ndarray | None,
    near_xy_m: np.ndarray,
) -> tuple[np.ndarray, float] | None:
    """As :func:`free_spot`, among the free spots within ``Tuning.demo_spot_within_m`` of
    ``near_xy_m`` (where the demonstration set ``obj`` down, m), nearest first; None when
    none passes the same tests (the caller then does as without it)."""
    options = _options(ctx, side, obj, t_obj_in_hand, r_obj, approach, np.asarray(near_xy_m, float))
    return _judged(ctx, side, obj, options, approach) if options else None


Option = tuple[np.ndarray, np.ndarray, float]  # (T_world_grasp where the descent ends, T_world_obj, turn)


def _options(
    ctx: SkillContext,
    side: str,
    obj: str,
    t_obj_in_hand: np.ndarray,
    r_obj: np.ndarray,
    approach: np.ndarray | None,
    near: np.ndarray | None,
) -> list[Option]:
    """The candidate spots and turns, best first: on the hand's own side and nearest to where
    ``obj`` is now, or nearest to ``near``."""
    world, t = ctx.world, TUNING
    in_hand = np.linalg.inv(t_obj_in_hand)
    back = np.array([0.0, 0.0, -1.0]) if approach is None else approach
    here = world.body_pose(obj)[:2, 3] if near is None else near
    own = 1.0 if side == "l" else -1.0  # the left hand's side is +y
    candidates = []
    for turn in t.spot_turns_rad if ctx.body(obj).round else (0.0,):
        r = rot_z(turn)[:3, :3]
        offsets = hand_offsets(in_hand, r @ r_obj, r @ back)
        radius = ctx.body(obj).radius
        for xy in free_spots(world, side, obj, radius, hand_xy_m=offsets, limit=t.spot_tries, near_xy_m=near):
            key = (near is None and float(xy[1]) * own < 0, float(np.linalg.norm(xy - here)), abs(turn))
            candidates.append((key, xy, turn))
    candidates.sort(key=lambda c: c[0])
    options = []
    for _, xy, turn in candidates:
        t_obj = make_T(rot_z(turn)[:3, :3] @ r_obj, (xy[0], xy[1], ctx.support_height(xy, exclude=obj)))
        down = t_obj.copy()
        down[2, 3] -= t.support_search_m
        options.append((down @ in_hand, t_obj, turn))
    return options


def _with_other(ctx: SkillContext, side: str, t_down: np.ndarray) -> bool:
    """Reached with the other hand keeping what it holds where it is (when it holds something)."""
    other = other_side(side)
    if ctx.world.held.get(other) is None:
        return True
    keep = ctx.ctl.ik.goal(other)
    return ctx.ctl.ik.try_reach_both({side: t_down, other: keep}) < REACH_TOLERANCE_M


def _judged(
    ctx: SkillContext, side: str, obj: str, options: list[Option], approach: np.ndarray | None
) -> tuple[np.ndarray, float] | None:
    """The first of ``options`` out of the way of the run's coming takes, reached with the other
    hand kept where it is, with room for the arm (:func:`_roomy`); then the first of the rest
    that passes the last two; None when none does."""
    t = TUNING
    back = np.array([0.0, 0.0, -1.0]) if approach is None else approach
    coming = _coming_postures(ctx, obj)
    clear: dict[tuple[float, float], bool] = {}

    def out_of_the_way(t_obj: np.ndarray) -> bool:
        at = (float(t_obj[0, 3]), float(t_obj[1, 3]))  # grid points: the same spot turned, the same key
        if at not in clear:
            clear[at] = all(room_to_object(ctx.world, s, q, obj, t_obj) >= t.arm_room_m for s, q in coming)
        return clear[at]

    first = [o for o in options if out_of_the_way(o[1])]
    judged = first + [o for o in options if not out_of_the_way(o[1])]
    for t_down, t_obj, turn in judged[: t.spot_tries]:
        way_back = rot_z(turn)[:3, :3] @ back if approach is not None else None
        if _with_other(ctx, side, t_down) and _roomy(ctx, side, obj, t_down, way_back):
            return t_obj[:2, 3], turn
    return None


def hand_offsets(hand_in_obj: np.ndarray, r_obj: np.ndarray, back: np.ndarray) -> tuple[np.ndarray, ...]:
    """Where the hand is relative to a spot (xy, m) with the object standing there turned as
    ``r_obj`` (world; ``hand_in_obj``: T_obj_grasp), and where it backs off to along ``back``
    (Motion.withdraw): :func:`~oacdsl.runtime.motion.spots.free_spots`' ``hand_xy_m``."""
    hand = (r_obj @ hand_in_obj[:3, 3])[:2]
    return hand, hand - TUNING.withdraw_back_m * back[:2]


def _roomy(ctx: SkillContext, side: str, obj: str, t_down: np.ndarray, approach: np.ndarray | None) -> bool:
    """Whether hand ``side`` reaches ``t_down`` (T_world_grasp where the guarded descent ends)
    and the IK's postures at the hover above it, where it rests and as it withdraws along
    ``approach`` keep the arm ``arm_room_m`` from the table and the objects, and the hand as
    much from the objects."""
    t = TUNING
    rest = t_down.copy()
    rest[2, 3] += t.support_search_m
    hover = rest.copy()
    hover[2, 3] += t.hover_m
    poses = [hover, t_down, rest] + [pose for pose, _ in withdrawal(rest, approach, t)]
    postures = ctx.ctl.ik.reach_postures(side, poses, t.pose_solve_tries)
    if postures[1][0].position_m > REACH_TOLERANCE_M:
        return False
    return all(
        arm_room(ctx.world, side, q, {obj}) >= t.arm_room_m
        and arm_room(ctx.world, side, q, {obj, ctx.world.layout.table}, hand=True) >= t.arm_room_m
        for _, q in postures[:1] + postures[2:]
    )


def _coming_postures(ctx: SkillContext, obj: str) -> list[tuple[str, Mapping[str, float]]]:
    """(side, IK posture) at the pre-grasp and the grasp of each take
    the run's later steps make of an object on the table other than ``obj``: that hand's
    first grasp of it whose approach is free now
    (:func:`~oacdsl.runtime.skills.grasp.grasp_candidates`)."""
    held = set(ctx.world.held.values())
    out: list[tuple[str, Mapping[str, float]]] = []
    for hand, other in ctx.coming:
        if other == obj or other in held or other not in ctx.objects() or hand not in ctx.world.layout.hands:
            continue
        if ctx.library.grasp_for(ctx.classes[other]) is None:
            continue
        plans = grasp_candidates(ctx, hand, other)
        if not plans:
            continue
        s, p = ctx.side(hand), plans[0]
        postures = ctx.ctl.ik.reach_postures(s, [p.pre_grasp, p.grasp], TUNING.pose_solve_tries)
        out.extend((s, q) for _, q in postures)
    return out
