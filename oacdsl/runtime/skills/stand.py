"""Bring a held object onto another turned as the demonstration leaves it (``touch``'s ``tilt``).

``tilt`` is the angle between the object's axis (its z, as it stood at the start) and the
target's axis where the demonstration ends (the composer writes it from the rigid fits:
:attr:`~oacdsl.segmentation.motionfeatures.MotionFeatures.end_tilt_rad`). When the object is held
nearly that way already (within the tuning's ``reorient_min_rad``), ``touch`` brings it down as it
is held; otherwise it is turned on the way:

- **into a slot**: when the target has slots (a rack, :mod:`oacdsl.runtime.racks`), the tilt is
  nearer a quarter turn than upright or upside down, and the object is thin enough along its axis
  for a slot, it goes into one standing on edge, its axis across the slot (a plate in a dish rack);
- **else turned on the target**: its axis tilted by the demonstrated angle about a horizontal
  axis, lowered onto the middle of the target.

The pose is chosen among candidates (each slot, either face forward, spins about the object's own
axis for a round object; horizontal tilt axes round the compass otherwise), nearest the hand
first, by whether the whole-body IK reaches it. The turn happens during the carry; the descent is
guarded (the wrist's ``force``), into a slot down to its floor.
"""

from __future__ import annotations

import math
from typing import TypeVar

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.handgap import hand_box_poses
from oacdsl.runtime.hands import OPEN, finger_joint_names
from oacdsl.runtime.motion import Motion, Tuning, down, other_side
from oacdsl.runtime.shapes import world_corners
from oacdsl.runtime.skills.base import REACH_TOLERANCE_M, SkillContext, cm, fmt_xyz
from oacdsl.runtime.transforms import MIN_JERK_PEAK, interpolate, make_T, rot_axis
from oacdsl.runtime.turning import frame_zx, hull_points, on_edge, placed_by_box, round_angles

__all__ = ["tilt_now", "needs_turn", "set_turned"]

T = TypeVar("T")


def tilt_now(ctx: SkillContext, obj: str, target: str) -> float:
    """The angle (rad) between ``obj``'s z axis and ``target``'s now."""
    z_o = ctx.world.body_pose(obj)[:3, 2]
    z_t = ctx.world.body_pose(target)[:3, 2]
    return math.acos(float(np.clip(z_o @ z_t, -1.0, 1.0)))


def needs_turn(ctx: SkillContext, obj: str, target: str, tilt: float, tuning_rad: float) -> bool:
    """Whether the held ``obj`` must be turned to end ``tilt`` (rad) from ``target``'s axis."""
    return abs(tilt - tilt_now(ctx, obj, target)) > tuning_rad


#: A pose to set an object down from: T_world_object (or T_world_grasp) above where it goes, how far
#: it may go down from there (m), a name for the place, and for a slot the middle of its floor and
#: its normal (world), else None.
Goal = tuple[np.ndarray, float, str, "tuple[np.ndarray, np.ndarray] | None"]


def _slot_poses(ctx: SkillContext, obj: str, target: str, hover: float, t: Tuning) -> list[Goal]:
    """(T_world_object above a slot, depth it goes down from there to the slot's floor (m), what, slot)
    for every slot of ``target`` that ``obj`` fits on edge, either face forward, spun about its
    own axis when it is round (the tuning's spins)."""
    body, t_t = ctx.body(obj), ctx.world.body_pose(target)
    thick = float(np.ptp(hull_points(body)[:, 2]))
    spins = t.stand_spin_tries if body.round else t.stand_square_spin_tries
    out: list[Goal] = []
    for k, s in enumerate(ctx.body(target).slots):
        if thick >= s.width_m:
            continue
        floor = t_t[:3, :3] @ np.asarray(s.floor_m) + t_t[:3, 3]
        normal = t_t[:3, :3] @ np.asarray(s.normal)
        along = t_t[:3, 0]
        top = floor[2] + s.depth_m
        for sign in (1.0, -1.0):
            base = frame_zx(sign * normal, along)
            for spin in round_angles(spins):
                r_obj = base @ rot_axis((0.0, 0.0, 1.0), spin)
                pose = placed_by_box(body, r_obj, floor[:2], top + hover)
                out.append((pose, hover + s.depth_m, f"slot {k + 1} of {target}", (floor, normal)))
    return out


def _least_turn(z_from: np.ndarray, z_to: np.ndarray, across: np.ndarray) -> np.ndarray:
    """The rotation (3x3) turning unit ``z_from`` onto unit ``z_to`` about an axis across both;
    half a turn about ``across`` when they are opposite."""
    axis = np.cross(z_from, z_to)
    norm = float(np.linalg.norm(axis))
    angle = math.atan2(norm, float(z_from @ z_to))
    if norm < 1e-9:
        return rot_axis(across, angle) if angle > 1.0 else np.eye(3)
    return rot_axis(axis / norm, angle)


def _tilted_poses(ctx: SkillContext, obj: str, target: str, tilt: float, hover: float, t: Tuning
                  ) -> list[Goal]:
    """(T_world_object over ``target``'s middle, how far it may go down, what, None): ``obj`` as held,
    turned the least that puts its axis at ``tilt`` from the target's, the target's axis turned by
    ``tilt`` about horizontal axes round the compass (an object held leaning 8°, turned by what is
    left of the tilt about those axes, missed the tilt by up to 16°)."""
    t_o = ctx.world.body_pose(obj)
    t_t = ctx.world.body_pose(target)
    tgt = world_corners(ctx.body(target), t_t)
    mid, top = np.mean([tgt.min(axis=0), tgt.max(axis=0)], axis=0), float(tgt[:, 2].max())
    depth = hover + float(np.ptp(tgt[:, 2]))
    out: list[Goal] = []
    for a in round_angles(t.stand_spin_tries):
        across = np.array([math.cos(a), math.sin(a), 0.0])
        r_obj = _least_turn(t_o[:3, 2], rot_axis(across, tilt) @ t_t[:3, 2], across) @ t_o[:3, :3]
        out.append((placed_by_box(ctx.body(obj), r_obj, mid[:2], top + hover), depth, f"the top of {target}",
                    None))
    return out


def _first_held_reach(ctx: SkillContext, side: str, options: list[tuple[np.ndarray, T]], what: str) -> T:
    """The payload of the first option whose hand pose the whole-body IK reaches with the other
    hand kept where it is commanded now (turning what it holds, the arm may need the torso,
    which the other hand's hold pulls back: reached alone, a pose was missed by 6 cm)."""
    ik = ctx.ctl.ik
    keep = {other_side(side): ik.goal(other_side(side))}
    best: tuple[float, np.ndarray] | None = None
    for target, payload in options:
        err = ik.try_reach_both({side: target, **keep})
        if err <= REACH_TOLERANCE_M:
            return payload
        if best is None or err < best[0]:
            best = (err, target)
    if best is None:
        raise RuntimeFailure(f"touch: no pose for {what}")
    raise RuntimeFailure(
        f"touch: {what} is out of reach: the best whole-body IK solution, the other hand kept where"
        f" it is, leaves the hand {cm(best[0])} from {fmt_xyz(best[1][:3, 3])}"
    )


def _hand_low(ctx: SkillContext, side: str, t_world_grasp: np.ndarray) -> float:
    """The lowest point (m) of hand ``side``'s boxes at ``t_world_grasp``, its fingers as they are
    now or open (:data:`~oacdsl.runtime.hands.OPEN`), whichever reaches lower."""
    q = ctx.world.joint_positions()
    now = {j: float(q[name]) for j, name in finger_joint_names(side).items()}
    return min(float(t[2, 3] - np.abs(t[2, :3]) @ h)
               for fingers in (now, OPEN) for t, h in hand_box_poses(side, t_world_grasp, fingers))


def _turn_s(ctx: SkillContext, side: str, first: np.ndarray, above: np.ndarray, t: Tuning) -> float:
    """How long hand ``side`` takes to turn from ``first`` to ``above`` (T_world_grasp):
    at least the tuning's carry time, and as long as its joints need at their speed limits
    through the turn (the whole-body IK's postures at the tuning's ``turn_sample_tries`` steps) at
    the peak speed of a min-jerk motion. Turning a plate on edge moves the forearm's roll joint
    by 2.7-2.8 rad, 3.5 s at its limit: turned in 1.6 s, the arm lagged the turn and swung the
    hand 17 cm up and 9 cm across, the plate into the other hand (30-53 N)."""
    poses = [interpolate(first, above, u) for u in np.linspace(0.0, 1.0, t.turn_sample_tries)]
    postures = [q for _, q in ctx.ctl.ik.reach_postures(side, poses, t.turn_solve_tries)]
    return max(t.carry_s, MIN_JERK_PEAK * ctx.ctl.ik.travel_s(postures))


def _carry_then_turn(ctx: SkillContext, m: Motion, obj: str, target: str, above: np.ndarray,
                     what: str) -> None:
    """Carry the held ``obj`` to ``above`` (T_world_grasp), turning it there: first as it is held to
    the hand's place over the target, then turned in place (a plate turned on the way swept into
    the other hand), when the whole-body IK reaches that first pose; else turned on the way."""
    t, side = m.tuning, m.side
    first = make_T(m.here()[:3, :3], above[:3, 3])
    keep = {other_side(side): ctx.ctl.ik.goal(other_side(side))}
    ctx.ctl.activity = f"carrying {obj} over {what}"
    if ctx.ctl.ik.try_reach_both({side: first, **keep}) <= REACH_TOLERANCE_M:
        m.carry(first, {obj, target}, t.carry_s)
        ctx.ctl.activity = f"turning {obj} over {what}"
        m.go(above, _turn_s(ctx, side, first, above, t))
    else:  # turned on the way, as slowly as the joints need for the turn
        far = float(np.linalg.norm(above[:3, 3] - m.here()[:3, 3]))
        m.carry(above, {obj, target}, max(_turn_s(ctx, side, m.here(), above, t), far / t.carry_speed_m_s))
    m.hold_still(t.turn_settle_s)


def _centre_across(ctx: SkillContext, m: Motion, obj: str,
                   line: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
    """Move the hand across a slot (``line``: the middle of its floor and its normal, world) until
    the held ``obj``'s middle is within the tuning's ``turn_centred_m`` of the slot's middle (the arm
    lags a turned load by a centimetre or two, the slot leaves the object about as much play);
    returns the hand's commanded pose then."""
    t = m.tuning
    floor, normal = line
    for _ in range(t.turn_centre_tries):
        pose = ctx.world.body_pose(obj)
        c = hull_points(ctx.body(obj)) @ pose[:3, :3].T + pose[:3, 3]
        off = float((np.mean([c.min(axis=0), c.max(axis=0)], axis=0) - floor) @ normal)
        if abs(off) <= t.turn_centred_m:
            break
        ctx.ctl.activity = f"centring {obj} over the slot"
        here = m.here()
        m.go(make_T(here[:3, :3], here[:3, 3] - off * normal), t.turn_centre_s)
        m.hold_still(t.pause_s)
    return m.here()


def set_turned(ctx: SkillContext, m: Motion, obj: str, target: str, tilt: float, hover: float,
               force: float) -> bool:
    """Carry the held ``obj`` over ``target`` turned to end ``tilt`` (rad) from its axis, into a
    slot when it has one that fits (module doc), and lower it until the two touch (into a slot:
    until the wrist feels ``force`` (N) or it reaches the floor); True when they touch."""
    side = m.side
    body_t = ctx.body(target)
    into_slot = on_edge(tilt) and bool(body_t.slots)
    poses = _slot_poses(ctx, obj, target, hover, m.tuning) if into_slot else []
    if into_slot and not poses:
        raise RuntimeFailure(f"touch: {obj} fits no slot of {target} on edge")
    if not poses:
        poses = _tilted_poses(ctx, obj, target, tilt, hover, m.tuning)
    _, obj_in_hand = ctx.held_pose(side, obj)
    hand_in_obj = np.linalg.inv(obj_in_hand)
    here = ctx.world.frame_pose(f"grasp_{side}")[:3, 3]
    options = [(pose @ hand_in_obj, (pose @ hand_in_obj, depth, what, line))
               for pose, depth, what, line in poses]
    # the hand highest first (in steps of the tuning's spot spacing: clear of a rack's walls, what it
    # holds hanging below it), then nearest
    step = m.tuning.spot_step_m
    options.sort(key=lambda o: (-math.floor(float(o[0][2, 3]) / step),
                                float(np.linalg.norm(o[0][:3, 3] - here))))
    if into_slot:  # the hand, open or closed, above the rack's walls where the object is let go
        top = float(world_corners(body_t, ctx.world.body_pose(target))[:, 2].max())
        margin = top + m.tuning.hand_clearance_m
        clear = [o for o in options if _hand_low(ctx, side, down(o[0], o[1][1])) >= margin]
        options = clear or options
    wanted = f"{obj} turned {math.degrees(tilt):.0f}° over {target}"
    above, depth, what, line = _first_held_reach(ctx, side, options, wanted)
    _carry_then_turn(ctx, m, obj, target, above, what)
    if line is not None:
        above = _centre_across(ctx, m, obj, line)
    ctx.ctl.activity = f"setting {obj} into {what}"
    if into_slot:
        # down to the slot's floor, looking below it as a set-down does, until it touches the rack
        guard = m.contact_or_force(obj, target, max(force, m.tuning.slot_force_n))
        m.approach(down(above, depth + m.tuning.support_search_m), guard, m.tuning.set_down_speed_m_s)
        touching = m.touching(obj, target)
        if touching():
            m.stay()  # at the edge of its reach the arm, stopped, would rise off the floor
            m.press()  # resting on it (the arm lags: where it first touched, it floats)
        return m.hold_still(m.tuning.contact_wait_s, touching) or touching()
    return m.approach(down(above, depth), m.contact_or_force(obj, target, force),
                      wait_for=m.touching(obj, target))

